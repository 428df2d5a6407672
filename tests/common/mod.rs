//! Random-input helpers shared by the property tests.
#![allow(dead_code)] // each test crate uses its own subset

use std::f64::consts::TAU;

use glam::DVec3;
use proptest::prelude::*;

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
