//! The ray-rotation-sheet star (Dr TIM's `EditableRayRotationSheetStar`): N ray-rotation
//! sheets ([`RayRotating`] about a fixed axis direction, Dr TIM's
//! `RayRotatingAboutArbitraryAxisDirection` in the global basis), each a rectangle with one side
//! on the star's axis, turned by 2π/N from one to the next ([`Star`]). Each sheet rotates a
//! ray's direction by `rotation_angle` about `rotation_axis_direction` (by default the star's
//! axis), oriented along the direction in which the ray crosses it. About the star's axis, a
//! ray that crosses the sheets round the axis in turn is turned by the angle at each, so with
//! N times the angle a whole turn, a ray in the plane across the axis closes a regular N-gon
//! (Dr TIM's "regular-polygon trajectory"): a curved-space simulation in which going round
//! the axis turns a direction by N times the angle.

use glam::DVec3;
use serde::Deserialize;

use super::star::{MAX_SHEETS, Star, check_count, shown, subset};
use super::{Edges, LensDevice, Part};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector};
use crate::surfaces::Surface;
use crate::surfaces::metatoys::{Basis, RayRotating, RotationAxis};

#[derive(Debug, Clone, PartialEq)]
pub struct RayRotationSheetStar {
    /// N ≥ 1.
    pub number_of_ray_rotation_sheets: u32,
    /// The rotation angle of each sheet, radians (Dr TIM's `rayRotationAngle`).
    pub rotation_angle: f64,
    /// The axis each sheet rotates ray directions about; non-zero.
    pub rotation_axis_direction: DVec3,
    pub centre: DVec3,
    /// Direction of the axis along which the sheets meet; non-zero.
    pub intersection_direction: DVec3,
    /// A point on sheet 1 (off the axis), which sets the star's rotation about its axis.
    pub point_on_ray_rotation_sheet1: DVec3,
    pub star_radius: f64,
    pub star_length: f64,
    pub ray_rotation_sheet_transmission_coefficient: f64,
    /// `None` shows every sheet; `Some((start, n))` shows n sheets from index `start`
    /// (modulo N).
    pub shown_sheets: Option<(i64, u32)>,
}

impl LensDevice for RayRotationSheetStar {
    /// The sheets `ray-rotation sheet 1` … `ray-rotation sheet N` and, with `edges`, the
    /// edges of the shown sheets (`top edge i`, `outer edge i`, `bottom edge i`) and the
    /// common `axial edge`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let n = self.number_of_ray_rotation_sheets;
        check_count("number_of_ray_rotation_sheets", n, MAX_SHEETS)?;
        let star = Star::new(
            self.centre,
            self.intersection_direction,
            self.point_on_ray_rotation_sheet1 - self.centre,
            self.star_radius,
            self.star_length,
        )
        .ok_or_else(|| {
            format!(
                "point_on_ray_rotation_sheet1 = {} lies on the star's axis (through centre = {} along {})",
                self.point_on_ray_rotation_sheet1, self.centre, self.intersection_direction
            )
        })?;
        let axis = self.rotation_axis_direction.normalize();
        let sheets = (0..n).filter(|&i| shown(self.shown_sheets, i, n)).map(|i| {
            (
                std::f64::consts::TAU * i as f64 / n as f64,
                (i + 1).to_string(),
            )
        });
        star.parts(sheets, edges, |phi, label| {
            // The axis in the sheet's own frame, so that it turns with the device's transform
            // (Dr TIM's global basis is the device's own).
            let surface = Surface::RayRotating(RayRotating {
                angle: self.rotation_angle,
                axis: RotationAxis::Direction(star.local(phi, axis), Basis::Local),
                transmission_coefficient: self.ray_rotation_sheet_transmission_coefficient,
                reflection_coefficient: 1.0,
            });
            Ok(vec![star.sheet(
                format!("ray-rotation sheet {label}"),
                phi,
                surface,
            )?])
        })
    }

    /// Dr TIM's sheets throw shadows (`RayRotatingAboutArbitraryAxisDirection(..., true)`).
    fn shadow_throwing(&self) -> bool {
        true
    }
}

/// `lenses = { type = "ray-rotation-sheet-star" }`: Dr TIM's `EditableRayRotationSheetStar`,
/// with the defaults of its constructor `EditableRayRotationSheetStar(parent, studio)` for every
/// key not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayRotationSheetStarKeys {
    number_of_ray_rotation_sheets: Option<u32>,
    rotation_angle_deg: Option<Finite>,
    rotation_axis_direction: Option<Direction>,
    centre: Option<Vector>,
    intersection_direction: Option<Direction>,
    point_on_ray_rotation_sheet1: Option<Vector>,
    star_radius: Option<Positive>,
    star_length: Option<Positive>,
    ray_rotation_sheet_transmission_coefficient: Option<Coefficient>,
    shown_ray_rotation_sheets_start_index: Option<i64>,
    number_of_shown_ray_rotation_sheets: Option<u32>,
}

impl RayRotationSheetStarKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let n = self.number_of_ray_rotation_sheets.unwrap_or(5);
        let shown_sheets = subset(
            self.shown_ray_rotation_sheets_start_index,
            self.number_of_shown_ray_rotation_sheets,
            n,
        );
        Ok(Box::new(RayRotationSheetStar {
            number_of_ray_rotation_sheets: n,
            // Dr TIM's default rotation angle is 1 (radian).
            rotation_angle: self.rotation_angle_deg.map_or(1.0, |a| a.0.to_radians()),
            rotation_axis_direction: self.rotation_axis_direction.map_or(DVec3::Y, |d| d.0),
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            intersection_direction: self.intersection_direction.map_or(DVec3::Y, |d| d.0),
            point_on_ray_rotation_sheet1: self
                .point_on_ray_rotation_sheet1
                .map_or(DVec3::new(1.0, 0.0, 10.0), |p| p.0),
            star_radius: self.star_radius.map_or(2.0, |r| r.0),
            star_length: self.star_length.map_or(1.0, |l| l.0),
            ray_rotation_sheet_transmission_coefficient: crate::keys::throughput(
                self.ray_rotation_sheet_transmission_coefficient,
            ),
            shown_sheets,
        }))
    }
}
