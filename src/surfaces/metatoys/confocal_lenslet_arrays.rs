//! Generalised confocal lenslet arrays (gCLAs, §5, Eq 39): two lenslet arrays sharing a focal
//! plane form an array of small telescopes, which change a ray's direction independently of
//! where it enters (apart from a small offset, neglected here as in TIM).
//!
//! With â the optical axis (from array 1 to array 2), û the u direction (the given u projected
//! perpendicular to â and normalised, §5.2) and v̂ = â × û, a ray entering through array 1 with
//! direction d leaves with
//!
//! d′ = ((d·û)/(d·â) − δ_u)/η_u û + ((d·v̂)/(d·â) − δ_v)/η_v v̂ + â            (Eq 39)
//!
//! where η is −(focal length of lenslet 2)/(focal length of lenslet 1) and δ the offset of
//! lenslet 2's axis over lenslet 1's focal length. A ray meets array 1 first if a and d point
//! to the same side of the surface; otherwise it meets array 2 first and Eq 39 holds with
//! â → −â, η → 1/η and δ → δ/η (û and v̂ unchanged). That makes the law reciprocal: sent back
//! along −d′, a ray leaves along −d.
//!
//! Impossible cases (documented choice): a ray that does not travel along the telescopes'
//! axis (d·â ≤ 0 for the array it meets first), or whose Eq 39 direction does not leave
//! through the far side of the sheet, cannot pass through a telescopelet and is reflected,
//! losslessly unless a reflection coefficient is given. (Dr TIM applies Eq 39 to every ray.)
//!
//! As Dr TIM's `GCLAsWithApertures` (its GUI's gCLAs), the sheet may be realistic: the light
//! passed on computed from the lenslets' apertures ([`Transmission`], see
//! `gcla_transmission`), and its telescopelets' pixellation simulated (a uniform diffractive
//! blur and a ray offset, [`Pixels`]). An optional v direction picks the sign of v̂ (Dr TIM
//! takes the part of v perpendicular to â and û); by default v̂ = â × û.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::gcla_transmission::{
    Apertures, Transmission, best_case, projection_transmission, reversed,
};
use super::pixellation::{Blur, GCLA_LAMBDA, GCLA_PIXEL_SIDE_LENGTH, Pixels};
use super::{Basis, HomogeneousPlanarImaging, Outgoing, crosses};
use crate::geometry::{Interaction, Transform};
use crate::keys::{Coefficient, Direction, Finite, NonZero, Positive, coefficient, throughput};
use crate::surfaces::{Redirection, Surface, reflect};

/// The gCLA surface: the telescopes' parameters, with a and u in either basis.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfocalLensletArrays {
    /// Optical axis, pointing from lenslet array 1 to array 2 (any length).
    pub a: DVec3,
    /// The u direction (projected perpendicular to a).
    pub u: DVec3,
    /// The v direction: only the side of the (a, u) plane it points to counts.
    pub v: DVec3,
    pub basis: Basis,
    /// (η_u, η_v), non-zero.
    pub eta: DVec2,
    /// (δ_u, δ_v).
    pub delta: DVec2,
    /// The fraction of the light transmitted.
    pub transmission: Transmission,
    /// Fraction of the light reflected where no ray gets through, in [0, 1].
    pub reflection_coefficient: f64,
    /// The telescopelets' pixellation, if simulated.
    pub pixels: Option<Pixels>,
    /// The imaging surface the arrays realise, where they were made as one (a device's
    /// interfaces): their a, u, v, η and δ are then its, and they move with the object.
    pub imaging: Option<HomogeneousPlanarImaging>,
}

/// The telescopelets' orthonormal basis and parameters at one point, in global coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Telescopelets {
    pub a_hat: DVec3,
    pub u_hat: DVec3,
    pub v_hat: DVec3,
    pub eta: DVec2,
    pub delta: DVec2,
}

