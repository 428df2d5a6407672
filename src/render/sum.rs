//! Exact sums of a pixel's samples. Each sample's colour is added in fixed point (80 binary
//! places in an `i128`), so adding is associative: sums of sample subsets, of checkpointed and
//! resumed work, add up to exactly the sum of one uninterrupted render, bit for bit, in any
//! order. Colours at or above 2⁻²⁷ (all but the faintest) are represented exactly; a sum's range
//! is ±2⁴⁷ (about 1.4·10¹⁴), beyond which it saturates. A NaN sample counts as 0.

use crate::math::Colour;

/// Binary places of the fixed-point sums.
const FRACTION_BITS: u32 = 80;

/// 2^FRACTION_BITS, exactly.
const SCALE: f64 = (1u128 << FRACTION_BITS) as f64;

/// `c` in fixed point (truncated; saturating; NaN is 0). Scaling by a power of two is exact;
/// a value below 2¹²⁶ (after scaling) is split exactly into a multiple of 2⁶³ and a rest, each
/// converted with one instruction (an f64 → i128 conversion is a slow library call).
#[inline]
fn fixed(c: f64) -> i128 {
    const HALF: f64 = (1u64 << 63) as f64;
    let x = c * SCALE;
    if x.abs() >= HALF * HALF {
        return x as i128;
    }
    // Truncated by the conversion itself (`trunc()` would be a library call).
    let high = (x / HALF) as i64;
    let low = x - high as f64 * HALF;
    ((high as i128) << 63) + low as i64 as i128
}

/// `s` rounded to the nearest f64 (ties to even), as `s as f64` does, but without its slow
/// library call (inlined: the mean of every pixel of every band needs three). A magnitude of
/// 64 bits or fewer is converted as a `u64`. A larger one is cut to its top 64 bits, the bits
/// cut off folded into the lowest one (a "sticky" bit, so that the rounding still sees whether
/// anything was below); halved the same way to fit an `i64` (one conversion instruction), and
/// scaled back by a power of two (exact).
#[inline]
fn to_f64(s: i128) -> f64 {
    let m = s.unsigned_abs();
    let (high, low) = ((m >> 64) as u64, m as u64);
    let v = if high == 0 {
        low as f64
    } else {
        let zeros = high.leading_zeros();
        // (low >> 1 >> 63 - zeros: a shift by 64 when zeros = 0 would overflow.)
        let top = (high << zeros) | ((low >> 1) >> (63 - zeros));
        let top = top | ((low << zeros) != 0) as u64;
        let half = ((top >> 1) | (top & 1)) as i64 as f64;
        // 2^(65 - zeros) built from its bits (powi with a variable exponent is a library
        // call too).
        half * f64::from_bits((1023 + 65 - zeros as u64) << 52)
    };
    if s < 0 { -v } else { v }
}

/// The exact sum of some samples of one pixel, per RGB channel.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Sum(pub [i128; 3]);

impl Sum {
    /// Adds one sample's colour.
    pub fn add_colour(&mut self, colour: Colour) {
        for (s, c) in self.0.iter_mut().zip(colour.to_array()) {
            *s = s.saturating_add(fixed(c));
        }
    }

    /// Adds another sum (of other samples of the same pixel).
    pub fn add(&mut self, other: &Sum) {
        for (s, o) in self.0.iter_mut().zip(other.0) {
            *s = s.saturating_add(o);
        }
    }

    /// The mean of one sample `c`: exactly `Sum` of `c` alone, then [`Sum::mean`] of 1, but
    /// without either where that gives `c` back: where each channel is +0 (−0 comes back as
    /// +0) or a multiple of 2⁻⁸⁰ (|c| ≥ 2⁻²⁸ has no bits below 2⁻⁸⁰) below the range's end 2⁴⁷.
    pub fn mean_of_one(c: Colour) -> Colour {
        let exact =
            |x: f64| x.to_bits() == 0 || (x.abs() >= 2f64.powi(-28) && x.abs() < 2f64.powi(47));
        if c.to_array().into_iter().all(exact) {
            return c;
        }
        let mut sum = Sum::default();
        sum.add_colour(c);
        sum.mean(1)
    }

