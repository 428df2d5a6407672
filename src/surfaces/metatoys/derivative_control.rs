//! A derivative-control surface (Dr TIM's `DerivativeControlSurface`, a `DirectionChanging`
//! surface, by Ewan, Maik and Johannes; research folder `refractiveTaylorSeries`): it turns one
//! pair of light-ray directions into each other, D_i0 on the inside into D_o0 on the outside,
//! and every other direction by a Jacobian matrix J about them.
//!
//! With (u, v, n) the surface's frame at the point (n the outward normal) and the tangential
//! components d = (d·u, d·v) of unit directions, a ray travelling outwards with unit direction
//! d_i leaves with tangential components
//!
//! ```text
//! d_o = d_o0 + J (d_i − d_i0),
//! ```
//!
//! its normal component filling the unit vector on the outside; a ray travelling inwards is
//! mapped back, d_i = d_i0 + J⁻¹ (d_o − d_o0) (Dr TIM's `getJacobian` for `INWARDS`), so the law
//! is reciprocal. Where the tangential part reaches length 1 the light is evanescent and is
//! reflected (Dr TIM's `DirectionChanging`), all of it. D_i0 and D_o0 are given as outward-going
//! directions; by default both are the normal and J the identity, a surface that changes
//! nothing.
//!
//! Dr TIM's subclass `DerivativeControlSurfaceRotatingPhaseHologramApproximation` (its program
//! `DerivativeControlSurfaceExplorer`) makes a view rotator: seen from the eye E, a point of the
//! view plane (through Q, normal â) appears rotated by θ about the line through E along â and
//! shrunk by the magnification factor M about the point C where that line meets the plane.
//! At the surface point P: D_i0 = P − E, and D_o0 = R − P, where R is the apparent position A
//! (the line from E through P meets the plane) rotated by θ about the axis through E and scaled
//! about C by 1/M (the normal where that line runs along the plane, as in Dr TIM); both
//! oriented outwards; and J = (1/m) [[cos φ, −sin φ], [sin φ, cos φ]] for
//! the pixel rotation angle φ and magnification m (Dr TIM's matrix for −φ).
//!
//! Pixellated (Dr TIM's `pixellated`), every point of a pixel (a cell of the plane coordinates,
//! `pixel_period_u` × `pixel_period_v`, centred on multiples of the periods) takes D_i0, D_o0
//! and the frame of the pixel's centre: each pixel deflects as one flat prism.

use glam::{DMat2, DQuat, DVec2, DVec3};
use serde::Deserialize;

use super::Outgoing;
use crate::geometry::{Interaction, Transform};
use crate::keys::{Array, Coefficient, Direction, Finite, NonZero, Positive, Vector, throughput};
use crate::surfaces::{Redirection, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct DerivativeControl {
    pub directions: CentralDirections,
    /// J, from inside to outside, in the frame's (u, v) components.
    pub jacobian: DMat2,
    /// The pixel periods along the plane coordinates, if pixellated.
    pub pixels: Option<DVec2>,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

/// Where D_i0 and D_o0 come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CentralDirections {
    /// Fixed outward-going directions, or the normal (`None`).
    Given {
        inside: Option<DVec3>,
        outside: Option<DVec3>,
    },
    /// Dr TIM's view rotator.
    ViewRotation(ViewRotation),
}

/// Dr TIM's `DerivativeControlSurfaceRotatingPhaseHologramApproximation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewRotation {
    /// E.
    pub eye_position: DVec3,
    /// Q, on the view plane.
    pub point_on_plane: DVec3,
    /// â, unit: the view plane's normal and the rotation axis.
    pub plane_normal: DVec3,
    /// θ, in radians.
    pub rotation_angle: f64,
    /// M.
    pub magnification_factor: f64,
}

impl ViewRotation {
    /// (D_i0, D_o0) at P, not yet oriented; D_o0 `None` where the line of sight from E
    /// through P runs along the plane (Dr TIM then takes the normal).
    fn directions(&self, p: DVec3) -> (DVec3, Option<DVec3>) {
        let (e, a) = (self.eye_position, self.plane_normal);
        let along = p - e;
        let t = (self.point_on_plane - p).dot(a) / along.dot(a);
        let apparent = p + t * along;
        let rotated = e + DQuat::from_axis_angle(a, self.rotation_angle) * (apparent - e);
        let centre = e + (self.point_on_plane - e).dot(a) * a;
        let image = centre + (rotated - centre) / self.magnification_factor;
        (
            along,
            (t.is_finite() && image.is_finite()).then_some(image - p),
        )
    }
}