impl Telescopelets {
    /// The basis of §5.2 from a and u; `None` if a is zero or u is parallel to it.
    pub fn new(a: DVec3, u: DVec3, eta: DVec2, delta: DVec2) -> Option<Telescopelets> {
        let a_hat = a.try_normalize()?;
        let u_hat = u.reject_from_normalized(a_hat).try_normalize()?;
        Some(Telescopelets {
            a_hat,
            u_hat,
            v_hat: a_hat.cross(u_hat),
            eta,
            delta,
        })
    }

    /// The same telescopelets with v̂ turned to the side of the (â, û) plane that `v` points
    /// to; `None` if `v` lies in that plane.
    pub fn towards(self, v: DVec3) -> Option<Telescopelets> {
        let side = v.dot(self.v_hat);
        (side != 0.0).then(|| Telescopelets {
            v_hat: self.v_hat * side.signum(),
            ..self
        })
    }

    /// Whether a ray with direction `d` meeting the sheet with unit normal `n` meets array 1
    /// first.
    fn array_1_first(&self, d: DVec3, n: DVec3) -> bool {
        self.a_hat.dot(n) * d.dot(n) > 0.0
    }

    /// â, η and δ as the ray meets them (§5.2's order rule).
    fn as_met(&self, d: DVec3, n: DVec3) -> (DVec3, DVec2, DVec2) {
        if self.array_1_first(d, n) {
            (self.a_hat, self.eta, self.delta)
        } else {
            (-self.a_hat, 1.0 / self.eta, self.delta / self.eta)
        }
    }

    /// Eq 39 with the order rule of §5.2, for a ray with direction `d` meeting the sheet with
    /// unit normal `n`, normalised (Eq 39 fixes the component along â at 1, not the length);
    /// `None` where no ray gets through (see the module notes).
    pub fn refract(&self, d: DVec3, n: DVec3) -> Option<DVec3> {
        let (a_hat, eta, delta) = self.as_met(d, n);
        let da = d.dot(a_hat);
        if da <= 0.0 || da.is_nan() {
            return None;
        }
        let slopes = (DVec2::new(d.dot(self.u_hat), d.dot(self.v_hat)) / da - delta) / eta;
        let out = slopes.x * self.u_hat + slopes.y * self.v_hat + a_hat;
        (out.is_finite() && crosses(d, out, n)).then(|| out.normalize())
    }

    /// The fraction of the light passed on to a ray with direction `d` that gets through
    /// (see `gcla_transmission`).
    pub fn transmission(&self, transmission: &Transmission, d: DVec3, n: DVec3) -> f64 {
        let (a_hat, eta, delta) = self.as_met(d, n);
        match transmission {
            Transmission::Constant(t) => *t,
            Transmission::GeometricBest => best_case(eta.x) * best_case(eta.y),
            Transmission::Geometric(apertures) => {
                let apertures = if self.array_1_first(d, n) {
                    *apertures
                } else {
                    reversed(apertures, self.eta)
                };
                let slopes = DVec2::new(d.dot(self.u_hat), d.dot(self.v_hat)) / d.dot(a_hat);
                (0..2)
                    .map(|i| {
                        projection_transmission(
                            eta[i],
                            delta[i],
                            (apertures.alpha1[i], apertures.alpha2[i]),
                            (apertures.sigma1[i], apertures.sigma2[i]),
                            slopes[i],
                        )
                    })
                    .product()
            }
        }
    }
}

impl ConfocalLensletArrays {
    /// The arrays realising `imaging` (Dr TIM's `HomogeneousPlanarImagingSurface.toGCLAs`), in
    /// the global basis, with lossless total internal reflection.
    pub fn imaging(
        imaging: HomogeneousPlanarImaging,
        transmission: Transmission,
    ) -> Result<ConfocalLensletArrays, String> {
        let t = imaging.telescopes()?;
        Ok(ConfocalLensletArrays {
            a: t.a_hat,
            u: t.u_hat,
            v: t.a_hat.cross(t.u_hat),
            basis: Basis::Global,
            eta: DVec2::splat(t.eta),
            delta: t.delta,
            transmission,
            reflection_coefficient: 1.0,
            pixels: None,
            imaging: Some(imaging),
        })
    }

