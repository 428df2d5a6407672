//! Recursive backwards ray tracing with a maximum trace level, as TIM does it.

use std::cell::Cell;

use glam::{DVec2, DVec3};

use crate::cameras::Camera;
use crate::geometry::{Hit, SceneGeometry, Shape};
use crate::math::{Frame, Ray};
use crate::scene::{ReferenceFrame, Scene, World, lights::Lights};
use crate::surfaces::{Colour, lenses::Exit};

/// Where a ray meets a surface, with everything a surface law needs.
pub struct Interaction<'a> {
    /// The incoming ray, in the frame of the object it meets.
    pub ray: Ray,
    /// The object, array element, primitive and distance along the ray.
    pub hit: Hit,
    pub geometry: &'a SceneGeometry,
    /// The frame the object is at rest in; rays leaving it are traced on in that frame.
    pub frame: ReferenceFrame,
    /// Remaining trace levels of the incoming ray.
    pub level: u32,
}

/// The first surface a ray meets, in whichever frame it is at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Found {
    pub frame: ReferenceFrame,
    /// The ray in that frame (Lorentz-transformed if it left the camera-frame scene).
    pub ray: Ray,
    pub hit: Hit,
}

impl Interaction<'_> {
    pub fn point(&self) -> DVec3 {
        self.ray.at(self.hit.t)
    }

    /// The surface frame at the hit (w the outward normal), of the array element that was hit,
    /// as seen by this ray (see [`SceneGeometry::frame_along`]); computed on demand, since some
    /// surfaces (constant colour) never need it.
    pub fn frame(&self) -> Frame {
        self.geometry
            .frame_along(&self.hit, self.point(), self.ray.direction)
    }

    /// The element's surface coordinates at the hit.
    pub fn coordinates(&self) -> DVec2 {
        self.geometry.coordinates(&self.hit, self.point())
    }

    /// Cartesian coordinates of the hit on a flat surface (see [`Shape::plane_coordinates`]).
    pub fn plane_coordinates(&self) -> Option<DVec2> {
        self.geometry.plane_coordinates(&self.hit, self.point())
    }

    /// Smallest distance a ray leaving this point must travel before it may hit anything, so
    /// it does not re-hit its own surface through rounding. Analytic shapes are intersected
    /// exactly in f64; Embree tests triangles in f32, hence the larger margin.
    pub fn self_hit_margin(&self) -> f64 {
        self.self_hit_margin_at(self.point())
    }

    /// The ray leaving the interaction point in `direction`, and the distance it must travel
    /// before it may hit anything.
    pub fn leaving(&self, direction: DVec3) -> (Ray, f64) {
        (
            self.ray.continued(self.hit.t, direction),
            self.self_hit_margin(),
        )
    }

    /// The ray leaving the interaction's object where `exit` says (a lens's exit, a
    /// teleporter's destination), and the distance it must travel before it may hit anything.
    /// It left `exit.path` earlier than it arrived.
    pub fn emerging(&self, exit: Exit) -> (Ray, f64) {
        let ray = Ray::new(
            exit.point,
            exit.direction,
            self.ray.time - self.hit.t - exit.path,
        );
        (ray, self.self_hit_margin_at(exit.point))
    }

    /// [`Self::self_hit_margin`] for a ray leaving the same object at another point `p`.
    fn self_hit_margin_at(&self, p: DVec3) -> f64 {
        let scale = 1.0 + p.abs().max_element();
        match self.geometry.shapes()[self.hit.object] {
            Shape::TriangleMesh(_) => 1e-5 * scale,
            _ => 1e-9 * scale,
        }
    }
}

