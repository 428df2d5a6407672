//! Pixellation (Dr TIM's `Pixellation`, `SingleSlitDiffraction`): a surface made of small
//! rectangular pixels (telescopelets, lenslets, hologram pixels) blurs what is seen through it
//! in two ways, each simulated by a random change of every ray that crosses it.
//!
//! - **Diffractive blur**: each pixel is an aperture of sides w_u × w_v, which diffracts. The
//!   tangential components of the ray direction change by sin θ_u = x_u λ / (π w_u) along u and
//!   likewise along v (as a phase hologram's kick), x drawn from the far field of a slit of
//!   width w under normal, uniform illumination, I(θ) ∝ sinc²(π w sin θ / λ): the probability
//!   density p(x) = sin² x / (π x²), of cumulative distribution
//!   P(x) = ½ + (Si(2x) − sin² x / x) / π. A ray whose new direction would be evanescent is
//!   reflected, losslessly, as Dr TIM does.
//! - **Ray offset**: the ray leaves from a point offset along u and v by amounts uniform in
//!   (−w_u, w_u) and (−w_v, w_v) (Dr TIM's range: light may enter and leave a pixel anywhere
//!   in it).
//!
//! The pixel sides lie along the surface frame's u and v. The random numbers are keyed by the
//! ray (its hit point and direction), so each sample of each pixel has its own and renders are
//! reproducible. Dr TIM draws x from a table of the inverse of P with linear interpolation;
//! here x is drawn exactly, by rejection from the envelope min(1, 1/x²)/π.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{hologram_direction, jacobian};
use crate::geometry::{Exit, Interaction, Transform};
use crate::keys::Positive;
use crate::math::random::{ray_key, uniform_keyed};
use crate::math::{Colour, HE_NE_WAVELENGTH};
use crate::surfaces::{Redirection, Surface, reflect};

/// How a pixel's diffraction spreads a ray's direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Blur {
    /// Dr TIM's `GCLAsWithApertures`: each tangential component changes by an amount uniform in
    /// (−λ/w, λ/w), up to the direction of the first diffraction minimum.
    Uniform,
    /// Single-slit diffraction, as described in the module notes.
    SingleSlit,
}

/// A surface's pixel imperfections: the pixels' sides, the wavelength and what is simulated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pixels {
    /// The pixels' sides along u and v.
    pub size: DVec2,
    /// The wavelength of the light, in the scene's units of length.
    pub lambda: f64,
    /// The diffractive blur, if simulated.
    pub blur: Option<Blur>,
    /// Whether the ray offset is simulated.
    pub ray_offset: bool,
    /// The directions of the pixels' sides in the scene (unit vectors), where they are not the
    /// surface frame's u and v: Dr TIM's `BoundingBoxSurface` kicks along its pixel array's
    /// periods on every face of its box. Each kick's part along the surface is applied.
    pub sides: Option<[DVec3; 2]>,
}

/// Dr TIM's default pixel side (`GCLAsWithApertures`: 2 mm in metres, "a good compromise
/// between diffraction and pixellation").
pub const GCLA_PIXEL_SIDE_LENGTH: f64 = 2e-3;

/// Dr TIM's default wavelength for gCLAs: 564 nm in metres, where the eye is most sensitive.
pub const GCLA_LAMBDA: f64 = 564e-9;

/// Most proposals of the single-slit sampler; each is accepted with probability π/4, so the
/// chance of running out is below 10⁻⁴⁰.
const MAX_PROPOSALS: u32 = 64;

