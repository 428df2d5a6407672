//! Realistic METATOYs (Dr TIM's `GCLAsWithApertures` and `Pixellation`) and variable-η CLAs,
//! read from scene text and applied through `Surface::redirect`, checked against independent
//! facts: the vignetting of telescopes of known lenses, the symmetry of the v direction, the
//! distributions of the diffractive blur and of the ray offset, and Eq 39 at each point.

mod common;

use std::f64::consts::PI;

use common::sheets::{leaves, redirect, sheet};
use glam::DVec3;
use timbre::geometry::Shape;
use timbre::surfaces::{Redirection, Surface};

/// A ray with slopes (s_u, s_v) against +z.
fn slopes(su: f64, sv: f64) -> DVec3 {
    DVec3::new(su, sv, 1.0)
}

const GCLA: &str = "type = \"gcla\", a = [0, 0, 1], u = [1, 0, 0]";

/// A telescope of magnification 2 (η = 2, apertures as wide as f₁, centred): light entering
/// lenslet 1 leaves spread over twice the aperture, of which lenslet 2 passes half in each
/// projection, ¼ in all; crossed the other way the beam shrinks to half and all of it passes.
#[test]
fn an_expanding_telescope_passes_a_quarter_of_a_full_aperture_and_a_shrinking_one_all() {
    for method in ["geometric", "geometric-best"] {
        let s = sheet(&format!(
            "{{ {GCLA}, eta_u = 2, eta_v = 2, transmission_coefficient_method = \"{method}\" }}"
        ));
        let (_, forwards) = leaves(redirect(&s, 0.3, 0.1, DVec3::Z));
        let (_, backwards) = leaves(redirect(&s, 0.3, 0.1, -DVec3::Z));
        assert_eq!((forwards, backwards), (0.25, 1.0), "{method}");
    }
}

/// Two equal lenses (η = −1), focal length f, apertures f wide: a ray of slope s through lens
/// 1 at height h crosses lens 2 at 2fs − h, so the beam through lens 1 lands shifted by 2fs
/// and 1 − 2|s| of it passes in that projection (the telescopes' vignetting). Offsetting lens
/// 2's aperture by α₂ f moves the clear direction to s = α₂/2 (Dr TIM's field-of-view
/// steering).
#[test]
fn inverting_telescopes_vignette_by_one_minus_twice_the_slope() {
    let s = sheet(&format!(
        "{{ {GCLA}, eta_u = -1, eta_v = -1, transmission_coefficient_method = \"geometric\" }}"
    ));
    for (su, sv) in [
        (0.0, 0.0),
        (0.2, 0.0),
        (-0.2, 0.1),
        (0.3, -0.45),
        (0.6, 0.0),
    ] {
        let (out, t) = leaves(redirect(&s, 0.0, 0.0, slopes(su, sv)));
        let expected = (1.0 - 2.0 * su.abs()).max(0.0) * (1.0 - 2.0 * sv.abs()).max(0.0);
        assert!(
            (t - expected).abs() < 1e-12,
            "({su}, {sv}): {t} vs {expected}"
        );
        // The direction is Eq 39's: the slopes inverted.
        assert!((out - slopes(-su, -sv).normalize()).length() < 1e-12);
    }
    let steered = sheet(&format!(
        "{{ {GCLA}, eta_u = -1, eta_v = -1, transmission_coefficient_method = \"geometric\", \
         alpha2_u = 0.2 }}"
    ));
    let t = |su| leaves(redirect(&steered, 0.0, 0.0, slopes(su, 0.0))).1;
    assert!((t(0.1) - 1.0).abs() < 1e-12);
    assert!((t(0.0) - 0.8).abs() < 1e-12 && (t(0.2) - 0.8).abs() < 1e-12);
}

