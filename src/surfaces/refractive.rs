//! Refraction by Snell's law, n₁ sin θ₁ = n₂ sin θ₂, with total internal reflection.
//!
//! `index_ratio` is n_inside / n_outside, where "outside" is the side the outward normal points
//! to. Transmitted (or totally internally reflected) light is scaled by the transmission
//! coefficient; Fresnel reflection is not modelled, as in TIM.

use glam::DVec3;
use serde::Deserialize;

use super::mirror::reflect;
use super::{Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, Positive, throughput};
use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct Refractive {
    /// n_inside / n_outside.
    pub index_ratio: f64,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

/// Direction of the ray refracted at a surface with unit outward normal `n` and
/// n_inside / n_outside = `index_ratio`; `None` for total internal reflection.
/// The tangential component of the direction is scaled by n₁/n₂ (Snell's law in vector form);
/// the result is a unit vector when `d` is.
pub fn refract(d: DVec3, n: DVec3, index_ratio: f64) -> Option<DVec3> {
    // Orient the normal against the incoming ray; η = n₁/n₂ for the side the ray comes from.
    let entering = d.dot(n) < 0.0;
    let (n, eta) = if entering {
        (n, 1.0 / index_ratio)
    } else {
        (-n, index_ratio)
    };
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(eta * d + (eta * cos_i - cos_t) * n)
}

impl Refractive {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let d = at.ray.direction;
        let n = at.normal();
        Redirection::Leaves {
            direction: refract(d, n, self.index_ratio).unwrap_or_else(|| reflect(d, n)),
            factor: Colour::splat(self.transmission_coefficient),
        }
    }
}

