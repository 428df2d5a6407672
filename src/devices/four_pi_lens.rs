//! The 4π lens (Dr TIM's `Editable4PiLens`; Courtial et al., "Ray-optical transformation optics
//! with ideal thin lenses makes omnidirectional lenses", Opt. Express 26, 17872 (2018)): a
//! lens, L1, in the principal plane (an equilateral triangle of circumradius `radius` about the
//! principal point), and lenses R1 that close it into a tetrahedron of length `length` along
//! the optical axis, with two inner vertices on the axis. "Inside space", the cell between L1
//! and the closer inner vertex, is imaged to outside space as L1 alone images it, whichever
//! lenses the light leaves through: the whole device is one lens in every direction.
//!
//! It is the tetrahedral ideal-lens cloak (`ideal_lens_cloak.rs`) with base centre, top
//! direction and base vertices set by the principal point, optical axis and transverse
//! directions, and the closer inner vertex seen from outside where L1 images it: with Dr
//! TIM's base focal length f₀₀ = −`focal_length_outwards`, at h₁′ = f₀₀ h₁ / (f₀₀ − h₁)
//! (the inverse of f₀₀ = h₁ h₁′ / (h₁′ − h₁)).

use glam::DVec3;
use serde::Deserialize;

use super::{EdgeDefaults, Edges, IdealLensCloak, LensDevice, LensType, Part};
use crate::keys::{Coefficient, Direction, Finite, NonZero, Positive, Vector};
use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct FourPiLens {
    pub principal_point: DVec3,
    pub optical_axis_direction: DVec3,
    /// The focal length from inside space to outside space (Dr TIM's sign).
    pub focal_length_outwards: f64,
    pub transverse_direction1: DVec3,
    pub transverse_direction2: DVec3,
    /// Distance of L1's vertices from the principal point.
    pub radius: f64,
    /// Distance of the tip from the principal point, along the optical axis.
    pub length: f64,
    pub closer_inner_vertex_distance: f64,
    pub farther_inner_vertex_distance: f64,
    pub individual_lens_transmission_coefficient: f64,
    /// What each lens is (Dr TIM's `lensType`).
    pub lens_type: LensType,
    /// Dr TIM's `showL1` and `showR1`: which lenses are made.
    pub show_l1: bool,
    pub show_r1: bool,
}

impl LensDevice for FourPiLens {
    /// The lenses, named as the cloak's (L1 is `base outer lens`), and with `edges` its frames.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        // Directions are unit vectors: a triple product below 1e-9 is a plane.
        let (a, t1, t2) = (
            self.optical_axis_direction,
            self.transverse_direction1,
            self.transverse_direction2,
        );
        if a.cross(t1).dot(t2).abs() < 1e-9 {
            return Err("optical_axis_direction, transverse_direction1 and transverse_direction2 must not lie in one plane".into());
        }
        let f00 = -self.focal_length_outwards;
        let h1 = self.closer_inner_vertex_distance;
        if f00 == h1 {
            return Err(format!(
                "with focal_length_outwards = {} inside space would be seen at infinity",
                self.focal_length_outwards
            ));
        }
        let cloak = IdealLensCloak {
            base_centre: self.principal_point,
            front_direction: -self.transverse_direction1,
            right_direction: -self.transverse_direction2,
            top_direction: self.optical_axis_direction,
            base_radius: self.radius,
            height: self.length,
            height_lower_inner_vertex_p: h1,
            height_upper_inner_vertex_p: self.farther_inner_vertex_distance,
            height_lower_inner_vertex_e: f00 * h1 / (f00 - h1),
            interface_transmission_coefficient: self.individual_lens_transmission_coefficient,
            lens_element_type: self.lens_type,
        };
        let mut parts = cloak.parts(edges)?;
        parts.retain(|p| {
            p.edge
                || if p.name == "base outer lens" {
                    self.show_l1
                } else {
                    self.show_r1
                }
        });
        Ok(parts)
    }

    /// Dr TIM's frames of the 4π lens: hidden, radius 0.01, `SurfaceColour.GREY50_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults {
            colour: Colour::splat(0.5),
            ..EdgeDefaults::HIDDEN_RED
        }
    }
}

/// `lenses = { type = "four-pi-lens" }`: Dr TIM's `Editable4PiLens`, with the defaults of its
/// constructor `Editable4PiLens(parent, studio)` for every key not given (L1 hidden).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FourPiLensKeys {
    principal_point: Option<Vector>,
    optical_axis_direction: Option<Direction>,
    focal_length_outwards: Option<NonZero>,
    transverse_direction1: Option<Direction>,
    transverse_direction2: Option<Direction>,
    radius: Option<Positive>,
    length: Option<Positive>,
    closer_inner_vertex_distance: Option<Finite>,
    farther_inner_vertex_distance: Option<Finite>,
    individual_lens_transmission_coefficient: Option<Coefficient>,
    lens_type: Option<LensType>,
    show_l1: Option<bool>,
    show_r1: Option<bool>,
}

impl FourPiLensKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let length = |x: Option<Positive>| x.map_or(1.0, |x| x.0);
        Ok(Box::new(FourPiLens {
            principal_point: self
                .principal_point
                .map_or(DVec3::new(0.0, 0.0, 5.0), |p| p.0),
            optical_axis_direction: self.optical_axis_direction.map_or(DVec3::Z, |d| d.0),
            focal_length_outwards: self.focal_length_outwards.map_or(1.0, |f| f.0),
            transverse_direction1: self.transverse_direction1.map_or(DVec3::X, |d| d.0),
            transverse_direction2: self.transverse_direction2.map_or(DVec3::Y, |d| d.0),
            radius: length(self.radius),
            length: length(self.length),
            closer_inner_vertex_distance: self
                .closer_inner_vertex_distance
                .map_or(1.0 / 3.0, |d| d.0),
            farther_inner_vertex_distance: self
                .farther_inner_vertex_distance
                .map_or(2.0 / 3.0, |d| d.0),
            individual_lens_transmission_coefficient: crate::keys::throughput(
                self.individual_lens_transmission_coefficient,
            ),
            lens_type: self.lens_type.unwrap_or_default(),
            show_l1: self.show_l1.unwrap_or(false),
            show_r1: self.show_r1.unwrap_or(true),
        }))
    }
}
