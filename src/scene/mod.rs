//! Scenes as data: objects (shape + surface), lights, camera, render settings, stereo output
//! and ray-trajectory sources; the standard studios; the TOML scene-file format; and the
//! built scene ([`Scene`]: the objects in Embree's BVHs), which `render` traces.

mod animation;
pub mod file;
pub mod lights;
mod ray_trajectory;
pub mod settings;
mod stereo;
pub mod studio;
mod summary;

use glam::DVec3;
use thiserror::Error;

pub use animation::{Animation, AnimationKeys, Interpolation, MAX_FRAMES, Track};
pub use ray_trajectory::{RayTrajectory, Spread};
pub use settings::RenderSettings;
pub use stereo::{Packing, Stereo};
pub use summary::{Report, SceneSummary};

use crate::cameras::{Camera, Focus, Shutter};
use crate::embree::{Device, EmbreeError};
use crate::geometry::{ObjectArray, SceneGeometry, Shape};
use crate::math::ReferenceFrame;
use crate::surfaces::Surface;
use lights::Lights;

/// Why a scene could not be built.
#[derive(Debug, Error)]
pub enum BuildError {
    #[error(transparent)]
    Embree(#[from] EmbreeError),
    /// [`Scene::build`] takes objects only; `trajectories::draw` turns trajectories into
    /// objects first.
    #[error(
        "the scene has ray trajectories that were not drawn (trajectories::draw) before it was built"
    )]
    UndrawnTrajectories,
}

/// A named shape with a surface property.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneObject {
    pub name: String,
    pub shape: Shape,
    pub surface: Surface,
    /// Whether the object casts shadows.
    pub shadow_throwing: bool,
    pub frame: ReferenceFrame,
    /// Which rays meet it: the camera's, the ray trajectories' or both.
    pub seen_by: SeenBy,
}

/// Which rays meet an object (`seen_by`). Dr TIM's programs often trace their ray trajectories
/// and then remove objects, or add them, before rendering: an object only the trajectories
/// meet is traced through and then left out of the picture; one only the camera sees is
/// passed by the trajectories as though it were not there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SeenBy {
    #[default]
    All,
    Camera,
    Trajectories,
}

impl SeenBy {
    /// Whether rays of `kind` (`Camera` or `Trajectories`) meet the object.
    pub fn meets(self, kind: SeenBy) -> bool {
        self == SeenBy::All || self == kind
    }
}

/// Everything needed to render a picture, before the BVH is built.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneDescription {
    pub objects: Vec<SceneObject>,
    /// Objects repeated on grids: each array's members (a range of `objects`) are placed at
    /// each of its offsets.
    pub arrays: Vec<ObjectArray>,
    pub lights: Lights,
    pub camera: Camera,
    /// Shapes (in the camera frame) the camera focuses on, with [`crate::cameras::Focus::Surface`].
    pub focus_surface: Vec<Shape>,
    /// A single view, or a stereo output of two views.
    pub stereo: Stereo,
    /// Warnings found while reading the scene's files (unsupported MTL keys).
    pub file_warnings: Vec<String>,
    pub render: RenderSettings,
    /// Rays whose paths are traced and drawn into the scene before it is rendered.
    pub trajectories: Vec<RayTrajectory>,
    /// The movie the file's `[animation]` makes of it, if any.
    pub animation: Option<Animation>,
}

impl SceneDescription {
    /// Whether `other` has the same objects (and so the same BVH, [`Scene::build`]): the two
    /// may differ in the camera, the stereo output and the render settings.
    pub fn same_objects(&self, other: &SceneDescription) -> bool {
        self.objects == other.objects
            && self.arrays == other.arrays
            && self.lights == other.lights
            && self.focus_surface == other.focus_surface
            && self.trajectories == other.trajectories
    }

