//! Ray queries and exact reference answers shared by the comparisons of `SceneGeometry` (Embree)
//! against brute force (`tests/embree_vs_reference.rs`, `tests/arrays.rs`).

use std::sync::OnceLock;

use glam::DVec3;
use timbre::embree::{Device, ExactRay};
use timbre::geometry::{AnalyticShape, Hit, SceneGeometry, Shape};

use super::rng::Rng;

/// One Embree device for every test of a test binary.
pub fn device() -> &'static Device {
    static DEVICE: OnceLock<Device> = OnceLock::new();
    DEVICE.get_or_init(|| Device::new("").expect("an Embree device"))
}

/// Whether `a` and `b` agree to `rel` relative (and absolute near zero).
pub fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * (1.0 + a.abs().max(b.abs()))
}

/// Whether two answers name the same (object, element, prim) at distances within `rel`
/// relative of each other, or both miss.
pub fn same_hit(a: Option<Hit>, b: Option<Hit>, rel: f64) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            (a.object, a.element, a.prim) == (b.object, b.element, b.prim) && close(a.t, b.t, rel)
        }
        _ => false,
    }
}

/// A ray query.
#[derive(Debug, Clone, Copy)]
pub struct Query {
    pub origin: DVec3,
    pub direction: DVec3,
    pub t_min: f64,
    pub t_max: f64,
}

/// A point of the shape (inside it for solids), for aiming rays.
pub fn sample_point(shape: &Shape, rng: &mut Rng) -> DVec3 {
    match shape {
        Shape::Sphere(s) => s.centre() + s.radius() * rng.f().cbrt() * rng.unit(),
        Shape::Plane(p) => {
            let f = p.frame(p.point(), 0);
            p.point() + rng.range(-5.0, 5.0) * f.u + rng.range(-5.0, 5.0) * f.v
        }
        Shape::Disc(d) => {
            let (rho, phi) = (
                d.radius() * rng.f().sqrt(),
                rng.range(0.0, std::f64::consts::TAU),
            );
            let f = d.frame(d.centre(), 0);
            d.centre() + rho * (phi.cos() * f.u + phi.sin() * f.v)
        }
        Shape::Cylinder(c) => {
            let radial = rng
                .unit()
                .reject_from_normalized(c.axis())
                .normalize_or_zero();
            c.start() + rng.f() * (c.end() - c.start()) + c.radius() * rng.f().sqrt() * radial
        }
        Shape::Parallelogram(p) => p.corner() + rng.f() * p.span_u() + rng.f() * p.span_v(),
        Shape::TriangleMesh(m) => {
            let [a, b, c] =
                m.triangles()[rng.index(m.triangles().len())].map(|i| m.vertices()[i as usize]);
            let (s, u) = (rng.f().sqrt(), rng.f());
            a * (1.0 - s) + b * (s * (1.0 - u)) + c * (s * u)
        }
        // Any other bounded shape: a point of its bounding box.
        other => {
            let (lo, hi) = other.bounds().expect("a bounded shape");
            lo + (hi - lo) * DVec3::new(rng.f(), rng.f(), rng.f())
        }
    }
}

/// A point on the surface of the shape, for rays leaving it.
pub fn surface_point(shape: &Shape, rng: &mut Rng) -> DVec3 {
    match shape {
        Shape::Sphere(s) => s.centre() + s.radius() * rng.unit(),
        Shape::Cylinder(c) => {
            let radial = rng
                .unit()
                .reject_from_normalized(c.axis())
                .normalize_or_zero();
            c.start() + rng.f() * (c.end() - c.start()) + c.radius() * radial
        }
        _ => sample_point(shape, rng),
    }
}

/// The tracer's self-hit margin (t_min) for a ray leaving `shape` at `origin`: 1e-9 × scale for
/// analytic shapes, 1e-5 × scale for meshes (Embree tests triangles in f32), where the scale is
/// 1 + the largest |coordinate| of `origin`.
pub fn self_hit_margin(shape: &Shape, origin: DVec3) -> f64 {
    let scale = 1.0 + origin.abs().max_element();
    let margin = if matches!(shape, Shape::TriangleMesh(_)) {
        1e-5
    } else {
        1e-9
    };
    margin * scale
}

/// Whether moving t_min and t_max by two f32 roundings (2^-22 relative) either way leaves the
/// shape's answer (for the ray from `origin`, e.g. in an array element's own placement)
/// unchanged.
pub fn interval_ends_do_not_matter(shape: &Shape, origin: DVec3, q: &Query) -> bool {
    let e = 2f64.powi(-22);
    let moved = |t: f64, sign: f64| {
        if t.is_finite() {
            t + sign * e * t.abs()
        } else {
            t
        }
    };
    let d = q.direction;
    let inner = shape.intersect(origin, d, moved(q.t_min, 1.0), moved(q.t_max, -1.0));
    let outer = shape.intersect(origin, d, moved(q.t_min, -1.0), moved(q.t_max, 1.0));
    inner.map(|h| h.0) == outer.map(|h| h.0)
}

/// The parameter interval in which the line o + t d is inside the box [lo, hi] (slab test).
pub fn box_interval(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> Option<(f64, f64)> {
    let (mut a, mut b) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return None;
            }
            continue;
        }
        let (t1, t2) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
        a = a.max(t1.min(t2));
        b = b.min(t1.max(t2));
    }
    (a <= b).then_some((a, b))
}

/// Traces a packet of 1 to 8 rays from `base`'s origin (with its t_min and t_max) with
/// `nearest8`, or from origins scattered about it (as a finite aperture's samples) with
/// `nearest_packet`: coherent (around an aim point 10 along `base`'s direction) or scattered,
/// drawn from `rng`. Fails if a lane beyond the packet's rays answers; otherwise hands each
/// ray's query, its lane's answer and the single-ray answer (`nearest`) to `check_lane`, and
/// returns how many lanes differ from the single-ray answer (see [`same_hit`], to 1e-12).
pub fn check_packet(
    scene: &SceneGeometry,
    base: Query,
    rng: &mut Rng,
    mut check_lane: impl FnMut(Query, Option<Hit>, Option<Hit>) -> Result<(), String>,
) -> Result<usize, String> {
    let aim = base.origin + 10.0 * base.direction;
    let coherent = rng.f() < 0.6;
    let apart = rng.f() < 0.3;
    let n = 1 + rng.index(8);
    let rays: Vec<ExactRay> = (0..n)
        .map(|_| {
            let origin = if apart {
                base.origin + 0.05 * rng.unit()
            } else {
                base.origin
            };
            let direction = if coherent {
                (aim + 0.5 * rng.unit() - origin).normalize()
            } else {
                rng.unit()
            };
            ExactRay { origin, direction }
        })
        .collect();
    let lanes = if apart {
        scene.nearest_packet(&rays, base.t_min, base.t_max)
    } else {
        let directions: Vec<DVec3> = rays.iter().map(|r| r.direction).collect();
        scene.nearest8(base.origin, &directions, base.t_min, base.t_max)
    };
    if lanes[n..].iter().any(Option::is_some) {
        return Err(format!(
            "the packet answered lanes beyond its {n} rays: {lanes:?}"
        ));
    }
    let mut differs = 0;
    for (ray, &lane) in rays.iter().zip(&lanes) {
        let q = Query {
            origin: ray.origin,
            direction: ray.direction,
            ..base
        };
        let single = scene.nearest(q.origin, q.direction, q.t_min, q.t_max);
        differs += usize::from(!same_hit(single, lane, 1e-12));
        check_lane(q, lane, single)?;
    }
    Ok(differs)
}
