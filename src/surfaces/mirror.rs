//! Mirror: specular reflection, r = d − 2 (d·n) n, scaled by a reflection coefficient.

use glam::DVec3;
use serde::Deserialize;

use super::{Redirection, Surface};
use crate::geometry::Interaction;
use crate::keys::{Coefficient, coefficient};

#[derive(Debug, Clone, PartialEq)]
pub struct Mirror {
    /// Fraction of the light that is reflected, in [0, 1].
    pub reflection_coefficient: f64,
}

/// Mirror image of direction `d` in a surface with unit normal `n` (either orientation).
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

impl Mirror {
    pub fn redirect(&self, at: &Interaction) -> Redirection<'static> {
        Redirection::Leaves {
            direction: reflect(at.ray.direction, at.normal()),
            factor: self.reflection_coefficient,
        }
    }
}

/// `type = "mirror"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MirrorKeys {
    #[serde(alias = "reflection")]
    reflection_coefficient: Option<Coefficient>,
}

impl MirrorKeys {
    pub fn build(self) -> Result<Surface, String> {
        Ok(Surface::Mirror(Mirror {
            reflection_coefficient: coefficient(self.reflection_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_of_incidence_equals_angle_of_reflection() {
        let n = DVec3::Y;
        let d = DVec3::new(1.0, -1.0, 0.0).normalize();
        let r = reflect(d, n);
        assert!((r - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-15);
        // The same for the opposite normal orientation, and reflecting twice restores d.
        assert!((reflect(d, -n) - r).length() < 1e-15);
        assert!((reflect(r, n) - d).length() < 1e-15);
    }

    #[test]
    fn normal_incidence_reverses_the_ray() {
        let n = DVec3::new(1.0, 2.0, 2.0) / 3.0;
        assert!((reflect(-n, n) - n).length() < 1e-15);
    }
}
