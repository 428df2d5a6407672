//! The geometry Dr TIM's stars share (`EditableLensStar`, `EditableRayRotationSheetStar`,
//! `EditableNegativeSpaceWedgeStar`): rectangular sheets, each with one side on the star's axis
//! (through `centre` along ŵ, from −length/2 to +length/2) and the opposite side on the
//! cylinder of radius `radius` about it. The sheet at azimuth φ lies in the half-plane of the
//! radial direction r̂(φ) = cos φ û + sin φ v̂, with û the reference direction perpendicular to
//! the axis and v̂ = ŵ × û; its outward normal (span_u × span_v) is the tangential direction
//! t̂(φ) = ŵ × r̂(φ), towards increasing azimuth. Its edges (Dr TIM's frames) are the top,
//! outer and bottom sides, and the common axial edge.

use glam::DVec3;

use super::{Edges, Face, Part};
use crate::geometry::{Parallelogram, Shape};
use crate::surfaces::Surface;

/// Most sheets a star may have (checked before any is made). The sheets all meet on the axis,
/// so their bounding boxes overlap there and every ray that meets the star is tested against a
/// share of all of them: a render's time grows with their number. At this limit a 32x24 image
/// at 1 sample a pixel of a star filling the view takes about 6 s of CPU time (3 s on two
/// cores), and with edges the star is 40 001 objects, far below a scene's limit.
pub const MAX_SHEETS: u32 = 10_000;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Star {
    centre: DVec3,
    w: DVec3,
    u: DVec3,
    v: DVec3,
    radius: f64,
    length: f64,
}

impl Star {
    /// The star about the axis through `centre` along `axis` (non-zero) whose azimuth 0 is the
    /// part of `towards` perpendicular to the axis; `None` if `towards` has (next to) no such
    /// part.
    pub fn new(
        centre: DVec3,
        axis: DVec3,
        towards: DVec3,
        radius: f64,
        length: f64,
    ) -> Option<Star> {
        let w = axis.normalize();
        let u = towards.reject_from_normalized(w);
        if u.length() <= 1e-12 * towards.length() {
            return None;
        }
        let u = u.normalize();
        Some(Star {
            centre,
            w,
            u,
            v: w.cross(u),
            radius,
            length,
        })
    }

    /// The unit radial direction r̂(φ).
    pub fn radial(&self, phi: f64) -> DVec3 {
        let (sin, cos) = phi.sin_cos();
        cos * self.u + sin * self.v
    }

    /// The unit tangential direction t̂(φ) = ŵ × r̂(φ), the normal of the sheet at φ.
    pub fn tangential(&self, phi: f64) -> DVec3 {
        let (sin, cos) = phi.sin_cos();
        -sin * self.u + cos * self.v
    }

    /// The components of `a` in the surface frame of the sheet at azimuth φ (u along the
    /// axis, v radial, w its normal t̂(φ)): what [`crate::surfaces::metatoys::Basis::Local`]
    /// takes, so that a direction given with the star moves with the sheet under transforms.
    pub fn local(&self, phi: f64, a: DVec3) -> DVec3 {
        DVec3::new(
            a.dot(self.w),
            a.dot(self.radial(phi)),
            a.dot(self.tangential(phi)),
        )
    }

    /// The end of the axis at −length/2, where every sheet has its corner.
    fn top(&self) -> DVec3 {
        self.centre - 0.5 * self.length * self.w
    }

    /// The sheet at azimuth φ: its corner and its spans along the axis and outwards.
    fn spans(&self, phi: f64) -> (DVec3, DVec3, DVec3) {
        (
            self.top(),
            self.length * self.w,
            self.radius * self.radial(phi),
        )
    }

    /// The sheet at azimuth φ, as a face.
    pub fn face(&self, phi: f64) -> Face {
        let (corner, span_u, span_v) = self.spans(phi);
        Face::Parallelogram {
            corner,
            span_u,
            span_v,
        }
    }

    /// The sheet at azimuth φ with `surface`, named `name`.
    pub fn sheet(&self, name: String, phi: f64, surface: Surface) -> Result<Part, String> {
        let (corner, span_u, span_v) = self.spans(phi);
        let shape =
            Parallelogram::new(corner, span_u, span_v).map_err(|e| format!("{name}: {e}"))?;
        Ok(Part {
            name,
            shape: Shape::Parallelogram(shape),
            surface,
            edge: false,
        })
    }

    /// The parts of the sheets at the azimuths φ with the labels of `sheets`: each sheet's own,
    /// as `sheet(φ, label)` makes them, and with `edges` its edges (`top edge LABEL`,
    /// `outer edge LABEL`, `bottom edge LABEL`); then the common `axial edge`.
    pub fn parts(
        &self,
        sheets: impl IntoIterator<Item = (f64, String)>,
        edges: Option<&Edges>,
        mut sheet: impl FnMut(f64, &str) -> Result<Vec<Part>, String>,
    ) -> Result<Vec<Part>, String> {
        let mut parts = Vec::new();
        for (phi, label) in sheets {
            parts.extend(sheet(phi, &label)?);
            if let Some(e) = edges {
                parts.extend(self.sheet_edges(e, phi, &label)?);
            }
        }
        if let Some(e) = edges {
            parts.push(self.axial_edge(e)?);
        }
        Ok(parts)
    }

    /// The edges of the sheet at azimuth φ.
    fn sheet_edges(&self, edges: &Edges, phi: f64, label: &str) -> Result<Vec<Part>, String> {
        let (top, axial, outer) = self.spans(phi);
        Ok(vec![
            edges.part(format!("top edge {label}"), top, top + outer)?,
            edges.part(
                format!("outer edge {label}"),
                top + outer,
                top + outer + axial,
            )?,
            edges.part(
                format!("bottom edge {label}"),
                top + outer + axial,
                top + axial,
            )?,
        ])
    }

    /// The edge along the axis, common to all sheets.
    fn axial_edge(&self, edges: &Edges) -> Result<Part, String> {
        let top = self.top();
        edges.part("axial edge".into(), top, top + self.length * self.w)
    }
}

/// Whether sheet (or wedge) `i` of `n` is shown: all of them with `None`; with
/// `Some((start, count))` the `count` from index `start`, modulo n (Dr TIM's shown start index
/// and number of shown sheets).
pub fn shown(subset: Option<(i64, u32)>, i: u32, n: u32) -> bool {
    match subset {
        None => true,
        Some((start, count)) => (i as i64 - start).rem_euclid(n as i64) < count.min(n) as i64,
    }
}

/// The shown subset that Dr TIM's start index and number of shown sheets (or wedges) keys
/// ask for, of `n`: none given, all shown; either given, the other defaults to 0 (start) or
/// n (count).
pub fn subset(start: Option<i64>, count: Option<u32>, n: u32) -> Option<(i64, u32)> {
    match (start, count) {
        (None, None) => None,
        (start, count) => Some((start.unwrap_or(0), count.unwrap_or(n))),
    }
}

/// The number of sheets (or wedges) `n` named by `key`, checked to be from 1 to `max`.
pub fn check_count(key: &str, n: u32, max: u32) -> Result<(), String> {
    if n == 0 || n > max {
        return Err(format!("{key} = {n} must be from 1 to {max}"));
    }
    Ok(())
}
