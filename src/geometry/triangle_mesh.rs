//! Triangle mesh: shared vertices and index triples. A triangle's outward normal follows its
//! winding: (v1 − v0) × (v2 − v0), i.e. counter-clockwise seen from outside.
//!
//! In a scene Embree traverses meshes natively; the f64 code here recomputes Embree's hits and
//! serves the brute-force reference intersector.

use std::path::Path;
use std::sync::Arc;

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::plane::plane_distance;
use super::{GeometryError, Shape, Transform};
use crate::keys::{Array, Vector};
use crate::math::Frame;
use crate::mesh;

/// A triangle mesh. Its data is shared, so cloning (into a scene) is cheap.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    data: Arc<MeshData>,
}

#[derive(PartialEq)]
struct MeshData {
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// Unit shading normals, one per vertex.
    normals: Option<Vec<DVec3>>,
    /// Zero-area triangles left out of `triangles`.
    removed: usize,
    /// Texture coordinates (u, v), one pair per vertex, when the file has them.
    uvs: Option<Vec<DVec2>>,
    /// Diffuse colours, one per vertex, when the file has them.
    colours: Option<Vec<DVec3>>,
}

/// A mesh shows its sizes and a digest of its data (FNV-1a over the mixed bits of every
/// coordinate and index, 64 bits at a time), not its values one by one: the scene hash, taken from the scene's
/// Debug text, stays fast for millions of triangles (formatting them took seconds).
impl std::fmt::Debug for MeshData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // Each word is mixed first: a multiply carries changes only upwards, so without it two
        // sign bits flipped would cancel.
        let mix = crate::math::random::mix;
        let mut digest = 0xcbf2_9ce4_8422_2325u64;
        let mut eat = |word: u64| digest = (digest ^ mix(word)).wrapping_mul(0x0000_0100_0000_01b3);
        let normals = self.normals.iter().flatten();
        for c in self
            .vertices
            .iter()
            .chain(normals)
            .flat_map(|v| v.to_array())
        {
            eat(c.to_bits());
        }
        for t in &self.triangles {
            eat(u64::from(t[0]) | u64::from(t[1]) << 32);
            eat(u64::from(t[2]));
        }
        for c in self.uvs.iter().flatten().flat_map(|c| c.to_array()) {
            eat(c.to_bits());
        }
        for c in self.colours.iter().flatten().flat_map(|c| c.to_array()) {
            eat(c.to_bits());
        }
        let mut out = f.debug_struct("MeshData");
        out.field("vertices", &self.vertices.len())
            .field("triangles", &self.triangles.len())
            .field("normals", &self.normals.is_some())
            .field("removed", &self.removed);
        // Shown only when there are some: meshes without them keep their text (and scene hash).
        if self.uvs.is_some() {
            out.field("uvs", &true);
        }
        if self.colours.is_some() {
            out.field("colours", &true);
        }
        out.field("digest", &format_args!("{digest:016x}")).finish()
    }
}

impl TriangleMesh {
    /// A flat-shaded mesh; see [`TriangleMesh::with_normals`].
    pub fn new(
        vertices: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<TriangleMesh, GeometryError> {
        TriangleMesh::with_normals(vertices, triangles, None)
    }

    /// A mesh with optional per-vertex shading normals. Triangles of zero area (which no ray
    /// can hit and which have no normal) are left out and counted
    /// ([`TriangleMesh::removed_degenerate`]); a mesh with no triangle left is an error, as are
    /// non-finite coordinates and indices beyond the vertices. Zero or non-finite normals
    /// disable smooth shading for the whole mesh.
    pub fn with_normals(
        vertices: Vec<DVec3>,
        mut triangles: Vec<[u32; 3]>,
        normals: Option<Vec<DVec3>>,
    ) -> Result<TriangleMesh, GeometryError> {
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
        let before = triangles.len();
        triangles.retain(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let normal = (b - a).cross(c - a);
            normal != DVec3::ZERO && normal.is_finite()
        });
        if triangles.is_empty() {
            return Err(GeometryError::Degenerate(if before == 0 {
                "triangle mesh has no triangles".into()
            } else {
                format!("all {before} triangles of the mesh have zero area")
            }));
        }
        let normals = normals
            .filter(|ns| ns.len() == n)
            .and_then(|ns| ns.into_iter().map(DVec3::try_normalize).collect());
        Ok(TriangleMesh {
            data: Arc::new(MeshData {
                vertices,
                removed: before - triangles.len(),
                triangles,
                normals,
                uvs: None,
                colours: None,
            }),
        })
    }

