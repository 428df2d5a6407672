//! Dr TIM's `EditableMirroredSpaceCancellingWedge`, the space-cancelling wedge of its nets of
//! 4-simplices: like [`super::space_cancelling_wedge`] a wedge of apex angle ν about its apex
//! edge that cancels the space between its legs, but made of N sub-wedges of angle ν/N and of
//! triangles: each surface has the apex edge as one side and its third vertex at `leg_length`
//! from the apex edge's centre, in the direction at its angle θ from the bisector
//! (cos θ b̂ + sin θ ĉ, ĉ = b̂ × â as there). Sub-wedge w is centred on
//! θ_w = −ν/2 + (w + ½)ν/N (less ν/(4N) for the symmetric negative-space wedges); its legs are
//! at θ_w ± ν/(2N).
//!
//! - `perfect`: the legs teleport to each other (Dr TIM's `Teleporting`, `PERFECT`), turning a
//!   ray by ν/N about the apex edge. Neighbouring sub-wedges' legs coincide, and a ray leaving
//!   one leg within the self-hit margin of the coincident one would not take the next jump: so
//!   whatever N, one pair is made, the legs at ∓ν/2 (the N jumps of ν/N in one).
//! - `negative-space-wedges`, `negative-space-wedges-symmetric`: leg 1 (at θ_w + ν/(2N)) and
//!   the bisector surface (at θ_w) rotate ray directions by 180° about their normals, a
//!   negative-space wedge of ν/(2N) that turns a ray by ν/N.
//!
//! Dr TIM's containment-mirror version (an intersection of mirror planes with the legs, which
//! its own comments say does not work as meant) and its mirror approximation are not built.

use std::f64::consts::PI;

use glam::DVec3;

use super::space_cancelling_wedge::{Gluing, check_number_of_wedges, teleporting_to};
use super::{Edges, Part};
use crate::geometry::{ConvexPolygon, Shape};
use crate::surfaces::Surface;
use crate::surfaces::metatoys::{RayRotating, RotationAxis};

#[derive(Debug, Clone, PartialEq)]
pub struct MirroredSpaceCancellingWedge {
    /// ν, radians, in (0, 2π].
    pub apex_angle: f64,
    pub apex_edge_centre: DVec3,
    pub apex_edge_direction: DVec3,
    /// Made perpendicular to the apex edge; must not be along it.
    pub bisector_direction: DVec3,
    pub leg_length: f64,
    pub apex_edge_length: f64,
    pub show_surfaces: bool,
    pub surface_transmission_coefficient: f64,
    pub gluing: Gluing,
    /// N ≥ 1 sub-wedges.
    pub number_of_negative_space_wedges: u32,
}

impl MirroredSpaceCancellingWedge {
    /// Refuses what Dr TIM's mirrored wedge does not make (or not as meant).
    pub fn check_gluing(gluing: Gluing) -> Result<(), String> {
        match gluing {
            Gluing::Perfect | Gluing::NegativeSpaceWedges | Gluing::NegativeSpaceWedgesSymmetric => {
                Ok(())
            }
            Gluing::NegativeSpaceWedgesWithContainmentMirrors => Err(
                "gluing_type = \"negative-space-wedges-with-containment-mirrors\" is not built for \
                 nets of 4-simplices (Dr TIM makes it of intersections of mirror planes that its \
                 comments say do not work as meant); use \"negative-space-wedges\" or \"perfect\""
                    .into(),
            ),
            other => Err(format!(
                "gluing_type = \"{}\" is not one Dr TIM's nets of 4-simplices offer; use \
                 \"perfect\", \"negative-space-wedges\" or \"negative-space-wedges-symmetric\"",
                crate::keys::kebab_case(&format!("{other:?}"))
            )),
        }
    }

