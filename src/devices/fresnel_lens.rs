//! Dr TIM's `EditableFresnelLens` (sceneObjects/FresnelLens.java): a Fresnel lens of
//! refractive index n that images a pair of conjugate points into each other stigmatically.
//! It is two [`FresnelLensSurface`]s back to back about the central plane (through
//! `lens_centre`, normal `forwards_central_plane_normal`): the front one's focal point is the
//! front conjugate point, the back one's the back conjugate point, and both optical axes are
//! the line through the two points. A ray from the front point is refracted by the front
//! surface into a ray along that line inside the glass, crosses the middle, and the back
//! surface refracts it through the back point: every ray from one point that passes through
//! the lens sections (and meets no step) passes exactly through the other.
//!
//! With "forwards" the direction along the line from one point to the other that has a
//! positive part along the central plane's normal, the front surface's principal(ish) plane is
//! the central plane moved forwards by half the `minimum_surface_separation` s (along the
//! axis), the back surface's the same moved backwards; each surface's sections step by
//! (thickness − s)/2, between its own `focal_length_min_…` and `focal_length_max_…`. As in
//! Dr TIM, the gap between the two surfaces' planes has no surfaces (Dr TIM's planes there are
//! invisible): rays cross it unrefracted, as if it were glass.
//!
//! Dr TIM's defaults (`FresnelLens(parent, studio)`): centre at the origin, normal (0, 0, −1),
//! front point (0, 0, −1), back point (0, 0, 1), n = 1.5, thickness 0.1, separation 0.01,
//! focal lengths from 0.5 to 0.955 on both sides (0.955 is the distance from the centre to a
//! conjugate point less half the difference of thickness and separation), black steps and
//! transmission coefficient 0.96 — twelve sections per side, about 0.78 in radius.

use glam::DVec3;
use serde::Deserialize;

use super::fresnel_lens_surface::{
    MAKE_STEP_SURFACES_BLACK, Sections, TRANSMISSION_COEFFICIENT, sections,
};
use super::{Edges, FresnelLensSurface, LensDevice, Part};
use crate::geometry::RefractiveIndex;
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector};

#[derive(Debug, Clone, PartialEq)]
pub struct FresnelLens {
    pub lens_centre: DVec3,
    /// Any length, non-zero.
    pub forwards_central_plane_normal: DVec3,
    pub front_conjugate_point: DVec3,
    pub back_conjugate_point: DVec3,
    /// n > 1.
    pub refractive_index: f64,
    pub thickness: f64,
    pub minimum_surface_separation: f64,
    /// The front and the back surface's sections.
    pub sections: [Sections; 2],
    pub make_step_surfaces_black: bool,
    pub transmission_coefficient: f64,
}

impl FresnelLens {
    /// The unit vector along the line from one conjugate point to the other that has a
    /// positive part along the central plane's normal (Dr TIM's
    /// `calculateOpticalAxisDirectionForwards`).
    fn forwards(&self) -> Result<DVec3, String> {
        let line = self.back_conjugate_point - self.front_conjugate_point;
        let along = line.dot(self.forwards_central_plane_normal);
        if line == DVec3::ZERO || along.abs() <= 1e-12 * line.length() {
            return Err(format!(
                "the line from front_conjugate_point {} to back_conjugate_point {} must cross \
                 the central plane (normal {})",
                self.front_conjugate_point,
                self.back_conjugate_point,
                self.forwards_central_plane_normal
            ));
        }
        Ok(line.normalize() * along.signum())
    }

    /// The front and the back surface.
    pub fn surfaces(&self) -> Result<[FresnelLensSurface; 2], String> {
        let s = self.minimum_surface_separation;
        if self.thickness <= s {
            return Err(format!(
                "the thickness {} must exceed the minimum_surface_separation {s}",
                self.thickness
            ));
        }
        let forwards = self.forwards()?;
        let normal = self.forwards_central_plane_normal;
        let side = |sign: f64, focal_point: DVec3, sections: Sections| FresnelLensSurface {
            point_in_principalish_plane: self.lens_centre + sign * 0.5 * s * forwards,
            outwards_principalish_plane_normal: sign * normal,
            focal_point,
            refractive_index: self.refractive_index,
            optical_axis_direction: sign * forwards,
            approximate_thickness: 0.5 * (self.thickness - s),
            sections,
            make_step_surfaces_black: self.make_step_surfaces_black,
            transmission_coefficient: self.transmission_coefficient,
        };
        Ok([
            side(1.0, self.front_conjugate_point, self.sections[0]),
            side(-1.0, self.back_conjugate_point, self.sections[1]),
        ])
    }
}

impl LensDevice for FresnelLens {
    /// `front surface/…` and `back surface/…`: each surface's `lens section I` and `step I`
    /// ([`FresnelLensSurface`]); no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a Fresnel lens has no edges to show (show_edges)".into());
        }
        let [front, back] = self.surfaces()?;
        let mut parts = front
            .parts_named("front surface/")
            .map_err(|e| format!("front surface: {e}"))?;
        parts.extend(
            back.parts_named("back surface/")
                .map_err(|e| format!("back surface: {e}"))?,
        );
        Ok(parts)
    }
}

/// Dr TIM's `FresnelLens(parent, studio)`: f_min and f_max of both sides.
const FOCAL_LENGTH_MIN: f64 = 0.5;
const FOCAL_LENGTH_MAX: f64 = 0.955;

