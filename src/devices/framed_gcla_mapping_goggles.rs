//! gCLA mapping goggles (Dr TIM's `EditableFramedGCLAMappingGoggles`, by Johannes Courtial and
//! Lena Mertens): goggles that map the view of a square so that its centre is avoided. A square
//! pyramid stands on a square base (centre B, side s) facing the eye E, its apex A a distance h
//! beyond the base along E→B. The base is cut into a central square and four triangles, each
//! triangle with its inner corner a fraction 1 − c (c the view-compression factor) of the way
//! from B to the middle of its outer side; each triangle and the pyramid face over the same
//! outer side are homogeneous planar imaging surfaces ([`HomogeneousPlanarImaging`], gCLAs):
//! the face images B to the triangle's inner corner, the triangle images the face's image of
//! the eye back to the eye, so that the eye sees through each pair along lines from itself.
//! The central square is open.

use glam::DVec3;
use serde::Deserialize;

use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{ConvexPolygon, Shape};
use crate::keys::{Direction, Finite, Positive, Vector};
use crate::surfaces::metatoys::{HomogeneousPlanarImaging, Transmission};
use crate::surfaces::{ConfocalLensletArrays, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct FramedGclaMappingGoggles {
    /// E: the centre of the pupil the goggles are designed for.
    pub eye_position: DVec3,
    /// B: the centre of the pyramid's base, the centre of the view's distortion.
    pub base_centre: DVec3,
    /// Unit vectors spanning the base (up made perpendicular to right, as Dr TIM does).
    pub right: DVec3,
    pub up: DVec3,
    pub base_centre_to_apex_distance: f64,
    pub base_side_length: f64,
    pub view_compression_factor: f64,
}

/// The four triangles: their names, the base corners (Dr TIM's p2 … p5: top left, top
/// right, bottom right, bottom left) at either end of their outer sides, and the names of
/// their inner sides from each of those corners (Dr TIM's frames).
const TRIANGLES: [(&str, usize, usize, [&str; 2]); 4] = [
    ("top", 0, 1, ["left", "right"]),
    ("right", 1, 2, ["top", "bottom"]),
    ("bottom", 2, 3, ["right", "left"]),
    ("left", 3, 0, ["bottom", "top"]),
];

impl FramedGclaMappingGoggles {
    /// The apex, the base corners (top left, top right, bottom right, bottom left) and the
    /// triangles' inner corners (top, right, bottom, left).
    fn points(&self) -> Result<(DVec3, [DVec3; 4], [DVec3; 4]), String> {
        let axis = (self.base_centre - self.eye_position)
            .try_normalize()
            .ok_or("the eye must not be at the base centre")?;
        let (b, r, u) = (self.base_centre, self.right, self.up);
        let w = 0.5 * self.base_side_length;
        let corners = [
            b - w * r + w * u,
            b + w * r + w * u,
            b + w * r - w * u,
            b - w * r - w * u,
        ];
        let i = (1.0 - self.view_compression_factor) * w;
        let inner = [b + i * u, b + i * r, b - i * u, b - i * r];
        Ok((b + self.base_centre_to_apex_distance * axis, corners, inner))
    }

    /// A triangle of gCLAs that images `inside` to `outside` (Dr TIM's `toGCLAs()`: the
    /// transmission coefficient of the best case, `GEOMETRIC_BEST`).
    fn window(
        name: String,
        corners: [DVec3; 3],
        imaging: HomogeneousPlanarImaging,
    ) -> Result<Part, String> {
        let arrays = ConfocalLensletArrays::imaging(imaging, Transmission::GeometricBest)
            .map_err(|e| format!("{name}: {e}"))?;
        Ok(Part {
            shape: Shape::ConvexPolygon(
                ConvexPolygon::new(corners.to_vec()).map_err(|e| format!("{name}: {e}"))?,
            ),
            name,
            surface: Surface::ConfocalLensletArrays(arrays),
            edge: false,
        })
    }
}

impl LensDevice for FramedGclaMappingGoggles {
    /// The windows `top face of the pyramid` and `top triangle in the base plane` (and right,
    /// bottom, left); with `edges` Dr TIM's frames, `apex of square pyramid`, `top left corner
    /// of base of square pyramid`, ..., `apex to top left corner`, `top of square base`, ...,
    /// `inner left side of top triangle`, `inner right side of top triangle`, ...
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let (apex, corners, inner) = self.points()?;
        let mut parts = Vec::new();
        for (k, &(side, a, b, _)) in TRIANGLES.iter().enumerate() {
            let (c1, c2) = (corners[a], corners[b]);
            let middle = 0.5 * (c1 + c2);
            let face = HomogeneousPlanarImaging {
                point_on_plane: apex,
                a: (c2 - c1).cross(apex - middle),
                inside_position: self.base_centre,
                outside_position: inner[k],
            };
            let triangle = HomogeneousPlanarImaging {
                point_on_plane: c1,
                a: (c2 - c1).cross(inner[k] - middle),
                inside_position: face.image(self.eye_position),
                outside_position: self.eye_position,
            };
            parts.push(Self::window(
                format!("{side} face of the pyramid"),
                [apex, c1, c2],
                face,
            )?);
            parts.push(Self::window(
                format!("{side} triangle in the base plane"),
                [inner[k], c1, c2],
                triangle,
            )?);
        }
        if let Some(e) = edges {
            let corner_names = ["top left", "top right", "bottom right", "bottom left"];
            parts.push(e.vertex("apex of square pyramid".into(), apex)?);
            for (name, &at) in corner_names.iter().zip(&corners) {
                parts.push(e.vertex(format!("{name} corner of base of square pyramid"), at)?);
            }
            for ((side, ..), &at) in TRIANGLES.iter().zip(&inner) {
                parts.push(e.vertex(format!("inner corner of {side} distorted triangle"), at)?);
            }
            for (name, &at) in corner_names.iter().zip(&corners) {
                parts.push(e.part(format!("apex to {name} corner"), apex, at)?);
            }
            for &(side, a, b, _) in &TRIANGLES {
                parts.push(e.part(format!("{side} of square base"), corners[a], corners[b])?);
            }
            for (k, &(side, a, b, [first, second])) in TRIANGLES.iter().enumerate() {
                let name = |s: &str| format!("inner {s} side of {side} triangle");
                parts.push(e.part(name(first), corners[a], inner[k])?);
                parts.push(e.part(name(second), inner[k], corners[b])?);
            }
        }
        Ok(parts)
    }

    /// Dr TIM's frames: shown, radius 0.01, `SurfaceColour.GREY50_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults::SHOWN_GREY
    }

    /// Dr TIM's `toGCLAs()` makes shadow-throwing gCLAs.
    fn shadow_throwing(&self) -> bool {
        true
    }
}

