//! Triangle mesh: shared vertices and index triples. A triangle's outward normal follows its
//! winding: (v1 − v0) × (v2 − v0), i.e. counter-clockwise seen from outside.
//!
//! In a scene Embree traverses meshes natively; the f64 code here recomputes Embree's hits and
//! serves the brute-force reference intersector.

use glam::{DVec2, DVec3};

use super::GeometryError;
use super::plane::plane_distance;
use crate::math::Frame;

#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    pub fn new(
        vertices: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<TriangleMesh, GeometryError> {
        if triangles.is_empty() {
            return Err(GeometryError::Degenerate(
                "triangle mesh has no triangles".into(),
            ));
        }
        for v in &vertices {
            super::check_point("mesh vertex", *v)?;
        }
        let n = vertices.len();
        if let Some(t) = triangles
            .iter()
            .find(|t| t.iter().any(|&i| i as usize >= n))
        {
            return Err(GeometryError::Degenerate(format!(
                "triangle {t:?} refers to a vertex beyond the {n} given"
            )));
        }
        Ok(TriangleMesh {
            vertices,
            triangles,
        })
    }

    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    fn corners(&self, prim: u32) -> [DVec3; 3] {
        self.triangles[prim as usize].map(|i| self.vertices[i as usize])
    }

    /// Möller–Trumbore intersection with triangle `prim`, in f64.
    pub fn intersect_triangle(
        &self,
        prim: u32,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<f64> {
        let [v0, v1, v2] = self.corners(prim);
        let (e1, e2) = (v1 - v0, v2 - v0);
        let p = direction.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let s = origin - v0;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = direction.dot(q) / det;
        let t = e2.dot(q) / det;
        (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > t_min && t < t_max).then_some(t)
    }

    /// Distance to triangle `prim`'s plane: recomputes an f32 hit whose f64 test just misses an
    /// edge (the point is then on the plane at most an f32 rounding outside the triangle).
    pub fn plane_distance(&self, prim: u32, origin: DVec3, direction: DVec3) -> Option<f64> {
        let [v0, v1, v2] = self.corners(prim);
        plane_distance(v0, (v1 - v0).cross(v2 - v0), origin, direction)
    }

    /// Nearest hit over all triangles (brute force): (t, triangle index).
    pub fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        (0..self.triangles.len() as u32)
            .filter_map(|i| {
                self.intersect_triangle(i, origin, direction, t_min, t_max)
                    .map(|t| (t, i))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// Frame of triangle `prim`: w its normal, u along its first edge.
    pub fn frame(&self, prim: u32) -> Frame {
        let [v0, v1, v2] = self.corners(prim);
        let n = (v1 - v0).cross(v2 - v0);
        Frame::from_normal_and_u(n, v1 - v0)
    }

    /// Surface coordinates of a mesh point: its world x and z (a mesh has no global
    /// parametrisation; this makes a chequerboard on a mesh look like one laid on the floor).
    pub fn coordinates(&self, p: DVec3) -> DVec2 {
        DVec2::new(p.x, p.z)
    }

    pub fn bounds(&self) -> (DVec3, DVec3) {
        let used = self
            .triangles
            .iter()
            .flatten()
            .map(|&i| self.vertices[i as usize]);
        used.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
    }
}