    /// The mean colour of `count` samples with this sum (black for none).
    pub fn mean(&self, count: u32) -> Colour {
        if count == 0 {
            return Colour::ZERO;
        }
        // Scaling by 2^-FRACTION_BITS is exact, so multiplying is dividing.
        let [r, g, b] = self.0;
        let unit = 1.0 / SCALE;
        let sum = Colour::new(to_f64(r) * unit, to_f64(g) * unit, to_f64(b) * unit);
        // One sample (the common case) needs no division.
        if count == 1 { sum } else { sum / count as f64 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_comes_back_exactly() {
        for c in [
            0.0,
            1.0,
            0.1,
            0.123_456_789_012_345_67,
            2.0f64.powi(-27),
            3.5e9,
        ] {
            let mut s = Sum::default();
            s.add_colour(Colour::splat(c));
            assert_eq!(s.mean(1), Colour::splat(c), "{c}");
        }
    }

    #[test]
    fn adding_is_associative_where_floating_point_is_not() {
        let samples = [0.1, 0.2, 0.3, 1e-9, 7.25, 1.0 / 3.0];
        // In f64 the grouping changes the result ...
        let (a, b, c) = (0.1f64, 0.2, 0.3);
        assert_ne!((a + b) + c, a + (b + c));
        // ... in fixed point it does not.
        let mut forward = Sum::default();
        for &v in &samples {
            forward.add_colour(Colour::splat(v));
        }
        let mut halves = [Sum::default(); 2];
        for (i, &v) in samples.iter().enumerate() {
            halves[i % 2].add_colour(Colour::splat(v));
        }
        let mut joined = halves[1];
        joined.add(&halves[0]);
        assert_eq!(forward, joined);
        let mean = forward.mean(samples.len() as u32).x;
        let exact = samples.iter().sum::<f64>() / samples.len() as f64;
        assert!((mean - exact).abs() < 1e-15, "{mean} {exact}");
    }

    #[test]
    fn the_fast_conversion_is_the_plain_one() {
        let values = [
            0.0,
            1.0,
            -1.0,
            0.3,
            -0.3,
            1e-30,
            2.0f64.powi(-17),
            7.5e13,
            -7.5e13,
            1e20,
        ];
        for c in values
            .into_iter()
            .chain((0..1000).map(|i| (i as f64 * 0.7361).sin() * 1e3))
        {
            assert_eq!(fixed(c), (c * SCALE) as i128, "{c}");
        }
    }

    #[test]
    fn the_fast_rounding_to_f64_is_the_plain_one() {
        let mut x = 0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c834_u128;
        let mut values = vec![0, 1, -1, i128::MAX, i128::MIN, 1 << 80, (1 << 80) + 1];
        // Ties and near-ties at the rounding position of a 64-bit-plus value.
        values.extend([(1i128 << 70) + (1 << 17), (1i128 << 70) + (1 << 17) + 1]);
        values.extend([(3i128 << 70) + (1 << 17), -(1i128 << 100) - (1 << 47)]);
        for _ in 0..10_000 {
            x = x
                .wrapping_mul(0x2360_ed05_1fc6_5da4_4385_df64_9fcc_f645)
                .wrapping_add(1);
            let shift = (x >> 120) as u32 % 127;
            values.push((x as i128) >> shift);
        }
        for v in values {
            assert_eq!(to_f64(v).to_bits(), (v as f64).to_bits(), "{v}");
        }
    }

    #[test]
    fn the_mean_of_one_sample_is_its_sum_s_mean() {
        let mut x = 0x2545_f491_4f6c_dd1d_u64;
        let mut values = vec![
            0.0,
            -0.0,
            1.0,
            2f64.powi(-28),
            2f64.powi(-28) * 1.5,
            2f64.powi(-29) * 1.5,
            2f64.powi(47),
            -2f64.powi(47),
            2f64.powi(47) * (1.0 - f64::EPSILON),
            1e-300,
            5e-324,
            f64::NAN,
            f64::INFINITY,
            -f64::INFINITY,
        ];
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Random bits: every exponent, sign and mantissa (NaNs included).
            values.push(f64::from_bits(x));
        }
        for c in values {
            let colour = Colour::new(c, 0.5, -c);
            let mut sum = Sum::default();
            sum.add_colour(colour);
            let (fast, plain) = (Sum::mean_of_one(colour), sum.mean(1));
            assert_eq!(
                fast.to_array().map(f64::to_bits),
                plain.to_array().map(f64::to_bits),
                "{c:e}"
            );
        }
    }

    #[test]
    fn extremes_saturate_and_nan_is_zero() {
        let mut s = Sum::default();
        s.add_colour(Colour::new(f64::NAN, f64::INFINITY, -f64::INFINITY));
        s.add_colour(Colour::new(0.0, 1.0, -1.0));
        assert_eq!(s.0, [0, i128::MAX, i128::MIN]);
        assert_eq!(Sum::default().mean(0), Colour::ZERO);
    }
}
