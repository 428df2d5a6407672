//! A Ninky Nonk silhouette (Dr TIM's `EditableNinkyNonkSilhouette`, the test object of its
//! relativistic-photography programs): the black outline of a toy train of six carriages of
//! different heights on round wheels, in a rectangle of Dr TIM's aspect ratio 1027 : 300, the
//! rest of which is empty. Dr TIM cuts its silhouette out of a black parallelogram with a
//! picture; this one is drawn here from flat shapes (its own drawing, not Dr TIM's picture), so
//! its edges are exact at any distance.

use glam::DVec3;
use serde::Deserialize;

use super::Part;
use crate::geometry::{ConvexPolygon, Disc, Shape};
use crate::keys::{Direction, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::{Coloured, Surface};

/// Dr TIM's aspect ratio, width / height.
pub const ASPECT_RATIO: f64 = 1027.0 / 300.0;

/// The carriages: left and right in units of the width, top in units of the height (bottoms
/// at the wheels' axles).
const CARRIAGES: [(f64, f64, f64); 6] = [
    (0.02, 0.20, 0.65),
    (0.23, 0.37, 0.92),
    (0.40, 0.52, 0.51),
    (0.55, 0.74, 0.82),
    (0.77, 0.86, 0.62),
    (0.89, 0.98, 0.96),
];

/// The wheels' radius and the carriages' floor, in units of the width.
const WHEEL: f64 = 0.025;
const FLOOR: f64 = 0.03;

#[derive(Debug, Clone, PartialEq)]
pub struct NinkyNonkSilhouette {
    pub bottom_left_corner: DVec3,
    /// Along the silhouette's width and height (normalised here).
    pub right_direction: DVec3,
    pub up_direction: DVec3,
    pub width: f64,
}

impl NinkyNonkSilhouette {
    pub fn parts(&self) -> Result<Vec<Part>, String> {
        let (r, u) = (
            self.right_direction.normalize(),
            self.up_direction.normalize(),
        );
        let normal = r.cross(u);
        if normal.length() < 1e-9 {
            return Err("right_direction and up_direction must not be parallel".into());
        }
        let at = |x: f64, y: f64| self.bottom_left_corner + self.width * (x * r + y * u);
        let black = Surface::Coloured(Coloured::matt(Colour::ZERO));
        let part = |name: String, shape: Result<Shape, _>| -> Result<Part, String> {
            Ok(Part {
                name,
                shape: shape.map_err(|e: crate::geometry::GeometryError| e.to_string())?,
                surface: black.clone(),
                edge: true,
            })
        };
        let rectangle = |x0: f64, x1: f64, y0: f64, y1: f64| {
            ConvexPolygon::new(vec![at(x0, y0), at(x1, y0), at(x1, y1), at(x0, y1)])
                .map(Shape::ConvexPolygon)
        };
        let height = 1.0 / ASPECT_RATIO;
        let mut parts = Vec::new();
        for (k, &(left, right, top)) in CARRIAGES.iter().enumerate() {
            parts.push(part(
                format!("carriage {}", k + 1),
                rectangle(left, right, FLOOR, top * height),
            )?);
            for (side, x) in [("left", left + 1.5 * WHEEL), ("right", right - 1.5 * WHEEL)] {
                let wheel = Disc::new(at(x, WHEEL), normal, WHEEL * self.width);
                parts.push(part(
                    format!("carriage {} {side} wheel", k + 1),
                    wheel.map(Shape::Disc),
                )?);
            }
            if let Some(&(next, _, _)) = CARRIAGES.get(k + 1) {
                parts.push(part(
                    format!("coupling {}", k + 1),
                    rectangle(right, next, 0.05, 0.07),
                )?);
            }
        }
        // The engine's funnel and the cab's roof.
        let engine = CARRIAGES[0].2 * height;
        parts.push(part(
            "funnel".into(),
            rectangle(0.05, 0.08, engine, 0.86 * height),
        )?);
        parts.push(part(
            "cab roof".into(),
            rectangle(0.12, 0.21, engine, engine + 0.07 * height),
        )?);
        Ok(parts)
    }
}

/// `aid = { type = "ninky-nonk-silhouette" }`: Dr TIM's `EditableNinkyNonkSilhouette(parent,
/// studio)`'s defaults: bottom-left corner (50, 0, 1000), right (1, 0, 0), up (0, 1, 0),
/// width 100.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NinkyNonkSilhouetteKeys {
    bottom_left_corner: Option<Vector>,
    right_direction: Option<Direction>,
    up_direction: Option<Direction>,
    width: Option<Positive>,
}

impl NinkyNonkSilhouetteKeys {
    pub fn build(self) -> Result<Vec<Part>, String> {
        NinkyNonkSilhouette {
            bottom_left_corner: self
                .bottom_left_corner
                .map_or(DVec3::new(50.0, 0.0, 1000.0), |c| c.0),
            right_direction: self.right_direction.map_or(DVec3::X, |d| d.0),
            up_direction: self.up_direction.map_or(DVec3::Y, |d| d.0),
            width: self.width.map_or(100.0, |w| w.0),
        }
        .parts()
        .map_err(|e| format!("ninky-nonk-silhouette: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dr TIM's default silhouette fills its 100 × 29.2 rectangle at z = 1000 from its bottom
    /// (the wheels stand on it) to near its top and across nearly its whole width, and nothing
    /// of it lies outside.
    #[test]
    fn the_default_silhouette_fills_dr_tims_rectangle() {
        let keys: NinkyNonkSilhouetteKeys = toml::from_str("").unwrap();
        let parts = keys.build().unwrap();
        let (lo, hi) = parts.iter().map(|p| p.shape.bounds().unwrap()).fold(
            (DVec3::INFINITY, DVec3::NEG_INFINITY),
            |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
        );
        let height = 100.0 / ASPECT_RATIO;
        assert!(
            lo.x >= 50.0 && hi.x <= 150.0 && lo.y >= -1e-9 && hi.y <= height,
            "{lo} {hi}"
        );
        assert!(lo.y.abs() < 1e-9 && hi.y > 0.9 * height, "{lo} {hi}");
        assert!(hi.x - lo.x > 0.95 * 100.0, "{lo} {hi}");
        assert!((lo.z - 1000.0).abs() < 1e-9 && (hi.z - 1000.0).abs() < 1e-9);
        assert!(
            parts
                .iter()
                .all(|p| p.surface == Surface::Coloured(Coloured::matt(Colour::ZERO)))
        );
    }

    #[test]
    fn parallel_directions_are_refused() {
        let keys: NinkyNonkSilhouetteKeys =
            toml::from_str("right_direction = [1, 0, 0]\nup_direction = [2, 0, 0]").unwrap();
        assert!(keys.build().unwrap_err().contains("must not be parallel"));
    }
}
