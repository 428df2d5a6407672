//! Complex-function metarefraction (Dr TIM's `Metarefractive` and `RefractiveComplex`) and
//! collineation surfaces (`CollineationSurface`), read from scene text and applied through
//! `Surface::redirect`, against independent facts: Snell's law, rotation about the normal, the
//! flip of one component, the complex power and exponential evaluated by hand, total internal
//! reflection, and the ideal thin lens as a collineation.

mod common;

use common::sheets::{leaves, redirect, sheet};
use glam::{DQuat, DVec3};
use timbre::surfaces::Redirection;

fn assert_close(got: DVec3, want: DVec3, what: &str) {
    assert!((got - want).length() < 1e-12, "{what}: {got} vs {want}");
}

/// Snell's law, n₁ sin θ₁ = n₂ sin θ₂ in vector form, for the unit direction `d` crossing the
/// plane z = 0 from index n₁ into n₂.
fn snell(d: DVec3, n1: f64, n2: f64) -> DVec3 {
    let t = DVec3::new(d.x, d.y, 0.0) * n1 / n2;
    t + DVec3::Z * d.z.signum() * (1.0 - t.length_squared()).sqrt()
}

/// The sheet's outside is +z (its outward normal): rays along −z cross inwards.
const INWARDS: [DVec3; 3] = [
    DVec3::new(0.3, -0.2, -0.93),
    DVec3::new(-0.5, 0.1, -0.86),
    DVec3::new(0.0, 0.4, -0.92),
];

#[test]
fn a_real_factor_is_snells_law_and_a_complex_index_ratio_is_too() {
    // Outside n = 1, inside n = 1.5: inwards the tangential part shrinks by 1/1.5.
    let multiplication = sheet(
        "{ type = \"complex-metarefraction\", function = { type = \"multiplication\", \
         inwards_factor = [0.6666666666666666, 0] } }",
    );
    let index = sheet("{ type = \"refractive-complex\", index_ratio = [1.5, 0] }");
    for d in INWARDS {
        let d = d.normalize();
        for s in [&multiplication, &index] {
            let (inside, t) = leaves(redirect(s, 0.1, 0.2, d));
            assert_close(inside, snell(d, 1.0, 1.5), "inwards");
            assert_eq!(t, 0.96);
            let (out, _) = leaves(redirect(s, 0.1, 0.2, -inside));
            assert_close(out, -d, "back out");
        }
    }
}

/// k = e^{iφ} turns the tangential direction by φ about the normal (from u towards v) going
/// inwards and by −φ going outwards.
#[test]
fn a_unit_complex_factor_rotates_about_the_normal() {
    let phi = 25f64.to_radians();
    let s = sheet(&format!(
        "{{ type = \"complex-metarefraction\", function = {{ type = \"multiplication\", \
         inwards_factor = [{}, {}] }} }}",
        phi.cos(),
        phi.sin()
    ));
    for d in INWARDS {
        let d = d.normalize();
        let (inside, _) = leaves(redirect(&s, 0.0, 0.0, d));
        assert_close(inside, DQuat::from_rotation_z(phi) * d, "inwards");
        let (outside, _) = leaves(redirect(&s, 0.0, 0.0, -d));
        assert_close(outside, DQuat::from_rotation_z(-phi) * -d, "outwards");
    }
}

#[test]
fn conjugation_flips_the_v_component() {
    let s = sheet("{ type = \"complex-metarefraction\", function = { type = \"conjugation\" } }");
    for d in INWARDS {
        let d = d.normalize();
        let (out, _) = leaves(redirect(&s, 0.0, 0.0, d));
        assert_close(out, DVec3::new(d.x, -d.y, d.z), "flipped");
    }
}

/// c = 0.6: inwards c² = 0.36; c = 0.5 i: c² = −0.25; outwards the square root, 0.36 → 0.6.
/// sin outwards: sin(0.3 i) = i sinh 0.3.
/// exp outwards: c = −0.9 gives e^−0.9 along u; ln inwards: c = 0.5 gives ln 0.5 = −0.693.
#[test]
fn powers_and_exponentials_map_the_tangential_direction() {
    let power = sheet(
        "{ type = \"complex-metarefraction\", function = { type = \"power\", inwards_exponent = 2 } }",
    );
    let along = |c: DVec3, sign: f64| c + DVec3::Z * sign * (1.0 - c.length_squared()).sqrt();
    let inwards = |x: f64, y: f64| along(DVec3::new(x, y, 0.0), -1.0);
    let (out, _) = leaves(redirect(&power, 0.0, 0.0, inwards(0.6, 0.0)));
    assert_close(out, inwards(0.36, 0.0), "0.6²");
    let (out, _) = leaves(redirect(&power, 0.0, 0.0, inwards(0.0, 0.5)));
    assert_close(out, inwards(-0.25, 0.0), "(0.5 i)²");
    let (out, _) = leaves(redirect(&power, 0.0, 0.0, -inwards(-0.36, 0.0)));
    assert_close(out, along(DVec3::new(0.6, 0.0, 0.0), 1.0), "√0.36");

    let exp = sheet("{ type = \"complex-metarefraction\", function = { type = \"exp\" } }");
    let outwards = |x: f64| along(DVec3::new(x, 0.0, 0.0), 1.0);
    let (out, _) = leaves(redirect(&exp, 0.0, 0.0, outwards(-0.9)));
    assert_close(out, outwards((-0.9f64).exp()), "exp(−0.9)");
    let (out, _) = leaves(redirect(&exp, 0.0, 0.0, inwards(0.5, 0.0)));
    assert_close(out, inwards(0.5f64.ln(), 0.0), "ln 0.5");
    // sin outwards: sin(0.3 i) = i sinh 0.3.
    let sin = sheet("{ type = \"complex-metarefraction\", function = { type = \"sin\" } }");
    let (out, _) = leaves(redirect(
        &sin,
        0.0,
        0.0,
        along(DVec3::new(0.0, 0.3, 0.0), 1.0),
    ));
    assert_close(
        out,
        along(DVec3::new(0.0, 0.3f64.sinh(), 0.0), 1.0),
        "sin 0.3i",
    );
}