impl DerivativeControl {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let frame = at.frame();
        let mut p = at.local_point();
        if let (Some(period), Some(c)) = (self.pixels, at.plane_coordinates()) {
            let centre = (c / period + 0.5).floor() * period;
            p += (centre.x - c.x) * frame.u + (centre.y - c.y) * frame.v;
        }
        let n = frame.w;
        let d = at.ray.direction.normalize();
        let outwards = d.dot(n) > 0.0;
        let outward = |x: DVec3| if x.dot(n) < 0.0 { -x } else { x };
        let (inside, outside) = match self.directions {
            CentralDirections::Given { inside, outside } => {
                (inside.unwrap_or(n), outside.unwrap_or(n))
            }
            CentralDirections::ViewRotation(r) => {
                let (i, o) = r.directions(p);
                (outward(i), o.map_or(n, outward))
            }
        };
        let tangential = |x: DVec3| {
            let x = x.normalize();
            DVec2::new(x.dot(frame.u), x.dot(frame.v))
        };
        let sign = if outwards { 1.0 } else { -1.0 };
        let (from, to, jacobian) = if outwards {
            (inside, outside, self.jacobian)
        } else {
            (outside, inside, self.jacobian.inverse())
        };
        let t = jacobian * (tangential(d) - tangential(sign * from)) + tangential(sign * to);
        let normal2 = 1.0 - t.length_squared();
        let out = (normal2 >= 0.0 && t.is_finite())
            .then(|| t.x * frame.u + t.y * frame.v + sign * normal2.sqrt() * n);
        Outgoing::or_mirrored(out, d, n).leaves(self.transmission_coefficient, 1.0)
    }

    /// The surface of an object placed by `t` (a rotation, uniform scaling and translation):
    /// the directions, the view rotator's points and the pixel periods move with it; J is read
    /// in the surface's own frame, which turns with it.
    pub fn transformed(&self, t: &Transform) -> Result<DerivativeControl, String> {
        let scale = t.uniform_scale().filter(|_| !t.reflects()).ok_or(
            "a derivative-control surface's Jacobian is read in the surface's frame, which \
                 only rotations, uniform scaling and translations keep: it cannot be scaled \
                 non-uniformly or mirrored",
        )?;
        let direction = |x: DVec3| t.vector(x).normalize();
        Ok(DerivativeControl {
            directions: match self.directions {
                CentralDirections::Given { inside, outside } => CentralDirections::Given {
                    inside: inside.map(direction),
                    outside: outside.map(direction),
                },
                CentralDirections::ViewRotation(r) => {
                    CentralDirections::ViewRotation(ViewRotation {
                        eye_position: t.point(r.eye_position),
                        point_on_plane: t.point(r.point_on_plane),
                        plane_normal: direction(r.plane_normal),
                        ..r
                    })
                }
            },
            pixels: self.pixels.map(|p| p * scale),
            ..self.clone()
        })
    }
}

/// `view_rotation = { ... }`: Dr TIM's view rotator (no GUI: the eye, plane and angle are
/// required; the factors default to 1 and the pixel rotation to 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ViewRotationKeys {
    eye_position: Vector,
    point_on_plane: Vector,
    plane_normal: Direction,
    rotation_angle_deg: Finite,
    magnification_factor: Option<NonZero>,
    pixel_rotation_angle_deg: Option<Finite>,
    pixel_magnification_factor: Option<NonZero>,
}

