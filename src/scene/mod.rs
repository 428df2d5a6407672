//! Scenes: objects (shape + surface), lights, camera and render settings; the standard studio;
//! the TOML scene-file format.

pub mod file;
pub mod lights;
pub mod studio;

use glam::DVec3;

use crate::cameras::PinholeCamera;
use crate::embree::{Device, EmbreeError};
use crate::geometry::{ObjectArray, SceneGeometry, Shape};
use crate::render::RenderSettings;
use crate::surfaces::Surface;
use lights::Lights;

/// A named shape with a surface property.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    pub name: String,
    pub shape: Shape,
    pub surface: Surface,
    /// Whether the object casts shadows.
    pub shadow_throwing: bool,
}

/// Everything needed to render a picture, before the BVH is built.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneDescription {
    pub objects: Vec<SceneObject>,
    /// Objects repeated on grids: each array's members (a range of `objects`) are placed at
    /// each of its offsets.
    pub arrays: Vec<ObjectArray>,
    pub lights: Lights,
    pub camera: PinholeCamera,
    pub render: RenderSettings,
}

/// What `timbre check` reports about a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSummary {
    pub objects: usize,
    /// Triangles of all meshes, counting every copy in arrays.
    pub triangles: u64,
    /// Copies of objects placed by arrays (Embree instances).
    pub instances: u64,
    /// Bounding box of all bounded objects and their copies, if there are any.
    pub bounds: Option<(DVec3, DVec3)>,
    /// Objects without bounds (planes).
    pub unbounded: usize,
}

impl SceneDescription {
    /// Counts and bounds of the scene's geometry.
    pub fn summary(&self) -> SceneSummary {
        let mut copies = vec![(1u64, DVec3::ZERO, DVec3::ZERO); self.objects.len()];
        let mut instances = 0;
        for a in &self.arrays {
            let lo = a.offsets.iter().fold(DVec3::INFINITY, |m, &o| m.min(o));
            let hi = a.offsets.iter().fold(DVec3::NEG_INFINITY, |m, &o| m.max(o));
            for c in &mut copies[a.objects.clone()] {
                *c = (a.offsets.len() as u64, lo, hi);
            }
            instances += a.offsets.len() as u64;
        }
        let mut summary = SceneSummary {
            objects: self.objects.len(),
            triangles: 0,
            instances,
            bounds: None,
            unbounded: 0,
        };
        for (o, &(n, lo, hi)) in self.objects.iter().zip(&copies) {
            if let Shape::TriangleMesh(m) = &o.shape {
                summary.triangles += n * m.triangles().len() as u64;
            }
            match o.shape.bounds() {
                Some(_) if n == 0 => {}
                Some((a, b)) => {
                    let (l, h) = summary
                        .bounds
                        .unwrap_or((DVec3::INFINITY, DVec3::NEG_INFINITY));
                    summary.bounds = Some((l.min(a + lo), h.max(b + hi)));
                }
                None => summary.unbounded += 1,
            }
        }
        summary
    }

    /// Things worth telling the user that are not errors: zero-area triangles left out of
    /// meshes.
    pub fn warnings(&self) -> Vec<String> {
        self.objects
            .iter()
            .filter_map(|o| match &o.shape {
                Shape::TriangleMesh(m) if m.removed_degenerate() > 0 => Some(format!(
                    "object '{}': {} zero-area triangles ignored",
                    o.name,
                    m.removed_degenerate()
                )),
                _ => None,
            })
            .collect()
    }
}

/// Object data the tracer needs per hit (the shape lives in the geometry).
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectInfo {
    pub name: String,
    pub surface: Surface,
}

/// A scene ready for tracing: geometry in Embree's BVH, surfaces and lights.
pub struct Scene {
    pub objects: Vec<ObjectInfo>,
    pub geometry: SceneGeometry,
    pub lights: Lights,
}

impl Scene {
    /// Builds the BVH for the objects of a description.
    pub fn build(device: &Device, description: &SceneDescription) -> Result<Scene, EmbreeError> {
        let objects = &description.objects;
        let geometry = SceneGeometry::build(
            device,
            objects
                .iter()
                .map(|o| (o.shape.clone(), o.shadow_throwing))
                .collect(),
            description.arrays.clone(),
        )?;
        Ok(Scene {
            objects: objects
                .iter()
                .map(|o| ObjectInfo {
                    name: o.name.clone(),
                    surface: o.surface.clone(),
                })
                .collect(),
            geometry,
            lights: description.lights.clone(),
        })
    }
}
