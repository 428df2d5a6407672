//! Light-ray fields (Dr TIM's `LightRayField` and its `LightRayFieldCollimated`,
//! `LightRayFieldRepresentingPointLightSource`, `LightRayFieldRepresentingPhaseFront` and
//! `LightRayFieldRepresentingParaxialOpticalVortex`): a transparent surface that shows, at each
//! point, light travelling in one direction f̂ there. A ray passes undeviated and gains the
//! field's colour times cos²(π θ / w) where the angle θ between f̂ and the direction light
//! travels along the ray (the reverse of the traced ray) is below half the angular fuzziness
//! w, nothing elsewhere; a bidirectional field also shows light travelling along −f̂.
//!
//! The fields' directions at a point P:
//! - `collimated`: the given direction;
//! - `point-source`: away from the source S, (P − S)/|P − S|, or towards it;
//! - `phase-front`: the surface's outward normal (the surface is the phase front);
//! - `optical-vortex`: the phase gradient of a paraxial vortex of charge m about a line
//!   through A along l̂, m φ + k z: f̂ ∝ (m/k) φ̂ / r + l̂, r the distance from the line and φ̂ the
//!   azimuthal direction, right-handed about l̂.

use glam::DVec3;
use serde::Deserialize;

use crate::geometry::{Interaction, Transform};
use crate::keys::{Direction, Finite, Positive, Rgb, Vector};
use crate::math::Colour;
use crate::surfaces::{Redirection, Surface};

/// Which field, with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Field {
    Collimated {
        direction: DVec3,
    },
    PointSource {
        position: DVec3,
        towards: bool,
    },
    PhaseFront,
    OpticalVortex {
        point: DVec3,
        direction: DVec3,
        m_over_k: f64,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub struct LightRayField {
    pub field: Field,
    pub colour: Colour,
    /// The angular fuzziness w, in radians.
    pub angular_fuzziness: f64,
    pub bidirectional: bool,
}

impl Field {
    /// The unit direction of the field's light at `p`, where the outward normal is `n`; not
    /// finite on a vortex's line or at a point source.
    pub fn direction(&self, p: DVec3, n: DVec3) -> DVec3 {
        match *self {
            Field::Collimated { direction } => direction,
            Field::PointSource { position, towards } => {
                (p - position).normalize() * if towards { -1.0 } else { 1.0 }
            }
            Field::PhaseFront => n,
            Field::OpticalVortex {
                point,
                direction,
                m_over_k,
            } => {
                let r = (p - point).reject_from_normalized(direction);
                let azimuthal = direction.cross(r) / r.length_squared();
                (m_over_k * azimuthal + direction).normalize()
            }
        }
    }
}

impl LightRayField {
    /// The fraction of the field's colour seen along light travelling in unit direction `l`
    /// where the field's direction is `f`.
    pub fn weight(&self, f: DVec3, l: DVec3) -> f64 {
        let cos = f.dot(l);
        let cos = if self.bidirectional { cos.abs() } else { cos };
        let ratio = cos.clamp(-1.0, 1.0).acos() / self.angular_fuzziness;
        if ratio.is_finite() && ratio <= 0.5 {
            (std::f64::consts::PI * ratio).cos().powi(2)
        } else {
            0.0
        }
    }

    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        let f = self.field.direction(at.local_point(), at.normal());
        let weight = if f.is_finite() {
            self.weight(f, -at.ray.direction.normalize())
        } else {
            0.0
        };
        Redirection::Glows {
            glow: self.colour * weight,
            factor: Colour::ONE,
        }
    }

    /// The field of an object placed by `t`: its points and directions move with it. A
    /// vortex's m/k is a length (its tilt is (m/k)/r), scaled with the object, and its sense
    /// turns in a mirror; so a vortex needs a rotation, uniform scaling and translation (or
    /// their mirror images).
    pub fn transformed(&self, t: &Transform) -> Result<LightRayField, String> {
        let direction = |d: DVec3| t.vector(d).normalize();
        let field = match self.field {
            Field::Collimated { direction: d } => Field::Collimated {
                direction: direction(d),
            },
            Field::PointSource { position, towards } => Field::PointSource {
                position: t.point(position),
                towards,
            },
            Field::PhaseFront => Field::PhaseFront,
            Field::OpticalVortex {
                point,
                direction: d,
                m_over_k,
            } => {
                let scale = t.uniform_scale().ok_or(
                    "an optical vortex's m/k is a length, defined only under rotations, \
                     uniform scaling and translations, so it cannot be scaled non-uniformly",
                )?;
                let handedness = if t.reflects() { -1.0 } else { 1.0 };
                Field::OpticalVortex {
                    point: t.point(point),
                    direction: direction(d),
                    m_over_k: m_over_k * scale * handedness,
                }
            }
        };
        Ok(LightRayField {
            field,
            ..self.clone()
        })
    }
}

