//! Dr TIM's `FresnelLensSurface` (sceneObjects/FresnelLensSurface.java): one side of a
//! stigmatic Fresnel lens, made of concentric *lens sections*, each a ring of a
//! [`LensSurface`] (the surface that refracts rays from the focal point F into rays along the
//! optical axis inside the glass), all ending in the *principal(ish) plane*, so that the glass
//! stays thin. Every section sends the rays from F that reach it along the axis inside, so the
//! whole surface images F to infinity inside the glass, exactly, as one lens surface does.
//!
//! **Sections** (Dr TIM's construction, `populateSceneObjectCollection`). ŵ is the optical
//! axis turned outwards (to the side the plane's outward normal N points to), P the point
//! where it meets the plane, f_P = (F − P)·ŵ > 0 (F in front of the plane, outside). Section k
//! (k = 0, 1, …, K) is the lens surface of focal length f_k = f_max − k t (t the approximate
//! thickness) on the outward side of the plane, outside the *Belin cone* of the previous
//! surface f_k + t: the cone with apex A = 2F − P (F mirrored in P's direction) through the
//! ellipse in which that surface cuts the plane. Dr TIM stops at the first f ≤ f_min − t
//! (subtracting t repeatedly), so K = ⌈(f_max − f_min)/t⌉ (to 10⁻⁹), f_min itself included.
//! Surfaces with f_k ≥ f_P do not reach the plane: their sections are empty and left out. The
//! lens surface's glass is the convex side of its sheet, so a section (the sheet's cap on the
//! plane, less the cone) is a ring between the ellipses of surfaces f_k + t and f_k.
//!
//! **Parts.** Each section is two surfaces, as in Dr TIM: `lens section I` (the cap's curved
//! face, the `refractive` law with index ratio n, its normal out of the glass) and, from the
//! second on, `step I` (the Belin cone between the plane and the cap: matt black with
//! `make_step_surfaces_black`, else refractive with ratio 1/n, as its normal points into the
//! glass). Dr TIM's section is closed by the plane, but as an *invisible* face: light crosses
//! it unrefracted, so it is no part here. The cone is Dr TIM's `BelinCone`, built exactly as a
//! circular cone under the linear map that takes its unit circle at height 1 to the ellipse.
//!
//! Dr TIM builds sections for a virtual focal point (f_P < 0: a diverging surface) with its
//! Belin cones turned inside out; timbre refuses that case with a message (not yet made).

use glam::{DAffine3, DMat3, DVec3};
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{
    Cone, Csg, CsgOperation, Cylinder, Ellipse, GeometryError, LensSurface, Masked, Plane,
    RefractiveIndex, Shape, Transformed,
};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::{Coloured, Refractive, Surface};

/// Dr TIM's `MyMath.TINY`, which the section count of [`Sections::Number`] adds to the focal
/// length through the plane's point.
const TINY: f64 = 1e-4;

/// The most sections a surface may have.
pub const MAX_SECTIONS: usize = 10_000;

/// Which lens surfaces the sections are made of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sections {
    /// Focal lengths from `max` down to `min` in steps of the thickness (Dr TIM's
    /// `lensSurfaceFMin`, `lensSurfaceFMax`).
    FocalLengths { min: f64, max: f64 },
    /// Dr TIM's backwards-compatible `numberOfLensSections` N: f_max = f₀ + TINY + N t, with
    /// f₀ the focal length of the surface through `point` (the principal(ish) plane's point
    /// or the lens centre), and f_min = f_max − 2 N t.
    Number { number: u32, point: DVec3 },
}