/// `lenses = { type = "fresnel-lens" }`: Dr TIM's `EditableFresnelLens`, with its defaults.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FresnelLensKeys {
    lens_centre: Option<Vector>,
    forwards_central_plane_normal: Option<Direction>,
    front_conjugate_point: Option<Vector>,
    back_conjugate_point: Option<Vector>,
    refractive_index: Option<RefractiveIndex>,
    thickness: Option<Positive>,
    minimum_surface_separation: Option<Positive>,
    focal_length_min_front: Option<Finite>,
    focal_length_max_front: Option<Finite>,
    focal_length_min_back: Option<Finite>,
    focal_length_max_back: Option<Finite>,
    number_of_lens_sections: Option<u32>,
    make_step_surfaces_black: Option<bool>,
    transmission_coefficient: Option<Coefficient>,
}

impl FresnelLensKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let lens_centre = self.lens_centre.map_or(DVec3::ZERO, |c| c.0);
        // Dr TIM's `numberOfLensSections` constructor counts from the surface through the
        // lens centre on each side.
        let f = |f: Option<Finite>| f.map(|f| f.0);
        let defaults = Some((FOCAL_LENGTH_MIN, FOCAL_LENGTH_MAX));
        let side = |min, max, side: &str| {
            sections(
                f(min),
                f(max),
                self.number_of_lens_sections,
                lens_centre,
                defaults,
                [
                    &format!("focal_length_min_{side}"),
                    &format!("focal_length_max_{side}"),
                    "number_of_lens_sections",
                ],
            )
        };
        let sections = [
            side(
                self.focal_length_min_front,
                self.focal_length_max_front,
                "front",
            )?,
            side(
                self.focal_length_min_back,
                self.focal_length_max_back,
                "back",
            )?,
        ];
        let v = |v: Option<Vector>, d: DVec3| v.map_or(d, |v| v.0);
        Ok(Box::new(FresnelLens {
            lens_centre,
            forwards_central_plane_normal: self
                .forwards_central_plane_normal
                .map_or(DVec3::NEG_Z, |d| d.0),
            front_conjugate_point: v(self.front_conjugate_point, DVec3::NEG_Z),
            back_conjugate_point: v(self.back_conjugate_point, DVec3::Z),
            refractive_index: self.refractive_index.map_or(1.5, |n| n.0),
            thickness: self.thickness.map_or(0.1, |t| t.0),
            minimum_surface_separation: self.minimum_surface_separation.map_or(0.01, |s| s.0),
            sections,
            make_step_surfaces_black: self
                .make_step_surfaces_black
                .unwrap_or(MAKE_STEP_SURFACES_BLACK),
            transmission_coefficient: self
                .transmission_coefficient
                .map_or(TRANSMISSION_COEFFICIENT, |c| c.0),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dr_tims_default() -> FresnelLens {
        FresnelLens {
            lens_centre: DVec3::ZERO,
            forwards_central_plane_normal: DVec3::NEG_Z,
            front_conjugate_point: DVec3::NEG_Z,
            back_conjugate_point: DVec3::Z,
            refractive_index: 1.5,
            thickness: 0.1,
            minimum_surface_separation: 0.01,
            sections: [Sections::FocalLengths {
                min: FOCAL_LENGTH_MIN,
                max: FOCAL_LENGTH_MAX,
            }; 2],
            make_step_surfaces_black: true,
            transmission_coefficient: 0.96,
        }
    }

    #[test]
    fn dr_tims_default_has_twelve_sections_a_side() {
        // Dr TIM's loop: f = 0.955, 0.91, …, 0.46 (twelve values above 0.5 − 0.045); all are
        // below f_P = 0.995, so every one reaches its plane.
        let parts = dr_tims_default().parts(None).unwrap();
        for side in ["front", "back"] {
            let count = |what: &str| {
                parts
                    .iter()
                    .filter(|p| p.name.starts_with(&format!("{side} surface/{what} ")))
                    .count()
            };
            assert_eq!((count("lens section"), count("step")), (12, 11), "{side}");
        }
    }

    #[test]
    fn the_front_surface_faces_the_front_point() {
        // Forwards is −z (along the normal (0, 0, −1)): the front surface's plane is at
        // z = −0.005, its outward normal −z, towards the front point (0, 0, −1).
        let [front, back] = dr_tims_default().surfaces().unwrap();
        assert_eq!(
            front.point_in_principalish_plane,
            DVec3::new(0.0, 0.0, -0.005)
        );
        assert_eq!(front.outwards_principalish_plane_normal, DVec3::NEG_Z);
        assert_eq!(
            back.point_in_principalish_plane,
            DVec3::new(0.0, 0.0, 0.005)
        );
        assert_eq!(back.focal_point, DVec3::Z);
        assert!((front.approximate_thickness - 0.045).abs() < 1e-15);
    }

    #[test]
    fn impossible_lenses_are_refused() {
        let thin = FresnelLens {
            thickness: 0.01,
            ..dr_tims_default()
        };
        assert!(thin.parts(None).unwrap_err().contains("must exceed"));
        let along_plane = FresnelLens {
            back_conjugate_point: DVec3::new(1.0, 0.0, -1.0),
            ..dr_tims_default()
        };
        assert!(along_plane.parts(None).unwrap_err().contains("must cross"));
    }
}