/// x distributed with density sin² x / (π x²), drawn by rejection from `random`'s numbers
/// (dimension `dim` onwards) with the envelope min(1, 1/x²)/π, half of whose mass is uniform
/// on (−1, 1) and half has density ∝ 1/x² on |x| > 1 (there x = ±1/s, s uniform in (0, 1]).
pub fn single_slit_x(random: &impl Fn(u32) -> f64, dim: u32) -> f64 {
    for k in 0..MAX_PROPOSALS {
        let [half, position, accept] = [0, 1, 2].map(|i| random(dim + 3 * k + i));
        let x = if half < 0.5 {
            2.0 * position - 1.0
        } else {
            let x = 1.0 / (1.0 - position);
            if half < 0.75 { x } else { -x }
        };
        let sinc2 = (x.sin() / x).powi(2);
        let envelope = 1f64.min(1.0 / (x * x));
        if x == 0.0 || accept * envelope < sinc2 {
            return x;
        }
    }
    0.0
}

impl Pixels {
    /// The change of the tangential direction components (sin θ_u, sin θ_v) for one ray.
    fn kick(&self, blur: Blur, random: &impl Fn(u32) -> f64) -> DVec2 {
        let unit = match blur {
            Blur::Uniform => DVec2::new(2.0 * random(0) - 1.0, 2.0 * random(1) - 1.0),
            Blur::SingleSlit => {
                DVec2::new(single_slit_x(random, 0), single_slit_x(random, 192))
                    / std::f64::consts::PI
            }
        };
        unit * self.lambda / self.size
    }

    /// The ray that a law sends on in unit `direction` carrying `factor`, blurred and offset
    /// by the pixels; if diffraction makes it evanescent, the incoming ray is reflected,
    /// carrying `reflection`.
    pub fn spread(
        &self,
        at: &Interaction,
        direction: DVec3,
        factor: f64,
        reflection: f64,
    ) -> Redirection<'static> {
        let frame = at.frame();
        let p = at.point();
        let key = ray_key(p, at.ray.direction);
        let random = |i| uniform_keyed(&key, i);
        let direction = match self.blur {
            None => direction,
            Some(blur) => {
                let local = jacobian(&frame).transpose() * direction;
                let kick = self.kick(blur, &random);
                let kick = match self.sides {
                    None => kick,
                    Some([a, b]) => {
                        let k = kick.x * a + kick.y * b;
                        DVec2::new(k.dot(frame.u), k.dot(frame.v))
                    }
                };
                match hologram_direction(local, kick) {
                    Some(local) => jacobian(&frame) * local,
                    None => {
                        return Redirection::Leaves {
                            direction: reflect(at.ray.direction, frame.w),
                            factor: Colour::splat(reflection),
                        };
                    }
                }
            }
        };
        let factor = Colour::splat(factor);
        if !self.ray_offset {
            return Redirection::Leaves { direction, factor };
        }
        // Dimensions 400 on, after the blur's.
        let offset = self.size * DVec2::new(2.0 * random(400) - 1.0, 2.0 * random(401) - 1.0);
        let exit = Exit {
            point: p + offset.x * frame.u + offset.y * frame.v,
            direction,
            path: 0.0,
        };
        Redirection::Jumps { exit, factor }
    }
}

/// Dr TIM's `Pixellation`: a surface that is otherwise transparent.
#[derive(Debug, Clone, PartialEq)]
pub struct Pixellation {
    pub pixels: Pixels,
}

impl Pixellation {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        self.pixels.spread(at, at.ray.direction, 1.0, 1.0)
    }

    /// The pixellation of an object placed by `t`: sides given in the scene turn with it, which
    /// a map that scales would not match (the pixel sizes and wavelength are lengths of the
    /// scene).
    pub fn transformed(&self, t: &Transform) -> Result<Pixellation, String> {
        let mut pixels = self.pixels;
        if let Some(sides) = pixels.sides {
            if t.uniform_scale().is_none_or(|k| (k - 1.0).abs() > 1e-12) {
                return Err(
                    "a pixellation with its pixels' sides given in the scene (a view \
                     rotator's diffraction blur) can be turned and moved but not scaled: its \
                     pixel sizes and wavelength are lengths of the scene; give its lengths \
                     instead"
                        .into(),
                );
            }
            pixels.sides = Some(sides.map(|side| t.vector(side).normalize()));
        }
        Ok(Pixellation { pixels })
    }
}

