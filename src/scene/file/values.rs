//! Validating value types: every number is checked while serde reads it, so an error carries
//! the span of the offending value.

use serde::{Deserialize, Deserializer, de};

use glam::DVec3;

use crate::surfaces::Colour;

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
