//! What scene-file keys take: validated values, each checked while serde reads it (so that an
//! error carries the span of the offending value), and `kinds!`, the tables with a `type` key
//! whose kinds (laws, shapes, devices) each read their own keys.
//!
//! Each kind's keys are a `#[derive(Deserialize)]` struct beside the type they make, in the
//! type's own file (`SphereKeys` in `geometry/sphere.rs`), with its aliases, units and defaults,
//! and a `build` that checks what no single value can (a direction parallel to another) and
//! makes the type.

use std::fmt;
use std::marker::PhantomData;

use glam::{DMat3, DVec2, DVec3};
use serde::{Deserialize, Deserializer, de};

/// Largest magnitude of any length or coordinate: far beyond any scene's scale, and small enough
/// that products of a few such numbers (cross products, squared lengths) stay finite.
pub const MAX_MAGNITUDE: f64 = 1e15;

/// Smallest magnitude of a [`NonZero`] number: far below any scene's scale, and large enough
/// that a scene's lengths divided by it stay finite.
pub const MIN_MAGNITUDE: f64 = 1e-15;

/// A number read by serde and accepted by `ok`, or the error "expected `expected`, got x".
pub fn checked<'de, D: Deserializer<'de>>(
    d: D,
    ok: impl Fn(f64) -> bool,
    expected: &str,
) -> Result<f64, D::Error> {
    let x = f64::deserialize(d)?;
    if ok(x) {
        Ok(x)
    } else {
        Err(de::Error::custom(format!("expected {expected}, got {x}")))
    }
}

/// A newtype of f64 read through [`checked`].
macro_rules! number {
    ($(#[$doc:meta])* $name:ident, $ok:expr, $expected:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy)]
        pub struct $name(pub f64);

        impl<'de> serde::Deserialize<'de> for $name {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                $crate::keys::checked(d, $ok, &$expected).map($name)
            }
        }
    };
}
pub(crate) use number;

number!(
    /// A finite number of magnitude at most [`MAX_MAGNITUDE`].
    Finite,
    |x: f64| x.abs() <= MAX_MAGNITUDE,
    format!("a finite number of magnitude at most {MAX_MAGNITUDE:e}")
);

number!(
    /// A positive number of at most [`MAX_MAGNITUDE`].
    Positive,
    |x: f64| x > 0.0 && x <= MAX_MAGNITUDE,
    format!("a positive number of at most {MAX_MAGNITUDE:e}")
);

number!(
    /// A non-negative number of at most [`MAX_MAGNITUDE`].
    NonNegative,
    |x: f64| (0.0..=MAX_MAGNITUDE).contains(&x),
    format!("a number from 0 to {MAX_MAGNITUDE:e}")
);

number!(
    /// A fraction of light in [0, 1].
    Coefficient,
    |x: f64| (0.0..=1.0).contains(&x),
    "a coefficient between 0 and 1"
);

/// A coefficient as a law's keys give it: 1 (all the light) when not given. The reflection of
/// the METATOYs' total internal reflection is lossless unless told otherwise, as in Dr TIM.
pub fn coefficient(c: Option<Coefficient>) -> f64 {
    c.map_or(1.0, |c| c.0)
}

/// Dr TIM's `SurfacePropertyPrimitive.DEFAULT_TRANSMISSION_COEFFICIENT`: the fraction of the
/// light that its surfaces and devices pass on (transmit, or for mirrors reflect) unless told
/// otherwise.
pub const DEFAULT_TRANSMISSION_COEFFICIENT: f64 = 0.96;

/// The fraction of the light a surface or a device's lens passes on, as its keys give it:
/// [`DEFAULT_TRANSMISSION_COEFFICIENT`] when not given.
pub fn throughput(c: Option<Coefficient>) -> f64 {
    c.map_or(DEFAULT_TRANSMISSION_COEFFICIENT, |c| c.0)
}

/// A finite, non-zero number of magnitude at least [`MIN_MAGNITUDE`] (a focal length, a
/// focal-length ratio η: laws divide by it).
#[derive(Debug, Clone, Copy)]
pub struct NonZero(pub f64);

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

/// Exactly `N` values: an array of fixed length. (`[T; N]` read from TOML drops the
/// elements after the `N`th without a word; this refuses them.)
#[derive(Debug, Clone, Copy)]
pub struct Array<T, const N: usize>(pub [T; N]);

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Array<T, N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Exactly<T, const N: usize>(PhantomData<T>);

        impl<'de, T: Deserialize<'de>, const N: usize> de::Visitor<'de> for Exactly<T, N> {
            type Value = [T; N];

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "an array of {N} values")
            }

            fn visit_seq<A: de::SeqAccess<'de>>(self, mut seq: A) -> Result<[T; N], A::Error> {
                let mut values = Vec::with_capacity(N);
                while values.len() < N {
                    match seq.next_element()? {
                        Some(value) => values.push(value),
                        None => break,
                    }
                }
                let mut given = values.len();
                while seq.next_element::<de::IgnoredAny>()?.is_some() {
                    given += 1;
                }
                match values.try_into() {
                    Ok(values) if given == N => Ok(values),
                    _ => Err(de::Error::custom(format!(
                        "expected an array of {N} values, got {given} value{}",
                        if given == 1 { "" } else { "s" }
                    ))),
                }
            }
        }

        d.deserialize_seq(Exactly(PhantomData)).map(Array)
    }
}