    /// The mesh with texture coordinates, one (u, v) per vertex (ignored unless there is one
    /// for each vertex and all are finite); [`Self::coordinates`] interpolates them.
    pub fn with_uvs(mut self, uvs: Vec<DVec2>) -> TriangleMesh {
        if uvs.len() == self.data.vertices.len() && uvs.iter().all(|c| c.is_finite()) {
            Arc::get_mut(&mut self.data).expect("not yet shared").uvs = Some(uvs);
        }
        self
    }

    /// The mesh with diffuse colours, one per vertex (ignored unless there is one for each).
    pub fn with_colours(mut self, colours: Vec<DVec3>) -> TriangleMesh {
        if colours.len() == self.data.vertices.len() {
            Arc::get_mut(&mut self.data)
                .expect("not yet shared")
                .colours = Some(colours);
        }
        self
    }

    /// The vertex colours interpolated barycentrically at point `p` of triangle `prim`, if
    /// the mesh has them.
    pub fn colour_at(&self, p: DVec3, prim: u32) -> Option<DVec3> {
        Some(self.interpolated(self.colours()?, p, prim))
    }

    /// Per-vertex diffuse colours, if the mesh has them.
    pub fn colours(&self) -> Option<&[DVec3]> {
        self.data.colours.as_deref()
    }

    /// Per-vertex texture coordinates, if the mesh has them.
    pub fn uvs(&self) -> Option<&[DVec2]> {
        self.data.uvs.as_deref()
    }