    /// The arrays of an object placed by `t`: those made as an imaging surface move with it
    /// (any invertible affine map keeps them one); the others' global vectors stay as given.
    pub fn transformed(&self, t: &Transform) -> Result<ConfocalLensletArrays, String> {
        match self.imaging {
            Some(imaging) => Ok(ConfocalLensletArrays {
                reflection_coefficient: self.reflection_coefficient,
                pixels: self.pixels,
                ..ConfocalLensletArrays::imaging(imaging.transformed(t), self.transmission)?
            }),
            None => Ok(self.clone()),
        }
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let frame = at.frame();
        let d = at.ray.direction;
        let telescopelets = Telescopelets::new(
            self.basis.to_global(self.a, &frame),
            self.basis.to_global(self.u, &frame),
            self.eta,
            self.delta,
        )
        .and_then(|t| t.towards(self.basis.to_global(self.v, &frame)));
        let Some((t, out)) = telescopelets.and_then(|t| Some((t, t.refract(d, frame.w)?))) else {
            return Outgoing::Reflected(reflect(d, frame.w))
                .leaves(0.0, self.reflection_coefficient);
        };
        let factor = t.transmission(&self.transmission, d, frame.w);
        match self.pixels {
            Some(pixels) => pixels.spread(at, out, factor, self.reflection_coefficient),
            None => Outgoing::Transmitted(out).leaves(factor, self.reflection_coefficient),
        }
    }
}

/// Dr TIM's `GCLAsTransmissionCoefficientCalculationMethodType`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum TransmissionCoefficientMethod {
    Constant,
    Geometric,
    GeometricBest,
}

/// `type = "confocal-lenslet-arrays"` (or `gcla`): â, û, η and δ of Eq 39; û must not be
/// along â, nor v in their plane. The realistic sheet's keys, with Dr TIM's GUI defaults:
/// `transmission_coefficient_method` ("constant", "geometric" or "geometric-best"; constant),
/// the apertures for "geometric" (`sigma1_u`… 1, `alpha1_u`… 0), `simulate_diffractive_blur`
/// and `simulate_ray_offset` (false), `pixel_side_length` (2e-3) and `lambda` (564e-9).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConfocalLensletArraysKeys {
    a: Direction,
    u: Direction,
    v: Option<Direction>,
    basis: Option<Basis>,
    eta_u: Option<NonZero>,
    eta_v: Option<NonZero>,
    delta_u: Option<Finite>,
    delta_v: Option<Finite>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
    transmission_coefficient_method: Option<TransmissionCoefficientMethod>,
    sigma1_u: Option<Positive>,
    sigma1_v: Option<Positive>,
    sigma2_u: Option<Positive>,
    sigma2_v: Option<Positive>,
    alpha1_u: Option<Finite>,
    alpha1_v: Option<Finite>,
    alpha2_u: Option<Finite>,
    alpha2_v: Option<Finite>,
    simulate_diffractive_blur: Option<bool>,
    simulate_ray_offset: Option<bool>,
    pixel_side_length: Option<Positive>,
    lambda: Option<Positive>,
}

