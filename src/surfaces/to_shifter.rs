//! The transformation-optics shifter (Dr TIM's `SurfaceOfTOShifter`): a spherical shell of
//! centre c, outer radius R and inner radius r₁, filled with the medium that makes the inner
//! sphere, and everything in it, appear shifted by δ from outside, while space outside is seen
//! as it is. Seen from outside (in "electromagnetic space") a point x of the shell is at
//!
//!   V(x) = x + f(r) δ,   r = |x − c|,
//!
//! with f(R) = 0 and f(r₁) = 1: Dr TIM's linear f = (R − r)/(R − r₁) or quadratic
//! f = (R² − r²)/(R² − r₁²); inside the inner sphere V(x) = x + δ. Its medium (ε = μ = the
//! tensor Dr TIM integrates) sends light along the curves V maps onto straight lines, so this
//! law traces them exactly instead of integrating: light entering the shell on the straight line
//! L(t) = A + t d̂ of electromagnetic space goes through the physical points x = A + t d̂ − u δ
//! with u = f(|x − c|), a conic in the plane of (t, u); it leaves the shell where that conic
//! first reaches u = 0 (the outer sphere) or u = 1 (the inner one), along d̂. Where
//! det ∂V/∂x < 0 (|δ| large: the inner sphere seen partly outside the device, Dr TIM's "abyss"
//! regime) the curve runs backwards along L, and the light can circle through the core for ever.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::Redirection;
use crate::geometry::{Exit, Interaction, Shape, Transform};
use crate::math::Colour;

/// Dr TIM's `ShiftFunctionType`: how the shift falls from δ at the inner sphere to 0 at the
/// outer one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShiftFunction {
    /// f(r) = (R − r)/(R − r₁).
    Linear,
    /// f(r) = (R² − r²)/(R² − r₁²).
    Quadratic,
}

/// The shell's medium, on its outer and inner spheres.
#[derive(Debug, Clone, PartialEq)]
pub struct ToShifter {
    pub centre: DVec3,
    pub radius: f64,
    pub inner_radius: f64,
    pub delta: DVec3,
    pub shift_function: ShiftFunction,
    /// The fraction of the light that passes the shell (once each passage).
    pub transmission_coefficient: f64,
}

/// Points drawn along a curved passage (for ray trajectories).
const PATH_POINTS: usize = 64;

/// The shortest chord of the inner sphere, in units of its radius, along which light enters
/// the core (along shorter ones, so nearly tangent, the tracer finds the sphere's far side only
/// to about 10⁻⁴ of its radius).
const GRAZE: f64 = 1e-3;

impl ToShifter {
    /// The shell of an object placed by `t` (a similarity map).
    pub fn transformed(&self, t: &Transform) -> Result<ToShifter, String> {
        let scale = t.uniform_scale().ok_or(
            "a transformation-optics shifter is spherical: it may be rotated, scaled uniformly \
             and moved, not stretched",
        )?;
        Ok(ToShifter {
            centre: t.point(self.centre),
            radius: scale * self.radius,
            inner_radius: scale * self.inner_radius,
            delta: t.vector(self.delta),
            ..self.clone()
        })
    }

