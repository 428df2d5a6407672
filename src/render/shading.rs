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

use super::Tracer;
use crate::geometry::Interaction;
use crate::math::Colour;
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
    /// The colour of a coloured surface seen at `at`, lit by the scene's lights.
    pub(super) fn lit(&self, surface: &Coloured, at: &Interaction) -> Colour {
        let lights = &self.scene.lights;
        let n = at.frame().w;
        let v = -at.ray.direction;
        let p = at.point();
        lights
            .points
            .iter()
            .fold(surface.diffuse * lights.ambient, |sum, light| {
                let to_light = light.position - p;
                let distance = to_light.length();
                let l = to_light / distance;
                let lit = phong(light, surface, n, v, l);
                if lit == Colour::ZERO || self.shadowed(at, l, distance) {
                    sum
                } else {
                    sum + lit
                }
            })
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