/// `lenses = { type = "framed-gcla-mapping-goggles" }`: Dr TIM's
/// `EditableFramedGCLAMappingGoggles`, with the defaults of its constructor `(parent, studio)`:
/// the eye at the origin, the base of side 1 about (0, 0, 5), its apex 1 beyond, the view
/// compressed by 0.5.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FramedGclaMappingGogglesKeys {
    eye_position: Option<Vector>,
    base_centre: Option<Vector>,
    right: Option<Direction>,
    up: Option<Direction>,
    base_centre_to_apex_distance: Option<Positive>,
    base_side_length: Option<Positive>,
    view_compression_factor: Option<Finite>,
}

impl FramedGclaMappingGogglesKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let right = self.right.map_or(DVec3::X, |d| d.0.normalize());
        let up = self
            .up
            .map_or(DVec3::Y, |d| d.0)
            .reject_from_normalized(right);
        if up.length() <= 1e-9 {
            return Err("up must not be along right".into());
        }
        let c = self.view_compression_factor.map_or(0.5, |c| c.0);
        if !(c > 0.0 && c <= 1.0) {
            return Err(format!(
                "view_compression_factor must be above 0 and at most 1 (the triangles' inner \
                 corners between the base's centre and the middles of its sides), not {c}"
            ));
        }
        Ok(Box::new(FramedGclaMappingGoggles {
            eye_position: self.eye_position.map_or(DVec3::ZERO, |p| p.0),
            base_centre: self.base_centre.map_or(DVec3::new(0.0, 0.0, 5.0), |p| p.0),
            right,
            up: up.normalize(),
            base_centre_to_apex_distance: self.base_centre_to_apex_distance.map_or(1.0, |d| d.0),
            base_side_length: self.base_side_length.map_or(1.0, |s| s.0),
            view_compression_factor: c,
        }))
    }
}