/// `type = "pixellation"`: `pixel_side_length_u`, `pixel_side_length_v` (Dr TIM's GUI default
/// 1e-4 each), `lambda` (632.8e-9), `simulate_diffractive_blur` and `simulate_ray_offset`
/// (both true).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PixellationKeys {
    pixel_side_length_u: Option<Positive>,
    pixel_side_length_v: Option<Positive>,
    lambda: Option<Positive>,
    simulate_diffractive_blur: Option<bool>,
    simulate_ray_offset: Option<bool>,
}

impl PixellationKeys {
    pub fn build(self) -> Result<Surface, String> {
        let side = |s: Option<Positive>| s.map_or(1e-4, |s| s.0);
        let blur = self.simulate_diffractive_blur.unwrap_or(true);
        Ok(Surface::Pixellation(Pixellation {
            pixels: Pixels {
                size: DVec2::new(
                    side(self.pixel_side_length_u),
                    side(self.pixel_side_length_v),
                ),
                lambda: self.lambda.map_or(HE_NE_WAVELENGTH, |l| l.0),
                blur: blur.then_some(Blur::SingleSlit),
                ray_offset: self.simulate_ray_offset.unwrap_or(true),
                sides: None,
            },
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::uniform;

    /// Si(x) = ∫₀ˣ sin t / t dt by Simpson's rule, independently of the sampler.
    fn si(x: f64) -> f64 {
        let n = 20_000;
        let h = x / n as f64;
        let f = |t: f64| if t == 0.0 { 1.0 } else { t.sin() / t };
        let inner: f64 = (1..n)
            .map(|i| f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        (f(0.0) + inner + f(x)) * h / 3.0
    }

    /// The fraction of single-slit samples with |x| < e is P(e) − P(−e) =
    /// (2/π) (Si(2e) − sin² e / e): inside the central maximum (e = π) 0.9028, the textbook
    /// share of a slit's far-field power in its central lobe; inside the second minima (2π)
    /// 0.9499; within half the first minimum's angle 0.7737.
    #[test]
    fn single_slit_samples_follow_the_sinc_squared_distribution() {
        let n = 400_000;
        let xs: Vec<f64> = (0..n)
            .map(|s| single_slit_x(&|d| uniform(3, 1, 2, s, d), 0))
            .collect();
        for (edge, sigmas) in [(1.0, 4.0), (2.0, 4.0), (0.5, 4.0)] {
            let edge = edge * std::f64::consts::PI;
            let expected =
                2.0 / std::f64::consts::PI * (si(2.0 * edge) - edge.sin().powi(2) / edge);
            let share = xs.iter().filter(|x| x.abs() < edge).count() as f64 / n as f64;
            let sigma = (expected * (1.0 - expected) / n as f64).sqrt();
            assert!(
                (share - expected).abs() < sigmas * sigma,
                "|x| < {edge}: {share} against {expected}"
            );
        }
        assert!(
            (2.0 / std::f64::consts::PI * si(2.0 * std::f64::consts::PI) - 0.9028).abs() < 1e-4
        );
        // Symmetric: as many samples on either side.
        let positive = xs.iter().filter(|&&x| x > 0.0).count() as f64 / n as f64;
        assert!(
            (positive - 0.5).abs() < 4.0 * (0.25 / n as f64).sqrt(),
            "{positive}"
        );
    }

    #[test]
    fn dr_tims_gui_defaults() {
        let keys: PixellationKeys = toml::from_str("").unwrap();
        let Surface::Pixellation(p) = keys.build().unwrap() else {
            panic!("the kind built")
        };
        assert_eq!(
            p.pixels,
            Pixels {
                size: DVec2::splat(1e-4),
                lambda: 632.8e-9,
                blur: Some(Blur::SingleSlit),
                ray_offset: true,
                sides: None,
            }
        );
    }
}