/// v only chooses the sign of v̂: turning it round is the same as turning δ_v round.
#[test]
fn v_chooses_the_side_of_the_v_axis() {
    let flipped = sheet(&format!(
        "{{ {GCLA}, v = [0, -3, 0.2], eta_v = 0.5, delta_v = 0.2 }}"
    ));
    let negated = sheet(&format!("{{ {GCLA}, eta_v = 0.5, delta_v = -0.2 }}"));
    for d in [slopes(0.1, 0.3), slopes(-0.2, -0.1), -slopes(0.3, 0.2)] {
        let (a, _) = leaves(redirect(&flipped, 0.0, 0.0, d));
        let (b, _) = leaves(redirect(&negated, 0.0, 0.0, d));
        assert!((a - b).length() < 1e-15, "{d}: {a} vs {b}");
    }
}

/// The changes of a normally incident ray's tangential direction components, for rays met at
/// `n` points of the sheet.
fn kicks(s: &(Shape, Surface), n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let (x, y) = (i as f64 * 1e-3, (i % 97) as f64 * 1e-2);
            let (d, _) = leaves(redirect(s, x, y, DVec3::Z));
            (d.x, d.y)
        })
        .collect()
}

/// GCLAsWithApertures's blur: each tangential component changes by an amount uniform in
/// (−λ/w, λ/w), whose mean square is (λ/w)²/3; the same ray is blurred the same way twice.
#[test]
fn the_gcla_blur_is_uniform_up_to_the_first_diffraction_minimum() {
    let s = sheet(&format!(
        "{{ {GCLA}, simulate_diffractive_blur = true, pixel_side_length = 1e-3, lambda = 1e-5 }}"
    ));
    let bound = 1e-5 / 1e-3;
    let n = 40_000;
    let k = kicks(&s, n);
    for c in [
        k.iter().map(|k| k.0).collect::<Vec<_>>(),
        k.iter().map(|k| k.1).collect(),
    ] {
        assert!(c.iter().all(|x| x.abs() < bound));
        let mean_square = c.iter().map(|x| x * x).sum::<f64>() / n as f64;
        // The mean square of a uniform variable on (−b, b) is b²/3, its variance 4b⁴/45.
        let sigma = (4.0 / 45.0 / n as f64).sqrt() * bound * bound;
        assert!(
            (mean_square - bound * bound / 3.0).abs() < 5.0 * sigma,
            "{mean_square}"
        );
        assert!(c.iter().any(|x| *x > 0.99 * bound) && c.iter().any(|x| *x < -0.99 * bound));
    }
    assert_eq!(kicks(&s, 10), kicks(&s, 10));
}

/// Pixellation's blur is a slit's far field: sin θ = x λ / (π w) with x of density
/// sin² x / (π x²), so |sin θ| < λ/(2w) (|x| < π/2) for (2/π)(Si(π) − 2/π) = 0.77366 of the rays
/// and |sin θ| < λ/w (the first minimum) for (2/π) Si(2π) = 0.90282 (Si(π) = 1.851937052,
/// Si(2π) = 1.418151576, Abramowitz and Stegun Table 5.1).
#[test]
fn pixellation_blurs_by_single_slit_diffraction() {
    let s = sheet(
        "{ type = \"pixellation\", pixel_side_length_u = 1e-3, pixel_side_length_v = 2e-3, \
         lambda = 1e-5, simulate_ray_offset = false }",
    );
    let n = 100_000;
    let k = kicks(&s, n);
    let si_pi = 1.851_937_052;
    let si_2pi = 1.418_151_576;
    for (c, w) in [
        (k.iter().map(|k| k.0).collect::<Vec<_>>(), 1e-3),
        (k.iter().map(|k| k.1).collect(), 2e-3),
    ] {
        let lambda_over_w = 1e-5 / w;
        for (edge, share) in [
            (0.5, 2.0 / PI * (si_pi - 2.0 / PI)),
            (1.0, 2.0 / PI * si_2pi),
        ] {
            let got = c.iter().filter(|x| x.abs() < edge * lambda_over_w).count() as f64 / n as f64;
            let sigma = (share * (1.0 - share) / n as f64).sqrt();
            assert!(
                (got - share).abs() < 5.0 * sigma,
                "w {w}, edge {edge}: {got} vs {share}"
            );
        }
    }
}

