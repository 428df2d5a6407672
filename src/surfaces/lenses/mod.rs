//! Perfect-imaging lenses on spheres (§3): Luneburg, Eaton and Maxwell-fisheye lenses and the
//! general GGRIN lens, each mapping the point and direction where a ray enters to those where
//! it leaves by a closed formula, as Dr TIM does; or any spherically symmetric index profile
//! traced by integrating the ray equation through it.
//!
//! Around each law the lens adds the invisible core of a multi-focal lens (§3.2) and refraction
//! at a surface whose index differs from the surrounding medium's (§3.3).

mod eaton;
mod ggrin;
mod gradient_index;
mod luneburg;
mod maxwell_fisheye;
mod profile;

pub use eaton::{EatonLensKeys, eaton};
pub use ggrin::{Ggrin, GgrinLensKeys};
pub use gradient_index::{GradientIndex, GradientIndexLensKeys};
pub use luneburg::{LuneburgLensKeys, luneburg};
pub use maxwell_fisheye::{MaxwellFisheyeLensKeys, maxwell_fisheye};
pub use profile::{IndexProfile, TableProfile};

use glam::DVec3;

use super::{Redirection, reflect, refract};
use crate::geometry::{Exit, Interaction, Shape, Sphere};
use serde::Deserialize;

use super::Surface;
use crate::keys::throughput;
use crate::keys::{Coefficient, Positive, number};
use crate::math::Colour;

/// What a lens does between entry and exit.
#[derive(Debug, Clone, PartialEq)]
pub enum LensLaw {
    /// Eqs 5–6.
    Luneburg,
    /// Eqs 7–8.
    Eaton,
    /// Eqs 9–10.
    MaxwellFisheye,
    /// Eqs 11–15.
    Ggrin(Ggrin),
    /// The ray equation integrated through an index profile.
    GradientIndex(GradientIndex),
}

impl LensLaw {
    /// The ray leaving `lens` after entering at `p` with direction `d` (inside the lens
    /// material); `None` for an integrated ray that never leaves.
    pub fn transmit(&self, lens: &Sphere, p: DVec3, d: DVec3) -> Option<Exit> {
        self.transmit_observed(lens, p, d, &mut |_| {})
    }

    /// [`Self::transmit`], showing `inside` the points of an integrated ray's curved path
    /// (see [`GradientIndex::transmit_observed`]); the closed forms have none.
    pub fn transmit_observed(
        &self,
        lens: &Sphere,
        p: DVec3,
        d: DVec3,
        inside: &mut dyn FnMut(DVec3),
    ) -> Option<Exit> {
        match self {
            LensLaw::Luneburg => Some(luneburg(lens, p, d)),
            LensLaw::Eaton => Some(eaton(lens, p, d)),
            LensLaw::MaxwellFisheye => Some(maxwell_fisheye(lens, p, d)),
            LensLaw::Ggrin(g) => Some(g.transmit(lens, p, d)),
            LensLaw::GradientIndex(g) => g.transmit_observed(lens, p, d, inside),
        }
    }

    pub fn name(&self) -> &'static str {
        match self {
            LensLaw::Luneburg => "Luneburg lens",
            LensLaw::Eaton => "Eaton lens",
            LensLaw::MaxwellFisheye => "Maxwell-fisheye lens",
            LensLaw::Ggrin(_) => "GGRIN lens",
            LensLaw::GradientIndex(_) => "gradient-index lens",
        }
    }
}

/// A lens surface: a law, optionally with an invisible core and an index step at the surface.
/// It must be the surface of a sphere.
#[derive(Debug, Clone, PartialEq)]
pub struct Lens {
    pub law: LensLaw,
    /// Radius R_t of the invisible core, in units of the lens radius, in [0, 1): rays whose
    /// straight line inside the lens passes closer than R_t to the centre cross it undeviated
    /// (§3.2), whatever the law.
    pub invisible_radius: f64,
    /// n_surface / n_surrounding (§3.3). An integrated profile is multiplied by it.
    pub index_ratio: f64,
    /// Fraction of the light transmitted through the lens (or reflected off it), in [0, 1].
    pub transmission_coefficient: f64,
}