/// Where |c′| > 1 the wave is evanescent: the ray is reflected, with the reflection
/// coefficient, not the transmission coefficient; a Julia-set sheet passes no light outwards.
#[test]
fn evanescent_rays_are_reflected_and_julia_sets_have_no_inverse() {
    let s = sheet(
        "{ type = \"complex-metarefraction\", function = { type = \"addition\", \
         inwards_offset = [0.8, 0] }, reflection_coefficient = 0.7 }",
    );
    let d = DVec3::new(0.5, 0.0, -0.75f64.sqrt());
    let (out, factor) = leaves(redirect(&s, 0.0, 0.0, d));
    assert_close(out, DVec3::new(d.x, d.y, -d.z), "mirrored");
    assert_eq!(factor, 0.7);
    let (out, _) = leaves(redirect(
        &s,
        0.0,
        0.0,
        DVec3::new(-0.3, 0.0, -0.91f64.sqrt()),
    ));
    assert_close(out, DVec3::new(0.5, 0.0, -0.75f64.sqrt()), "−0.3 + 0.8");
    // ln 0 is infinite: a ray crossing an exp sheet inwards along the normal is reflected.
    let exp = sheet("{ type = \"complex-metarefraction\", function = { type = \"exp\" } }");
    let (out, _) = leaves(redirect(&exp, 0.0, 0.0, -DVec3::Z));
    assert_close(out, DVec3::Z, "ln 0");
    let julia = sheet(
        "{ type = \"complex-metarefraction\", function = { type = \"julia-set\", \
         constant = [-0.1, 0.2], iterations = 3 } }",
    );
    assert_eq!(redirect(&julia, 0.0, 0.0, DVec3::Z), Redirection::Lost);
    // Inwards: z₀ = c, three times z² + C.
    let c = num(0.2, 0.1);
    let z = (0..3).fold(c, |z, _| add(mul(z, z), num(-0.1, 0.2)));
    let (out, _) = leaves(redirect(
        &julia,
        0.0,
        0.0,
        DVec3::new(0.2, 0.1, -0.95f64.sqrt()),
    ));
    assert_close(
        out,
        DVec3::new(z.0, z.1, -(1.0 - z.0 * z.0 - z.1 * z.1).sqrt()),
        "julia",
    );
}

/// Complex numbers as pairs, multiplied by hand.
fn num(re: f64, im: f64) -> (f64, f64) {
    (re, im)
}
fn add(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 + b.0, a.1 + b.1)
}
fn mul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

/// A collineation surface (Dr TIM's `CollineationSurface`) with the identity changes nothing;
/// with a translation along the sheet it moves rays along it, keeping their direction; with
/// the thin-lens collineation f (x, y, z) / (z + f) it bends rays traced along +z exactly as
/// an ideal thin lens of focal length f at the origin does (the lens is reciprocal, so the
/// traced ray bends as the light does), leaving from where they met it.
#[test]
fn collineation_surfaces_image_lines() {
    let identity = sheet(
        "{ type = \"collineation-surface\", collineation = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]] }",
    );
    let shift = sheet(
        "{ type = \"collineation-surface\", collineation = [[1, 0, 0, 0.5], [0, 1, 0, -0.25], [0, 0, 1, 0], [0, 0, 0, 1]] }",
    );
    let lens = sheet(
        "{ type = \"collineation-surface\", collineation = [[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, 2, 0], [0, 0, 1, 2]] }",
    );
    let ideal = sheet(
        "{ type = \"ideal-thin-lens\", focal_length = 2, principal_point = [0, 0, 0], optical_axis = [0, 0, 1] }",
    );
    let jumps = |r: Redirection| match r {
        Redirection::Jumps { exit, factor } => (exit.point, exit.direction, factor.x),
        other => panic!("expected a jump, got {other:?}"),
    };
    for (x, y) in [(0.0, 0.0), (0.4, -0.3), (-1.2, 0.7)] {
        for d in [
            DVec3::new(0.1, 0.2, 1.0),
            DVec3::new(-0.3, 0.0, 0.8),
            DVec3::new(0.2, -0.1, -1.0),
        ] {
            let d = d.normalize();
            let (p, e, t) = jumps(redirect(&identity, x, y, d));
            assert_close(p, DVec3::new(x, y, 0.0), "identity: where");
            assert_close(e, d, "identity: direction");
            assert_eq!(t, 0.96);
            let (p, e, _) = jumps(redirect(&shift, x, y, d));
            assert_close(p, DVec3::new(x + 0.5, y - 0.25, 0.0), "shift: where");
            assert_close(e, d, "shift: direction");
            if d.z > 0.0 {
                let (p, e, _) = jumps(redirect(&lens, x, y, d));
                let (lensed, _) = leaves(redirect(&ideal, x, y, d));
                assert_close(p, DVec3::new(x, y, 0.0), "lens: where");
                assert_close(e, lensed, "lens: direction");
            }
        }
    }
}