impl ConfocalLensletArraysKeys {
    pub fn build(self) -> Result<Surface, String> {
        let (a, u) = (self.a.0, self.u.0);
        // Directions are unit vectors: a sine below 1e-9 is parallel.
        if a.cross(u).length() < 1e-9 {
            return Err(format!(
                "confocal-lenslet-arrays: u = {u} must not be parallel to a = {a}"
            ));
        }
        let v = self.v.map_or(a.cross(u), |v| v.0);
        if v.dot(a.cross(u).normalize()).abs() < 1e-9 {
            return Err(format!(
                "confocal-lenslet-arrays: v = {v} must not lie in the plane of a = {a} and u = {u}"
            ));
        }
        let transmission = self.transmission()?;
        let pixels = self.pixels();
        let finite = |d: Option<Finite>| d.map_or(0.0, |d| d.0);
        Ok(Surface::ConfocalLensletArrays(ConfocalLensletArrays {
            a,
            u,
            v,
            basis: self.basis.unwrap_or_default(),
            // Dr TIM's GUI's (η_u, η_v) = (1, 1).
            eta: DVec2::new(
                self.eta_u.map_or(1.0, |e| e.0),
                self.eta_v.map_or(1.0, |e| e.0),
            ),
            delta: DVec2::new(finite(self.delta_u), finite(self.delta_v)),
            transmission,
            reflection_coefficient: coefficient(self.reflection_coefficient),
            pixels,
            imaging: None,
        }))
    }

    /// The transmission, refusing keys the method does not use.
    fn transmission(&self) -> Result<Transmission, String> {
        let method = self
            .transmission_coefficient_method
            .unwrap_or(TransmissionCoefficientMethod::Constant);
        let apertures = [self.sigma1_u, self.sigma1_v, self.sigma2_u, self.sigma2_v];
        let offsets = [self.alpha1_u, self.alpha1_v, self.alpha2_u, self.alpha2_v];
        let given = apertures.iter().any(Option::is_some) || offsets.iter().any(Option::is_some);
        if method != TransmissionCoefficientMethod::Geometric && given {
            return Err(
                "confocal-lenslet-arrays: the apertures (`sigma1_u`…, `alpha1_u`…) are \
                        only used with transmission_coefficient_method = \"geometric\""
                    .into(),
            );
        }
        if method != TransmissionCoefficientMethod::Constant
            && self.transmission_coefficient.is_some()
        {
            return Err(
                "confocal-lenslet-arrays: `transmission_coefficient` is only used with \
                        transmission_coefficient_method = \"constant\" (the others compute it)"
                    .into(),
            );
        }
        let side = |s: Option<Positive>| s.map_or(1.0, |s| s.0);
        let offset = |a: Option<Finite>| a.map_or(0.0, |a| a.0);
        let pair = |x: f64, y: f64| DVec2::new(x, y);
        Ok(match method {
            TransmissionCoefficientMethod::Constant => {
                Transmission::Constant(throughput(self.transmission_coefficient))
            }
            TransmissionCoefficientMethod::GeometricBest => Transmission::GeometricBest,
            TransmissionCoefficientMethod::Geometric => Transmission::Geometric(Apertures {
                sigma1: pair(side(self.sigma1_u), side(self.sigma1_v)),
                sigma2: pair(side(self.sigma2_u), side(self.sigma2_v)),
                alpha1: pair(offset(self.alpha1_u), offset(self.alpha1_v)),
                alpha2: pair(offset(self.alpha2_u), offset(self.alpha2_v)),
            }),
        })
    }

