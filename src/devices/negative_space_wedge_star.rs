//! The negative-space-wedge star (Dr TIM's `EditableNegativeSpaceWedgeStar`; Courtial and
//! Georgantzis): N wedges about the star's axis, wedge i centred on the azimuth 2πi/N from
//! `direction_of_centre_of_wedge0`, each two sheets ([`Star`]) that rotate ray directions by
//! 180° about their normals (Dr TIM's `RayRotating` with angle π: "negative refraction", the
//! tangential direction reversed) at the azimuths ±ω/2 about its centre, with the wedge angle
//! ω = δ/(2N) for the deficit angle δ.
//!
//! A rotation by π about a unit normal n̂ is −(1 − 2n̂n̂ᵀ), minus the mirror in the sheet, so a
//! ray that crosses both sheets of a wedge leaves on the line it came on (as a set) mirrored in
//! one sheet's plane and then in the other's: turned by 2ω about the star's axis, position and
//! direction. Each wedge thereby cuts 2ω out of the space round the axis, and the star δ: a
//! ray that goes once round the axis through all wedges turns by 2π − δ, as on a cone whose
//! development lacks a sector of angle δ.

use glam::DVec3;
use serde::Deserialize;

use super::star::{MAX_SHEETS, Star, check_count, shown, subset};
use super::{Edges, LensDevice, Part};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector};
use crate::surfaces::Surface;
use crate::surfaces::metatoys::{RayRotating, RotationAxis};

#[derive(Debug, Clone, PartialEq)]
pub struct NegativeSpaceWedgeStar {
    /// δ, radians.
    pub deficit_angle: f64,
    /// N ≥ 1.
    pub number_of_negative_space_wedges: u32,
    pub centre: DVec3,
    /// Direction of the axis along which the wedges meet; non-zero.
    pub axis_direction: DVec3,
    /// Towards the centre of wedge 0 (off the axis), which sets the star's rotation about its
    /// axis.
    pub direction_of_centre_of_wedge0: DVec3,
    pub star_radius: f64,
    pub star_length: f64,
    pub sheet_transmission_coefficient: f64,
    /// `None` shows every wedge; `Some((start, n))` shows n wedges from index `start`
    /// (modulo N).
    pub shown_wedges: Option<(i64, u32)>,
}

impl LensDevice for NegativeSpaceWedgeStar {
    /// The sheets `wedge i sheet 1` and `wedge i sheet 2` (i from 1) and, with `edges`, the
    /// edges of the shown sheets (`top edge wedge i sheet j`, `outer edge …`, `bottom edge …`)
    /// and the common `axial edge`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let n = self.number_of_negative_space_wedges;
        check_count("number_of_negative_space_wedges", n, MAX_SHEETS / 2)?;
        let star = Star::new(
            self.centre,
            self.axis_direction,
            self.direction_of_centre_of_wedge0,
            self.star_radius,
            self.star_length,
        )
        .ok_or_else(|| {
            format!(
                "direction_of_centre_of_wedge0 = {} is along the star's axis_direction = {}",
                self.direction_of_centre_of_wedge0, self.axis_direction
            )
        })?;
        let surface = Surface::RayRotating(RayRotating {
            angle: std::f64::consts::PI,
            axis: RotationAxis::Normal,
            transmission_coefficient: self.sheet_transmission_coefficient,
            reflection_coefficient: 1.0,
        });
        let wedge_angle = self.deficit_angle / (2.0 * n as f64);
        let sheets = (0..n)
            .filter(|&i| shown(self.shown_wedges, i, n))
            .flat_map(|i| {
                let centre = std::f64::consts::TAU * i as f64 / n as f64;
                [(1, -0.5), (2, 0.5)].map(|(j, side)| {
                    (
                        centre + side * wedge_angle,
                        format!("wedge {} sheet {j}", i + 1),
                    )
                })
            });
        star.parts(sheets, edges, |phi, label| {
            Ok(vec![star.sheet(label.to_string(), phi, surface.clone())?])
        })
    }
}

/// `lenses = { type = "negative-space-wedge-star" }`: Dr TIM's
/// `EditableNegativeSpaceWedgeStar`, with the defaults of its constructor
/// `EditableNegativeSpaceWedgeStar(parent, studio)` for every key not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NegativeSpaceWedgeStarKeys {
    deficit_angle_deg: Option<Finite>,
    number_of_negative_space_wedges: Option<u32>,
    centre: Option<Vector>,
    axis_direction: Option<Direction>,
    direction_of_centre_of_wedge0: Option<Direction>,
    star_radius: Option<Positive>,
    star_length: Option<Positive>,
    sheet_transmission_coefficient: Option<Coefficient>,
    shown_negative_space_wedges_start_index: Option<i64>,
    number_of_shown_negative_space_wedges: Option<u32>,
}

impl NegativeSpaceWedgeStarKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let n = self.number_of_negative_space_wedges.unwrap_or(100);
        let deficit = self.deficit_angle_deg.map_or(340.0, |d| d.0);
        // A deficit of 360° cuts out all the space round the axis; beyond it the wedges
        // overlap.
        if !(deficit > 0.0 && deficit < 360.0) {
            return Err(format!(
                "deficit_angle_deg must be between 0 and 360, got {deficit}"
            ));
        }
        let shown_wedges = subset(
            self.shown_negative_space_wedges_start_index,
            self.number_of_shown_negative_space_wedges,
            n,
        );
        Ok(Box::new(NegativeSpaceWedgeStar {
            deficit_angle: deficit.to_radians(),
            number_of_negative_space_wedges: n,
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            axis_direction: self.axis_direction.map_or(DVec3::Y, |d| d.0),
            direction_of_centre_of_wedge0: self
                .direction_of_centre_of_wedge0
                .map_or(DVec3::X, |d| d.0),
            star_radius: self.star_radius.map_or(2.0, |r| r.0),
            star_length: self.star_length.map_or(1.0, |l| l.0),
            sheet_transmission_coefficient: crate::keys::throughput(
                self.sheet_transmission_coefficient,
            ),
            shown_wedges,
        }))
    }
}
