//! Validating value types: every number is checked while serde reads it, so an error carries
//! the span of the offending value.

use serde::{Deserialize, Deserializer, de};

use glam::{DMat3, DVec2, DVec3};

use crate::math::Colour;

/// Largest magnitude of any length or coordinate: far beyond any scene's scale, and small enough
/// that products of a few such numbers (cross products, squared lengths) stay finite.
pub(super) const MAX_MAGNITUDE: f64 = 1e15;

/// A finite number of magnitude at most [`MAX_MAGNITUDE`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Finite(pub f64);

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if x.abs() <= MAX_MAGNITUDE {
            Ok(Finite(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a finite number of magnitude at most {MAX_MAGNITUDE:e}, got {x}"
            )))
        }
    }
}

/// A positive number of at most [`MAX_MAGNITUDE`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Positive(pub f64);

impl<'de> Deserialize<'de> for Positive {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if x > 0.0 && x <= MAX_MAGNITUDE {
            Ok(Positive(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a positive number of at most {MAX_MAGNITUDE:e}, got {x}"
            )))
        }
    }
}

/// A fraction of light in [0, 1].
#[derive(Debug, Clone, Copy)]
pub(super) struct Coefficient(pub f64);

impl<'de> Deserialize<'de> for Coefficient {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if (0.0..=1.0).contains(&x) {
            Ok(Coefficient(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a coefficient between 0 and 1, got {x}"
            )))
        }
    }
}

/// Three finite numbers: a point, a vector or an RGB colour.
#[derive(Debug, Clone, Copy)]
pub(super) struct Vector(pub DVec3);

impl<'de> Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let [x, y, z] = <[Finite; 3]>::deserialize(d)?;
        Ok(Vector(DVec3::new(x.0, y.0, z.0)))
    }
}

/// A colour: three finite, non-negative numbers.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rgb(pub Colour);

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let c = Vector::deserialize(d)?.0;
        if c.min_element() < 0.0 {
            return Err(de::Error::custom(format!(
                "expected a colour with non-negative components, got {c}"
            )));
        }
        Ok(Rgb(c))
    }
}

/// A distance of a GGRIN lens's focal point from its centre, in units of the lens radius: at
/// least 1, or `inf` (TOML's infinity).
#[derive(Debug, Clone, Copy)]
pub(super) struct LensDistance(pub f64);

impl<'de> Deserialize<'de> for LensDistance {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if x >= 1.0 && (x <= MAX_MAGNITUDE || x == f64::INFINITY) {
            Ok(LensDistance(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a distance in units of the lens radius, at least 1 (the surface) or inf, got {x}"
            )))
        }
    }
}

/// A radius in units of the lens radius, in [0, 1).
#[derive(Debug, Clone, Copy)]
pub(super) struct InnerRadius(pub f64);

impl<'de> Deserialize<'de> for InnerRadius {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        if (0.0..1.0).contains(&x) {
            Ok(InnerRadius(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a radius in units of the lens radius, at least 0 and less than 1, got {x}"
            )))
        }
    }
}

/// Smallest magnitude of a [`NonZero`] number: far below any scene's scale, and large enough
/// that a scene's lengths divided by it stay finite.
pub(super) const MIN_MAGNITUDE: f64 = 1e-15;

/// A finite, non-zero number of magnitude at least [`MIN_MAGNITUDE`] (a focal length, a
/// focal-length ratio η: laws divide by it).
#[derive(Debug, Clone, Copy)]
pub(super) struct NonZero(pub f64);

impl<'de> Deserialize<'de> for NonZero {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = Finite::deserialize(d)?.0;
        if x.abs() >= MIN_MAGNITUDE {
            Ok(NonZero(x))
        } else if x == 0.0 {
            Err(de::Error::custom("expected a non-zero number, got 0"))
        } else {
            Err(de::Error::custom(format!(
                "expected a non-zero number of magnitude at least {MIN_MAGNITUDE:e}, got {x:e}"
            )))
        }
    }
}

/// A non-negative number of at most [`MAX_MAGNITUDE`].
#[derive(Debug, Clone, Copy)]
pub(super) struct NonNegative(pub f64);

impl<'de> Deserialize<'de> for NonNegative {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = Finite::deserialize(d)?.0;
        if x >= 0.0 {
            Ok(NonNegative(x))
        } else {
            Err(de::Error::custom(format!(
                "expected a non-negative number, got {x}"
            )))
        }
    }
}

/// Two finite numbers: surface coordinates or a tangential vector.
#[derive(Debug, Clone, Copy)]
pub(super) struct Vector2(pub DVec2);

impl<'de> Deserialize<'de> for Vector2 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let [x, y] = <[Finite; 2]>::deserialize(d)?;
        Ok(Vector2(DVec2::new(x.0, y.0)))
    }
}

/// A metric tensor (Eq 18): a symmetric, non-singular 3×3 matrix, given row by row.
#[derive(Debug, Clone, Copy)]
pub(super) struct MetricTensor(pub DMat3);

impl<'de> Deserialize<'de> for MetricTensor {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let rows = <[[Finite; 3]; 3]>::deserialize(d)?;
        let g = |i: usize, j: usize| rows[i][j].0;
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            if g(i, j) != g(j, i) {
                return Err(de::Error::custom(format!(
                    "a metric tensor must be symmetric, but g{}{} = {} and g{}{} = {}",
                    i + 1,
                    j + 1,
                    g(i, j),
                    j + 1,
                    i + 1,
                    g(j, i)
                )));
            }
        }
        let m = DMat3::from_cols_array_2d(&rows.map(|r| r.map(|x| x.0)));
        // Scaled to a largest element of 1 so that the test neither underflows nor overflows.
        let scale = m.to_cols_array().iter().fold(0.0f64, |s, x| s.max(x.abs()));
        if scale == 0.0 || (m * (1.0 / scale)).determinant().abs() <= 1e-12 {
            return Err(de::Error::custom(
                "the metric tensor is singular or ill-conditioned (determinant 0 relative to its largest element), so refraction into it is undefined (Eq 30: a = 0)",
            ));
        }
        Ok(MetricTensor(m))
    }
}

/// A direction: three finite numbers, not all zero, normalised (after scaling by the largest
/// component, so tiny but non-zero vectors keep their direction).
#[derive(Debug, Clone, Copy)]
pub(super) struct Direction(pub DVec3);

impl<'de> Deserialize<'de> for Direction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vector::deserialize(d)?.0;
        let largest = v.abs().max_element();
        if largest == 0.0 {
            return Err(de::Error::custom(
                "expected a direction, got the zero vector",
            ));
        }
        Ok(Direction((v / largest).normalize()))
    }
}