impl Lens {
    /// The lens with law `law` and nothing else: no invisible core, matched index, lossless.
    pub fn new(law: LensLaw) -> Lens {
        Lens {
            law,
            invisible_radius: 0.0,
            index_ratio: 1.0,
            transmission_coefficient: 1.0,
        }
    }

    /// The ratio of the index just inside the surface to the surrounding medium's.
    pub fn surface_index(&self) -> f64 {
        match &self.law {
            LensLaw::GradientIndex(g) => self.index_ratio * g.profile.n(1.0),
            _ => self.index_ratio,
        }
    }

    /// The ray that emerges from `lens` when a ray arrives at `p` on its surface from outside
    /// with direction `d` (unit): refracted into the surface index (§3.3), carried across by
    /// the invisible core (§3.2) or the law, and refracted out. `None` for an integrated ray
    /// that never leaves.
    ///
    /// Beyond the critical angle on the way in (a surface index below the surroundings') the
    /// ray is reflected off the surface: the exit is `p` itself, after no time. On the way out
    /// there is no total internal reflection: every law conserves the angular momentum n r sin θ
    /// (spherical symmetry), so the ray meets the surface from inside at the angle it was
    /// refracted to on the way in, below the critical angle; a ray that rounding puts beyond it
    /// (near grazing incidence) leaves along the tangent.
    pub fn emerge(&self, lens: &Sphere, p: DVec3, d: DVec3) -> Option<Exit> {
        self.emerge_observed(lens, p, d, &mut |_| {})
    }

    /// [`Self::emerge`], showing `inside` the points of an integrated ray's curved path
    /// between entry and exit (see [`LensLaw::transmit_observed`]).
    pub fn emerge_observed(
        &self,
        lens: &Sphere,
        p: DVec3,
        d: DVec3,
        inside: &mut dyn FnMut(DVec3),
    ) -> Option<Exit> {
        let (centre, radius) = (lens.centre(), lens.radius());
        let n_surface = self.surface_index();
        // A matched surface (ratio exactly 1) leaves directions exactly as they are.
        if n_surface == 1.0 {
            return self.cross(lens, p, d, inside);
        }
        let n = (p - centre) / radius;
        let Some(refracted) = refract(d, n, n_surface) else {
            return Some(Exit {
                point: p,
                direction: reflect(d, n),
                path: 0.0,
            });
        };
        let exit = self.cross(lens, p, refracted, inside)?;
        let n = (exit.point - centre) / radius;
        let direction = refract(exit.direction, n, n_surface)
            .unwrap_or_else(|| exit.direction.reject_from_normalized(n).normalize());
        Some(Exit { direction, ..exit })
    }

    /// One passage from `p` in direction `d` inside the lens to the surface.
    fn cross(
        &self,
        lens: &Sphere,
        p: DVec3,
        d: DVec3,
        inside: &mut dyn FnMut(DVec3),
    ) -> Option<Exit> {
        let x = p - lens.centre();
        let along = x.dot(d);
        if (x - along * d).length() < self.invisible_radius * lens.radius() {
            return Some(Exit::chord(p, p - 2.0 * along * d, d));
        }
        let exit = self.law.transmit_observed(lens, p, d, inside)?;
        Some(match self.law {
            LensLaw::GradientIndex(_) => Exit {
                path: self.index_ratio * exit.path,
                ..exit
            },
            _ => exit,
        })
    }