/// `type = "derivative-control"`: Dr TIM's default `DerivativeControlSurface()`: D_i0 and D_o0
/// the normal, J the identity, not pixellated (pixel periods 1 × 1), transmission 0.96.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DerivativeControlKeys {
    jacobian: Option<Array<Array<Finite, 2>, 2>>,
    inside_direction: Option<Direction>,
    outside_direction: Option<Direction>,
    view_rotation: Option<ViewRotationKeys>,
    pixellated: Option<bool>,
    pixel_period_u: Option<Positive>,
    pixel_period_v: Option<Positive>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl DerivativeControlKeys {
    pub fn build(self) -> Result<Surface, String> {
        let pixellated = self.pixellated.unwrap_or(false);
        if !pixellated && (self.pixel_period_u.is_some() || self.pixel_period_v.is_some()) {
            return Err(
                "derivative-control: pixel_period_u and pixel_period_v need pixellated = true"
                    .into(),
            );
        }
        let (directions, jacobian) = match self.view_rotation {
            Some(r) => {
                if self.jacobian.is_some()
                    || self.inside_direction.is_some()
                    || self.outside_direction.is_some()
                {
                    return Err("derivative-control: a view_rotation sets the central \
                                directions and the Jacobian; give it alone, without \
                                jacobian, inside_direction or outside_direction"
                        .into());
                }
                let phi = r.pixel_rotation_angle_deg.map_or(0.0, |a| a.0).to_radians();
                let m = r.pixel_magnification_factor.map_or(1.0, |m| m.0);
                let rotation = ViewRotation {
                    eye_position: r.eye_position.0,
                    point_on_plane: r.point_on_plane.0,
                    plane_normal: r.plane_normal.0,
                    rotation_angle: r.rotation_angle_deg.0.to_radians(),
                    magnification_factor: r.magnification_factor.map_or(1.0, |m| m.0),
                };
                let j = DMat2::from_cols(
                    DVec2::new(phi.cos(), phi.sin()),
                    DVec2::new(-phi.sin(), phi.cos()),
                ) / m;
                (CentralDirections::ViewRotation(rotation), j)
            }
            None => {
                let j = self.jacobian.map_or(DMat2::IDENTITY, |rows| {
                    let [a, b] = rows.0.map(|row| DVec2::from(row.0.map(|x| x.0)));
                    DMat2::from_cols(DVec2::new(a.x, b.x), DVec2::new(a.y, b.y))
                });
                let size = j.to_cols_array().iter().fold(0f64, |m, x| m.max(x.abs()));
                if size == 0.0 || (j / size).determinant().abs() < 1e-12 {
                    return Err(
                        "derivative-control: `jacobian` must be an invertible 2 × 2 \
                                matrix (rays crossing inwards are mapped by its inverse)"
                            .into(),
                    );
                }
                let directions = CentralDirections::Given {
                    inside: self.inside_direction.map(|d| d.0),
                    outside: self.outside_direction.map(|d| d.0),
                };
                (directions, j)
            }
        };
        Ok(Surface::DerivativeControl(DerivativeControl {
            directions,
            jacobian,
            pixels: pixellated.then(|| {
                DVec2::new(
                    self.pixel_period_u.map_or(1.0, |p| p.0),
                    self.pixel_period_v.map_or(1.0, |p| p.0),
                )
            }),
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape};
    use crate::surfaces::tests::{leaves, meet};

    /// The plane z = 0 with outward normal +z and u = x, v = y (Dr TIM's `ParametrisedPlane`
    /// of its default).
    fn plane() -> Shape {
        Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap())
    }

    fn surface(keys: &str) -> DerivativeControl {
        let keys: DerivativeControlKeys = toml::from_str(keys).unwrap();
        let Surface::DerivativeControl(s) = keys.build().unwrap() else {
            panic!("the kind built")
        };
        s
    }

    /// The direction leaving `s` for a ray from `from` along `d` meeting the plane.
    fn through(s: &DerivativeControl, from: DVec3, d: DVec3) -> DVec3 {
        let shape = plane();
        leaves(s.redirect(&meet(&shape, from, d))).0
    }

    fn close(a: DVec3, b: DVec3) {
        assert!((a - b).length() < 1e-12, "{a} is not {b}");
    }

    #[test]
    fn dr_tims_default_changes_nothing() {
        let s = surface("");
        assert_eq!(s.transmission_coefficient, 0.96);
        assert_eq!((s.jacobian, s.pixels), (DMat2::IDENTITY, None));
        for d in [DVec3::new(0.3, -0.2, 1.0), DVec3::new(-0.5, 0.1, -0.4)] {
            let from = -2.0 * d;
            close(through(&s, from, d), d.normalize());
        }
    }

    #[test]
    fn a_rotation_jacobian_rotates_the_tangential_direction() {
        // DerivativeControlSurfaceRotating's J = [[cos θ, sin θ], [−sin θ, cos θ]] turns the
        // tangential part of an outgoing ray by −θ about the normal; the normal part stays.
        let theta = 0.4f64;
        let (c, s) = (theta.cos(), theta.sin());
        let dc = surface(&format!("jacobian = [[{c}, {s}], [{}, {c}]]", -s));
        let d = DVec3::new(0.3, -0.2, 0.9).normalize();
        let expected = DVec3::new(c * d.x + s * d.y, -s * d.x + c * d.y, d.z);
        close(through(&dc, -d, d), expected);
    }

    #[test]
    fn the_central_directions_map_onto_each_other_and_the_law_is_reciprocal() {
        let dc = surface(
            "jacobian = [[1.2, 0.3], [-0.1, 0.8]]\ninside_direction = [0.2, 0.1, 1]\n\
             outside_direction = [-0.3, 0.25, 1]",
        );
        let (di0, do0) = (
            DVec3::new(0.2, 0.1, 1.0).normalize(),
            DVec3::new(-0.3, 0.25, 1.0).normalize(),
        );
        // Outwards along D_i0: out along D_o0; inwards along −D_o0: in along −D_i0.
        close(through(&dc, -di0, di0), do0);
        close(through(&dc, do0, -do0), -di0);
        // Any ray: what goes out along d′ comes back in along −d.
        let d = DVec3::new(-0.1, 0.3, 0.8).normalize();
        let out = through(&dc, -d, d);
        close(through(&dc, out, -out), -d);
        // The tangential change is J times the incident one's.
        let t = |x: DVec3| DVec2::new(x.x, x.y);
        let expected = DVec2::new(-0.3, 0.25) / DVec3::new(-0.3, 0.25, 1.0).length()
            + DMat2::from_cols(DVec2::new(1.2, -0.1), DVec2::new(0.3, 0.8)) * (t(d) - t(di0));
        assert!((t(out) - expected).length() < 1e-12);
    }

    #[test]
    fn the_view_rotator_shows_the_view_plane_rotated_and_shrunk() {
        // DerivativeControlSurfaceExplorer: eye at z = −5, view plane z = 10, 20°; here also
        // shrunk by M = 2. A line of sight from the eye through P leaves towards the apparent
        // point A rotated by 20° about the z axis and halved (worked out here).
        let dc = surface(
            "view_rotation = { eye_position = [0, 0, -5], point_on_plane = [0, 0, 10], \
             plane_normal = [0, 0, 1], rotation_angle_deg = 20, magnification_factor = 2 }",
        );
        let eye = DVec3::new(0.0, 0.0, -5.0);
        for p in [DVec3::new(0.4, 0.1, 0.0), DVec3::new(-0.2, 0.7, 0.0)] {
            let out = through(&dc, eye, p - eye);
            // A = E + 3 (P − E) on z = 10; rotated and halved about (0, 0, 10).
            let a = eye + 3.0 * (p - eye);
            let (c, s) = (20f64.to_radians().cos(), 20f64.to_radians().sin());
            let image = DVec3::new(c * a.x - s * a.y, s * a.x + c * a.y, 2.0 * 10.0) / 2.0;
            close(out, (image - p).normalize());
        }
    }

    #[test]
    fn pixellated_each_pixel_deflects_like_its_centre() {
        let dc = surface(
            "pixellated = true\npixel_period_u = 0.1\npixel_period_v = 0.1\n\
             view_rotation = { eye_position = [0, 0, -5], point_on_plane = [0, 0, 10], \
             plane_normal = [0, 0, 1], rotation_angle_deg = 20 }",
        );
        let smooth = surface(
            "view_rotation = { eye_position = [0, 0, -5], point_on_plane = [0, 0, 10], \
             plane_normal = [0, 0, 1], rotation_angle_deg = 20 }",
        );
        // Parallel rays through two points of the pixel centred on (0.3, 0.1) leave parallel,
        // as through the pixel's centre; the smooth surface turns them differently.
        let d = DVec3::new(0.05, 0.02, 1.0).normalize();
        let at = |s: &DerivativeControl, x: f64, y: f64| through(s, DVec3::new(x, y, 0.0) - d, d);
        close(at(&dc, 0.27, 0.08), at(&dc, 0.3, 0.1));
        close(at(&dc, 0.33, 0.14), at(&smooth, 0.3, 0.1));
        assert!((at(&smooth, 0.27, 0.08) - at(&smooth, 0.3, 0.1)).length() > 1e-4);
    }

    #[test]
    fn a_jacobian_that_pushes_the_ray_past_grazing_reflects_it() {
        let dc = surface("jacobian = [[5, 0], [0, 5]]");
        let d = DVec3::new(0.5, 0.0, 0.75f64.sqrt());
        let shape = plane();
        let (out, factor) = leaves(dc.redirect(&meet(&shape, -d, d)));
        close(out, DVec3::new(d.x, 0.0, -d.z));
        assert_eq!(factor, 1.0);
    }
}
