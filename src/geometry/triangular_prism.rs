//! Triangular prism (Dr TIM's `EditableTriangularPrism`): the triangle A, B, C and its copy
//! moved by `extrusion` (not necessarily perpendicular to the triangle), joined by three
//! parallelograms.

use glam::DVec3;
use serde::Deserialize;

use super::polyhedron::{Face, Polyhedral, Polyhedron, spans_no_volume};
use super::{GeometryError, Shape};
use crate::keys::{Array, Vector};

#[derive(Debug, Clone, PartialEq)]
pub struct TriangularPrism {
    vertices: [DVec3; 3],
    extrusion: DVec3,
    polyhedron: Polyhedron,
}

impl TriangularPrism {
    pub fn new(vertices: [DVec3; 3], extrusion: DVec3) -> Result<TriangularPrism, GeometryError> {
        for v in vertices {
            super::check_point("triangular prism vertex", v)?;
        }
        let [a, b, c] = vertices;
        let area = (b - a).cross(c - a).length();
        if area <= 1e-12 * (b - a).length() * (c - a).length() || !area.is_finite() {
            return Err(GeometryError::Degenerate(
                "the triangular prism's vertices are repeated or collinear".into(),
            ));
        }
        super::check_direction("triangular prism extrusion", extrusion)?;
        if spans_no_volume(b - a, c - a, extrusion) {
            return Err(GeometryError::Degenerate(
                "the triangular prism's extrusion is parallel to the plane of its vertices".into(),
            ));
        }
        let inside = (a + b + c) / 3.0 + 0.5 * extrusion;
        let mut faces: Vec<Face> = (0..3)
            .map(|i| {
                let (p, q) = (vertices[i], vertices[(i + 1) % 3]);
                Face::new(p, q - p, extrusion, inside)
            })
            .collect();
        faces.push(Face::new(a, b - a, c - a, inside));
        faces.push(Face::new(a + extrusion, b - a, c - a, inside));
        let corners = vertices.map(|v| v + extrusion);
        Ok(TriangularPrism {
            vertices,
            extrusion,
            polyhedron: Polyhedron::new(faces, &[vertices, corners].concat()),
        })
    }

    pub fn vertices(&self) -> [DVec3; 3] {
        self.vertices
    }

    pub fn extrusion(&self) -> DVec3 {
        self.extrusion
    }
}

impl Polyhedral for TriangularPrism {
    fn polyhedron(&self) -> &Polyhedron {
        &self.polyhedron
    }
}

/// `type = "triangular-prism"`: Dr TIM's `EditableTriangularPrism(parent, studio)`, base
/// (0, 0, 10), (0, 0, 11), (−1, 0, 11) extruded along (0, 1, 0), where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriangularPrismKeys {
    vertices: Option<Array<Vector, 3>>,
    extrusion: Option<Vector>,
}

impl TriangularPrismKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let vertices = self.vertices.map_or(
            [(0.0, 10.0), (0.0, 11.0), (-1.0, 11.0)].map(|(x, z)| DVec3::new(x, 0.0, z)),
            |v| v.0.map(|v| v.0),
        );
        Ok(Shape::TriangularPrism(TriangularPrism::new(
            vertices,
            self.extrusion.map_or(DVec3::Y, |e| e.0),
        )?))
    }
}