    pub fn vertices(&self) -> &[DVec3] {
        &self.data.vertices
    }

    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.data.triangles
    }

    /// Per-vertex shading normals, if the mesh has them.
    pub fn normals(&self) -> Option<&[DVec3]> {
        self.data.normals.as_deref()
    }

    /// How many zero-area triangles were left out when the mesh was made.
    pub fn removed_degenerate(&self) -> usize {
        self.data.removed
    }

    /// The mesh placed by `t`; a reflection reverses the windings so outward stays outward.
    pub fn transformed(&self, t: &Transform) -> Result<TriangleMesh, GeometryError> {
        let vertices = self.vertices().iter().map(|&v| t.point(v)).collect();
        let mut triangles = self.triangles().to_vec();
        if t.reflects() {
            for tri in &mut triangles {
                tri.swap(1, 2);
            }
        }
        let normals = self
            .normals()
            .map(|ns| ns.iter().map(|&n| t.normal(n)).collect());
        let mut mesh = TriangleMesh::with_normals(vertices, triangles, normals)?;
        let data = Arc::get_mut(&mut mesh.data).expect("just made");
        data.removed += self.data.removed;
        data.uvs = self.data.uvs.clone();
        data.colours = self.data.colours.clone();
        Ok(mesh)
    }

    #[inline]
    fn corners(&self, prim: u32) -> [DVec3; 3] {
        self.data.triangles[prim as usize].map(|i| self.data.vertices[i as usize])
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
        (0..self.triangles().len() as u32)
            .filter_map(|i| {
                self.intersect_triangle(i, origin, direction, t_min, t_max)
                    .map(|t| (t, i))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// The normal of triangle `prim` from its winding (not normalised).
    #[inline]
    pub fn face_normal(&self, prim: u32) -> DVec3 {
        let [v0, v1, v2] = self.corners(prim);
        (v1 - v0).cross(v2 - v0)
    }

    /// Frame at point `p` of triangle `prim`. w is the triangle's normal (its winding gives the
    /// outward side) or, when the mesh has vertex normals, the normals interpolated
    /// barycentrically at `p`, turned to the outward side if they point inwards; u lies along
    /// the triangle's first edge, made perpendicular to w.
    pub fn frame(&self, p: DVec3, prim: u32) -> Frame {
        let [v0, v1, _] = self.corners(prim);
        let geometric = self.face_normal(prim);
        let smooth = self.normals().and_then(|normals| {
            let n = self.interpolated(normals, p, prim);
            let n = n.try_normalize()?;
            Some(if n.dot(geometric) < 0.0 { -n } else { n })
        });
        Frame::from_normal_and_u(smooth.unwrap_or(geometric), v1 - v0)
    }

    /// Per-vertex `values` interpolated barycentrically at point `p` of triangle `prim`.
    fn interpolated<T>(&self, values: &[T], p: DVec3, prim: u32) -> T
    where
        T: Copy + std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T>,
    {
        let [v0, v1, v2] = self.corners(prim);
        let [a, b, c] = self.data.triangles[prim as usize].map(|i| values[i as usize]);
        let geometric = self.face_normal(prim);
        // Barycentric weights of p: sub-triangle areas over the whole.
        let area = |x: DVec3, y: DVec3| (y - p).cross(x - p).dot(geometric);
        let whole = geometric.length_squared();
        let (w0, w1) = (area(v2, v1) / whole, area(v0, v2) / whole);
        a * w0 + b * w1 + c * (1.0 - w0 - w1)
    }

    /// Surface coordinates of point `p` of triangle `prim`: the texture coordinates
    /// interpolated barycentrically when the mesh has them; else its world x and z (a mesh
    /// has no global parametrisation; this makes a chequerboard on a mesh look like one laid
    /// on the floor).
    pub fn coordinates(&self, p: DVec3, prim: u32) -> DVec2 {
        match self.uvs() {
            Some(uvs) => self.interpolated(uvs, p, prim),
            None => DVec2::new(p.x, p.z),
        }
    }

    pub fn bounds(&self) -> (DVec3, DVec3) {
        let used = self
            .triangles()
            .iter()
            .flatten()
            .map(|&i| self.vertices()[i as usize]);
        used.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
    }
}

/// `type = "triangle-mesh"`: the triangles as indices into the vertices.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriangleMeshKeys {
    vertices: Vec<Vector>,
    triangles: Vec<Array<u32, 3>>,
}

impl TriangleMeshKeys {
    pub fn build(self) -> Result<Shape, GeometryError> {
        let vertices = self.vertices.into_iter().map(|v| v.0).collect();
        Ok(Shape::TriangleMesh(TriangleMesh::new(
            vertices,
            self.triangles.into_iter().map(|t| t.0).collect(),
        )?))
    }
}

/// `type = "mesh"`: a mesh file (OBJ or PLY), relative to the scene file, shaded with the
/// file's vertex normals where it has them unless `smooth = false`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshKeys {
    file: String,
    #[serde(default = "yes")]
    smooth: bool,
}

fn yes() -> bool {
    true
}

impl MeshKeys {
    /// A mesh file is not a shape of its own that others can be made of: it may be many parts.
    pub fn build(self) -> Result<Shape, GeometryError> {
        Err(GeometryError::Degenerate(format!(
            "a mesh file ('{}') cannot be a member of another shape (of a union, intersection, \
             difference, inverse, masked or transformed shape)",
            self.file
        )))
    }

    /// The mesh file's name, as given (relative to the scene file).
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The parts of the mesh file, relative to `dir`, as triangle meshes, each with its name
    /// ("" for a file of one part); materials are not read.
    pub fn load(self, dir: &Path) -> Result<Vec<(String, Shape)>, String> {
        let (parts, _) = self.load_with(dir, None)?;
        Ok(parts
            .into_iter()
            .map(|(name, shape, _)| (name, shape))
            .collect())
    }