/// The `field` table.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum FieldKeys {
    Collimated {
        direction: Direction,
    },
    PointSource {
        position: Vector,
        towards: Option<bool>,
    },
    PhaseFront {},
    OpticalVortex {
        point: Option<Vector>,
        direction: Option<Direction>,
        m_over_k: Option<Finite>,
    },
}

/// `type = "light-ray-field"`: `field` (table, default `{ type = "phase-front" }`, the one in
/// Dr TIM's GUI), `colour` (red), `angular_fuzziness_deg` (1) and `bidirectional` (false), Dr
/// TIM's GUI's; a vortex's `point` ([0, 0, 0]), `direction` ([0, 0, 1]) and `m_over_k` (0), its
/// constructor's.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightRayFieldKeys {
    field: Option<FieldKeys>,
    colour: Option<Rgb>,
    angular_fuzziness_deg: Option<Positive>,
    bidirectional: Option<bool>,
}

impl LightRayFieldKeys {
    pub fn build(self) -> Result<Surface, String> {
        let field = match self.field.unwrap_or(FieldKeys::PhaseFront {}) {
            FieldKeys::Collimated { direction } => Field::Collimated {
                direction: direction.0.normalize(),
            },
            FieldKeys::PointSource { position, towards } => Field::PointSource {
                position: position.0,
                towards: towards.unwrap_or(false),
            },
            FieldKeys::PhaseFront {} => Field::PhaseFront,
            FieldKeys::OpticalVortex {
                point,
                direction,
                m_over_k,
            } => Field::OpticalVortex {
                point: point.map_or(DVec3::ZERO, |p| p.0),
                direction: direction.map_or(DVec3::Z, |d| d.0.normalize()),
                m_over_k: m_over_k.map_or(0.0, |m| m.0),
            },
        };
        Ok(Surface::LightRayField(LightRayField {
            field,
            colour: self.colour.map_or(Colour::new(1.0, 0.0, 0.0), |c| c.0),
            angular_fuzziness: self.angular_fuzziness_deg.map_or(1.0, |w| w.0).to_radians(),
            bidirectional: self.bidirectional.unwrap_or(false),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(field: Field, bidirectional: bool) -> LightRayField {
        LightRayField {
            field,
            colour: Colour::ONE,
            angular_fuzziness: 10f64.to_radians(),
            bidirectional,
        }
    }

    /// cos²(π θ / w): 1 along the field, ½ at θ = w/4, 0 from w/2 on.
    #[test]
    fn the_weight_falls_as_cos_squared_to_half_the_fuzziness() {
        let f = field(Field::PhaseFront, false);
        let at = |deg: f64| {
            let a = deg.to_radians();
            f.weight(DVec3::Z, DVec3::new(a.sin(), 0.0, a.cos()))
        };
        assert!((at(0.0) - 1.0).abs() < 1e-15);
        assert!((at(2.5) - 0.5).abs() < 1e-12);
        assert_eq!((at(5.0001), at(90.0), at(180.0)), (0.0, 0.0, 0.0));
        let both = field(Field::PhaseFront, true);
        assert!((both.weight(DVec3::Z, -DVec3::Z) - 1.0).abs() < 1e-15);
    }

    /// A vortex of m/k = 0.5 about the z axis: at (2, 0, 0) the field tilts by m/(k r) = 0.25
    /// towards +y (φ̂ there), right-handed about +z; on the line it has no direction.
    #[test]
    fn an_optical_vortex_turns_about_its_line() {
        let vortex = Field::OpticalVortex {
            point: DVec3::new(0.0, 0.0, 3.0),
            direction: DVec3::Z,
            m_over_k: 0.5,
        };
        let d = vortex.direction(DVec3::new(2.0, 0.0, -1.0), DVec3::Z);
        assert!((d - DVec3::new(0.0, 0.25, 1.0).normalize()).length() < 1e-15);
        let d = vortex.direction(DVec3::new(0.0, -1.0, 0.0), DVec3::Z);
        assert!((d - DVec3::new(0.5, 0.0, 1.0).normalize()).length() < 1e-15);
        assert!(
            !vortex
                .direction(DVec3::new(0.0, 0.0, 1.0), DVec3::Z)
                .is_finite()
        );
    }
}
