//! Dr TIM's `EditableGCLAsPinchTransformationWindow` (and its older
//! `EditablePinchTransformationWindow`, whose element types both make the same gCLAs): a window
//! of width w, height h and thickness t that funnels the light through an opening smaller than
//! itself, a transformation-optics device in which physical space is "pinched" with respect to
//! electromagnetic space, while the view through it is as through an open window.
//!
//! Across the window (right x̂, up ŷ, ẑ = x̂ × ŷ from front to back), with corners p₁ (front
//! bottom), p₂ (front top), p₆ (back top), p₅ (back bottom) on its left side and p₉ the point
//! of the middle plane (1 − s) h above the bottom (s the central strain factor), physical space
//! is cut into the triangular prisms (p₁, p₂, p₉), (p₂, p₆, p₉) and (p₆, p₅, p₉) along x̂, and
//! the wedge (p₅, p₁, p₉) below, which light does not reach (Dr TIM's wall closes it). Seen
//! from outside, each prism is the one with p₉ moved to the bottom of the middle plane, p₉′:
//! the three tile the whole window. Each region is seen through that affine map, and each face
//! between them, the front window, the inner front and back diagonal windows and the back
//! window, is the homogeneous planar imaging surface (gCLAs) that images the region behind it
//! into the one in front.

use glam::{DMat4, DVec3};
use serde::Deserialize;

use super::affine_regions::{Region, affine, imaging_between};
use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{ConvexPolygon, Parallelepiped, Parallelogram, Shape};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector, throughput};
use crate::math::Colour;
use crate::surfaces::metatoys::{Apertures, Transmission};
use crate::surfaces::{Coloured, ConfocalLensletArrays, Surface};

/// Dr TIM's `GCLAsTransmissionCoefficientCalculationMethodType`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum TransmissionMethod {
    Constant,
    /// With Dr TIM's default apertures.
    Geometric,
    GeometricBest,
}

/// Dr TIM's wall round the window (`EditableRectangularFrame`) and its wedge.
#[derive(Debug, Clone, PartialEq)]
pub struct Wall {
    pub additional_wall_width: f64,
    pub additional_wall_height: f64,
    pub additional_wall_thickness: f64,
    pub show_wall_wedge: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct PinchTransformationWindow {
    pub centre: DVec3,
    /// Unit x̂ (to the right) and ŷ (upwards), not parallel.
    pub x: DVec3,
    pub y: DVec3,
    pub width: f64,
    pub height: f64,
    pub thickness: f64,
    pub central_strain_factor: f64,
    pub transmission: Transmission,
    pub wall: Option<Wall>,
}

/// Dr TIM's wall: `SurfaceColour.GREY80_MATT`.
const WALL_GREY: f64 = 0.8;

impl PinchTransformationWindow {
    /// ẑ, from the front to the back.
    fn z(&self) -> DVec3 {
        self.x.cross(self.y).normalize()
    }

    /// Dr TIM's points p₁ … p₁₀, and p₉′ and p₁₀′ (indices 11, 12): p₁–p₄ the front corners
    /// (left bottom, left top, right top, right bottom), p₅–p₈ the back ones, p₉ and p₁₀ the
    /// inner vertices on the left and right, p₉′ and p₁₀′ where they are seen.
    fn points(&self) -> [DVec3; 13] {
        let (l, r) = (-0.5 * self.width * self.x, 0.5 * self.width * self.x);
        let (d, u) = (-0.5 * self.height * self.y, 0.5 * self.height * self.y);
        let (f, b) = (
            -0.5 * self.thickness * self.z(),
            0.5 * self.thickness * self.z(),
        );
        let c = self.centre;
        let raised = (1.0 - self.central_strain_factor) * self.height * self.y;
        [
            DVec3::ZERO,
            c + l + d + f,
            c + l + u + f,
            c + r + u + f,
            c + r + d + f,
            c + l + d + b,
            c + l + u + b,
            c + r + u + b,
            c + r + d + b,
            c + l + d + raised,
            c + r + d + raised,
            c + l + d,
            c + r + d,
        ]
    }

    /// The region of the prism of left-side corners `a`, `b` and p₉, seen through the affine
    /// map that keeps `a` and `b` (and the right side's) and moves p₉ to p₉′.
    fn region(&self, p: &[DVec3; 13], a: usize, b: usize) -> Result<Region, String> {
        let along = self.width * self.x;
        let seen = affine(
            [p[a], p[b], p[9], p[a] + along],
            [p[a], p[b], p[11], p[a] + along],
        )
        .ok_or("the window's prisms are flat: its directions or sizes are degenerate")?;
        Ok(Region {
            seen,
            inside: (p[a] + p[b] + p[9] + along * 1.5) / 3.0,
        })
    }