/// The ray offset moves the ray's start along u and v by amounts uniform in (−w, w), in the
/// sheet, keeping its direction.
#[test]
fn the_ray_offset_is_uniform_within_a_pixel_side() {
    let s = sheet(&format!(
        "{{ {GCLA}, eta_u = -1, eta_v = -1, simulate_ray_offset = true, pixel_side_length = 0.01 }}"
    ));
    let n = 20_000;
    let d = slopes(0.1, -0.2);
    let (mut sum_u2, mut largest) = (0.0, 0f64);
    for i in 0..n {
        let (x, y) = (i as f64 * 1e-3, 0.5);
        let Redirection::Jumps { exit, factor } = redirect(&s, x, y, d) else {
            panic!("a ray offset jumps")
        };
        let offset = exit.point - DVec3::new(x, y, 0.0);
        assert!(offset.z.abs() < 1e-12 && offset.x.abs() < 0.01 && offset.y.abs() < 0.01);
        assert!((exit.direction - slopes(-0.1, 0.2).normalize()).length() < 1e-12);
        assert_eq!(factor.x, 0.96);
        sum_u2 += offset.x * offset.x;
        largest = largest.max(offset.x.abs());
    }
    let expected = 0.01 * 0.01 / 3.0;
    assert!((sum_u2 / n as f64 - expected).abs() < 0.03 * expected);
    assert!(largest > 0.0099);
}

/// Variable-η CLAs at a point where η = η_P + (Q − P)·∇η are Eq 39's gCLAs with telescopes
/// along the inward normal, η_u = η_v = η and no offset, in both directions of crossing.
#[test]
fn variable_eta_clas_are_local_gclas_along_the_normal() {
    let variable = sheet(
        "{ type = \"variable-eta-confocal-lenslet-arrays\", inwards_eta_at_p = 0.5, \
         point_p = [0.2, 0, 0], grad_eta = [0.5, -0.25, 0] }",
    );
    for (x, y) in [(0.2, 0.0), (1.0, 0.4), (-1.3, -0.7), (3.0, 1.0)] {
        let eta = 0.5 + 0.5 * (x - 0.2) - 0.25 * y;
        let gcla = sheet(&format!(
            "{{ type = \"gcla\", a = [0, 0, -1], u = [1, 0, 0], eta_u = {eta}, eta_v = {eta} }}"
        ));
        for d in [slopes(0.3, -0.2), -slopes(-0.1, 0.4), slopes(0.0, 0.5)] {
            let (a, t) = leaves(redirect(&variable, x, y, d));
            let (b, _) = leaves(redirect(&gcla, x, y, d));
            assert!((a - b).length() < 1e-14, "({x}, {y}), {d}: {a} vs {b}");
            assert_eq!(t, 0.96);
        }
    }
}

/// An ideal thin lenslet array with diffractive blur (Dr TIM's `RectangularIdealThinLensletArray`)
/// blurs by its lenslets' single-slit diffraction: rays through the lenslets' centres, which the
/// lenses leave undeviated, leave within the first minimum (|sin θ| < λ/w) for
/// (2/π) Si(2π) = 0.90282 of them; without the blur every one goes straight on.
#[test]
fn lenslet_arrays_blur_by_their_apertures_diffraction() {
    let keys = "type = \"ideal-thin-lenslet-array\", centre = [0, 0, 0], period = [1e-3, 1e-3], focal_length = 0.01";
    let blurred = sheet(&format!(
        "{{ {keys}, simulate_diffractive_blur = true, lambda = 1e-5 }}"
    ));
    let sharp = sheet(&format!("{{ {keys} }}"));
    let n = 40_000;
    let inside = (0..n)
        .filter(|&i| {
            let (x, y) = ((i % 200) as f64 * 1e-3, (i / 200) as f64 * 1e-3);
            let (d, _) = leaves(redirect(&blurred, x, y, DVec3::Z));
            let (straight, _) = leaves(redirect(&sharp, x, y, DVec3::Z));
            assert!((straight - DVec3::Z).length() < 1e-12);
            d.x.abs() < 1e-2
        })
        .count() as f64
        / n as f64;
    let share = 2.0 / PI * 1.418_151_576;
    assert!(
        (inside - share).abs() < 5.0 * (share * (1.0 - share) / n as f64).sqrt(),
        "{inside}"
    );
}