    /// Where a ray meeting the lens goes on. A ray that meets it from inside (a camera or
    /// light path starting within the sphere) passes the surface as if it were transparent. A
    /// ray that leaves where it arrived after no time (reflected off the surface, §3.3, or
    /// aimed exactly at the centre of a closed-form Eaton lens) leaves from the hit point; an
    /// integrated ray that never leaves is lost. `inside` is shown an integrated ray's curved
    /// path.
    pub fn redirect(
        &self,
        at: &Interaction,
        inside: &mut dyn FnMut(DVec3),
    ) -> Redirection<'static> {
        let d = at.ray.direction;
        let factor = Colour::splat(self.transmission_coefficient);
        let Shape::Sphere(sphere) = at.shape else {
            return Redirection::Lost;
        };
        let lens = Sphere::new(sphere.centre() + at.offset, sphere.radius())
            .expect("a sphere's translated copy is a sphere");
        let p = at.point();
        if d.dot(p - lens.centre()) >= 0.0 {
            return Redirection::Leaves {
                direction: d,
                factor,
            };
        }
        match self.emerge_observed(&lens, p, d, inside) {
            Some(exit) if exit.point == p && exit.path == 0.0 => Redirection::Leaves {
                direction: exit.direction,
                factor,
            },
            Some(exit) => Redirection::Crosses { exit, factor },
            None => Redirection::Lost,
        }
    }
}

number!(
    /// A radius in units of the lens radius, in [0, 1).
    InnerRadius,
    |x: f64| (0.0..1.0).contains(&x),
    "a radius in units of the lens radius, at least 0 and less than 1"
);

/// The keys every lens has: its invisible core (none when not given), the index step at its
/// surface (none) and its transmission coefficient (1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensKeys {
    invisible_radius: Option<InnerRadius>,
    index_ratio: Option<Positive>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl LensKeys {
    /// The lens of law `law` with these keys.
    fn lens(self, law: LensLaw) -> Surface {
        Surface::Lens(Lens {
            law,
            invisible_radius: self.invisible_radius.map_or(0.0, |r| r.0),
            index_ratio: self.index_ratio.map_or(1.0, |n| n.0),
            transmission_coefficient: throughput(self.transmission_coefficient),
        })
    }
}

/// How a Luneburg, Eaton or Maxwell-fisheye lens is rendered.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum Method {
    /// The paper's closed-form entry-to-exit map.
    #[default]
    Mapping,
    /// The ray equation integrated through the index profile.
    Integration,
}

/// The keys of a lens whose law has a closed form (Luneburg, Eaton, Maxwell fisheye): the
/// `method` and every lens's keys.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClosedFormLensKeys {
    method: Option<Method>,
    #[serde(flatten)]
    lens: LensKeys,
}

impl ClosedFormLensKeys {
    /// The lens of closed form `mapping`, or integrated through `profile`.
    fn build(self, mapping: LensLaw, profile: IndexProfile) -> Result<Surface, String> {
        let law = match self.method.unwrap_or_default() {
            Method::Mapping => mapping,
            Method::Integration => LensLaw::GradientIndex(GradientIndex { profile }),
        };
        Ok(self.lens.lens(law))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Cylinder, Disc, Plane};
    use crate::surfaces::tests::{crosses, leaves, meet};

    fn every_law() -> Vec<LensLaw> {
        vec![
            LensLaw::Luneburg,
            LensLaw::Eaton,
            LensLaw::MaxwellFisheye,
            LensLaw::Ggrin(Ggrin {
                r: f64::INFINITY,
                r_prime: 2.0,
                phi: std::f64::consts::PI,
            }),
            LensLaw::GradientIndex(GradientIndex {
                profile: IndexProfile::Luneburg,
            }),
        ]
    }

