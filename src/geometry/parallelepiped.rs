//! Parallelepiped: centre + a e₀ + b e₁ + c e₂ with a, b, c ∈ [−½, ½] (Dr TIM's
//! `Parallelepiped`: a centre and three edge vectors).

use glam::DVec3;
use serde::Deserialize;

use super::polyhedron::{Face, Polyhedral, Polyhedron, spans_no_volume};
use super::{GeometryError, Shape};
use crate::keys::{Array, Vector};

#[derive(Debug, Clone, PartialEq)]
pub struct Parallelepiped {
    centre: DVec3,
    edges: [DVec3; 3],
    polyhedron: Polyhedron,
}

impl Parallelepiped {
    pub fn new(centre: DVec3, edges: [DVec3; 3]) -> Result<Parallelepiped, GeometryError> {
        super::check_point("parallelepiped centre", centre)?;
        for e in edges {
            super::check_direction("parallelepiped edge", e)?;
        }
        if spans_no_volume(edges[0], edges[1], edges[2]) {
            return Err(GeometryError::Degenerate(
                "the parallelepiped's edges are coplanar (they span no volume)".into(),
            ));
        }
        Ok(Parallelepiped {
            centre,
            edges,
            polyhedron: polyhedron(centre, edges),
        })
    }

    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    pub fn edges(&self) -> [DVec3; 3] {
        self.edges
    }
}

impl Polyhedral for Parallelepiped {
    fn polyhedron(&self) -> &Polyhedron {
        &self.polyhedron
    }
}

/// The parallelepiped about `centre` with edges `edges` (spanning a volume): its faces are
/// −e₀, +e₀, −e₁, +e₁, −e₂, +e₂ (the face on the side each points to), and on the faces ±eₖ
/// u runs along eₖ₊₁ and v across towards eₖ₊₂ (indices mod 3).
pub(super) fn polyhedron(centre: DVec3, edges: [DVec3; 3]) -> Polyhedron {
    let mut faces = Vec::with_capacity(6);
    for k in 0..3 {
        let (a, b, c) = (edges[k], edges[(k + 1) % 3], edges[(k + 2) % 3]);
        for side in [-0.5, 0.5] {
            faces.push(Face::new(centre + side * a - 0.5 * (b + c), b, c, centre));
        }
    }
    let vertices: Vec<DVec3> = (0..8)
        .map(|i| {
            let sign = |k: usize| if i & (1 << k) == 0 { -0.5 } else { 0.5 };
            centre + sign(0) * edges[0] + sign(1) * edges[1] + sign(2) * edges[2]
        })
        .collect();
    Polyhedron::new(faces, &vertices)
}

/// `type = "parallelepiped"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelepipedKeys {
    centre: Vector,
    edges: Array<Vector, 3>,
}

impl ParallelepipedKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        Ok(Shape::Parallelepiped(Parallelepiped::new(
            self.centre.0,
            self.edges.0.map(|e| e.0),
        )?))
    }
}
