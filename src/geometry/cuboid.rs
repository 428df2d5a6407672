//! Cuboid: the box of edge lengths `size` centred on `centre`, its edges along x, y and z; a
//! parallelepiped with the edges (size_x, 0, 0), (0, size_y, 0) and (0, 0, size_z).

use glam::DVec3;
use serde::Deserialize;

use super::polyhedron::{Polyhedral, Polyhedron};
use super::{GeometryError, Shape, parallelepiped};
use crate::keys::{Array, Positive, Vector};

#[derive(Debug, Clone, PartialEq)]
pub struct Cuboid {
    centre: DVec3,
    size: DVec3,
    polyhedron: Polyhedron,
}

impl Cuboid {
    pub fn new(centre: DVec3, size: DVec3) -> Result<Cuboid, GeometryError> {
        super::check_point("cuboid centre", centre)?;
        super::check_positive("cuboid size x", size.x)?;
        super::check_positive("cuboid size y", size.y)?;
        super::check_positive("cuboid size z", size.z)?;
        let edges = [size.x * DVec3::X, size.y * DVec3::Y, size.z * DVec3::Z];
        Ok(Cuboid {
            centre,
            size,
            polyhedron: parallelepiped::polyhedron(centre, edges),
        })
    }

    pub fn centre(&self) -> DVec3 {
        self.centre
    }

    pub fn size(&self) -> DVec3 {
        self.size
    }
}

impl Polyhedral for Cuboid {
    fn polyhedron(&self) -> &Polyhedron {
        &self.polyhedron
    }
}

/// `type = "cuboid"`: `size` along x, y and z; Dr TIM's `Cuboid(parent, studio)`, centre
/// (0, 0, 10) and faces 1 from it (size 2 × 2 × 2), where not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CuboidKeys {
    centre: Option<Vector>,
    size: Option<Array<Positive, 3>>,
}

impl CuboidKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let size = self
            .size
            .map_or(DVec3::splat(2.0), |s| DVec3::from(s.0.map(|s| s.0)));
        Ok(Shape::Cuboid(Cuboid::new(
            self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            size,
        )?))
    }
}