/// Traces rays through one scene; one per worker (it counts the rays it traces).
///
/// Rays start in the camera frame. They meet the camera-frame objects first; a ray that leaves
/// the last of them (or misses them all) is Lorentz-transformed into the scene frame there
/// (§2.1) and traced on through the scene-frame objects, never returning to the camera frame.
pub struct Tracer<'a> {
    scene: &'a Scene,
    camera: &'a Camera,
    shadows: bool,
    rays: Cell<u64>,
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, camera: &'a Camera, shadows: bool) -> Tracer<'a> {
        Tracer {
            scene,
            camera,
            shadows,
            rays: Cell::new(0),
        }
    }

    /// Rays (nearest-hit and shadow) traced so far.
    pub fn rays_traced(&self) -> u64 {
        self.rays.get()
    }

    pub fn lights(&self) -> &Lights {
        &self.scene.lights
    }

    /// The colour seen along `ray`, in `frame` (hits closer than `t_min` are ignored), with
    /// `level` trace levels left. A ray with no levels left, or that hits nothing, is black.
    pub fn trace(&self, ray: &Ray, t_min: f64, level: u32, frame: ReferenceFrame) -> Colour {
        if level == 0 {
            return Colour::ZERO;
        }
        self.first(ray, t_min, frame)
            .map_or(Colour::ZERO, |found| self.shade(&found, level))
    }

    /// The first surface along `ray`, which starts in `frame`.
    pub fn first(&self, ray: &Ray, t_min: f64, frame: ReferenceFrame) -> Option<Found> {
        if frame == ReferenceFrame::Camera {
            if let Some(world) = &self.scene.camera_frame
                && let Some(hit) = self.nearest(world, ray, t_min)
            {
                return Some(Found {
                    frame,
                    ray: *ray,
                    hit,
                });
            }
            let ray = self.camera.to_scene_frame(ray);
            return self.first(&ray, 0.0, ReferenceFrame::Scene);
        }
        let hit = self.nearest(&self.scene.scene_frame, ray, t_min)?;
        Some(Found {
            frame,
            ray: *ray,
            hit,
        })
    }

    /// [`Tracer::trace`] of primary rays (at most 8, in the camera frame): adds each ray's
    /// colour to `colours` and, if asked, records the surface it meets first in `firsts`. Rays
    /// that reach the scene frame from the same origin (primary rays of neighbouring pixels)
    /// are intersected as one packet.
    pub(crate) fn trace_packet(
        &self,
        rays: &[Ray],
        level: u32,
        colours: &mut [Colour],
        mut firsts: Option<&mut [Option<Found>]>,
    ) {
        let rays = &rays[..rays.len().min(8)];
        if level == 0 || rays.is_empty() {
            return;
        }
        let mut record = |i: usize, found: Option<Found>| {
            if let Some(f) = firsts.as_deref_mut() {
                f[i] = found;
            }
        };
        let mut transformed = [rays[0]; 8];
        let scene_rays = if self.camera.boost().is_identity() {
            rays
        } else {
            for (s, r) in transformed.iter_mut().zip(rays) {
                *s = self.camera.to_scene_frame(r);
            }
            &transformed[..rays.len()]
        };
        if self.scene.camera_frame.is_some()
            || scene_rays.iter().any(|r| r.origin != scene_rays[0].origin)
        {
            for (i, r) in rays.iter().enumerate() {
                let found = self.first(r, 0.0, ReferenceFrame::Camera);
                if let Some(f) = &found {
                    colours[i] += self.shade(f, level);
                }
                record(i, found);
            }
            return;
        }
        let mut directions = [DVec3::ZERO; 8];
        for (d, r) in directions.iter_mut().zip(scene_rays) {
            *d = r.direction;
        }
        self.rays.set(self.rays.get() + rays.len() as u64);
        let hits = self.scene.scene_frame.geometry.nearest8(
            scene_rays[0].origin,
            &directions[..rays.len()],
            0.0,
            f64::INFINITY,
        );
        for (i, (hit, ray)) in hits.into_iter().zip(scene_rays).enumerate() {
            let found = hit.map(|hit| Found {
                frame: ReferenceFrame::Scene,
                ray: *ray,
                hit,
            });
            if let Some(f) = &found {
                colours[i] += self.shade(f, level);
            }
            record(i, found);
        }
    }

    /// The nearest hit along `ray` in `world`.
    fn nearest(&self, world: &World, ray: &Ray, t_min: f64) -> Option<Hit> {
        self.rays.set(self.rays.get() + 1);
        world
            .geometry
            .nearest(ray.origin, ray.direction, t_min, f64::INFINITY)
    }

    /// The objects at rest in `frame`.
    fn world(&self, frame: ReferenceFrame) -> &World {
        self.scene
            .world(frame)
            .expect("rays meet only objects that exist")
    }

    /// The colour of the surface found, seen along its ray.
    pub fn shade(&self, found: &Found, level: u32) -> Colour {
        let world = self.world(found.frame);
        let at = Interaction {
            ray: found.ray,
            hit: found.hit,
            geometry: &world.geometry,
            frame: found.frame,
            level,
        };
        world.objects[found.hit.object].surface.colour(self, &at)
    }

    /// The description index and outward normal of the surface found.
    pub fn identify(&self, found: &Found) -> (usize, DVec3) {
        let world = self.world(found.frame);
        let normal = world
            .geometry
            .frame(&found.hit, found.ray.at(found.hit.t))
            .w;
        (world.objects[found.hit.object].id, normal)
    }

    /// The colour seen along the ray that leaves the interaction point in `direction`, one trace
    /// level down, in the interaction's frame.
    pub fn trace_from(&self, at: &Interaction, direction: DVec3) -> Colour {
        let (ray, margin) = at.leaving(direction);
        self.trace(&ray, margin, at.level - 1, at.frame)
    }

    /// The colour seen along the ray that leaves the interaction's object where `exit` says,
    /// one trace level down, in the interaction's frame: for laws that move the ray through the
    /// object (§3's lenses) or elsewhere (teleporting).
    pub fn trace_emerging(&self, at: &Interaction, exit: Exit) -> Colour {
        let (ray, margin) = at.emerging(exit);
        self.trace(&ray, margin, at.level - 1, at.frame)
    }

    /// Whether a shadow-throwing object at rest in the interaction's frame hides a light at
    /// `distance` in unit direction `l` from the interaction point (always false with shadows
    /// switched off).
    pub fn shadowed(&self, at: &Interaction, l: DVec3, distance: f64) -> bool {
        if !self.shadows {
            return false;
        }
        self.rays.set(self.rays.get() + 1);
        at.geometry
            .shadowed(at.point(), l, at.self_hit_margin(), distance)
    }
}