    /// [`Self::load`] with each part's material, when `open` is given to read the MTL files
    /// an OBJ file names (relative to the OBJ file), and the MTL files' warnings. A part with
    /// a material is named after it too.
    #[allow(clippy::type_complexity)]
    pub fn load_with(
        self,
        dir: &Path,
        open: Option<mesh::Open>,
    ) -> Result<(Vec<(String, Shape, Option<mesh::Material>)>, Vec<String>), String> {
        let path = dir.join(self.file);
        let loaded = mesh::load_with(&path, open).map_err(|e| e.to_string())?;
        let single = loaded.meshes.len() == 1;
        let materials = &loaded.materials;
        let parts = loaded
            .meshes
            .into_iter()
            .zip(loaded.material_of)
            .zip(loaded.uvs)
            .zip(loaded.colours)
            .enumerate()
            .filter(|(_, (((m, _), _), _))| !m.triangles.is_empty())
            .map(|(i, (((m, material), uvs), colours))| {
                let material = material.map(|k| materials[k].clone());
                let name = match (single, m.name.is_empty(), &material) {
                    (true, _, _) => String::new(),
                    (false, true, Some(mat)) => mat.name.clone(),
                    (false, false, Some(mat)) => format!("{} ({})", m.name, mat.name),
                    (false, true, None) => format!("part {}", i + 1),
                    (false, false, None) => m.name.clone(),
                };
                let normals = m.normals.filter(|_| self.smooth);
                let part = if single {
                    String::new()
                } else {
                    format!(" (part '{name}')")
                };
                TriangleMesh::with_normals(m.vertices, m.triangles, normals)
                    .map(|t| match uvs {
                        Some(uvs) => t.with_uvs(uvs),
                        None => t,
                    })
                    .map(|t| match colours {
                        Some(colours) => t.with_colours(colours),
                        None => t,
                    })
                    .map(|t| (name, Shape::TriangleMesh(t), material))
                    .map_err(|e| format!("{}{part}: {e}", path.display()))
            })
            .collect::<Result<_, _>>()?;
        Ok((parts, loaded.warnings))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(normals: Option<Vec<DVec3>>) -> TriangleMesh {
        let v = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        TriangleMesh::with_normals(v, vec![[0, 1, 2]], normals).unwrap()
    }

    #[test]
    fn the_debug_text_tells_meshes_apart_by_every_bit() {
        let text = |v: Vec<DVec3>, t: Vec<[u32; 3]>, n: Option<Vec<DVec3>>| {
            format!("{:?}", TriangleMesh::with_normals(v, t, n).unwrap())
        };
        let v = || vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let t = || vec![[0, 1, 2], [0, 2, 3]];
        let base = text(v(), t(), None);
        assert_eq!(base, text(v(), t(), None));
        let mut nudged = v();
        nudged[2].y = f64::from_bits(1f64.to_bits() + 1);
        assert_ne!(base, text(nudged, t(), None));
        assert_ne!(base, text(v(), vec![[0, 1, 2], [0, 3, 2]], None));
        let normals = vec![DVec3::Z; 4];
        let with_normals = text(v(), t(), Some(normals.clone()));
        assert_ne!(base, with_normals);
        let mut tilted = normals;
        tilted[3] = DVec3::new(0.0, 0.6, 0.8);
        assert_ne!(with_normals, text(v(), t(), Some(tilted)));
        // Mirrored in x: two sign bits flipped must not cancel.
        let mut mirrored = v();
        mirrored[1].x = -1.0;
        mirrored[3].x = -0.0;
        assert_ne!(base, text(mirrored, t(), None));
        // Sizes, not values: the text stays short however large the mesh.
        assert!(base.len() < 200, "{base}");
    }

    #[test]
    fn vertex_colours_at_the_centroid_are_their_mean() {
        let colours = vec![
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 0.5),
        ];
        let m = triangle(None).with_colours(colours);
        let c = m.colour_at(DVec3::new(1.0, 1.0, 0.0) / 3.0, 0).unwrap();
        assert!(
            (c - DVec3::new(1.0, 1.0, 0.5) / 3.0).length() < 1e-15,
            "{c}"
        );
        // At a corner, its own colour.
        assert!((m.colour_at(DVec3::X, 0).unwrap() - DVec3::Y).length() < 1e-15);
        assert_eq!(triangle(None).colour_at(DVec3::ZERO, 0), None);
    }

