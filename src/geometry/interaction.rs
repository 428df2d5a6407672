//! Where a ray meets a surface: what a surface law is given, and the rays that leave.

use glam::{DVec2, DVec3};

#[cfg(doc)]
use super::SceneGeometry;
use super::{Hit, Shape};
use crate::embree::ExactRay;
use crate::math::{Frame, Ray};

/// Where a ray meets a surface, with everything a surface law needs: the ray, the hit (the
/// object, the array copy, the part of its shape, the distance), the object's shape and the
/// copy's offset. A plain value, made from a hit in a scene ([`SceneGeometry::interaction`]) or
/// on a shape alone ([`Interaction::on`]); the frame, normal and surface coordinates are
/// computed from the shape when a law asks for them (some never do).
#[derive(Debug, Clone, Copy)]
pub struct Interaction<'a> {
    /// The incoming ray, in the frame of the object it meets.
    pub ray: Ray,
    /// The object, array element, primitive and distance along the ray.
    pub hit: Hit,
    /// The object's shape, where it is placed (before the array copy's offset).
    pub shape: &'a Shape,
    /// The offset of the array copy that was hit (zero outside arrays).
    pub offset: DVec3,
}

/// Where and how a ray leaves an object at another point than it met it: a lens's exit, a
/// teleporter's destination.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exit {
    /// On the object's (or the destination's) surface.
    pub point: DVec3,
    /// Unit vector.
    pub direction: DVec3,
    /// The time the passage takes (c = 1): the optical path length ∫n ds for rays integrated
    /// through a lens; for closed-form laws, which say nothing about the path inside, the
    /// straight distance from entry to exit (TIM's equivalent length of vacuum).
    pub path: f64,
}

impl Exit {
    /// Leaving from `exit` in `direction` (normalised here) after entering at `entry`, timed
    /// by the straight distance.
    pub fn chord(entry: DVec3, exit: DVec3, direction: DVec3) -> Exit {
        Exit {
            point: exit,
            direction: direction.normalize(),
            path: entry.distance(exit),
        }
    }
}

impl<'a> Interaction<'a> {
    /// `ray` meeting part `prim` of `shape` (object 0, in no array) at distance `t`: an
    /// interaction without a scene, for a law's own tests.
    pub fn on(shape: &'a Shape, ray: Ray, t: f64, prim: u32) -> Interaction<'a> {
        Interaction {
            ray,
            hit: Hit {
                object: 0,
                element: 0,
                prim,
                t,
            },
            shape,
            offset: DVec3::ZERO,
        }
    }

    pub fn point(&self) -> DVec3 {
        self.ray.at(self.hit.t)
    }

    /// The hit point relative to the array copy that was hit: in the coordinates of the
    /// object's own positions (those of its surface law, after the object's transform).
    pub fn local_point(&self) -> DVec3 {
        self.point() - self.offset
    }

    /// The surface frame at the hit (w the outward normal), of the array element that was hit,
    /// as seen by this ray (see [`Shape::frame_along`]).
    pub fn frame(&self) -> Frame {
        let (p, prim) = (self.local_point(), self.hit.prim);
        self.shape.frame_along(p, prim, self.ray.direction)
    }

    /// The outward normal of [`Self::frame`], alone.
    pub fn normal(&self) -> DVec3 {
        let (p, prim) = (self.local_point(), self.hit.prim);
        self.shape.normal_along(p, prim, self.ray.direction)
    }

    /// The element's surface coordinates at the hit.
    pub fn coordinates(&self) -> DVec2 {
        self.shape.coordinates(self.local_point(), self.hit.prim)
    }

    /// Cartesian coordinates of the hit on a flat surface (see [`Shape::plane_coordinates`]).
    pub fn plane_coordinates(&self) -> Option<DVec2> {
        self.shape
            .plane_coordinates(self.local_point(), self.hit.prim)
    }

    /// The surface-coordinate axes ∂p/∂c₁, ∂p/∂c₂ at the hit (see
    /// [`Shape::coordinate_axes`]).
    pub fn coordinate_axes(&self) -> Option<[DVec3; 2]> {
        self.shape
            .coordinate_axes(self.local_point(), self.hit.prim)
    }

    /// Smallest distance a ray leaving this point must travel before it may hit anything, so
    /// it does not re-hit its own surface through rounding. Analytic shapes are intersected
    /// exactly in f64; Embree tests triangles in f32, hence the larger margin.
    pub fn self_hit_margin(&self) -> f64 {
        self.self_hit_margin_at(self.point())
    }

    /// The shadow ray towards a light at `distance` in unit direction `l`: the segment from
    /// the interaction point that a shadow-throwing object must cross to hide the light.
    pub fn shadow_segment(&self, l: DVec3, distance: f64) -> (ExactRay, f64, f64) {
        let origin = self.point();
        let ray = ExactRay {
            origin,
            direction: l,
        };
        (ray, self.self_hit_margin_at(origin), distance)
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
        match self.shape {
            Shape::TriangleMesh(_) => 1e-5 * scale,
            _ => 1e-9 * scale,
        }
    }
}