/// Three finite numbers: a point, a vector or an RGB colour.
#[derive(Debug, Clone, Copy)]
pub struct Vector(pub DVec3);

impl<'de> Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let [x, y, z] = Array::<Finite, 3>::deserialize(d)?.0;
        Ok(Vector(DVec3::new(x.0, y.0, z.0)))
    }
}

/// Two finite numbers: surface coordinates or a tangential vector.
#[derive(Debug, Clone, Copy)]
pub struct Vector2(pub DVec2);

impl<'de> Deserialize<'de> for Vector2 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let [x, y] = Array::<Finite, 2>::deserialize(d)?.0;
        Ok(Vector2(DVec2::new(x.0, y.0)))
    }
}

/// A direction: three finite numbers, not all zero, normalised (after scaling by the largest
/// component, so tiny but non-zero vectors keep their direction).
#[derive(Debug, Clone, Copy)]
pub struct Direction(pub DVec3);

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

/// A colour: three finite, non-negative numbers (red, green, blue).
#[derive(Debug, Clone, Copy)]
pub struct Rgb(pub DVec3);

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

/// A 3×3 matrix of finite numbers, given row by row.
#[derive(Debug, Clone, Copy)]
pub struct Matrix(pub DMat3);

impl<'de> Deserialize<'de> for Matrix {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let rows = Array::<Array<Finite, 3>, 3>::deserialize(d)?.0;
        Ok(Matrix(
            DMat3::from_cols_array_2d(&rows.map(|r| r.0.map(|x| x.0))).transpose(),
        ))
    }
}

/// A table with a `type` key naming one of several kinds, each read by its own keys struct
/// (`#[serde(deny_unknown_fields)]`, in the kind's own file, with a `build(self)` that makes
/// the kind): the enum of the kinds, one line each, its `build`, which hands the table to the
/// kind's keys, and `kind`, the name the table's `type` gives. The names are the variants' in
/// kebab case; attributes on a variant give aliases.
macro_rules! kinds {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident -> $built:ty {
            $($(#[$variant_meta:meta])* $variant:ident($keys:ty),)*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, serde::Deserialize)]
        #[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
        $vis enum $name {
            $($(#[$variant_meta])* $variant($keys),)*
        }

        impl $name {
            /// What the table describes, made by its kind's keys.
            $vis fn build(self) -> $built {
                match self {
                    $($name::$variant(keys) => keys.build(),)*
                }
            }

            /// The kind's name, as `type` gives it.
            $vis fn kind(&self) -> String {
                match self {
                    $($name::$variant(_) => $crate::keys::kebab_case(stringify!($variant)),)*
                }
            }
        }
    };
}
pub(crate) use kinds;

/// `LensStar` as `lens-star`: a kind's name from its variant's.
pub fn kebab_case(camel: &str) -> String {
    let mut name = String::new();
    for (i, c) in camel.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            name.push('-');
        }
        name.extend(c.to_lowercase());
    }
    name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_named_in_kebab_case() {
        assert_eq!(kebab_case("LensStar"), "lens-star");
        assert_eq!(kebab_case("Sphere"), "sphere");
        assert_eq!(
            kebab_case("IdealThinCylindricalLens"),
            "ideal-thin-cylindrical-lens"
        );
    }

    #[test]
    fn values_out_of_range_are_refused_with_what_was_expected() {
        let read = |text: &str| toml::from_str::<toml::Table>(&format!("x = {text}")).unwrap();
        let positive = |text: &str| {
            read(text)["x"]
                .clone()
                .try_into::<Positive>()
                .map(|p| p.0)
                .map_err(|e| e.to_string())
        };
        assert_eq!(positive("2.5"), Ok(2.5));
        let e = positive("-1").unwrap_err();
        assert!(
            e.contains("expected a positive number of at most 1e15, got -1"),
            "{e}"
        );
        assert!(positive("1e16").is_err() && positive("nan").is_err());
        let direction = |text: &str| read(text)["x"].clone().try_into::<Direction>();
        let d = direction("[0, 3, 4]").unwrap().0;
        assert!((d - DVec3::new(0.0, 0.6, 0.8)).length() < 1e-15);
        // A tiny vector keeps its direction (scaled before it is normalised).
        let d = direction("[1e-200, 0, 1e-200]").unwrap().0;
        assert!((d - DVec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-15);
        assert!(direction("[0, 0, 0]").is_err());
    }
}