    /// The pixellation, if any is simulated (the pixel side and wavelength are the sheet's
    /// and may be given either way).
    fn pixels(&self) -> Option<Pixels> {
        let blur = self.simulate_diffractive_blur.unwrap_or(false);
        let ray_offset = self.simulate_ray_offset.unwrap_or(false);
        (blur || ray_offset).then(|| Pixels {
            size: DVec2::splat(
                self.pixel_side_length
                    .map_or(GCLA_PIXEL_SIDE_LENGTH, |s| s.0),
            ),
            lambda: self.lambda.map_or(GCLA_LAMBDA, |l| l.0),
            blur: blur.then_some(Blur::Uniform),
            ray_offset,
            sides: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Plane, Shape, Sphere};
    use crate::surfaces::tests::{leaves, meet};

    #[test]
    fn u_is_projected_perpendicular_to_a_and_the_basis_is_right_handed() {
        let t = Telescopelets::new(
            DVec3::new(0.0, 0.0, 2.0),
            DVec3::new(3.0, 0.0, 5.0),
            DVec2::ONE,
            DVec2::ZERO,
        )
        .unwrap();
        assert_eq!((t.a_hat, t.u_hat, t.v_hat), (DVec3::Z, DVec3::X, DVec3::Y));
        assert_eq!(
            Telescopelets::new(DVec3::Z, DVec3::Z * 2.0, DVec2::ONE, DVec2::ZERO),
            None
        );
    }

    #[test]
    fn eta_one_without_offset_leaves_rays_unchanged() {
        let t = Telescopelets::new(DVec3::Z, DVec3::X, DVec2::ONE, DVec2::ZERO).unwrap();
        let d = DVec3::new(0.3, -0.2, 0.9);
        let out = t.refract(d, DVec3::Z).unwrap();
        assert!((out.normalize() - d.normalize()).length() < 1e-15);
        let back = t.refract(-d, DVec3::Z).unwrap();
        assert!((back.normalize() + d.normalize()).length() < 1e-15);
    }

    #[test]
    fn rays_that_cannot_cross_are_refused() {
        // The axis is tilted 84° from the normal: a ray crossing the sheet against the axis
        // (d·â < 0) cannot travel from lenslet 1 to lenslet 2.
        let t = Telescopelets::new(
            DVec3::new(1.0, 0.0, 0.1),
            DVec3::Z,
            DVec2::splat(0.1),
            DVec2::ZERO,
        )
        .unwrap();
        assert_eq!(t.refract(DVec3::new(-0.2, 0.0, 1.0), DVec3::Z), None);
    }

    fn gcla(a: DVec3, u: DVec3, basis: Basis, eta: DVec2, delta: DVec2) -> ConfocalLensletArrays {
        ConfocalLensletArrays {
            a,
            u,
            v: a.cross(u),
            basis,
            eta,
            delta,
            transmission: Transmission::Constant(0.9),
            reflection_coefficient: 0.5,
            pixels: None,
            imaging: None,
        }
    }

    /// η = 1 and δ = 0 are telescopes of magnification 1 with aligned axes, which change no
    /// direction: through `redirect` on a tilted plane, in either direction of crossing and
    /// with the axis along the normal or tilted, and on a sphere with â along the local normal.
    #[test]
    fn unit_telescopes_leave_the_direction_unchanged() {
        let n = DVec3::new(0.0, 0.6, 0.8);
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, n, DVec3::X).unwrap());
        for a in [n, -n, DVec3::new(0.3, 0.5, 0.8)] {
            let sheet = gcla(a, DVec3::X, Basis::Global, DVec2::ONE, DVec2::ZERO);
            for d in [DVec3::new(0.2, -0.3, -0.9), DVec3::new(-0.1, 0.5, 0.85)] {
                let d = d.normalize();
                let (out, factor) = leaves(sheet.redirect(&meet(&plane, -3.0 * d, d)));
                let out = out.normalize(); // see `redirect_leaves_along_a_unit_vector`
                assert!((out - d).length() < 1e-14, "a = {a}, d = {d}: {out}");
                assert_eq!(factor, 0.9);
            }
        }
        let sphere = Shape::Sphere(Sphere::new(DVec3::new(0.0, 0.0, 5.0), 2.0).unwrap());
        let sheet = gcla(DVec3::Z, DVec3::X, Basis::Local, DVec2::ONE, DVec2::ZERO);
        let d = DVec3::new(0.1, 0.2, 1.0).normalize();
        let (out, _) = leaves(sheet.redirect(&meet(&sphere, DVec3::new(0.5, 0.3, 0.0), d)));
        assert!((out.normalize() - d).length() < 1e-14, "{out}");
    }