    #[test]
    fn texture_coordinates_are_interpolated_barycentrically() {
        let uvs = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 2.0),
        ];
        let m = triangle(None).with_uvs(uvs);
        // p = 0.5·v0 + 0.25·v1 + 0.25·v2 = (0.25, 0.25, 0): (u, v) = 0.25·(1, 0) + 0.25·(0, 2).
        let c = m.coordinates(DVec3::new(0.25, 0.25, 0.0), 0);
        assert!((c - DVec2::new(0.25, 0.5)).length() < 1e-15, "{c}");
        // Without them: world x and z.
        assert_eq!(
            triangle(None).coordinates(DVec3::new(0.25, 0.5, 0.0), 0),
            DVec2::new(0.25, 0.0)
        );
        // They survive a transform, and the digest tells them apart.
        let moved = m.transformed(&Transform::translation(DVec3::Z)).unwrap();
        assert_eq!(moved.uvs(), m.uvs());
        let other = triangle(None).with_uvs(vec![DVec2::ZERO, DVec2::X, DVec2::Y]);
        assert_ne!(format!("{m:?}"), format!("{other:?}"));
        assert!(!format!("{:?}", triangle(None)).contains("uvs"));
    }

    #[test]
    fn vertex_normals_are_interpolated_barycentrically() {
        let n = [
            DVec3::new(-1.0, 0.0, 1.0).normalize(),
            DVec3::new(1.0, 0.0, 1.0).normalize(),
            DVec3::new(0.0, 1.0, 1.0).normalize(),
        ];
        let m = triangle(Some(n.to_vec()));
        // At each corner the corner's own normal ...
        for (p, n) in [DVec3::ZERO, DVec3::X, DVec3::Y].into_iter().zip(n) {
            assert!((m.frame(p, 0).w - n).length() < 1e-12);
        }
        // ... and in between the normalised weighted sum.
        let p = DVec3::new(0.25, 0.5, 0.0);
        let w = (0.25 * n[0] + 0.25 * n[1] + 0.5 * n[2]).normalize();
        let f = m.frame(p, 0);
        assert!((f.w - w).length() < 1e-12);
        assert!(f.u.dot(f.w).abs() < 1e-12 && (f.u.cross(f.v) - f.w).length() < 1e-12);
    }

    #[test]
    fn inward_vertex_normals_are_turned_outwards_and_flat_meshes_use_the_winding() {
        let m = triangle(Some(vec![DVec3::NEG_Z; 3]));
        assert_eq!(m.frame(DVec3::new(0.2, 0.2, 0.0), 0).w, DVec3::Z);
        let flat = triangle(None);
        assert_eq!(flat.frame(DVec3::new(0.2, 0.2, 0.0), 0).w, DVec3::Z);
        // A zero normal disables smooth shading for the whole mesh.
        let bad = triangle(Some(vec![DVec3::X, DVec3::ZERO, DVec3::X]));
        assert!(bad.normals().is_none());
    }

    #[test]
    fn zero_area_triangles_are_left_out_and_counted() {
        let v = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(2.0, 0.0, 0.0)];
        let m = TriangleMesh::new(v.clone(), vec![[0, 1, 2], [0, 1, 3], [2, 2, 1]]).unwrap();
        assert_eq!(
            (m.triangles(), m.removed_degenerate()),
            (&[[0, 1, 2]][..], 2)
        );
        let e = TriangleMesh::new(v, vec![[0, 1, 3]])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("all 1 triangles of the mesh have zero area"),
            "{e}"
        );
    }

    #[test]
    fn a_reflection_reverses_the_winding() {
        let mirror =
            Transform::new(DVec3::new(1.0, 1.0, -1.0), DVec3::Z, 0.0, DVec3::ZERO).unwrap();
        let m = triangle(None).transformed(&mirror).unwrap();
        assert_eq!(m.frame(DVec3::new(0.2, 0.2, 0.0), 0).w, DVec3::NEG_Z);
    }
}
