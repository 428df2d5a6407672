//! Scenes: objects (shape + surface), lights, camera and render settings; the standard studio;
//! the TOML scene-file format.

pub mod file;
pub mod lights;
pub mod studio;

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
