//! Tim's head, Dr TIM's test character: a skin-coloured head with a blue cap and visor, eyes
//! with irises and pupils, a nose, eyebrows, lips and ears. The parts' positions and sizes,
//! in units of the head's radius in the head's own basis (right, top, back), are Dr TIM's.

use glam::DVec3;
use serde::Deserialize;

use super::Part;
use crate::geometry::{Cylinder, Disc, GeometryError, Shape, Sphere, SphericalCap};
use crate::keys::{Direction, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::{Coloured, Surface};

/// Tim's head, facing `front_direction` with the top of the head towards `top_direction`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimHead {
    pub centre: DVec3,
    pub radius: f64,
    pub front_direction: DVec3,
    pub top_direction: DVec3,
}

/// The irises and pupils lie on spheres slightly larger than the eyeballs' (as Dr TIM's do), so
/// no two surfaces coincide.
const ABOVE: f64 = 1.001;

fn skin() -> Surface {
    Surface::Coloured(Coloured::shiny(Colour::new(
        239.0 / 256.0,
        208.0 / 256.0,
        207.0 / 256.0,
    )))
}

impl TimHead {
    pub fn parts(&self) -> Result<Vec<Part>, String> {
        self.build().map_err(|e| e.to_string())
    }

    fn build(&self) -> Result<Vec<Part>, GeometryError> {
        let direction = |what: &str, v: DVec3| {
            v.try_normalize().filter(|v| v.is_finite()).ok_or_else(|| {
                GeometryError::Degenerate(format!("the {what} must be a non-zero vector"))
            })
        };
        let top = direction("top direction", self.top_direction)?;
        let back = direction(
            "front direction's part perpendicular to the top direction",
            -self.front_direction.reject_from_normalized(top),
        )?;
        let right = top.cross(back);
        let r = self.radius;
        // A point given in head radii in the basis (right, top, back).
        let at = |x: f64, y: f64, z: f64| self.centre + r * (x * right + y * top + z * back);
        let front = -back;
        let blue_matt = || Surface::Coloured(Coloured::matt(Colour::new(0.0, 0.0, 1.0)));
        let part = |name: &str, shape: Shape, surface: Surface| Part {
            name: name.to_string(),
            shape,
            surface,
            edge: true,
        };
        let sphere = |c: DVec3, radius: f64| Sphere::new(c, radius).map(Shape::Sphere);
        let cylinder =
            |a: DVec3, b: DVec3, radius: f64| Cylinder::new(a, b, radius).map(Shape::Cylinder);
        // A cap on the sphere (c, ρ) round the direction `pole`, with rim radius `rim`.
        let cap = |c: DVec3, rho: f64, pole: DVec3, rim: f64| {
            let rho = ABOVE * rho;
            SphericalCap::new(c, c + rho * pole, (rim / rho).asin().to_degrees())
                .map(Shape::SphericalCap)
        };
        // Dr TIM's cap: on the sphere about the head's centre through this point (radius
        // 1.0101 r, just outside the head), with a rim of radius 0.9 r.
        let cap_centre = at(0.1694, 0.9608, 0.2614);
        let cap_angle = (0.9 * r / cap_centre.distance(self.centre)).asin();
        let mut parts = vec![
            part("head", sphere(self.centre, r)?, skin()),
            part(
                "cap",
                Shape::SphericalCap(SphericalCap::new(
                    self.centre,
                    cap_centre,
                    cap_angle.to_degrees(),
                )?),
                blue_matt(),
            ),
            part(
                "visor",
                Shape::Disc(Disc::new(
                    at(0.1736, 0.6333, -0.5468),
                    0.1677 * right + 0.9513 * top + 0.2588 * back,
                    0.7 * r,
                )?),
                blue_matt(),
            ),
            part("nose", sphere(at(0.0, 0.0, -1.0), 0.2 * r)?, skin()),
        ];
        for (side, x) in [("right", -1.0), ("left", 1.0)] {
            let eye = at(0.25 * x, 0.25, -0.9);
            let e = 0.15 * r;
            parts.extend([
                part(
                    &format!("{side} eye"),
                    sphere(eye, e)?,
                    Surface::Coloured(Coloured::shiny(Colour::ONE)),
                ),
                part(
                    &format!("{side} iris"),
                    cap(eye, e, front, 0.6 * e)?,
                    Surface::Coloured(Coloured::shiny(Colour::new(0.0, 0.0, 1.0))),
                ),
                part(
                    &format!("{side} pupil"),
                    cap(eye, ABOVE * e, front, 0.2 * e)?,
                    Surface::Coloured(Coloured::shiny(Colour::ZERO)),
                ),
                part(
                    &format!("{side} eyebrow"),
                    cylinder(
                        at(0.45 * x, 0.5, -0.85),
                        at(0.05 * x, 0.55, -0.9),
                        0.025 * r,
                    )?,
                    Surface::Coloured(Coloured::matt(Colour::ZERO)),
                ),
                part(
                    &format!("{side} ear"),
                    Shape::Disc(Disc::new(at(x, 0.0, 0.0), back, 0.2 * r)?),
                    skin(),
                ),
            ]);
        }
        for (name, y) in [("upper lip", -0.25), ("lower lip", -0.35)] {
            parts.push(part(
                name,
                cylinder(at(-0.33, y, -1.0), at(0.33, y, -1.0), 0.05 * r)?,
                Surface::Coloured(Coloured::shiny(Colour::new(1.0, 0.0, 0.0))),
            ));
        }
        Ok(parts)
    }
}

/// `aid = { type = "tim-head" }`: Dr TIM's `EditableTimHead(parent, studio)` where not given,
/// centred on (0, 0, 10), radius 1, looking along −z with its top along y.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimHeadKeys {
    centre: Option<Vector>,
    radius: Option<Positive>,
    front_direction: Option<Direction>,
    top_direction: Option<Direction>,
}

impl TimHeadKeys {
    pub fn build(self) -> Result<Vec<Part>, String> {
        TimHead {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            radius: self.radius.map_or(1.0, |r| r.0),
            front_direction: self.front_direction.map_or(DVec3::NEG_Z, |d| d.0),
            top_direction: self.top_direction.map_or(DVec3::Y, |d| d.0),
        }
        .parts()
        .map_err(|e| format!("tim-head: {e}"))
    }
}
