//! Recursive backwards ray tracing with a maximum trace level, as TIM does it.

use std::cell::Cell;

use glam::{DVec2, DVec3};

use crate::geometry::{Hit, SceneGeometry, Shape};
use crate::math::{Frame, Ray};
use crate::scene::{Scene, lights::Lights};
use crate::surfaces::Colour;

/// Where a ray meets a surface, with everything a surface law needs.
pub struct Interaction<'a> {
    pub ray: Ray,
    /// The object, array element, primitive and distance along the ray.
    pub hit: Hit,
    pub geometry: &'a SceneGeometry,
    /// Remaining trace levels of the incoming ray.
    pub level: u32,
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

    /// Smallest distance a ray leaving this point must travel before it may hit anything, so
    /// it does not re-hit its own surface through rounding. Analytic shapes are intersected
    /// exactly in f64; Embree tests triangles in f32, hence the larger margin.
    pub fn self_hit_margin(&self) -> f64 {
        let scale = 1.0 + self.point().abs().max_element();
        match self.geometry.shapes()[self.hit.object] {
            Shape::TriangleMesh(_) => 1e-5 * scale,
            _ => 1e-9 * scale,
        }
    }
}

/// Traces rays through one scene; one per worker (it counts the rays it traces).
pub struct Tracer<'a> {
    scene: &'a Scene,
    shadows: bool,
    rays: Cell<u64>,
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, shadows: bool) -> Tracer<'a> {
        Tracer {
            scene,
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

    /// The colour seen along `ray` (hits closer than `t_min` are ignored) with `level` trace
    /// levels left, and the hit. A ray with no levels left, or that hits nothing, is black.
    pub fn trace(&self, ray: &Ray, t_min: f64, level: u32) -> (Colour, Option<Hit>) {
        if level == 0 {
            return (Colour::ZERO, None);
        }
        let hit = self.nearest(ray, t_min);
        let colour = hit.map_or(Colour::ZERO, |hit| self.shade(ray, &hit, level));
        (colour, hit)
    }

    /// [`Tracer::trace`] (from t = 0) for the first 8 of `rays`, intersected as one packet when
    /// they share an origin (primary rays of neighbouring pixels); entries past the rays are
    /// black misses.
    pub(crate) fn trace_packet(&self, rays: &[Ray], level: u32) -> [(Colour, Option<Hit>); 8] {
        let rays = &rays[..rays.len().min(8)];
        let mut directions = [DVec3::ZERO; 8];
        for (d, r) in directions.iter_mut().zip(rays) {
            *d = r.direction;
        }
        let same_origin = rays.iter().all(|r| r.origin == rays[0].origin);
        if level == 0 || rays.is_empty() || !same_origin {
            return std::array::from_fn(|i| {
                rays.get(i)
                    .map_or((Colour::ZERO, None), |r| self.trace(r, 0.0, level))
            });
        }
        self.rays.set(self.rays.get() + rays.len() as u64);
        let hits = self.scene.geometry.nearest8(
            rays[0].origin,
            &directions[..rays.len()],
            0.0,
            f64::INFINITY,
        );
        std::array::from_fn(|i| match hits[i] {
            Some(hit) => (self.shade(&rays[i], &hit, level), Some(hit)),
            None => (Colour::ZERO, None),
        })
    }

    /// The nearest hit along `ray`.
    pub fn nearest(&self, ray: &Ray, t_min: f64) -> Option<Hit> {
        self.rays.set(self.rays.get() + 1);
        self.scene
            .geometry
            .nearest(ray.origin, ray.direction, t_min, f64::INFINITY)
    }

    /// The colour of the surface at `hit`, seen along `ray`.
    pub fn shade(&self, ray: &Ray, hit: &Hit, level: u32) -> Colour {
        let at = Interaction {
            ray: *ray,
            hit: *hit,
            geometry: &self.scene.geometry,
            level,
        };
        self.scene.objects[hit.object].surface.colour(self, &at)
    }

    /// The colour seen along the ray that leaves the interaction point in `direction`, one trace
    /// level down.
    pub fn trace_from(&self, at: &Interaction, direction: DVec3) -> Colour {
        let ray = at.ray.continued(at.hit.t, direction);
        self.trace(&ray, at.self_hit_margin(), at.level - 1).0
    }

    /// Whether a shadow-throwing object hides a light at `distance` in unit direction `l` from
    /// the interaction point (always false with shadows switched off).
    pub fn shadowed(&self, at: &Interaction, l: DVec3, distance: f64) -> bool {
        if !self.shadows {
            return false;
        }
        self.rays.set(self.rays.get() + 1);
        self.scene
            .geometry
            .shadowed(at.point(), l, at.self_hit_margin(), distance)
    }
}
