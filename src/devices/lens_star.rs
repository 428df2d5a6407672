//! The lens star (Dr TIM's `EditableLensStar`): N ideal thin lenses of focal length f, each a
//! rectangle with one side on the star's axis (through `centre`, along
//! `intersection_direction`) and the opposite side on the cylinder of radius `star_radius`
//! about it, turned by 2π/N from one to the next. Lens i lies in the half-plane of the radial
//! direction r̂ᵢ = cos φᵢ û + sin φᵢ v̂ (φᵢ = 2πi/N, û towards `point_on_lens1`), its principal
//! point at `centre` + `principal_point_distance` r̂ᵢ and its optical axis the tangential
//! direction −sin φᵢ û + cos φᵢ v̂.
//!
//! With the principal points on the axis (`principal_point_distance` = 0), the lenses of a full
//! loop image every point to itself (each lens's map fixes the axis; see `tests/devices.rs`),
//! so every ray that goes once round the star closes on itself; the regular-polygon
//! trajectory's inscribed circle has radius 2f sin(π/N).

use glam::DVec3;
use serde::Deserialize;

use super::star::{MAX_SHEETS, Star, check_count, shown, subset};
use super::{Edges, LensDevice, LensType, Part};
use crate::keys::{Coefficient, Direction, Finite, NonZero, Positive, Vector};
use crate::surfaces::ThinLens;

#[derive(Debug, Clone, PartialEq)]
pub struct LensStar {
    /// N ≥ 1.
    pub number_of_lenses: u32,
    /// f of every lens; non-zero.
    pub focal_length: f64,
    /// Distance of each lens's principal point from the axis.
    pub principal_point_distance: f64,
    pub centre: DVec3,
    /// Direction of the axis along which the lenses meet; non-zero.
    pub intersection_direction: DVec3,
    /// A point on lens 1 (off the axis), which sets the star's rotation about its axis.
    pub point_on_lens1: DVec3,
    pub star_radius: f64,
    pub star_length: f64,
    pub lens_transmission_coefficient: f64,
    /// What each lens is (Dr TIM's `thinLensType`).
    pub thin_lens_type: LensType,
    /// `None` shows every lens; `Some((start, n))` shows n lenses from index `start`
    /// (modulo N; Dr TIM's `shownLensesStartIndex` and `numberOfShownLenses`).
    pub shown_lenses: Option<(i64, u32)>,
}

impl LensDevice for LensStar {
    /// The lenses `lens 1` … `lens N` and, with `edges`, the edges of the shown lenses
    /// (`top edge i`, `outer edge i`, `bottom edge i`) and the common `axial edge`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let n = self.number_of_lenses;
        check_count("number_of_lenses", n, MAX_SHEETS)?;
        let star = Star::new(
            self.centre,
            self.intersection_direction,
            self.point_on_lens1 - self.centre,
            self.star_radius,
            self.star_length,
        )
        .ok_or_else(|| {
            format!(
                "point_on_lens1 = {} lies on the star's axis (through centre = {} along {})",
                self.point_on_lens1, self.centre, self.intersection_direction
            )
        })?;
        let sheets = (0..n).filter(|&i| shown(self.shown_lenses, i, n)).map(|i| {
            (
                std::f64::consts::TAU * i as f64 / n as f64,
                (i + 1).to_string(),
            )
        });
        star.parts(sheets, edges, |phi, label| {
            let lens = ThinLens {
                principal_point: self.centre + self.principal_point_distance * star.radial(phi),
                optical_axis: star.tangential(phi),
                focal_length: self.focal_length,
                gradient: None,
                transmission_coefficient: self.lens_transmission_coefficient,
            };
            let part = self
                .thin_lens_type
                .part(format!("lens {label}"), star.face(phi), lens)?;
            Ok(part.into_iter().collect())
        })
    }
}

/// `lenses = { type = "lens-star" }`: Dr TIM's `EditableLensStar`, with the defaults of its
/// constructor `EditableLensStar(parent, studio)` for every key not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LensStarKeys {
    number_of_lenses: Option<u32>,
    focal_length: Option<NonZero>,
    principal_point_distance: Option<Finite>,
    centre: Option<Vector>,
    intersection_direction: Option<Direction>,
    point_on_lens1: Option<Vector>,
    star_radius: Option<Positive>,
    star_length: Option<Positive>,
    lens_transmission_coefficient: Option<Coefficient>,
    thin_lens_type: Option<LensType>,
    shown_lenses_start_index: Option<i64>,
    number_of_shown_lenses: Option<u32>,
}

impl LensStarKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let number_of_lenses = self.number_of_lenses.unwrap_or(5);
        let shown_lenses = subset(
            self.shown_lenses_start_index,
            self.number_of_shown_lenses,
            number_of_lenses,
        );
        Ok(Box::new(LensStar {
            number_of_lenses,
            focal_length: self.focal_length.map_or(1.0, |f| f.0),
            principal_point_distance: self.principal_point_distance.map_or(0.0, |d| d.0),
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            intersection_direction: self.intersection_direction.map_or(DVec3::Y, |d| d.0),
            point_on_lens1: self
                .point_on_lens1
                .map_or(DVec3::new(1.0, 0.0, 10.0), |p| p.0),
            star_radius: self.star_radius.map_or(2.0, |r| r.0),
            star_length: self.star_length.map_or(1.0, |l| l.0),
            lens_transmission_coefficient: crate::keys::throughput(
                self.lens_transmission_coefficient,
            ),
            thin_lens_type: self.thin_lens_type.unwrap_or_default(),
            shown_lenses,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn star() -> LensStar {
        LensStar {
            number_of_lenses: 5,
            focal_length: 1.0,
            principal_point_distance: 0.0,
            centre: DVec3::new(0.0, 0.0, 10.0),
            intersection_direction: DVec3::Y,
            point_on_lens1: DVec3::new(1.0, 0.0, 10.0),
            star_radius: 2.0,
            star_length: 1.0,
            lens_transmission_coefficient: 0.96,
            thin_lens_type: LensType::IdealThinLens,
            shown_lenses: None,
        }
    }

    #[test]
    fn shown_lenses_wrap_round() {
        let s = LensStar {
            shown_lenses: Some((-1, 2)),
            ..star()
        };
        let names: Vec<String> = s.parts(None).unwrap().into_iter().map(|p| p.name).collect();
        assert_eq!(names, ["lens 1", "lens 5"]);
    }

    #[test]
    fn a_point_on_the_axis_is_refused() {
        let s = LensStar {
            point_on_lens1: DVec3::new(0.0, 3.0, 10.0),
            ..star()
        };
        assert!(s.parts(None).unwrap_err().contains("point_on_lens1"));
    }
}