    /// §3's lenses are defined by a sphere's centre and radius: on any other shape (a plane,
    /// a disc, a cylinder) no light comes back along the ray.
    #[test]
    fn a_lens_law_on_a_shape_that_is_not_a_sphere_is_lost() {
        let shapes = [
            Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap()),
            Shape::Disc(Disc::new(DVec3::ZERO, DVec3::Z, 1.0).unwrap()),
            Shape::Cylinder(Cylinder::new(-DVec3::Z, DVec3::Z, 1.0).unwrap()),
        ];
        let d = DVec3::new(0.1, 0.2, -1.0);
        for shape in &shapes {
            let at = meet(shape, DVec3::new(0.05, 0.0, 0.5) - 2.0 * d, d);
            for law in every_law() {
                let lens = Lens::new(law);
                assert_eq!(
                    lens.redirect(&at, &mut |_| {}),
                    Redirection::Lost,
                    "{shape:?}"
                );
            }
        }
    }

    /// The invisible core (§3.2): a ray whose straight line passes closer than R_t to the
    /// centre crosses the lens undeviated, leaving where that line meets the sphere again
    /// (the far end of the chord), along d; one passing farther away obeys the law (here
    /// Luneburg's focus C + R d̂). A ray that meets the lens from inside passes it as if it
    /// were transparent.
    #[test]
    fn rays_through_the_invisible_core_cross_undeviated() {
        let (centre, radius) = (DVec3::new(1.0, -2.0, 0.5), 2.0);
        let sphere = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let lens = Lens {
            invisible_radius: 0.5,
            transmission_coefficient: 0.8,
            ..Lens::new(LensLaw::Luneburg)
        };
        let d = DVec3::new(0.3, 0.4, -0.6).normalize();
        let e = d.any_orthonormal_vector();
        for b in [0.0, 0.3, 0.99] {
            let at = meet(&sphere, centre - 5.0 * d + b * e, d);
            let (exit, factor) = crosses(lens.redirect(&at, &mut |_| {}));
            assert_eq!(factor, 0.8);
            // The far end of the chord at distance b from the centre.
            let far = centre + b * e + (radius * radius - b * b).sqrt() * d;
            assert!(
                (exit.point - far).length() < 1e-12,
                "b = {b}: {}",
                exit.point
            );
            assert!((exit.direction - d).length() < 1e-15);
        }
        for b in [1.01, 1.5, 1.9] {
            let at = meet(&sphere, centre - 5.0 * d + b * e, d);
            let (exit, _) = crosses(lens.redirect(&at, &mut |_| {}));
            assert!(
                (exit.point - (centre + radius * d)).length() < 1e-12,
                "b = {b}"
            );
        }
        let from_inside = meet(&sphere, centre + 0.5 * e, d);
        assert_eq!(leaves(lens.redirect(&from_inside, &mut |_| {})), (d, 0.8));
    }

    /// An index step at the surface (§3.3): where the lens's surface index is below the
    /// surroundings' (ratio 0.8), a ray arriving beyond the critical angle arcsin 0.8 is
    /// reflected off the surface as off a mirror (angle of reflection equals angle of
    /// incidence) and does not enter.
    #[test]
    fn beyond_the_critical_angle_a_lens_of_lower_index_reflects() {
        let (centre, radius) = (DVec3::ZERO, 1.0);
        let sphere = Shape::Sphere(Sphere::new(centre, radius).unwrap());
        let lens = Lens {
            index_ratio: 0.8,
            ..Lens::new(LensLaw::MaxwellFisheye)
        };
        let d = DVec3::Z;
        // Impact parameter 0.9: sin θ = 0.9 > 0.8.
        let at = meet(&sphere, DVec3::new(0.9, 0.0, -3.0), d);
        let n = at.point() - centre;
        let (out, factor) = leaves(lens.redirect(&at, &mut |_| {}));
        assert_eq!(factor, 1.0);
        assert!(
            (out.dot(n) + d.dot(n)).abs() < 1e-14 && (out.cross(n) - d.cross(n)).length() < 1e-14
        );
        // Impact parameter 0.7 (sin θ = 0.7 < 0.8) enters, and crosses.
        let at = meet(&sphere, DVec3::new(0.7, 0.0, -3.0), d);
        crosses(lens.redirect(&at, &mut |_| {}));
    }
}