    /// The wedge's parts, each name prefixed with `prefix`: the surfaces (`sub-wedge W leg
    /// surface 1`, `… leg surface 2`, `… bisector surface`) and, with `edges`, Dr TIM's frame
    /// (spheres at the apex edge's ends and the surfaces' third vertices, cylinders along the
    /// apex edge and from its ends to the third vertices).
    pub fn parts_named(&self, prefix: &str, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        Self::check_gluing(self.gluing)?;
        check_number_of_wedges(self.number_of_negative_space_wedges)?;
        let n = match self.gluing {
            Gluing::Perfect => 1,
            _ => self.number_of_negative_space_wedges,
        };
        let nu = self.apex_angle;
        if !(nu > 0.0 && nu <= 2.0 * PI) {
            return Err(format!(
                "a wedge's apex angle must be above 0° and at most 360°, got {}°",
                nu.to_degrees()
            ));
        }
        let a = self.apex_edge_direction.normalize();
        let b = self
            .bisector_direction
            .reject_from_normalized(a)
            .normalize();
        let c = b.cross(a);
        let half = 0.5 * self.apex_edge_length * a;
        let (bottom, top) = (self.apex_edge_centre - half, self.apex_edge_centre + half);
        let vertex = |theta: f64| {
            let (sin, cos) = theta.sin_cos();
            self.apex_edge_centre + self.leg_length * (cos * b + sin * c)
        };
        let triangle = |name: &str, v: DVec3| {
            ConvexPolygon::new(vec![bottom, top, v])
                .map(Shape::ConvexPolygon)
                .map_err(|e| format!("{prefix}{name}: {e}"))
        };
        let rotating = Surface::RayRotating(RayRotating {
            angle: PI,
            axis: RotationAxis::Normal,
            transmission_coefficient: self.surface_transmission_coefficient,
            reflection_coefficient: 1.0,
        });
        let mut parts = Vec::new();
        let frame = |parts: &mut Vec<Part>, name: &str, v: DVec3| -> Result<(), String> {
            if let Some(e) = edges {
                parts.push(e.vertex(format!("{prefix}{name}, vertex 3"), v)?);
                parts.push(e.part(format!("{prefix}{name}, apex edge top to vertex 3"), top, v)?);
                parts.push(e.part(
                    format!("{prefix}{name}, apex edge bottom to vertex 3"),
                    bottom,
                    v,
                )?);
            }
            Ok(())
        };
        let width = nu / n as f64;
        let shift = if self.gluing == Gluing::NegativeSpaceWedgesSymmetric {
            0.25
        } else {
            0.0
        };
        for w in 0..n {
            let centre = -0.5 * nu + (w as f64 + 0.5 - shift) * width;
            let name = |s: &str| format!("sub-wedge {w} {s}");
            let (leg1, leg2) = (vertex(centre + 0.5 * width), vertex(centre - 0.5 * width));
            let surfaces: Vec<(String, DVec3, Surface)> = if self.gluing == Gluing::Perfect {
                let to = |destination| {
                    teleporting_to(destination, self.surface_transmission_coefficient)
                };
                vec![
                    (
                        name("leg surface 1"),
                        leg1,
                        to(triangle(&name("leg surface 2"), leg2)?),
                    ),
                    (
                        name("leg surface 2"),
                        leg2,
                        to(triangle(&name("leg surface 1"), leg1)?),
                    ),
                ]
            } else {
                vec![
                    (name("leg surface 1"), leg1, rotating.clone()),
                    (name("bisector surface"), vertex(centre), rotating.clone()),
                ]
            };
            for (name, v, surface) in surfaces {
                if self.show_surfaces {
                    parts.push(Part {
                        name: format!("{prefix}{name}"),
                        shape: triangle(&name, v)?,
                        surface,
                        edge: false,
                    });
                }
                frame(&mut parts, &name, v)?;
            }
        }
        if let Some(e) = edges {
            parts.push(e.vertex(format!("{prefix}apex edge bottom"), bottom)?);
            parts.push(e.vertex(format!("{prefix}apex edge top"), top)?);
            parts.push(e.part(format!("{prefix}apex edge"), bottom, top)?);
        }
        Ok(parts)
    }
}
