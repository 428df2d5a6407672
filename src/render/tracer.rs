//! Recursive backwards ray tracing with a maximum trace level, as TIM does it.

use std::cell::Cell;

use glam::DVec3;

use crate::cameras::Camera;
use crate::embree::ExactRay;
use crate::geometry::{Hit, Interaction};
use crate::math::{Colour, Ray, ReferenceFrame};
use crate::scene::{Scene, World};
use crate::surfaces::Redirection;

use super::shading::ShadowRays;

/// The first surface a ray meets, in whichever frame it is at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Found {
    pub frame: ReferenceFrame,
    /// The ray in that frame (Lorentz-transformed if it left the camera-frame scene).
    pub ray: Ray,
    pub hit: Hit,
}

/// Traces rays through one scene; one per worker (it counts the rays it traces).
///
/// Rays start in the camera frame. They meet the camera-frame objects first; a ray that leaves
/// the last of them (or misses them all) is Lorentz-transformed into the scene frame there
/// (§2.1) and traced on through the scene-frame objects, never returning to the camera frame.
pub struct Tracer<'a> {
    pub(super) scene: &'a Scene,
    camera: &'a Camera,
    shadows: bool,
    /// Whether lit surfaces show their albedo instead of being lit ([`Tracer::albedo`]).
    albedo: bool,
    rays: Cell<u64>,
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, camera: &'a Camera, shadows: bool) -> Tracer<'a> {
        Tracer {
            scene,
            camera,
            shadows,
            albedo: false,
            rays: Cell::new(0),
        }
    }

    /// A tracer of the albedo a denoiser is guided by (Intel Open Image Denoise's definition):
    /// the ray is followed through every law as the colour is (mirrors, lenses, METATOYs, each
    /// one's transmission factor, absorption, mixes), but a lit surface shows its diffuse
    /// colour instead of being lit, so that what is seen through an optical component keeps
    /// its texture; emitting surfaces show their colour.
    pub fn albedo(scene: &'a Scene, camera: &'a Camera) -> Tracer<'a> {
        Tracer {
            albedo: true,
            ..Tracer::new(scene, camera, false)
        }
    }

    /// Rays (nearest-hit and shadow) traced so far.
    pub fn rays_traced(&self) -> u64 {
        self.rays.get()
    }

    /// The colour seen along `ray`, in `frame` (hits closer than `t_min` are ignored), with
    /// `level` trace levels left. A ray with no levels left, or that hits nothing, is black.
    pub fn trace(&self, ray: &Ray, t_min: f64, level: u32, frame: ReferenceFrame) -> Colour {
        if level == 0 {
            return Colour::ZERO;
        }
        self.first(ray, t_min, frame)
            .map_or(Colour::ZERO, |found| self.seen(&found, level, frame))
    }

    /// [`Self::shade`] of a surface found by a ray that started in `from`: as the camera sees
    /// it (Doppler-shifted, if asked for) where the ray crossed from the camera frame into the
    /// scene frame. The albedo is not shifted.
    fn seen(&self, found: &Found, level: u32, from: ReferenceFrame) -> Colour {
        let colour = self.shade(found, level);
        if from == ReferenceFrame::Camera && found.frame == ReferenceFrame::Scene && !self.albedo {
            self.camera.seen(colour, found.ray.direction)
        } else {
            colour
        }
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
    /// colour to `colours` and, if asked, records the surface it meets first in `firsts`.
    /// Without camera-frame objects the rays are intersected as one packet.
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
        // Found only when asked for: copying it costs in the hot loop.
        let mut record = |i: usize, found: &dyn Fn() -> Option<Found>| {
            if let Some(f) = firsts.as_deref_mut() {
                f[i] = found();
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
        // Doppler-shifted colours are shaded one ray at a time, each as the camera sees it.
        if self.scene.camera_frame.is_some() || self.camera.doppler() {
            for (i, r) in rays.iter().enumerate() {
                let found = self.first(r, 0.0, ReferenceFrame::Camera);
                if let Some(f) = &found {
                    colours[i] += self.seen(f, level, ReferenceFrame::Camera);
                }
                record(i, &|| found);
            }
            return;
        }
        let mut packet = [ExactRay::PLACEHOLDER; 8];
        for (p, r) in packet.iter_mut().zip(scene_rays) {
            (p.origin, p.direction) = (r.origin, r.direction);
        }
        self.rays.set(self.rays.get() + rays.len() as u64);
        let hits = self.scene.scene_frame.geometry.nearest_packet(
            &packet[..rays.len()],
            0.0,
            f64::INFINITY,
        );
        // Lanes that meet coloured surfaces are shaded once all their shadow rays have been
        // traced, as packets.
        let world = self.world(ReferenceFrame::Scene);
        let mut lit: [Option<Colour>; 8] = [None; 8];
        let mut shadow_rays = ShadowRays::new(&world.geometry);
        for (i, (hit, ray)) in hits.iter().zip(scene_rays).enumerate() {
            if let Some(hit) = hit {
                let at = world.geometry.interaction(*ray, *hit);
                match world.objects[hit.object].surface.redirect(&at, &mut |_| {}) {
                    Redirection::Lit(coloured) if self.shadows => {
                        lit[i] = Some(coloured.diffuse * self.scene.lights.ambient);
                        self.light_paths(&coloured, &at, |colour, l, distance| {
                            let segment = at.shadow_segment(l, distance);
                            shadow_rays.push(i, colour, segment, &mut lit, &self.rays);
                        });
                    }
                    r => colours[i] += self.follow(r, &at, level, ReferenceFrame::Scene),
                }
            }
            record(i, &|| {
                hit.map(|hit| Found {
                    frame: ReferenceFrame::Scene,
                    ray: *ray,
                    hit,
                })
            });
        }
        shadow_rays.flush(&mut lit, &self.rays);
        for (colour, lit) in colours.iter_mut().zip(lit) {
            if let Some(lit) = lit {
                *colour += lit;
            }
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

    /// The colour of the surface found, seen along its ray: the surface's law says where the
    /// ray goes on ([`Redirection`]), and the continued ray is traced one level down in the
    /// frame of the object it leaves.
    pub fn shade(&self, found: &Found, level: u32) -> Colour {
        self.shade_hit(found.frame, &found.ray, &found.hit, level)
    }

    /// [`Self::shade`] of `hit` on `ray`, in `frame`.
    fn shade_hit(&self, frame: ReferenceFrame, ray: &Ray, hit: &Hit, level: u32) -> Colour {
        let world = self.world(frame);
        let at = world.geometry.interaction(*ray, *hit);
        let surface = &world.objects[hit.object].surface;
        self.follow(surface.redirect(&at, &mut |_| {}), &at, level, frame)
    }

    /// The colour a surface law's redirection at `at` shows: lit by the lights, emitted, or
    /// seen along the continued ray, traced one level down in `frame`.
    fn follow(
        &self,
        redirection: Redirection,
        at: &Interaction,
        level: u32,
        frame: ReferenceFrame,
    ) -> Colour {
        let on = |(ray, margin)| self.trace_on(&ray, margin, level - 1, frame);
        match redirection {
            Redirection::Lit(coloured) if self.albedo => coloured.diffuse,
            Redirection::Lit(coloured) => self.lit(&coloured, at, frame),
            Redirection::Emits(colour) => colour,
            Redirection::Lost => Colour::ZERO,
            Redirection::Leaves { direction, factor } => factor * on(at.leaving(direction)),
            Redirection::Crosses { exit, factor } | Redirection::Jumps { exit, factor } => {
                factor * on(at.emerging(exit))
            }
            Redirection::Absorbs {
                absorption,
                direction,
                factor,
            } => factor * self.absorbed(absorption, at, direction, level, frame),
            Redirection::Glows { glow, factor } => glow + factor * on(at.leaving(at.ray.direction)),
            Redirection::Mixes(parts) => parts
                .iter()
                .map(|part| {
                    let redirection = part.surface.redirect(at, &mut |_| {});
                    part.weight * self.follow(redirection, at, level, frame)
                })
                .sum(),
        }
    }

    /// The colour seen along a ray that enters an absorbing solid at `at` in `direction`: what
    /// its next hit shows, of which each channel keeps exp(−absorption·t) over the distance t
    /// to that hit, unless the hit is on the same object (its exit accounts for the whole
    /// path).
    #[inline(never)]
    fn absorbed(
        &self,
        absorption: Colour,
        at: &Interaction,
        direction: DVec3,
        level: u32,
        frame: ReferenceFrame,
    ) -> Colour {
        if level <= 1 {
            return Colour::ZERO;
        }
        let (ray, margin) = at.leaving(direction);
        let Some(found) = self.first(&ray, margin, frame) else {
            return Colour::ZERO;
        };
        let colour = self.seen(&found, level - 1, frame);
        if found.frame == frame && found.hit.object == at.hit.object {
            colour
        } else {
            // A channel that absorbs nothing keeps all of it, even over any distance.
            let keep = |a: f64| {
                if a == 0.0 {
                    1.0
                } else {
                    (-a * found.hit.t).exp()
                }
            };
            colour * Colour::new(keep(absorption.x), keep(absorption.y), keep(absorption.z))
        }
    }

    /// [`Self::trace`] of a ray continued from a surface, kept out of line so that the
    /// common surfaces with a colour of their own are shaded without its stack frame.
    #[inline(never)]
    fn trace_on(&self, ray: &Ray, t_min: f64, level: u32, frame: ReferenceFrame) -> Colour {
        self.trace(ray, t_min, level, frame)
    }

    /// The description index and outward normal of the surface found.
    pub fn identify(&self, found: &Found) -> (usize, DVec3) {
        let world = self.world(found.frame);
        let at = world.geometry.interaction(found.ray, found.hit);
        let normal = at.shape.frame(at.local_point(), at.hit.prim).w;
        (world.objects[found.hit.object].id, normal)
    }

    /// Whether a shadow-throwing object at rest in `frame` (the interaction's) hides a light
    /// at `distance` in unit direction `l` from the interaction point (always false with
    /// shadows switched off).
    pub(super) fn shadowed(
        &self,
        at: &Interaction,
        l: DVec3,
        distance: f64,
        frame: ReferenceFrame,
    ) -> bool {
        if !self.shadows {
            return false;
        }
        self.rays.set(self.rays.get() + 1);
        let (ray, t_min, t_max) = at.shadow_segment(l, distance);
        self.world(frame)
            .geometry
            .shadowed(ray.origin, ray.direction, t_min, t_max)
    }
}
