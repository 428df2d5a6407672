//! Helpers shared by the integration tests: random inputs for the property tests (here),
//! deterministic random numbers ([`rng`]), ray queries and exact reference answers ([`rays`]),
//! the rules by which Embree's answers are judged against them ([`verdict`]), rendering scene
//! text and comparing pictures ([`images`]), and running the `timbre` command ([`cli`]).
#![allow(dead_code)] // each test crate uses its own subset

pub mod cli;
pub mod glass;
pub mod images;
pub mod rays;
pub mod rng;
pub mod sheets;
pub mod verdict;

use std::f64::consts::TAU;
use std::ops::Range;

use glam::DVec3;
use proptest::prelude::*;
use timbre::geometry::{Cylinder, Disc, Parallelogram, Shape, Sphere};

/// `cases` per property, or `PROPTEST_CASES` from the environment (for soak runs).
pub fn config(cases: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(cases);
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// A point in the cube [−a, a]³.
pub fn point_in(a: f64) -> impl Strategy<Value = DVec3> {
    (-a..a, -a..a, -a..a).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// Unit vector from two uniforms in [0, 1), uniform on the sphere.
pub fn unit_from(u0: f64, u1: f64) -> DVec3 {
    let z = 2.0 * u0 - 1.0;
    let s = (1.0 - z * z).max(0.0).sqrt();
    let phi = TAU * u1;
    DVec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// A uniformly distributed unit vector.
pub fn unit_vector() -> impl Strategy<Value = DVec3> {
    (0.0..1.0f64, 0.0..1.0f64).prop_map(|(a, b)| unit_from(a, b))
}

pub const AXES: [DVec3; 6] = [
    DVec3::X,
    DVec3::Y,
    DVec3::Z,
    DVec3::NEG_X,
    DVec3::NEG_Y,
    DVec3::NEG_Z,
];

/// Mostly random unit vectors, sometimes a coordinate axis (flat or axis-parallel shapes, flat
/// bounding boxes in Embree).
pub fn normal_vector() -> impl Strategy<Value = DVec3> {
    prop_oneof![
        3 => unit_vector(),
        1 => (0..6usize).prop_map(|i| AXES[i]),
    ]
}

/// A number whose logarithm is uniform in [ln lo, ln hi).
pub fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.ln()..hi.ln()).prop_map(f64::exp)
}

/// A sphere centred within `spread` of the origin, of radius 0.05 to `radius`.
pub fn sphere_shape(spread: f64, radius: f64) -> impl Strategy<Value = Shape> {
    (point_in(spread), log_uniform(0.05, radius))
        .prop_map(|(c, r)| Shape::Sphere(Sphere::new(c, r).unwrap()))
}

/// A disc centred within `spread` of the origin, of radius 0.05 to `radius`.
pub fn disc_shape(spread: f64, radius: f64) -> impl Strategy<Value = Shape> {
    (point_in(spread), normal_vector(), log_uniform(0.05, radius))
        .prop_map(|(c, n, r)| Shape::Disc(Disc::new(c, n, r).unwrap()))
}

/// A cylinder starting within `spread` of the origin, of length 0.05 to `length` and radius
/// 0.01 to `radius`.
pub fn cylinder_shape(spread: f64, length: f64, radius: f64) -> impl Strategy<Value = Shape> {
    (
        point_in(spread),
        normal_vector(),
        log_uniform(0.05, length),
        log_uniform(0.01, radius),
    )
        .prop_map(|(s, a, l, r)| Shape::Cylinder(Cylinder::new(s, s + l * a, r).unwrap()))
}

/// A parallelogram with its corner within `spread` of the origin and spans of length 0.05 to
/// `span`, not nearly parallel.
pub fn parallelogram_shape(spread: f64, span: f64) -> impl Strategy<Value = Shape> {
    (
        point_in(spread),
        unit_vector(),
        normal_vector(),
        log_uniform(0.05, span),
        log_uniform(0.05, span),
    )
        .prop_filter_map("parallel spans", |(c, a, b, la, lb)| {
            Parallelogram::new(c, la * a, lb * b)
                .ok()
                .filter(|_| a.cross(b).length() > 0.05)
        })
        .prop_map(Shape::Parallelogram)
}

/// The vertices and triangles of a small random mesh: a number in `vertices` of points within
/// `size` of a point within `spread` of the origin, and a number in `triangles` of random index
/// triples, of which only those spanning a triangle of some area (twice the area above 1e-2)
/// are kept, so there may be none.
pub fn mesh_parts(
    spread: f64,
    size: f64,
    vertices: Range<usize>,
    triangles: Range<usize>,
) -> impl Strategy<Value = (Vec<DVec3>, Vec<[u32; 3]>)> {
    (
        point_in(spread),
        prop::collection::vec(point_in(size), vertices),
    )
        .prop_flat_map(move |(offset, local)| {
            let n = local.len() as u32;
            let vertices: Vec<DVec3> = local.into_iter().map(|v| v + offset).collect();
            (
                Just(vertices),
                prop::collection::vec(prop::array::uniform3(0..n), triangles.clone()),
            )
        })
        .prop_map(|(vertices, raw)| {
            let triangles: Vec<[u32; 3]> = raw
                .into_iter()
                .filter(|t| {
                    let [a, b, c] = t.map(|i| vertices[i as usize]);
                    (b - a).cross(c - a).length() > 1e-2
                })
                .collect();
            (vertices, triangles)
        })
}