    /// Eq 39 derived independently, in the (u, a) projection of Fig. 16: lens 1 (focal length
    /// f₁) focuses rays of slope s = (d·û)/(d·â) to the height f₁ s in the common focal plane;
    /// lens 2 (focal length f₂ = −η f₁, its axis offset by o = δ f₁) sees that point at
    /// height f₁ s − o, a distance f₂ in front of it, and sends the rays on parallel to the
    /// undeviated one through its centre, of slope s′ = −(f₁ s − o)/f₂ = (s − δ)/η; likewise
    /// in (v, a). So with â along the sheet's normal the tangential components, relative to the
    /// normal one, become (s_u − δ_u)/η_u and (s_v − δ_v)/η_v. Light sent back along −d′
    /// retraces its path through the telescope (reciprocity) and leaves along −d.
    #[test]
    fn telescopes_along_the_normal_scale_the_slopes() {
        let plane =
            Shape::Plane(Plane::new(DVec3::new(0.0, 0.0, 1.0), DVec3::Z, DVec3::X).unwrap());
        let (eta, delta) = (DVec2::new(2.0, -0.5), DVec2::new(0.1, -0.2));
        let sheet = gcla(DVec3::Z, DVec3::X, Basis::Global, eta, delta);
        for d in [
            DVec3::new(0.2, -0.1, 1.0),
            DVec3::new(-0.5, 0.3, 0.8),
            DVec3::new(0.0, 0.0, 1.0),
        ] {
            let d = d.normalize();
            let (out, factor) = leaves(sheet.redirect(&meet(&plane, DVec3::new(0.3, 0.2, 0.0), d)));
            assert_eq!(factor, 0.9);
            let out = out.normalize(); // see `redirect_leaves_along_a_unit_vector`
            let (s_u, s_v) = (d.x / d.z, d.y / d.z);
            let expected = DVec3::new((s_u - delta.x) / eta.x, (s_v - delta.y) / eta.y, 1.0);
            assert!((out - expected.normalize()).length() < 1e-14, "{d}: {out}");
            let back = meet(&plane, DVec3::new(0.3, 0.2, 1.0) + out, -out);
            let (returned, _) = leaves(sheet.redirect(&back));
            assert!(
                (returned.normalize() + d).length() < 1e-14,
                "{d}: {returned}"
            );
        }
        // With η = −1 (two equal lenses), no offset: telescopes that invert the tangential
        // components (s′ = −s).
        let inverting = gcla(DVec3::Z, DVec3::X, Basis::Global, -DVec2::ONE, DVec2::ZERO);
        let d = DVec3::new(0.3, -0.4, 0.866).normalize();
        let (out, _) = leaves(inverting.redirect(&meet(&plane, DVec3::ZERO, d)));
        let out = out.normalize();
        assert!(
            (out - DVec3::new(-d.x, -d.y, d.z)).length() < 1e-14,
            "{out}"
        );
    }

    /// `Redirection::Leaves` promises a unit direction, as every other law gives; Eq 39's d′
    /// has component 1 along â, not length 1: the ray (0.2, −0.1, 1)/|…| leaves along
    /// (0.05, −0.2, 1)/|…|.
    #[test]
    fn redirect_leaves_along_a_unit_vector() {
        let plane = Shape::Plane(Plane::new(DVec3::ZERO, DVec3::Z, DVec3::X).unwrap());
        let sheet = gcla(
            DVec3::Z,
            DVec3::X,
            Basis::Global,
            DVec2::new(2.0, -0.5),
            DVec2::new(0.1, -0.2),
        );
        let d = DVec3::new(0.2, -0.1, 1.0).normalize();
        let (out, _) = leaves(sheet.redirect(&meet(&plane, -d, d)));
        assert!(
            (out.length() - 1.0).abs() < 1e-14,
            "|{out}| = {}",
            out.length()
        );
        let expected = DVec3::new(0.05, -0.2, 1.0).normalize();
        assert!((out - expected).length() < 1e-14, "{out}");
    }
}