impl Sections {
    /// (f_min, f_max) for surfaces of focal point `focal_point`, unit outward axis `axis`,
    /// index `n` and thickness `t`.
    pub fn focal_lengths(
        self,
        focal_point: DVec3,
        axis: DVec3,
        n: f64,
        t: f64,
    ) -> Result<(f64, f64), String> {
        match self {
            Sections::FocalLengths { min, max } => Ok((min, max)),
            Sections::Number { number, point } => {
                let f0 = LensSurface::focal_length_through(point, focal_point, axis, n)
                    .ok_or_else(|| {
                        format!(
                            "no lens surface with focal point {focal_point} and refractive index \
                             {n} passes through {point}"
                        )
                    })?;
                let max = f0 + TINY + f64::from(number) * t;
                Ok((max - 2.0 * f64::from(number) * t, max))
            }
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct FresnelLensSurface {
    pub point_in_principalish_plane: DVec3,
    /// Out of the glass (any length, non-zero).
    pub outwards_principalish_plane_normal: DVec3,
    pub focal_point: DVec3,
    /// n > 1 (inside over outside).
    pub refractive_index: f64,
    /// Either way along the axis (any length, non-zero).
    pub optical_axis_direction: DVec3,
    /// t > 0: the step between the sections' focal lengths.
    pub approximate_thickness: f64,
    pub sections: Sections,
    pub make_step_surfaces_black: bool,
    pub transmission_coefficient: f64,
}

/// `err`, prefixed with what it concerns.
fn located(what: &str, err: GeometryError) -> String {
    format!("{what}: {err}")
}

/// The Belin cone with apex `apex` through `ellipse`, as a circular cone of half angle 45°
/// and height 1 under the map (x, y, z) ↦ apex + x e₁ + y e₂ + z (centre − apex); the mantle
/// alone if `open`.
fn belin_cone(apex: DVec3, ellipse: &Ellipse, open: bool) -> Result<Shape, GeometryError> {
    let [e1, e2] = ellipse.semi_axes;
    let map =
        DAffine3::from_mat3_translation(DMat3::from_cols(e1, e2, ellipse.centre - apex), apex);
    let cone = Cone::new(DVec3::ZERO, DVec3::Z, 45.0, 1.0, open)?;
    Ok(Shape::Transformed(Transformed::new(
        Shape::Cone(cone),
        map,
    )?))
}

impl FresnelLensSurface {
    /// The unit optical axis turned outwards and the point P where it meets the plane.
    fn axis_and_principal_point(&self) -> Result<(DVec3, DVec3), String> {
        let normal = self.outwards_principalish_plane_normal.normalize();
        let axis = self.optical_axis_direction.normalize();
        let across = axis.dot(normal);
        if across.abs() <= 1e-12 {
            return Err(format!(
                "optical_axis_direction {} lies in the principal(ish) plane (normal {})",
                self.optical_axis_direction, self.outwards_principalish_plane_normal
            ));
        }
        let axis = axis * across.signum();
        let s = normal.dot(self.point_in_principalish_plane - self.focal_point) / axis.dot(normal);
        Ok((axis, self.focal_point + s * axis))
    }

    /// The sections' parts, named `{prefix}lens section I` and `{prefix}step I`.
    pub fn parts_named(&self, prefix: &str) -> Result<Vec<Part>, String> {
        let (n, t, f) = (
            self.refractive_index,
            self.approximate_thickness,
            self.focal_point,
        );
        let (axis, principal) = self.axis_and_principal_point()?;
        let f_p = (f - principal).dot(axis);
        if f_p <= 0.0 {
            return Err(format!(
                "the focal point {f} must lie on the outward side of the principal(ish) plane \
                 (f = {f_p}); a virtual focal point (a diverging Fresnel-lens surface) is not \
                 supported"
            ));
        }
        let (f_min, f_max) = self.sections.focal_lengths(f, axis, n, t)?;
        let count = ((f_max - f_min) / t - 1e-9).ceil() + 1.0;
        if count > MAX_SECTIONS as f64 {
            return Err(format!(
                "{count} lens surfaces from f_max = {f_max} down to f_min = {f_min} in steps of \
                 {t}: at most {MAX_SECTIONS} are allowed"
            ));
        }
        let normal = self.outwards_principalish_plane_normal;
        let plane = Plane::new(principal, -normal, normal.any_orthogonal_vector())
            .map_err(|e| located("principal(ish) plane", e))?;
        let apex = 2.0 * f - principal;
        let surface = |focal_length: f64| {
            LensSurface::new(f, axis, focal_length, n)
                .map_err(|e| located(&format!("lens surface of focal length {focal_length}"), e))
        };
        let section_of = |s: &LensSurface| {
            s.plane_section(principal, normal)
                .map_err(|e| located("principal(ish) plane", e))
        };
        let face = Surface::Refractive(Refractive {
            index_ratio: n,
            transmission_coefficient: self.transmission_coefficient,
        });
        let step = if self.make_step_surfaces_black {
            Surface::Coloured(Coloured::matt(Colour::ZERO))
        } else {
            Surface::Refractive(Refractive {
                index_ratio: 1.0 / n,
                transmission_coefficient: self.transmission_coefficient,
            })
        };
        let mut previous = if f_max + t > 0.0 {
            section_of(&surface(f_max + t)?)?
        } else {
            None
        };
        let mut parts = Vec::new();
        let mut number = 0;
        for k in 0..count.max(0.0) as usize {
            let f_k = f_max - k as f64 * t;
            if f_k <= 0.0 {
                break;
            }
            let lens = surface(f_k)?;
            let Some(section) = section_of(&lens)? else {
                continue;
            };
            number += 1;
            let name = |what: &str| format!("{prefix}{what} {number}");
            let fail = |what: &str, e: GeometryError| located(&name(what), e);
            // A cylinder about the axis round the cap: its points have z from the ellipse's
            // lowest up to the vertex, and the glass's cross-section at height z is the disc
            // of the sheet's radius there, which grows downwards.
            let (low, high) = (section.z_range.0, -f_k);
            let radius = lens.radius_at(low);
            let margin = 1e-3 * (radius + high - low);
            let bound = Cylinder::new(
                f + (low - margin) * axis,
                f + (high + margin) * axis,
                radius + margin,
            )
            .map_err(|e| fail("lens section", e))?;
            let mut mask = vec![Shape::Plane(plane.clone()), Shape::Cylinder(bound)];
            if let Some(inner) = &previous {
                let cone = belin_cone(apex, &inner.ellipse, false)
                    .and_then(|c| Csg::new(CsgOperation::Inverse, vec![c]))
                    .map_err(|e| fail("step", e))?;
                mask.push(Shape::Csg(cone));
            }
            let cap = Csg::new(CsgOperation::Intersection, mask)
                .and_then(|mask| Masked::new(Shape::LensSurface(lens.clone()), Shape::Csg(mask)))
                .map_err(|e| fail("lens section", e))?;
            parts.push(Part {
                name: name("lens section"),
                shape: Shape::Masked(cap),
                surface: face.clone(),
                edge: false,
            });
            if let Some(inner) = &previous {
                let wall = belin_cone(apex, &inner.ellipse, true)
                    .and_then(|c| Masked::new(c, Shape::LensSurface(lens)))
                    .map_err(|e| fail("step", e))?;
                parts.push(Part {
                    name: name("step"),
                    shape: Shape::Masked(wall),
                    surface: step.clone(),
                    edge: false,
                });
            }
            previous = Some(section);
        }
        if parts.is_empty() {
            return Err(format!(
                "no lens section: none of the lens surfaces from f_max = {f_max} down to \
                 f_min = {f_min} reaches the principal(ish) plane, {f_p} from the focal point"
            ));
        }
        Ok(parts)
    }
}

impl LensDevice for FresnelLensSurface {
    /// `lens section I` and `step I` for the sections I = 1, 2, … from the axis outwards (no
    /// step for the first); no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a Fresnel-lens surface has no edges to show (show_edges)".into());
        }
        self.parts_named("")
    }
}

/// Dr TIM's defaults for what `FresnelLensSurface`'s constructors take and its editable
/// container, `EditableFresnelLens`, sets: black steps, transmission coefficient 0.96
/// (`SurfacePropertyPrimitive.DEFAULT_TRANSMISSION_COEFFICIENT`).
pub const MAKE_STEP_SURFACES_BLACK: bool = true;
pub const TRANSMISSION_COEFFICIENT: f64 = 0.96;

/// The sections from the keys: `lens_surface_f_min` and `lens_surface_f_max`, or
/// `number_of_lens_sections` (with `point`), not both.
pub fn sections(
    f_min: Option<f64>,
    f_max: Option<f64>,
    number: Option<u32>,
    point: DVec3,
    defaults: Option<(f64, f64)>,
    names: [&str; 3],
) -> Result<Sections, String> {
    match (f_min, f_max, number, defaults) {
        (None, None, Some(number), _) => Ok(Sections::Number { number, point }),
        (_, _, Some(_), _) => Err(format!(
            "give either {} and {} or {}, not both",
            names[0], names[1], names[2]
        )),
        (Some(min), Some(max), None, _) => Ok(Sections::FocalLengths { min, max }),
        (min, max, None, Some((dmin, dmax))) => Ok(Sections::FocalLengths {
            min: min.unwrap_or(dmin),
            max: max.unwrap_or(dmax),
        }),
        _ => Err(format!(
            "give {} and {}, or {}",
            names[0], names[1], names[2]
        )),
    }
}

/// `lenses = { type = "fresnel-lens-surface" }`: Dr TIM's `FresnelLensSurface`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FresnelLensSurfaceKeys {
    point_in_principalish_plane: Vector,
    outwards_principalish_plane_normal: Direction,
    focal_point: Vector,
    refractive_index: RefractiveIndex,
    optical_axis_direction: Direction,
    approximate_thickness: Positive,
    lens_surface_f_min: Option<Finite>,
    lens_surface_f_max: Option<Finite>,
    number_of_lens_sections: Option<u32>,
    make_step_surfaces_black: Option<bool>,
    transmission_coefficient: Option<Coefficient>,
}