    /// A hash (16 hexadecimal digits) of everything that decides the picture apart from the
    /// image size and the sampling (spp, seed): objects, lights, camera, stereo output, ray
    /// trajectories, the maximum trace level and shadows. Parts of a render and checkpoints
    /// record it, so that work on different scenes is never combined.
    pub fn hash(&self) -> String {
        /// FNV-1a (64 bits) of the text written into it.
        struct Fnv(u64);
        impl std::fmt::Write for Fnv {
            fn write_str(&mut self, s: &str) -> std::fmt::Result {
                for &b in s.as_bytes() {
                    self.0 = (self.0 ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
                }
                Ok(())
            }
        }
        let mut h = Fnv(0xcbf2_9ce4_8422_2325);
        let r = &self.render;
        // Debug output of f64 round-trips, so equal text means equal values.
        let _ = std::fmt::write(
            &mut h,
            format_args!(
                "{:?}{:?}{:?}{:?}{:?}{:?}{:?}{}{}",
                self.objects,
                self.arrays,
                self.lights,
                self.camera,
                self.focus_surface,
                self.stereo,
                self.trajectories,
                r.max_trace_level,
                r.shadows
            ),
        );
        format!("{:016x}", h.0)
    }

    /// Things worth telling the user that are not errors: zero-area triangles left out of
    /// meshes; unsupported keys of MTL files; a moving camera with the focus-surface shutter focused on shapes (pixels that
    /// miss them start their rays at a different time, see [`crate::cameras::Shutter`]).
    pub fn warnings(&self) -> Vec<String> {
        let c = &self.camera;
        let seam = !c.boost().is_identity()
            && c.shutter().0 == Shutter::FocusSurface
            && c.focus() == Focus::Surface;
        let seam = seam.then(|| {
            "camera: with a moving camera and the focus-surface shutter, pixels whose chief rays miss the focus_surface shapes are timed as if focused at infinity; make the shapes cover the whole view (e.g. a sphere round the camera) to avoid a seam".to_string()
        });
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
            .chain(self.objects.iter().filter_map(|o| {
                o.surface
                    .check_shape(&o.shape)
                    .err()
                    .map(|e| format!("object '{}': {e}; it renders black", o.name))
            }))
            .chain(seam)
            .chain(self.file_warnings.iter().cloned())
            .chain(self.trajectories_miss_camera_frame())
            .chain(self.lenses_around(self.camera.position(), SeenBy::Camera).map(|name| {
                format!(
                    "camera: inside lens '{name}', whose surface rays from inside pass unchanged"
                )
            }))
            .chain(self.trajectories.iter().flat_map(|t| {
                self.lenses_around(t.start, SeenBy::Trajectories).map(|name| {
                    format!(
                        "ray trajectory '{}': starts inside lens '{name}', whose surface rays from inside pass unchanged",
                        t.name
                    )
                })
            }))
            .collect()
    }

    /// A warning that trajectories do not meet the camera-frame objects, if there are both.
    fn trajectories_miss_camera_frame(&self) -> Option<String> {
        let moving = self
            .objects
            .iter()
            .filter(|o| o.frame == ReferenceFrame::Camera)
            .count();
        (moving > 0 && !self.trajectories.is_empty()).then(|| {
            format!("ray trajectories are traced through the scene-frame objects only; they do not meet the objects moving with the camera ({moving})")
        })
    }

    /// Names of the lenses (§3) that rays of `kind` meet whose sphere, or one of whose array
    /// copies, contains `point`, and of the transformation-optics shifters' outer spheres
    /// whose shell does.
    fn lenses_around(&self, point: DVec3, kind: SeenBy) -> impl Iterator<Item = &str> {
        self.objects.iter().enumerate().filter_map(move |(i, o)| {
            let Shape::Sphere(s) = &o.shape else {
                return None;
            };
            // The radius within which, and beyond which, `point` is inside.
            let (radius, hollow) = match &o.surface {
                Surface::Lens(_) => (s.radius(), 0.0),
                Surface::ToShifter(t) if s.radius() == t.radius => (t.radius, t.inner_radius),
                _ => return None,
            };
            if !o.seen_by.meets(kind) {
                return None;
            }
            let offsets = self
                .arrays
                .iter()
                .find(|a| a.objects.contains(&i))
                .map_or(&[DVec3::ZERO][..], |a| &a.offsets);
            offsets
                .iter()
                .any(|&offset| {
                    let r = point.distance(s.centre() + offset);
                    hollow < r && r < radius
                })
                .then_some(o.name.as_str())
        })
    }
}

/// Object data the tracer needs per hit (the shape lives in the geometry).
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectInfo {
    /// Index of the object in the scene description (the object AOV).
    pub id: usize,
    pub name: String,
    pub surface: Surface,
}

/// The objects at rest in one reference frame, with their BVH; `objects` is indexed by the
/// geometry's object index.
pub struct World {
    pub objects: Vec<ObjectInfo>,
    pub geometry: SceneGeometry,
}

/// A scene ready for tracing: the scene-frame and camera-frame objects in Embree's BVHs, the
/// camera's focus surface, and the lights.
pub struct Scene {
    pub scene_frame: World,
    /// The camera-frame scene, if any object moves with the camera.
    pub camera_frame: Option<World>,
    /// The focus-surface shapes, if there are any.
    pub focus_surface: Option<SceneGeometry>,
    pub lights: Lights,
    /// All object names, by description index.
    pub object_names: Vec<String>,
}

impl Scene {
    /// Builds the BVHs for the objects of a description. Ray trajectories must have been
    /// drawn into it as objects first (`trajectories::draw`).
    pub fn build(device: &Device, description: &SceneDescription) -> Result<Scene, BuildError> {
        if !description.trajectories.is_empty() {
            return Err(BuildError::UndrawnTrajectories);
        }
        let world = |frame| World::build(device, description, frame, SeenBy::Camera);
        let camera_frame = if description
            .objects
            .iter()
            .any(|o| o.frame == ReferenceFrame::Camera && o.seen_by.meets(SeenBy::Camera))
        {
            Some(world(ReferenceFrame::Camera)?)
        } else {
            None
        };
        let focus_surface = if description.focus_surface.is_empty() {
            None
        } else {
            let shapes = description
                .focus_surface
                .iter()
                .map(|s| (s.clone(), false))
                .collect();
            Some(SceneGeometry::build(device, shapes, Vec::new())?)
        };
        Ok(Scene {
            scene_frame: world(ReferenceFrame::Scene)?,
            camera_frame,
            focus_surface,
            lights: description.lights.clone(),
            object_names: description.objects.iter().map(|o| o.name.clone()).collect(),
        })
    }

