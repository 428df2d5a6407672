//! Dr TIM's `RefractiveViewRotator` (research/viewRotation/RefractiveViewRotator.java): a
//! sheet of refractive wedges, one per pixel of the ocular plane, each of which refracts the
//! ray from the eye through its pixel's centre towards the point of a view plane that the
//! eye would see in the direction rotated by θ about an axis (and magnified by M), so that,
//! from the eye, the view plane looks rotated (`SurfaceOfRefractiveViewRotator`, without its
//! derivative-control surfaces). Dr TIM builds the wedges voxel by voxel inside a bounding box;
//! timbre traces the glass as one exact solid, [`crate::geometry::ViewRotator`], whose doc gives
//! the construction. Dr TIM's optional diffraction blur (its `BoundingBoxSurface`) changes the
//! direction of every ray leaving the box by a pixel's single-slit diffraction; here that is a
//! second part, the box's surface, just outside the glass's.

use glam::{DVec2, DVec3};
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{Parallelepiped, RefractiveIndex, Shape, ViewRotator, ViewRotatorSpec};
use crate::keys::{
    Coefficient, Direction, Finite, NonNegative, NonZero, Positive, Vector, coefficient,
};
use crate::surfaces::appearance::TwoSided;
use crate::surfaces::metatoys::{Blur, Pixellation, Pixels};
use crate::surfaces::{Refractive, Surface, Transparent};

#[derive(Debug, Clone, PartialEq)]
pub struct RefractiveViewRotator {
    pub spec: ViewRotatorSpec,
    pub transmission_coefficient: f64,
    /// The wavelength of the diffraction blur, if simulated.
    pub diffraction_blur: Option<f64>,
}

/// Dr TIM's wavelength for the blur (`SurfaceOfPixelArray.getLambda`: green, in metres).
const BLUR_LAMBDA: f64 = 550e-9;

impl RefractiveViewRotator {
    /// The part that blurs rays leaving the box: the box's surface, each face moved out by
    /// g = 10⁻⁶ (1 + r), r the box's reach from the origin, so that a ray leaving the glass
    /// through a face of the box meets it next: g exceeds the distance 10⁻⁹ (1 + |p|) a ray
    /// leaving a surface at p travels before it may hit another wherever the device is placed
    /// within 1000 (1 + r) of the origin. From outside it is transparent.
    fn blur(&self, lambda: f64) -> Result<Part, String> {
        let spec = &self.spec;
        let [a, b, c] = spec.bounding_box_span_vectors;
        let reach = [a, b, c]
            .iter()
            .fold(spec.bounding_box_centre.abs(), |r, s| r + 0.5 * s.abs())
            .max_element();
        let gap = 1e-6 * (1.0 + reach);
        let volume = a.dot(b.cross(c));
        // A span's faces are 1/|its reciprocal vector| apart.
        let widen = |span: DVec3, reciprocal: DVec3| {
            span * (1.0 + 2.0 * gap * reciprocal.length() / volume.abs())
        };
        let spans = [
            widen(a, b.cross(c)),
            widen(b, c.cross(a)),
            widen(c, a.cross(b)),
        ];
        let shape = Parallelepiped::new(spec.bounding_box_centre, spans)
            .map_err(|e| format!("the diffraction blur's box: {e}"))?;
        let pixels = Pixels {
            size: DVec2::new(spec.period_vector_1.length(), spec.period_vector_2.length()),
            lambda,
            blur: Some(Blur::SingleSlit),
            ray_offset: false,
            sides: Some([
                spec.period_vector_1.normalize(),
                spec.period_vector_2.normalize(),
            ]),
        };
        Ok(Part {
            name: "diffraction blur".into(),
            shape: Shape::Parallelepiped(shape),
            surface: Surface::TwoSided(TwoSided {
                sides: Box::new([
                    Surface::Pixellation(Pixellation { pixels }),
                    Surface::Transparent(Transparent {
                        transmission_coefficient: 1.0,
                    }),
                ]),
            }),
            edge: false,
        })
    }
}

impl LensDevice for RefractiveViewRotator {
    /// `wedges`, glass of index n, and with the diffraction blur `diffraction blur`, the box's
    /// surface; no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a refractive view rotator has no edges to show (show_edges)".into());
        }
        let shape = ViewRotator::new(&self.spec).map_err(|e| e.to_string())?;
        let mut parts = vec![Part {
            name: "wedges".into(),
            shape: Shape::ViewRotator(Box::new(shape)),
            surface: Surface::Refractive(Refractive {
                index_ratio: self.spec.refractive_index,
                transmission_coefficient: self.transmission_coefficient,
            }),
            edge: false,
        }];
        if let Some(lambda) = self.diffraction_blur {
            parts.push(self.blur(lambda)?);
        }
        Ok(parts)
    }
}

/// `lenses = { type = "refractive-view-rotator" }`: Dr TIM's `RefractiveViewRotator` (it has
/// no editable form, so its geometry is required; the magnification and the transmission
/// coefficient default to the research programs' 1, the derivative-control thickness to 0 and
/// the diffraction blur to off).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefractiveViewRotatorKeys {
    bounding_box_centre: Vector,
    bounding_box_span_vector_1: Vector,
    bounding_box_span_vector_2: Vector,
    bounding_box_span_vector_3: Vector,
    eye_position: Vector,
    ocular_plane_centre: Vector,
    period_vector_1: Vector,
    period_vector_2: Vector,
    rotation_angle_deg: Finite,
    rotation_axis_direction: Direction,
    magnification_factor: Option<NonZero>,
    view_plane_point: Vector,
    view_plane_normal: Direction,
    refractive_index: RefractiveIndex,
    wedge_thickness: NonNegative,
    derivative_control_thickness: Option<Finite>,
    simulate_diffraction_blur: Option<bool>,
    lambda: Option<Positive>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl RefractiveViewRotatorKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let spec = ViewRotatorSpec {
            bounding_box_centre: self.bounding_box_centre.0,
            bounding_box_span_vectors: [
                self.bounding_box_span_vector_1.0,
                self.bounding_box_span_vector_2.0,
                self.bounding_box_span_vector_3.0,
            ],
            eye_position: self.eye_position.0,
            ocular_plane_centre: self.ocular_plane_centre.0,
            period_vector_1: self.period_vector_1.0,
            period_vector_2: self.period_vector_2.0,
            rotation_angle_deg: self.rotation_angle_deg.0,
            rotation_axis_direction: self.rotation_axis_direction.0,
            magnification_factor: self.magnification_factor.map_or(1.0, |m| m.0),
            view_plane_point: self.view_plane_point.0,
            view_plane_normal: self.view_plane_normal.0,
            refractive_index: self.refractive_index.0,
            wedge_thickness: self.wedge_thickness.0,
            derivative_control_thickness: self.derivative_control_thickness.map_or(0.0, |d| d.0),
        };
        let diffraction_blur = match (self.simulate_diffraction_blur, self.lambda) {
            (Some(true), lambda) => Some(lambda.map_or(BLUR_LAMBDA, |l| l.0)),
            (_, None) => None,
            (_, Some(_)) => {
                return Err(
                    "lambda is the wavelength of the diffraction blur: it needs \
                     simulate_diffraction_blur = true"
                        .into(),
                );
            }
        };
        // Refuse a geometry the glass cannot follow here, where the key's line is known.
        ViewRotator::new(&spec).map_err(|e| e.to_string())?;
        Ok(Box::new(RefractiveViewRotator {
            spec,
            transmission_coefficient: coefficient(self.transmission_coefficient),
            diffraction_blur,
        }))
    }
}
