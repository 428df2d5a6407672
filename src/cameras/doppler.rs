//! The Doppler shift and headlight effect of a moving camera (beyond Dr TIM, whose paper
//! neglects both in §2): the colour and brightness of light that reaches the camera along a
//! ray, from its colour in the scene frame.
//!
//! D = ν_camera/ν_scene = γ(1 + β·d̂′) for light arriving along the unit backwards-traced
//! scene-frame direction d̂′ (the light travels along −d̂′; moving towards where it comes
//! from, β·d̂′ > 0, blue-shifts it). Each RGB channel is a narrow band of fixed width in
//! frequency at the wavelength λ_R, λ_G or λ_B; the scene's spectrum is the piecewise-linear
//! function of wavelength through (λ_B, B), (λ_G, G), (λ_R, R), constant beyond λ_B and λ_R.
//! The camera's channel at λ sees the scene's light of wavelength Dλ, with the spectral
//! radiance per unit frequency, L_ν, multiplied by D³ (L_ν/ν³ is invariant): the headlight
//! effect. (Radiance integrated over all frequencies would scale by D⁴; a channel is a band
//! of given width, so it takes D³.)

use crate::math::Colour;

/// The wavelengths of the blue, green and red channels, in nm (near the dominant wavelengths
/// of the sRGB primaries), increasing.
pub const CHANNEL_WAVELENGTHS_NM: [f64; 3] = [465.0, 549.0, 612.0];

/// The scene spectrum of `colour` at wavelength `lambda` (nm): piecewise linear through the
/// channels' wavelengths, constant beyond them; exactly a channel's value at its wavelength.
pub fn spectrum(colour: Colour, lambda: f64) -> f64 {
    let [b, g, r] = CHANNEL_WAVELENGTHS_NM;
    let line = |x0: f64, y0: f64, x1: f64, y1: f64| y0 + (y1 - y0) * (lambda - x0) / (x1 - x0);
    if lambda < b {
        colour.z
    } else if lambda < g {
        line(b, colour.z, g, colour.y)
    } else if lambda < r {
        line(g, colour.y, r, colour.x)
    } else {
        colour.x
    }
}

/// The colour the camera sees of light whose scene-frame colour is `colour`, for the Doppler
/// factor `d` = ν_camera/ν_scene: each channel at λ shows D³ times the spectrum at Dλ.
pub fn doppler_shifted(colour: Colour, d: f64) -> Colour {
    let [b, g, r] = CHANNEL_WAVELENGTHS_NM.map(|lambda| spectrum(colour, d * lambda));
    d * d * d * Colour::new(r, g, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_shift_leaves_every_colour_exactly() {
        for c in [
            Colour::new(0.1, 0.7, 0.3),
            Colour::new(1e-300, 5.5, 0.0),
            Colour::new(0.2, 0.2, 0.9),
        ] {
            assert_eq!(doppler_shifted(c, 1.0), c);
        }
    }

    #[test]
    fn white_stays_white_and_brightens_by_the_cube() {
        let white = Colour::ONE;
        for d in [0.3, 0.9, 1.5, 3.0] {
            let seen = doppler_shifted(white, d);
            assert!(
                (seen - Colour::splat(d * d * d)).length() < 1e-14,
                "{d}: {seen}"
            );
        }
    }

    #[test]
    fn blue_shift_moves_red_light_into_the_green_channel() {
        // Pure red (1, 0, 0): the green channel at 549 nm sees the scene at 549·D nm. With
        // D = 612/549 that is 612 nm, all red; with D = 580.5/549 halfway, half of it.
        let red = Colour::X;
        let d = 612.0 / 549.0;
        let seen = doppler_shifted(red, d);
        assert!(
            (seen.y - d.powi(3)).abs() < 1e-12 && (seen.x - d.powi(3)).abs() < 1e-12,
            "{seen}"
        );
        let d = 580.5 / 549.0;
        assert!((doppler_shifted(red, d).y - 0.5 * d.powi(3)).abs() < 1e-12);
        // The blue channel at 465 nm sees 465·D < 549 nm: no red there.
        assert_eq!(doppler_shifted(red, d).z, 0.0);
    }
}