impl FresnelLensSurfaceKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let point = self.point_in_principalish_plane.0;
        Ok(Box::new(FresnelLensSurface {
            point_in_principalish_plane: point,
            outwards_principalish_plane_normal: self.outwards_principalish_plane_normal.0,
            focal_point: self.focal_point.0,
            refractive_index: self.refractive_index.0,
            optical_axis_direction: self.optical_axis_direction.0,
            approximate_thickness: self.approximate_thickness.0,
            sections: sections(
                self.lens_surface_f_min.map(|f| f.0),
                self.lens_surface_f_max.map(|f| f.0),
                self.number_of_lens_sections,
                point,
                None,
                [
                    "lens_surface_f_min",
                    "lens_surface_f_max",
                    "number_of_lens_sections",
                ],
            )?,
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

    /// Dr TIM's `CollimatingFresnelLensSurfaceTest`: F at the origin, axis outwards −z, lens
    /// centre at z = 1, thickness 0.1, 3 sections.
    fn collimating() -> FresnelLensSurface {
        FresnelLensSurface {
            point_in_principalish_plane: DVec3::new(0.0, 0.0, 1.0),
            outwards_principalish_plane_normal: DVec3::NEG_Z,
            focal_point: DVec3::ZERO,
            refractive_index: 1.5,
            optical_axis_direction: DVec3::NEG_Z,
            approximate_thickness: 0.1,
            sections: Sections::Number {
                number: 3,
                point: DVec3::new(0.0, 0.0, 1.0),
            },
            make_step_surfaces_black: false,
            transmission_coefficient: 0.96,
        }
    }

    #[test]
    fn three_sections_as_dr_tims_loop_makes_them() {
        // f_max = 1 + 1e-4 + 0.3; Dr TIM's loop visits f_max − k 0.1 for k = 0 … 6, of which
        // 0.9001, 0.8001 and 0.7001 reach the plane z = 1 (f < f_P = 1).
        let parts = collimating().parts(None).unwrap();
        let names: Vec<&str> = parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "lens section 1",
                "lens section 2",
                "step 2",
                "lens section 3",
                "step 3"
            ]
        );
        // The first section's vertex is at F − f ŵ = (0, 0, 0.9001).
        let (t, _) = parts[0]
            .shape
            .intersect(DVec3::new(0.0, 0.0, -10.0), DVec3::Z, 0.0, 100.0)
            .unwrap();
        assert!((t - 10.9001).abs() < 1e-12, "{t}");
    }

    #[test]
    fn impossible_surfaces_are_refused() {
        let virtual_focus = FresnelLensSurface {
            focal_point: DVec3::new(0.0, 0.0, 2.0),
            sections: Sections::FocalLengths { min: 0.5, max: 0.9 },
            ..collimating()
        };
        assert!(virtual_focus.parts(None).unwrap_err().contains("virtual"));
        let in_plane = FresnelLensSurface {
            optical_axis_direction: DVec3::X,
            ..collimating()
        };
        assert!(in_plane.parts(None).unwrap_err().contains("lies in the"));
        let none = FresnelLensSurface {
            sections: Sections::FocalLengths { min: 1.5, max: 2.0 },
            ..collimating()
        };
        assert!(none.parts(None).unwrap_err().contains("no lens section"));
    }
}