    fn window(
        &self,
        name: &str,
        vertices: [DVec3; 4],
        r1: &Region,
        r2: &Region,
    ) -> Result<Part, String> {
        let imaging = imaging_between(&vertices, r1, r2);
        let arrays = ConfocalLensletArrays::imaging(imaging, self.transmission)
            .map_err(|e| format!("{name}: {e}"))?;
        Ok(Part {
            shape: Shape::ConvexPolygon(
                ConvexPolygon::new(vertices.to_vec()).map_err(|e| format!("{name}: {e}"))?,
            ),
            name: name.into(),
            surface: Surface::ConfocalLensletArrays(arrays),
            edge: false,
        })
    }

    /// Dr TIM's wall: a plate of thickness t + the additional thickness round the window's
    /// opening, the additional width to its left and right and height above and below, in
    /// four sides, and the wedge's front and back; opaque, they throw shadows whatever the
    /// window's `shadow_throwing` (Dr TIM's goes to the gCLAs only).
    fn wall(&self, wall: &Wall, p: &[DVec3; 13]) -> Result<Vec<Part>, String> {
        let grey = Surface::Coloured(Coloured::matt(Colour::splat(WALL_GREY)));
        let (w, h) = (wall.additional_wall_width, wall.additional_wall_height);
        let depth = (self.thickness + wall.additional_wall_thickness) * self.z();
        let side = |name: &str, across: f64, up: f64, size_x: f64, size_y: f64| {
            let centre = self.centre + across * self.x + up * self.y;
            Parallelepiped::new(centre, [size_x * self.x, size_y * self.y, depth])
                .map(|s| Part {
                    shape: Shape::Parallelepiped(s),
                    name: name.into(),
                    surface: grey.clone(),
                    edge: true,
                })
                .map_err(|e| format!("{name}: {e}"))
        };
        let (half_w, half_h) = (0.5 * self.width, 0.5 * self.height);
        let mut parts = vec![
            side(
                "wall left side",
                -half_w - 0.5 * w,
                0.0,
                w,
                self.height + 2.0 * h,
            )?,
            side(
                "wall right side",
                half_w + 0.5 * w,
                0.0,
                w,
                self.height + 2.0 * h,
            )?,
            side("wall bottom side", 0.0, -half_h - 0.5 * h, self.width, h)?,
            side("wall top side", 0.0, half_h + 0.5 * h, self.width, h)?,
        ];
        if wall.show_wall_wedge {
            for (name, corner) in [("front of wedge", p[1]), ("back of wedge", p[5])] {
                let shape = Parallelogram::new(corner, self.width * self.x, p[9] - corner)
                    .map_err(|e| format!("{name}: {e}"))?;
                parts.push(Part {
                    shape: Shape::Parallelogram(shape),
                    name: name.into(),
                    surface: grey.clone(),
                    edge: true,
                });
            }
        }
        Ok(parts)
    }

    /// Dr TIM's frames: spheres at the ten points, cylinders along the window's edges, the
    /// diagonals and the wedge's edges.
    fn frames(&self, e: &Edges, p: &[DVec3; 13]) -> Result<Vec<Part>, String> {
        let spheres = [
            ("front left bottom corner", 1),
            ("front left top corner", 2),
            ("front right top corner", 3),
            ("front right bottom corner", 4),
            ("back left bottom corner", 5),
            ("back left top corner", 6),
            ("back right top corner", 7),
            ("back right bottom corner", 8),
            ("left inner vertex", 9),
            ("right inner vertex", 10),
        ];
        let cylinders = [
            ("front left cylinder", 1, 2),
            ("front top cylinder", 2, 3),
            ("front right cylinder", 3, 4),
            ("front bottom cylinder", 4, 1),
            ("back left cylinder", 5, 6),
            ("back top cylinder", 6, 7),
            ("back right cylinder", 7, 8),
            ("back bottom cylinder", 8, 5),
            ("left front diagonal cylinder", 2, 9),
            ("left back diagonal cylinder", 6, 9),
            ("right front diagonal cylinder", 3, 10),
            ("right back diagonal cylinder", 7, 10),
            ("bottom central cylinder", 9, 10),
            ("left top cylinder", 2, 6),
            ("left bottom front cylinder", 1, 9),
            ("left bottom back cylinder", 9, 5),
            ("right top cylinder", 3, 7),
            ("right bottom front cylinder", 4, 10),
            ("right bottom back cylinder", 10, 8),
        ];
        let mut parts = Vec::new();
        for (name, i) in spheres {
            parts.push(e.vertex(name.into(), p[i])?);
        }
        for (name, i, j) in cylinders {
            parts.push(e.part(name.into(), p[i], p[j])?);
        }
        Ok(parts)
    }
}

impl LensDevice for PinchTransformationWindow {
    /// The gCLAs `front window`, `inner front diagonal window`, `inner back diagonal window`
    /// and `back window`; with the wall, `wall left side` (and right, bottom, top), `front of
    /// wedge` and `back of wedge`; with `edges` Dr TIM's frames (`front left bottom corner`,
    /// ..., `left inner vertex`, `right inner vertex`, `front left cylinder`, ...).
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let p = self.points();
        let depth = self.thickness * self.z();
        let outside = |side: f64| Region {
            seen: DMat4::IDENTITY,
            inside: self.centre + side * depth,
        };
        let front = self.region(&p, 1, 2)?;
        let top = self.region(&p, 2, 6)?;
        let back = self.region(&p, 6, 5)?;
        let mut parts = vec![
            self.window(
                "front window",
                [p[1], p[2], p[3], p[4]],
                &outside(-1.0),
                &front,
            )?,
            self.window(
                "inner front diagonal window",
                [p[9], p[2], p[3], p[10]],
                &front,
                &top,
            )?,
            self.window(
                "inner back diagonal window",
                [p[9], p[6], p[7], p[10]],
                &top,
                &back,
            )?,
            self.window(
                "back window",
                [p[5], p[6], p[7], p[8]],
                &back,
                &outside(1.0),
            )?,
        ];
        if let Some(wall) = &self.wall {
            parts.extend(self.wall(wall, &p)?);
        }
        if let Some(e) = edges {
            parts.extend(self.frames(e, &p)?);
        }
        Ok(parts)
    }