    /// The objects at rest in `frame` (the camera frame's may be absent).
    pub fn world(&self, frame: ReferenceFrame) -> Option<&World> {
        match frame {
            ReferenceFrame::Scene => Some(&self.scene_frame),
            ReferenceFrame::Camera => self.camera_frame.as_ref(),
        }
    }
}

impl World {
    /// The objects of `description` at rest in `frame` that rays of `kind` meet, in their
    /// order. Each array is restricted to its members among them, which stay contiguous.
    pub(crate) fn build(
        device: &Device,
        description: &SceneDescription,
        frame: ReferenceFrame,
        kind: SeenBy,
    ) -> Result<World, EmbreeError> {
        // New index of each object of this frame.
        let mut index = vec![usize::MAX; description.objects.len()];
        let mut objects = Vec::new();
        let mut shapes = Vec::new();
        for (id, o) in description.objects.iter().enumerate() {
            if o.frame == frame && o.seen_by.meets(kind) {
                index[id] = objects.len();
                objects.push(ObjectInfo {
                    id,
                    name: o.name.clone(),
                    surface: o.surface.clone(),
                });
                shapes.push((o.shape.clone(), o.shadow_throwing));
            }
        }
        let arrays = description
            .arrays
            .iter()
            .filter_map(|a| {
                let members: Vec<usize> = a
                    .objects
                    .clone()
                    .map(|i| index[i])
                    .filter(|&i| i != usize::MAX)
                    .collect();
                let (&first, &last) = (members.first()?, members.last()?);
                Some(ObjectArray {
                    objects: first..last + 1,
                    offsets: a.offsets.clone(),
                })
            })
            .collect();
        Ok(World {
            objects,
            geometry: SceneGeometry::build(device, shapes, arrays)?,
        })
    }
}
