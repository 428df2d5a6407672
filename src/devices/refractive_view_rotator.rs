//! Dr TIM's `RefractiveViewRotator` (research/viewRotation/RefractiveViewRotator.java): a
//! sheet of refractive wedges, one per pixel of the ocular plane, each of which refracts the
//! ray from the eye through its pixel's centre towards the point of a view plane that the
//! eye would see in the direction rotated by θ about an axis (and magnified by M), so that,
//! from the eye, the view plane looks rotated (`SurfaceOfRefractiveViewRotator`, without its
//! derivative control). Dr TIM builds the wedges voxel by voxel inside a bounding box; timbre
//! traces the glass as one exact solid, [`crate::geometry::ViewRotator`], whose doc gives the
//! construction.

use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{RefractiveIndex, Shape, ViewRotator, ViewRotatorSpec};
use crate::keys::{Coefficient, Direction, Finite, NonNegative, NonZero, Vector, coefficient};
use crate::surfaces::{Refractive, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct RefractiveViewRotator {
    pub spec: ViewRotatorSpec,
    pub transmission_coefficient: f64,
}

impl LensDevice for RefractiveViewRotator {
    /// `wedges`, glass of index n; no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a refractive view rotator has no edges to show (show_edges)".into());
        }
        let shape = ViewRotator::new(&self.spec).map_err(|e| e.to_string())?;
        Ok(vec![Part {
            name: "wedges".into(),
            shape: Shape::ViewRotator(Box::new(shape)),
            surface: Surface::Refractive(Refractive {
                index_ratio: self.spec.refractive_index,
                transmission_coefficient: self.transmission_coefficient,
            }),
            edge: false,
        }])
    }
}

/// `lenses = { type = "refractive-view-rotator" }`: Dr TIM's `RefractiveViewRotator` (it has
/// no editable form, so its geometry is required; the magnification and the transmission
/// coefficient default to the research programs' 1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefractiveViewRotatorKeys {
    bounding_box_centre: Vector,
    bounding_box_span_vector_1: Vector,
    bounding_box_span_vector_2: Vector,
    bounding_box_span_vector_3: Vector,
    eye_position: Vector,
    ocular_plane_centre: Vector,
    period_vector_1: Vector,
    period_vector_2: Vector,
    rotation_angle_deg: Finite,
    rotation_axis_direction: Direction,
    magnification_factor: Option<NonZero>,
    view_plane_point: Vector,
    view_plane_normal: Direction,
    refractive_index: RefractiveIndex,
    wedge_thickness: NonNegative,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl RefractiveViewRotatorKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let spec = ViewRotatorSpec {
            bounding_box_centre: self.bounding_box_centre.0,
            bounding_box_span_vectors: [
                self.bounding_box_span_vector_1.0,
                self.bounding_box_span_vector_2.0,
                self.bounding_box_span_vector_3.0,
            ],
            eye_position: self.eye_position.0,
            ocular_plane_centre: self.ocular_plane_centre.0,
            period_vector_1: self.period_vector_1.0,
            period_vector_2: self.period_vector_2.0,
            rotation_angle_deg: self.rotation_angle_deg.0,
            rotation_axis_direction: self.rotation_axis_direction.0,
            magnification_factor: self.magnification_factor.map_or(1.0, |m| m.0),
            view_plane_point: self.view_plane_point.0,
            view_plane_normal: self.view_plane_normal.0,
            refractive_index: self.refractive_index.0,
            wedge_thickness: self.wedge_thickness.0,
        };
        // Refuse a geometry the glass cannot follow here, where the key's line is known.
        ViewRotator::new(&spec).map_err(|e| e.to_string())?;
        Ok(Box::new(RefractiveViewRotator {
            spec,
            transmission_coefficient: coefficient(self.transmission_coefficient),
        }))
    }
}