    /// Dr TIM's frames: hidden, radius 0.01, `SurfaceColour.WHITE_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults {
            colour: Colour::splat(1.0),
            ..EdgeDefaults::HIDDEN_RED
        }
    }

    /// Dr TIM's window throws shadows (its `shadowThrowing`, true by default).
    fn shadow_throwing(&self) -> bool {
        true
    }
}

/// `lenses = { type = "gclas-pinch-transformation-window" }`: Dr TIM's
/// `EditableGCLAsPinchTransformationWindow`, with the defaults of its constructor `(parent,
/// studio)` for every key not given.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GclasPinchTransformationWindowKeys {
    centre: Option<Vector>,
    right_direction: Option<Direction>,
    up_direction: Option<Direction>,
    width: Option<Positive>,
    height: Option<Positive>,
    thickness: Option<Positive>,
    central_strain_factor: Option<Finite>,
    gclas_transmission_coefficient: Option<Coefficient>,
    gclas_transmission_coefficient_method: Option<TransmissionMethod>,
    show_wall: Option<bool>,
    additional_wall_width: Option<Positive>,
    additional_wall_height: Option<Positive>,
    additional_wall_thickness: Option<Positive>,
    show_wall_wedge: Option<bool>,
}

impl GclasPinchTransformationWindowKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let x = self.right_direction.map_or(DVec3::X, |d| d.0);
        let y = self.up_direction.map_or(DVec3::Y, |d| d.0);
        if x.cross(y).length() <= 1e-6 {
            return Err("up_direction must not be along right_direction".into());
        }
        let s = self.central_strain_factor.map_or(0.5, |s| s.0);
        if !(0.001..=0.999).contains(&s) {
            return Err(format!(
                "central_strain_factor = {s} must lie between 0.001 and 0.999: the opening the \
                 light is funnelled through is that fraction of the window's height"
            ));
        }
        let method = self
            .gclas_transmission_coefficient_method
            .unwrap_or(TransmissionMethod::GeometricBest);
        let transmission = match method {
            TransmissionMethod::Constant => {
                Transmission::Constant(throughput(self.gclas_transmission_coefficient))
            }
            TransmissionMethod::Geometric | TransmissionMethod::GeometricBest => {
                if self.gclas_transmission_coefficient.is_some() {
                    return Err("gclas_transmission_coefficient is only used with \
                         gclas_transmission_coefficient_method = \"constant\" (the others, \
                         the default \"geometric-best\" and \"geometric\", compute it)"
                        .into());
                }
                match method {
                    TransmissionMethod::Geometric => Transmission::Geometric(Apertures::default()),
                    _ => Transmission::GeometricBest,
                }
            }
        };
        let show_wall = self.show_wall.unwrap_or(true);
        let wall_keys = [
            self.additional_wall_width.is_some(),
            self.additional_wall_height.is_some(),
            self.additional_wall_thickness.is_some(),
            self.show_wall_wedge.is_some(),
        ];
        if !show_wall && wall_keys.contains(&true) {
            return Err(
                "the additional_wall_... and show_wall_wedge keys belong to the wall, \
                        which show_wall = false leaves out"
                    .into(),
            );
        }
        let window = PinchTransformationWindow {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 5.0), |c| c.0),
            x: x.normalize(),
            y: y.normalize(),
            width: self.width.map_or(1.0, |w| w.0),
            height: self.height.map_or(1.0, |h| h.0),
            thickness: self.thickness.map_or(0.5, |t| t.0),
            central_strain_factor: s,
            transmission,
            wall: show_wall.then(|| Wall {
                additional_wall_width: self.additional_wall_width.map_or(1.0, |w| w.0),
                additional_wall_height: self.additional_wall_height.map_or(1.0, |h| h.0),
                additional_wall_thickness: self.additional_wall_thickness.map_or(0.2, |t| t.0),
                show_wall_wedge: self.show_wall_wedge.unwrap_or(true),
            }),
        };
        // Refuse bad parameters when the scene is read.
        window.parts(None)?;
        Ok(Box::new(window))
    }
}
