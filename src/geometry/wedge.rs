//! Wedge (Dr TIM's space-cancelling wedges): an isosceles triangle extruded along its apex
//! edge. The apex edge, of length `apex_edge_length`, is centred on `apex_edge_centre` and runs
//! along `apex_edge_direction`; the two legs, of length `leg_length`, leave it at ± half the
//! apex angle from the bisector, `bisector_direction` made perpendicular to the edge.
//!
//! It is the triangular prism with vertices P, P + ℓ (cos ½ν b̂ − sin ½ν ĉ) and
//! P + ℓ (cos ½ν b̂ + sin ½ν ĉ) and extrusion L â, where â is the edge's direction, b̂ the
//! bisector's, ĉ = â × b̂, ν the apex angle, ℓ the leg length, L the edge's length and
//! P = centre − ½L â.

use glam::DVec3;
use serde::Deserialize;

use super::polyhedron::{Polyhedral, Polyhedron};
use super::{GeometryError, Shape, TriangularPrism};
use crate::keys::{Direction, Positive, Vector};

#[derive(Debug, Clone, PartialEq)]
pub struct Wedge {
    prism: TriangularPrism,
}

impl Wedge {
    /// A wedge of apex angle `apex_angle` (radians, between 0 and π).
    pub fn new(
        apex_edge_centre: DVec3,
        apex_edge_direction: DVec3,
        bisector_direction: DVec3,
        apex_angle: f64,
        leg_length: f64,
        apex_edge_length: f64,
    ) -> Result<Wedge, GeometryError> {
        super::check_point("wedge apex edge centre", apex_edge_centre)?;
        let a = super::check_direction("wedge apex edge direction", apex_edge_direction)?;
        super::check_direction("wedge bisector direction", bisector_direction)?;
        let b = bisector_direction.reject_from_normalized(a);
        if b.length() <= 1e-9 * bisector_direction.length() {
            return Err(GeometryError::Degenerate(
                "the wedge's bisector direction is parallel to its apex edge".into(),
            ));
        }
        let b = b.normalize();
        if !(apex_angle > 0.0 && apex_angle < std::f64::consts::PI) {
            let degrees = (apex_angle.to_degrees() * 1e9).round() / 1e9;
            return Err(GeometryError::Degenerate(format!(
                "the wedge's apex angle must be between 0° and 180°, got {degrees}°"
            )));
        }
        super::check_positive("wedge leg length", leg_length)?;
        super::check_positive("wedge apex edge length", apex_edge_length)?;
        let c = a.cross(b);
        let (sin, cos) = (0.5 * apex_angle).sin_cos();
        let apex = apex_edge_centre - 0.5 * apex_edge_length * a;
        let leg = |side: f64| apex + leg_length * (cos * b + side * sin * c);
        let prism = TriangularPrism::new([apex, leg(-1.0), leg(1.0)], apex_edge_length * a)
            .map_err(|e| GeometryError::Degenerate(format!("the wedge is too thin: {e}")))?;
        Ok(Wedge { prism })
    }

    /// The wedge as the triangular prism it is.
    pub fn prism(&self) -> &TriangularPrism {
        &self.prism
    }
}

impl Polyhedral for Wedge {
    fn polyhedron(&self) -> &Polyhedron {
        self.prism.polyhedron()
    }
}

/// `type = "wedge"`: the apex angle in degrees.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WedgeKeys {
    apex_edge_centre: Vector,
    apex_edge_direction: Direction,
    bisector_direction: Direction,
    apex_angle_deg: Positive,
    leg_length: Positive,
    apex_edge_length: Positive,
}

impl WedgeKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Wedge(Wedge::new(
            self.apex_edge_centre.0,
            self.apex_edge_direction.0,
            self.bisector_direction.0,
            self.apex_angle_deg.0.to_radians(),
            self.leg_length.0,
            self.apex_edge_length.0,
        )?))
    }
}