/// `type = "refractive"`: Dr TIM's `Refractive` with its GUI's defaults, index ratio 1 and
/// transmission coefficient 0.96.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefractiveKeys {
    index_ratio: Option<Positive>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl RefractiveKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Refractive(Refractive {
            index_ratio: self.index_ratio.map_or(1.0, |n| n.0),
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    /// Direction in the x–y plane at angle θ to −y (travelling downwards onto the plane y = 0).
    fn downwards(theta: f64) -> DVec3 {
        DVec3::new(theta.sin(), -theta.cos(), 0.0)
    }

    #[test]
    fn snells_law_entering_glass() {
        // Air to glass (n = 1.5) at 30°: sin θ₂ = sin 30° / 1.5 = 1/3.
        let t = refract(downwards(30f64.to_radians()), DVec3::Y, 1.5).unwrap();
        assert!((t.x - 1.0 / 3.0).abs() < 1e-15, "{t}");
        assert!(t.y < 0.0 && (t.length() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn snells_law_leaving_glass() {
        // Inside the glass (the ray travels along the outward normal's side): sin θ₂ = 1.5 sin θ₁.
        let d = -downwards(20f64.to_radians()); // upwards, towards the outside
        let t = refract(d, DVec3::Y, 1.5).unwrap();
        assert!((t.x.abs() - 1.5 * 20f64.to_radians().sin()).abs() < 1e-15);
        assert!(t.y > 0.0);
    }

    #[test]
    fn critical_angle_separates_refraction_from_tir() {
        let critical = (1.0f64 / 1.5).asin(); // 41.81°
        let up = |theta: f64| -downwards(theta);
        let grazing = refract(up(critical - 1e-9), DVec3::Y, 1.5).unwrap();
        assert!(
            grazing.y.abs() < 1e-3,
            "just below the critical angle the ray leaves grazing"
        );
        assert_eq!(refract(up(critical + 1e-9), DVec3::Y, 1.5), None);
    }

    #[test]
    fn index_ratio_one_is_undeviated_and_normal_incidence_is_undeviated() {
        let d = DVec3::new(0.3, -0.8, 0.52).normalize();
        assert!((refract(d, DVec3::Y, 1.0).unwrap() - d).length() < 1e-15);
        assert!((refract(-DVec3::Y, DVec3::Y, 2.4).unwrap() + DVec3::Y).length() < 1e-15);
    }

    /// Checks `out` against Snell's law for a ray `d` crossing from index `n1` into `n2` at a
    /// surface with unit normal `n` (either orientation): n₁ sin θ₁ = n₂ sin θ₂ with the sines
    /// taken as |d × n|, the ray on the far side, in the plane of incidence and bent towards or
    /// away from the normal without changing the way it runs along the surface.
    fn assert_snell(d: DVec3, n: DVec3, n1: f64, n2: f64, out: DVec3) {
        assert!((out.length() - 1.0).abs() < 1e-14, "{out}");
        let (sin1, sin2) = (d.cross(n).length(), out.cross(n).length());
        assert!(
            (n1 * sin1 - n2 * sin2).abs() < 1e-14,
            "{n1} {sin1} {n2} {sin2}"
        );
        assert!(out.dot(n) * d.dot(n) > 0.0, "crosses");
        assert!(
            out.dot(d.cross(n)).abs() < 1e-14,
            "in the plane of incidence"
        );
        assert!(out.cross(n).dot(d.cross(n)) > 0.0, "on along the surface");
    }

    /// Mirror image: the angle of reflection equals the angle of incidence, back on the same
    /// side, in the plane of incidence.
    fn assert_reflected(d: DVec3, n: DVec3, out: DVec3) {
        assert!((out.dot(n) + d.dot(n)).abs() < 1e-14, "{out}");
        assert!((out.cross(n) - d.cross(n)).length() < 1e-14, "{out}");
    }

    /// `Refractive::redirect` on the plane z = 0 (outward normal +z, glass below with
    /// n_inside/n_outside = 1.5): entering, sin θ₂ = sin θ₁ / 1.5; leaving, sin θ₂ =
    /// 1.5 sin θ₁; beyond the critical angle arcsin(1/1.5) = 41.8° the ray is totally
    /// internally reflected. Every ray carries the transmission coefficient.
    #[test]
    fn redirect_on_a_plane_obeys_snells_law_and_total_internal_reflection() {
        let glass = Refractive {
            index_ratio: 1.5,
            transmission_coefficient: 0.9,
        };
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let n = DVec3::Z;
        // A plane of incidence at azimuth 0.7 rad, not along an axis.
        let across = DVec3::new(0.7f64.cos(), 0.7f64.sin(), 0.0);
        let at_angle = |deg: f64, down: bool| {
            let t = deg.to_radians();
            let z = if down { -t.cos() } else { t.cos() };
            t.sin() * across + z * DVec3::Z
        };
        for deg in [0.0, 10.0, 35.0, 60.0, 89.0] {
            let d = at_angle(deg, true);
            let at = meet(&plane, -3.0 * d, d);
            let (out, factor) = leaves(glass.redirect(&at));
            assert_eq!(factor, 0.9);
            if deg == 0.0 {
                assert!((out - d).length() < 1e-15, "normal incidence is undeviated");
            } else {
                assert_snell(d, n, 1.0, 1.5, out);
            }
        }
        for deg in [10.0, 25.0, 41.0] {
            let d = at_angle(deg, false);
            let (out, _) = leaves(glass.redirect(&meet(&plane, -3.0 * d, d)));
            assert_snell(d, n, 1.5, 1.0, out);
        }
        for deg in [42.0, 50.0, 80.0] {
            let d = at_angle(deg, false);
            let (out, factor) = leaves(glass.redirect(&meet(&plane, -3.0 * d, d)));
            assert_reflected(d, n, out);
            assert_eq!(factor, 0.9);
        }
    }

    /// The same on a sphere, whose outward normal at the hit is (P − C)/R: a water drop
    /// (n = 1.33) entered from outside and left from inside, total internal reflection from
    /// inside near grazing, and an air bubble (index ratio 0.8) that reflects rays arriving
    /// from outside beyond arcsin 0.8 = 53°.
    #[test]
    fn redirect_on_a_sphere_obeys_snells_law_with_the_outward_normal() {
        let centre = DVec3::new(0.5, -1.0, 2.0);
        let radius = 2.0;
        let sphere = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let drop = Refractive {
            index_ratio: 1.33,
            transmission_coefficient: 0.95,
        };
        let bubble = Refractive {
            index_ratio: 0.8,
            transmission_coefficient: 1.0,
        };
        let d = DVec3::new(0.2, 0.1, 1.0).normalize();
        let sideways = d.any_orthonormal_vector();
        for b in [0.1, 0.5, 0.9, 1.5, 1.9] {
            // From outside, with impact parameter b.
            let origin = centre - 5.0 * d + b * sideways;
            let at = meet(&sphere, origin, d);
            let n = (at.point() - centre) / radius;
            let (out, factor) = leaves(drop.redirect(&at));
            assert_eq!(factor, 0.95);
            assert_snell(d, n, 1.0, 1.33, out);
            let (out, _) = leaves(bubble.redirect(&at));
            let sin = d.cross(n).length();
            if sin < 0.8 {
                assert_snell(d, n, 1.0, 0.8, out);
            } else {
                assert_reflected(d, n, out);
            }
            // From inside, along the same line (from a point inside the sphere).
            let at = meet(&sphere, centre + b * sideways, d);
            let n = (at.point() - centre) / radius;
            let (out, _) = leaves(drop.redirect(&at));
            if 1.33 * d.cross(n).length() < 1.0 {
                assert_snell(d, n, 1.33, 1.0, out);
            } else {
                assert_reflected(d, n, out);
            }
        }
        // b = 1.9 from the centre gives sin θ = 0.95 inside the drop: 1.33 × 0.95 > 1, TIR.
        let at = meet(&sphere, centre + 1.9 * sideways, d);
        let n = (at.point() - centre) / radius;
        assert!(1.33 * d.cross(n).length() > 1.0);
        assert_reflected(d, n, leaves(drop.redirect(&at)).0);
    }
}
