//! Shading of coloured surfaces by TIM's studio lighting: an ambient light plus point lights
//! with Phong highlights and hard shadows.
//!
//! Seen along a ray with direction d hitting a coloured surface at p with unit normal n, a
//! point light at L of colour C (Phong exponent k) adds, with l = (L − p)/|L − p|, v = −d and
//! r = 2 (n·l) n − l (the mirrored light direction):
//!
//! - nothing when the light and the viewer are on opposite sides of the surface
//!   (sign(n·l) ≠ sign(n·v)), or when a shadow-throwing object lies between p and L;
//! - diffuse × C × |n·l| (two-sided Lambert);
//! - specular × C × (r·v)^k when r·v > 0 (Phong).
//!
//! The ambient light adds ambient × diffuse.

use glam::DVec3;

use std::cell::Cell;

use super::Tracer;
use crate::embree::ExactRay;
use crate::geometry::{Interaction, SceneGeometry};
use crate::math::{Colour, ReferenceFrame};
use crate::scene::lights::PointLight;
use crate::surfaces::Coloured;

/// The contribution of `light` without shadowing to `surface`, for unit normal `n`, unit
/// direction to the viewer `v` and unit direction to the light `l`.
pub fn phong(light: &PointLight, surface: &Coloured, n: DVec3, v: DVec3, l: DVec3) -> Colour {
    let (nl, nv) = (n.dot(l), n.dot(v));
    if nl * nv <= 0.0 {
        return Colour::ZERO;
    }
    let diffuse = surface.diffuse * light.colour * nl.abs();
    let r = 2.0 * nl * n - l;
    let cos_alpha = r.dot(v);
    // A matt surface's highlight is exactly zero: no power to take.
    let specular = if cos_alpha > 0.0 && surface.specular != Colour::ZERO {
        surface.specular * light.colour * cos_alpha.powf(light.phong_exponent)
    } else {
        Colour::ZERO
    };
    diffuse + specular
}

impl Tracer<'_> {
    /// The colour of a coloured surface seen at `at` (on an object at rest in `frame`), lit by
    /// the scene's lights.
    pub(super) fn lit(
        &self,
        surface: &Coloured,
        at: &Interaction,
        frame: ReferenceFrame,
    ) -> Colour {
        let mut sum = surface.diffuse * self.scene.lights.ambient;
        self.light_paths(surface, at, |lit, l, distance| {
            if !self.shadowed(at, l, distance, frame) {
                sum += lit;
            }
        });
        sum
    }

    /// Hands `each` every point light's contribution to a coloured surface at `at` without
    /// shadowing, with the unit direction and distance to the light, in the scene's order of
    /// lights; lights that add nothing are left out.
    pub(super) fn light_paths(
        &self,
        surface: &Coloured,
        at: &Interaction,
        mut each: impl FnMut(Colour, DVec3, f64),
    ) {
        if self.scene.lights.points.is_empty() {
            return;
        }
        let n = at.normal();
        let v = -at.ray.direction;
        let p = at.point();
        for light in &self.scene.lights.points {
            let to_light = light.position - p;
            let distance = to_light.length();
            let l = to_light / distance;
            let lit = phong(light, surface, n, v, l);
            if lit != Colour::ZERO {
                each(lit, l, distance);
            }
        }
    }
}

/// The shadow rays of a packet's lanes, traced 8 at a time as Embree packets: each comes with
/// its lane and the light's contribution, added to the lane's colour if nothing blocks it.
pub(super) struct ShadowRays<'a> {
    geometry: &'a SceneGeometry,
    /// Each shadow ray's lane and its light's contribution.
    contributions: [(usize, Colour); 8],
    segments: [(ExactRay, f64, f64); 8],
    n: usize,
}

impl<'a> ShadowRays<'a> {
    pub fn new(geometry: &'a SceneGeometry) -> Self {
        ShadowRays {
            geometry,
            contributions: [(0, Colour::ZERO); 8],
            segments: [(ExactRay::PLACEHOLDER, 0.0, 0.0); 8],
            n: 0,
        }
    }

    /// Adds the shadow ray `segment` of lane `lane`, whose light adds `lit`; traces the batch
    /// when it is full, adding to `colours` and counting the rays in `rays`.
    pub fn push(
        &mut self,
        lane: usize,
        lit: Colour,
        segment: (ExactRay, f64, f64),
        colours: &mut [Option<Colour>; 8],
        rays: &Cell<u64>,
    ) {
        (self.contributions[self.n], self.segments[self.n]) = ((lane, lit), segment);
        self.n += 1;
        if self.n == 8 {
            self.flush(colours, rays);
        }
    }

    /// Traces the shadow rays pushed so far; each unblocked light's contribution is added to
    /// its lane's colour, in the order pushed.
    pub fn flush(&mut self, colours: &mut [Option<Colour>; 8], rays: &Cell<u64>) {
        if self.n == 0 {
            return;
        }
        rays.set(rays.get() + self.n as u64);
        let blocked = self.geometry.shadowed8(&self.segments[..self.n]);
        for (&(lane, lit), blocked) in self.contributions[..self.n].iter().zip(blocked) {
            if let (Some(colour), false) = (&mut colours[lane], blocked) {
                *colour += lit;
            }
        }
        self.n = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light() -> PointLight {
        PointLight {
            position: DVec3::ZERO,
            colour: Colour::ONE,
            phong_exponent: 40.0,
        }
    }

    #[test]
    fn lambert_term_is_two_sided_and_needs_viewer_and_light_on_one_side() {
        let s = Coloured::matt(Colour::new(0.5, 0.25, 1.0));
        let l = DVec3::new(0.0, 0.6, 0.8);
        let v = DVec3::new(0.6, 0.8, 0.0);
        let front = phong(&light(), &s, DVec3::Y, v, l);
        assert!((front - 0.6 * s.diffuse).length() < 1e-15);
        // Flipping the normal changes nothing (two-sided) ...
        assert_eq!(phong(&light(), &s, -DVec3::Y, v, l), front);
        // ... but a light behind the surface, as seen by the viewer, contributes nothing.
        let behind = DVec3::new(0.0, -0.6, 0.8);
        assert_eq!(phong(&light(), &s, DVec3::Y, v, behind), Colour::ZERO);
    }

    #[test]
    fn phong_highlight_peaks_in_the_mirror_direction() {
        let s = Coloured::shiny(Colour::ZERO);
        let l = DVec3::new(1.0, 1.0, 0.0).normalize();
        let mirror = DVec3::new(-1.0, 1.0, 0.0).normalize();
        assert!((phong(&light(), &s, DVec3::Y, mirror, l) - Colour::ONE).length() < 1e-12);
        // 10° off the mirror direction: cos(10°)^40.
        let a = 10f64.to_radians();
        let off = DVec3::new(
            -(45f64.to_radians() + a).sin(),
            (45f64.to_radians() + a).cos(),
            0.0,
        );
        let expected = a.cos().powf(40.0);
        assert!((phong(&light(), &s, DVec3::Y, off, l).x - expected).abs() < 1e-12);
    }
}