    /// The passage of light entering the shell at `p` (on the outer sphere, or on the inner
    /// one from the core, as `from_core` says) in unit direction `d`: where it leaves, and
    /// the points of its curved path shown to `inside`. `None` where it only grazes the shell.
    pub fn pass(
        &self,
        centre: DVec3,
        p: DVec3,
        d: DVec3,
        from_core: bool,
        inside: &mut dyn FnMut(DVec3),
    ) -> Option<Exit> {
        let (big_r, r1, delta) = (self.radius, self.inner_radius, self.delta);
        let u0 = if from_core { 1.0 } else { 0.0 };
        // The electromagnetic-space line A + t d̂, relative to the centre; in the coordinates
        // (v, u), v = t − u (d̂·δ), the physical point is x = A + v d̂ − u w, w ⟂ d̂.
        let a = p - centre + u0 * delta;
        let w = delta - delta.dot(d) * d;
        let start = DVec2::new(-u0 * delta.dot(d), u0);
        // The conic Q = m_vv v² + m_uu u² + 2 (q_v v + q_u u) + q_0 = 0 (m_vu = 0).
        let (m_uu, q_u) = match self.shift_function {
            // r² + (R² − r₁²) u − R².
            ShiftFunction::Quadratic => (
                w.length_squared(),
                -a.dot(w) + 0.5 * (big_r * big_r - r1 * r1),
            ),
            // r² − (R − (R − r₁) u)².
            ShiftFunction::Linear => {
                let k = big_r - r1;
                (w.length_squared() - k * k, -a.dot(w) + big_r * k)
            }
        };
        let q_v = a.dot(d);
        let gradient = |x: DVec2| 2.0 * DVec2::new(x.x + q_v, m_uu * x.y + q_u);
        let quadratic = |e: DVec2| e.x * e.x + m_uu * e.y * e.y;
        let physical = |x: DVec2| centre + a + x.x * d - x.y * w;

        // The points where light leaves the strip 0 < u < 1 moving outwards: the far end of the
        // line's chord of the outer sphere (u = 0), the near end of its chord of the inner one
        // (u = 1), each a root of v² + 2 v (b·d̂) + |b|² − ρ² = 0 for the line b + v d̂. A
        // chord of the inner sphere shorter than GRAZE r₁ is taken as a graze: the light goes
        // on in the shell (along the same conic, as it would after crossing so short a chord),
        // rather than into a core the tracer could not then leave accurately.
        let chord = |b: DVec3, rho: f64, far: bool, shortest: f64| {
            let half = b.dot(d);
            let disc = half * half - (b.length_squared() - rho * rho);
            (disc > 0.25 * shortest * shortest).then(|| {
                let root = disc.sqrt();
                if far { -half + root } else { -half - root }
            })
        };
        let scale = big_r + delta.length();
        let candidates = [
            chord(a, big_r, true, 0.0).map(|v| DVec2::new(v, 0.0)),
            chord(a - w, r1, false, GRAZE * r1).map(|v| DVec2::new(v, 1.0)),
        ]
        .into_iter()
        .flatten()
        .filter(|&c| physical(c).distance(p) > 1e-12 * (big_r + (p - centre).length()));

        // Along the conic from the start, the chord from the start turns steadily away from the
        // tangent τ = (Q_u, −Q_v), towards ∇Q where τᵀMτ < 0; the first exit reached is the
        // one whose chord has turned least.
        let g = gradient(start);
        let tangent = DVec2::new(g.y, -g.x);
        if tangent.length() <= 1e-12 * scale {
            return None;
        }
        let tangent = tangent.normalize();
        let turn = if quadratic(tangent) < 0.0 { 1.0 } else { -1.0 };
        let turned = |c: DVec2| {
            let chord = c - start;
            (turn * tangent.perp_dot(chord).atan2(tangent.dot(chord)))
                .rem_euclid(std::f64::consts::PI)
        };
        let exit = candidates.min_by(|x, y| turned(*x).total_cmp(&turned(*y)))?;

        // The curved path: the conic's second point on chords turned from 0 to the exit's,
        // closer together where the curve runs fast.
        let last = turned(exit);
        let at = |angle: f64| {
            let e = DVec2::from_angle(turn * angle).rotate(tangent);
            physical(start + (-gradient(start).dot(e) / quadratic(e)) * e)
        };
        let spacing = 0.02 * scale;
        let mut previous = (0.0, p);
        for i in 1..=PATH_POINTS {
            let angle = last * i as f64 / PATH_POINTS as f64;
            let next = (
                angle,
                if i == PATH_POINTS {
                    physical(exit)
                } else {
                    at(angle)
                },
            );
            // (Where the conic is a pair of lines, δ along the light, some chords meet it
            // nowhere else: those give no point.)
            if !next.1.is_finite() {
                continue;
            }
            fill(&at, previous, next, spacing, 8, inside);
            if i < PATH_POINTS {
                inside(next.1);
            }
            previous = next;
        }
        Some(Exit::chord(p, physical(exit), d))
    }

    /// Light meeting either sphere from outside the shell crosses it ([`Self::pass`]); light
    /// meeting it from within the shell (a camera there) passes as if it were transparent.
    pub fn redirect(
        &self,
        at: &Interaction,
        inside: &mut dyn FnMut(DVec3),
    ) -> Redirection<'static> {
        let factor = Colour::splat(self.transmission_coefficient);
        let Shape::Sphere(_) = at.shape else {
            return Redirection::Lost;
        };
        let (centre, p, d) = (self.centre + at.offset, at.point(), at.ray.direction);
        let x = p - centre;
        let on_inner = x.length() < 0.5 * (self.radius + self.inner_radius);
        let entering = (d.dot(x) < 0.0) != on_inner;
        if !entering {
            return Redirection::Leaves {
                direction: d,
                factor,
            };
        }
        match self.pass(centre, p, d, on_inner, inside) {
            Some(exit) => Redirection::Crosses { exit, factor },
            None => Redirection::Leaves {
                direction: d,
                factor,
            },
        }
    }
}

/// The points of the path `at` between `from` and `to` (each an angle and its point), so that
/// neighbours lie at most `spacing` apart, halving the angle at most `depth` times.
fn fill(
    at: &dyn Fn(f64) -> DVec3,
    from: (f64, DVec3),
    to: (f64, DVec3),
    spacing: f64,
    depth: u32,
    inside: &mut dyn FnMut(DVec3),
) {
    if depth == 0 || from.1.distance(to.1) <= spacing {
        return;
    }
    let angle = 0.5 * (from.0 + to.0);
    let middle = (angle, at(angle));
    if !middle.1.is_finite() {
        return;
    }
    fill(at, from, middle, spacing, depth - 1, inside);
    inside(middle.1);
    fill(at, middle, to, spacing, depth - 1, inside);
}
