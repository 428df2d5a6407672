//! Deterministic random numbers: each (seed, pixel, sample) has its own random stream, so an
//! image does not depend on the order in which pixels are rendered or the number of threads;
//! surface laws with random errors key theirs by the ray.

/// SplitMix64's finaliser: a bijective 64-bit mix with good avalanche.
pub fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Uniform number in [0, 1) for dimension `dim` of sample `sample` of pixel (x, y).
pub fn uniform(seed: u64, x: u32, y: u32, sample: u32, dim: u32) -> f64 {
    let key = [
        ((x as u64) << 32) | y as u64,
        ((sample as u64) << 32) | dim as u64,
    ];
    unit(seed, &key)
}

/// Uniform number in [0, 1) for dimension `dim` determined by `key` alone: reproducible noise
/// for surface laws with random errors, keyed by the ray.
pub fn uniform_keyed(key: &[u64], dim: u32) -> f64 {
    unit(dim as u64, key)
}

/// The key of a ray's random choices at a surface: the bits of its hit point and direction,
/// which differ from sample to sample (each has its own pixel position and pupil point).
pub fn ray_key(p: glam::DVec3, d: glam::DVec3) -> [u64; 6] {
    [p.x, p.y, p.z, d.x, d.y, d.z].map(f64::to_bits)
}

/// `seed` and `key` hashed to [0, 1).
fn unit(seed: u64, key: &[u64]) -> f64 {
    let h = key
        .iter()
        .fold(mix(seed ^ 0x9e37_79b9_7f4a_7c15), |h, &k| mix(h ^ mix(k)));
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_uniform_and_distinct() {
        let n = 100_000;
        let mean: f64 = (0..n).map(|s| uniform(7, 3, 4, s, 0)).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.005, "{mean}");
        assert_ne!(uniform(7, 3, 4, 0, 0), uniform(7, 4, 3, 0, 0));
        assert_ne!(uniform(7, 3, 4, 0, 0), uniform(8, 3, 4, 0, 0));
        assert_eq!(uniform(7, 3, 4, 9, 1), uniform(7, 3, 4, 9, 1));
    }
}
