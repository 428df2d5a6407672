//! The `[camera]` table: projection, aperture and focus, velocity and shutter (§2), and the
//! stereo output (anaglyphs, frame packing, autostereograms).

use std::ops::Range;

use glam::DVec3;
use serde::Deserialize;

use super::parts::Spanned;
use super::{SceneFileError, Source};
use crate::cameras::{
    Camera, DEFAULT_FOCUS_DISTANCE, Focus, LensType, LenticularArrayKeys, PositiveSpaceOnlyKeys,
    Projection, Shutter, Transformation,
};
use crate::geometry::Shape;
use crate::geometry::ShapeKeys;
use crate::keys::{Direction, Finite, NonNegative, Positive, Vector};
use crate::math::{HE_NE_WAVELENGTH, LorentzTransform};
use crate::scene::{Packing, Stereo, studio};

/// Keys left out take the standard camera's values (so `--set camera.position=...` works on a
/// file without a `[camera]`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraSection {
    #[serde(rename = "type")]
    kind: Option<CameraKind>,
    position: Option<Vector>,
    view_direction: Option<Spanned<Vector>>,
    look_at: Option<Spanned<Vector>>,
    up: Option<Vector>,
    horizontal_view_angle_deg: Option<Spanned<Positive>>,
    view_width: Option<Spanned<Positive>>,
    aperture_radius: Option<Spanned<NonNegative>>,
    diffractive_aperture: Option<Spanned<bool>>,
    lambda: Option<Spanned<Positive>>,
    focus_distance: Option<Spanned<Positive>>,
    focus_surface: Option<Spanned<Vec<Spanned<ShapeKeys>>>>,
    beta: Option<Spanned<Vector>>,
    transformation: Option<Spanned<TransformationName>>,
    doppler: Option<Spanned<bool>>,
    shutter: Option<Spanned<ShutterName>>,
    shutter_time: Option<Spanned<Finite>>,
    detector_distance: Option<Spanned<Positive>>,
    lens_type: Option<Spanned<LensTypeName>>,
    shutter_plane_point: Option<Spanned<Vector>>,
    shutter_plane_normal: Option<Spanned<Direction>>,
    stereo: Option<Spanned<StereoName>>,
    eye_separation: Option<Spanned<Vector>>,
    autostereogram: Option<Spanned<AutostereogramSection>>,
    positive_space_only: Option<Spanned<PositiveSpaceOnlyKeys>>,
    lenticular_array: Option<Spanned<LenticularArrayKeys>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum CameraKind {
    Pinhole,
    #[serde(alias = "finite_aperture")]
    FiniteAperture,
    Orthographic,
    /// Dr TIM's `SurroundAnaglyphCamera` (`StandardPanorama3DGeometry`): a 360° panorama.
    Equirectangular,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum ShutterName {
    #[serde(alias = "detector_plane")]
    DetectorPlane,
    #[serde(alias = "entrance_pupil")]
    EntrancePupil,
    #[serde(alias = "focus_surface")]
    FocusSurface,
    #[serde(alias = "arbitrary_plane")]
    ArbitraryPlane,
    #[serde(alias = "fixed_point_surface")]
    FixedPointSurface,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum TransformationName {
    Lorentz,
    Galileo,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum LensTypeName {
    #[serde(alias = "ideal_lens")]
    IdealLens,
    #[serde(alias = "lens_hologram")]
    LensHologram,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum StereoName {
    None,
    Anaglyph,
    #[serde(alias = "colour_anaglyph", alias = "color-anaglyph")]
    ColourAnaglyph,
    #[serde(alias = "side_by_side")]
    SideBySide,
    #[serde(alias = "side_by_side_half")]
    SideBySideHalf,
    #[serde(alias = "top_bottom")]
    TopBottom,
    #[serde(alias = "top_bottom_half")]
    TopBottomHalf,
    Autostereogram,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct AutostereogramSection {
    eye_separation_px: Option<u32>,
    depth_of_field: Option<f64>,
    near: Option<NonNegative>,
    far: Option<Positive>,
    #[serde(default = "super::yes")]
    colour: bool,
}

/// What the `[camera]` table describes.
pub(super) struct CameraSetup {
    pub camera: Camera,
    pub focus_surface: Vec<Shape>,
    pub stereo: Stereo,
}

/// Makes the error of a camera key: at the key's span, or the table's.
type At<'a> = &'a dyn Fn(Option<Range<usize>>, &str) -> SceneFileError;

impl CameraSection {
    /// The camera, its focus surface and the stereo output; `span` is the table's.
    pub(super) fn build(
        self,
        source: &Source,
        span: Option<Range<usize>>,
    ) -> Result<CameraSetup, SceneFileError> {
        let at = |s: Option<Range<usize>>, m: &str| source.error(s.or(span.clone()), m.to_string());
        let position = self.position.map_or(studio::CAMERA_POSITION, |v| v.0);
        let view = match (&self.view_direction, &self.look_at) {
            (Some(_), Some(l)) => {
                return Err(at(
                    Some(l.span()),
                    "give the camera view_direction or look_at, not both",
                ));
            }
            (Some(v), None) => v.get_ref().0,
            (None, Some(l)) => {
                let view = l.get_ref().0 - position;
                if view == DVec3::ZERO {
                    return Err(at(
                        Some(l.span()),
                        "the camera's look_at point is its position: no direction to look in",
                    ));
                }
                view
            }
            (None, None) => studio::CAMERA_VIEW_DIRECTION,
        };
        let up = self.up.map_or(studio::CAMERA_UP, |v| v.0);
        let aperture = self
            .aperture_radius
            .as_ref()
            .map(|a| (a.span(), a.get_ref().0));
        let kind = self.kind.unwrap_or(match aperture {
            Some((_, r)) if r > 0.0 => CameraKind::FiniteAperture,
            _ => CameraKind::Pinhole,
        });
        let camera =
            Camera::new(position, view, up, self.projection(kind, &at)?).ok_or_else(|| {
                at(
                    None,
                    "camera view_direction and up must be non-zero and not parallel",
                )
            })?;
        let radius = aperture_radius(kind, aperture, &at)?;
        let diffraction = self.diffraction(kind, &at)?;
        let focus = self.focus(kind, &at)?;
        let shutter = self.shutter(kind, focus, &at)?;
        let focus_surface = focus_surface(self.focus_surface, source, &at)?;
        let boost = match &self.beta {
            Some(b) => LorentzTransform::new(b.get_ref().0).ok_or_else(|| {
                at(
                    Some(b.span()),
                    &format!(
                        "beta must have a magnitude below 1 (the speed of light), got {}",
                        b.get_ref().0.length()
                    ),
                )
            })?,
            None => *camera.boost(),
        };
        // Dr TIM's positive-space-only camera is at rest and monocular: its remap assumes rays
        // along the star's axis, which a moving camera's aberration and stereo eyes' focusing
        // would tilt.
        if self.positive_space_only.is_some() {
            let moving = self.beta.as_ref().filter(|b| b.get_ref().0 != DVec3::ZERO);
            if let Some(b) = moving {
                return Err(at(
                    Some(b.span()),
                    "a positive_space_only camera is at rest (its rays run along the star's axis): no beta",
                ));
            }
            let stereo = self
                .stereo
                .as_ref()
                .filter(|s| !matches!(s.get_ref(), StereoName::None));
            if let Some(s) = stereo {
                return Err(at(
                    Some(s.span()),
                    "a positive_space_only camera has one eye (its rays run along the star's axis): no stereo",
                ));
            }
        }
        let transformation = match self.transformation.as_ref().map(|t| *t.get_ref()) {
            None | Some(TransformationName::Lorentz) => Transformation::Lorentz,
            Some(TransformationName::Galileo) => Transformation::Galileo,
        };
        let doppler = self.doppler.as_ref().is_some_and(|d| *d.get_ref());
        if doppler && transformation == Transformation::Galileo {
            return Err(at(
                self.doppler.as_ref().map(Spanned::span),
                "doppler = true needs the Lorentz transformation (the headlight law is relativistic)",
            ));
        }
        let camera = camera
            .with_aperture(radius, focus)
            .with_shutter(
                shutter,
                self.shutter_time.as_ref().map_or(0.0, |t| t.get_ref().0),
                self.detector_distance
                    .as_ref()
                    .map_or(1.0, |d| d.get_ref().0),
            )
            .with_velocity(boost)
            .with_transformation(transformation)
            .with_doppler(doppler)
            .with_diffraction(diffraction);
        let stereo = stereo(
            &camera,
            kind,
            self.stereo.as_ref().map(|s| (*s.get_ref(), s.span())),
            self.eye_separation,
            self.autostereogram,
            &at,
        )?;
        Ok(CameraSetup {
            camera,
            focus_surface,
            stereo,
        })
    }

    /// The projection of a camera of `kind`: a view angle, or an orthographic view width.
    fn projection(&self, kind: CameraKind, at: At) -> Result<Projection, SceneFileError> {
        if kind == CameraKind::Equirectangular {
            let given = [
                (
                    "horizontal_view_angle_deg",
                    self.horizontal_view_angle_deg.as_ref().map(Spanned::span),
                ),
                ("view_width", self.view_width.as_ref().map(Spanned::span)),
                (
                    "positive_space_only",
                    self.positive_space_only.as_ref().map(Spanned::span),
                ),
                (
                    "lenticular_array",
                    self.lenticular_array.as_ref().map(Spanned::span),
                ),
            ];
            if let Some((key, span)) = given.into_iter().find(|(_, s)| s.is_some()) {
                return Err(at(
                    span,
                    &format!(
                        "an equirectangular camera sees all round (360° by 180°): it has no {key}"
                    ),
                ));
            }
            return Ok(Projection::Equirectangular);
        }
        if kind == CameraKind::Orthographic {
            if let Some(a) = &self.horizontal_view_angle_deg {
                return Err(at(
                    Some(a.span()),
                    "an orthographic camera has a view_width, not a view angle",
                ));
            }
            let w = self
                .view_width
                .as_ref()
                .ok_or_else(|| at(None, "an orthographic camera needs view_width"))?;
            let positive_space_only = match &self.positive_space_only {
                Some(p) => Some(p.get_ref().build().map_err(|e| at(Some(p.span()), &e))?),
                None => None,
            };
            let lenticular_array = match &self.lenticular_array {
                Some(l) if positive_space_only.is_some() => {
                    return Err(at(
                        Some(l.span()),
                        "a camera has either lenticular_array or positive_space_only, not both",
                    ));
                }
                Some(l) => Some(l.get_ref().build().map_err(|e| at(Some(l.span()), &e))?),
                None => None,
            };
            return Ok(Projection::Orthographic {
                view_width: w.get_ref().0,
                positive_space_only,
                lenticular_array,
            });
        }
        if let Some(l) = &self.lenticular_array {
            return Err(at(
                Some(l.span()),
                "lenticular_array is for orthographic cameras (type = \"orthographic\"), Dr TIM's LenticularArrayCamera",
            ));
        }
        if let Some(p) = &self.positive_space_only {
            return Err(at(
                Some(p.span()),
                "positive_space_only is for orthographic cameras (type = \"orthographic\"), Dr TIM's PositiveSpaceOnlyOrthographicCamera",
            ));
        }
        if let Some(w) = &self.view_width {
            return Err(at(
                Some(w.span()),
                "view_width is for orthographic cameras (type = \"orthographic\")",
            ));
        }
        let angle = self
            .horizontal_view_angle_deg
            .as_ref()
            .map_or(studio::CAMERA_VIEW_ANGLE_DEG, |a| a.get_ref().0);
        if angle >= 180.0 {
            let s = self.horizontal_view_angle_deg.as_ref().map(Spanned::span);
            return Err(at(s, "horizontal_view_angle_deg must be below 180"));
        }
        Ok(Projection::Perspective {
            horizontal_view_angle: angle.to_radians(),
        })
    }

    /// The shutter model and its keys: a lens type for the detector plane only, a plane for
    /// the arbitrary-plane shutter only (Dr TIM's GUI's point (0, 0, 0), normal (0, 0, 1)),
    /// and no opening time for the fixed-point-surface shutter, which needs a focus plane and
    /// the Lorentz transformation.
    fn shutter(&self, kind: CameraKind, focus: Focus, at: At) -> Result<Shutter, SceneFileError> {
        let name = self
            .shutter
            .as_ref()
            .map_or(ShutterName::EntrancePupil, |s| *s.get_ref());
        if kind == CameraKind::Equirectangular {
            if matches!(
                name,
                ShutterName::DetectorPlane | ShutterName::FixedPointSurface
            ) {
                return Err(at(
                    self.shutter.as_ref().map(Spanned::span),
                    "an equirectangular camera has no detector plane and no focus plane to keep fixed: its shutter is entrance-pupil, focus-surface or arbitrary-plane",
                ));
            }
            if let Some(d) = &self.detector_distance {
                return Err(at(
                    Some(d.span()),
                    "an equirectangular camera has no detector plane: no detector_distance",
                ));
            }
        }
        let only = |span: Option<Range<usize>>, key: &str, shutter: &str| {
            Err(at(
                span,
                &format!("{key} is for the {shutter} shutter (shutter = \"{shutter}\")"),
            ))
        };
        if let Some(l) = &self.lens_type
            && name != ShutterName::DetectorPlane
        {
            return only(Some(l.span()), "lens_type", "detector-plane");
        }
        if name != ShutterName::ArbitraryPlane {
            if let Some(p) = &self.shutter_plane_point {
                return only(Some(p.span()), "shutter_plane_point", "arbitrary-plane");
            }
            if let Some(n) = &self.shutter_plane_normal {
                return only(Some(n.span()), "shutter_plane_normal", "arbitrary-plane");
            }
        }
        Ok(match name {
            ShutterName::EntrancePupil => Shutter::EntrancePupil,
            ShutterName::DetectorPlane => Shutter::DetectorPlane(match &self.lens_type {
                Some(l) if *l.get_ref() == LensTypeName::LensHologram => LensType::LensHologram,
                _ => LensType::IdealLens,
            }),
            ShutterName::FocusSurface => Shutter::FocusSurface,
            ShutterName::ArbitraryPlane => Shutter::ArbitraryPlane {
                point: self
                    .shutter_plane_point
                    .as_ref()
                    .map_or(DVec3::ZERO, |p| p.get_ref().0),
                normal: self
                    .shutter_plane_normal
                    .as_ref()
                    .map_or(DVec3::Z, |n| n.get_ref().0),
            },
            ShutterName::FixedPointSurface => {
                if let Some(t) = &self.shutter_time {
                    return Err(at(
                        Some(t.span()),
                        "the fixed-point-surface shutter has no shutter_time: it times each ray so that the focus surface stays in place",
                    ));
                }
                if let Some(t) = self
                    .transformation
                    .as_ref()
                    .filter(|t| *t.get_ref() == TransformationName::Galileo)
                {
                    return Err(at(
                        Some(t.span()),
                        "the fixed-point-surface shutter needs the Lorentz transformation (under Galileo's, light does not travel at c in the camera frame, where the shutter times its rays)",
                    ));
                }
                if focus == Focus::Surface {
                    return Err(at(
                        self.focus_surface.as_ref().map(Spanned::span),
                        "the fixed-point-surface shutter needs a focus plane (focus_distance): where a chief ray misses a focus_surface there is no point to keep fixed",
                    ));
                }
                Shutter::FixedPointSurface
            }
        })
    }

    /// The wavelength with which a finite aperture diffracts (`diffractive_aperture`, Dr TIM's
    /// `diffractiveAperture`; `lambda`, by default Dr TIM's HeNe wavelength in metres), if it
    /// does: only a finite aperture can, and a `lambda` without `diffractive_aperture` would do
    /// nothing.
    fn diffraction(&self, kind: CameraKind, at: At) -> Result<Option<f64>, SceneFileError> {
        let diffracts = self.diffractive_aperture.as_ref().filter(|d| *d.get_ref());
        if let Some(d) = diffracts
            && kind != CameraKind::FiniteAperture
        {
            return Err(at(
                Some(d.span()),
                "diffractive_aperture is for the finite-aperture camera (type = \"finite-aperture\"): a pinhole, orthographic or equirectangular camera has no aperture to diffract",
            ));
        }
        match (diffracts, &self.lambda) {
            // A wavelength with the diffraction switched off explicitly is kept for when it is
            // switched on (`--set`, the preview's toggle); without that switch it would do
            // nothing.
            (None, Some(l)) if self.diffractive_aperture.is_none() => Err(at(
                Some(l.span()),
                "lambda is the wavelength with which the aperture diffracts: it needs diffractive_aperture = true",
            )),
            (None, _) => Ok(None),
            (Some(_), l) => Ok(Some(l.as_ref().map_or(HE_NE_WAVELENGTH, |l| l.get_ref().0))),
        }
    }

    /// A focus plane at a distance (for the equirectangular camera a sphere, by default at
    /// infinity: Dr TIM's `StandardPanorama3DGeometry`), or the focus surface's shapes.
    fn focus(&self, kind: CameraKind, at: At) -> Result<Focus, SceneFileError> {
        Ok(match (&self.focus_distance, &self.focus_surface) {
            (Some(_), Some(s)) => {
                return Err(at(
                    Some(s.span()),
                    "give focus_distance or focus_surface, not both",
                ));
            }
            (Some(d), None) => Focus::Plane {
                distance: d.get_ref().0,
            },
            (None, Some(_)) => Focus::Surface,
            (None, None) if kind == CameraKind::Equirectangular => Focus::Plane {
                distance: f64::INFINITY,
            },
            (None, None) => Focus::Plane {
                distance: DEFAULT_FOCUS_DISTANCE,
            },
        })
    }
}

/// The aperture radius of a camera of `kind`: only finite-aperture cameras have one (> 0).
fn aperture_radius(
    kind: CameraKind,
    aperture: Option<(Range<usize>, f64)>,
    at: At,
) -> Result<f64, SceneFileError> {
    match (kind, aperture) {
        (CameraKind::FiniteAperture, Some((_, r))) if r > 0.0 => Ok(r),
        (CameraKind::FiniteAperture, a) => Err(at(
            a.map(|a| a.0),
            "a finite-aperture camera needs aperture_radius > 0",
        )),
        (_, Some((s, r))) if r > 0.0 => Err(at(
            Some(s),
            "only a finite-aperture camera (type = \"finite-aperture\") has an aperture_radius",
        )),
        _ => Ok(0.0),
    }
}

/// The shapes of `focus_surface` (mesh files relative to the scene file).
fn focus_surface(
    shapes: Option<Spanned<Vec<Spanned<ShapeKeys>>>>,
    source: &Source,
    at: At,
) -> Result<Vec<Shape>, SceneFileError> {
    let mut focus_surface = Vec::new();
    if let Some(shapes) = shapes {
        if shapes.get_ref().is_empty() {
            return Err(at(
                Some(shapes.span()),
                "focus_surface needs at least one shape",
            ));
        }
        for shape in shapes.into_inner() {
            let span = shape.span();
            let parts = shape
                .into_inner()
                .parts(source.dir())
                .map_err(|e| at(Some(span.clone()), &format!("focus_surface: {e}")))?;
            focus_surface.extend(parts.into_iter().map(|(_, s)| s));
        }
    }
    Ok(focus_surface)
}

/// The stereo output `name` of `camera`, with its eye separation (by default 0.4 to the
/// camera's right; for the equirectangular camera Dr TIM's interpupillary distance 1, of
/// `StandardPanorama3DGeometry`) or autostereogram options.
fn stereo(
    camera: &Camera,
    kind: CameraKind,
    stereo: Option<(StereoName, Range<usize>)>,
    eye_separation: Option<Spanned<Vector>>,
    autostereogram_section: Option<Spanned<AutostereogramSection>>,
    at: At,
) -> Result<Stereo, SceneFileError> {
    let (name, name_span) = stereo.map_or((StereoName::None, None), |(n, s)| (n, Some(s)));
    let (right, _) = camera.right_up();
    let eye_span = eye_separation.as_ref().map(Spanned::span);
    let default = match kind {
        CameraKind::Equirectangular => 1.0,
        _ => 0.4,
    };
    let eye_separation = eye_separation
        .as_ref()
        .map_or(default * right, |e| e.get_ref().0);
    let two_eyes = !matches!(name, StereoName::None | StereoName::Autostereogram);
    if two_eyes && eye_separation == DVec3::ZERO {
        return Err(at(eye_span, "eye_separation must not be zero"));
    }
    let along = eye_separation.dot(camera.view_direction());
    if along.abs() > 1e-9 * eye_separation.length() {
        return Err(at(
            eye_span,
            &format!(
                "eye_separation must be perpendicular to the view direction (the eyes lie in the pupil plane); its component along it is {along}"
            ),
        ));
    }
    if kind == CameraKind::Equirectangular && name == StereoName::Autostereogram {
        return Err(at(
            name_span,
            "an autostereogram is made of a picture in perspective: not of an equirectangular camera's",
        ));
    }
    if let Some(a) = &autostereogram_section
        && name != StereoName::Autostereogram
    {
        return Err(at(
            Some(a.span()),
            "[camera.autostereogram] needs stereo = \"autostereogram\"",
        ));
    }
    let packing = |packing, half| Stereo::FramePacking {
        eye_separation,
        packing,
        half,
    };
    Ok(match name {
        StereoName::None => Stereo::Mono,
        StereoName::Anaglyph => Stereo::Anaglyph {
            eye_separation,
            colour: false,
        },
        StereoName::ColourAnaglyph => Stereo::Anaglyph {
            eye_separation,
            colour: true,
        },
        StereoName::SideBySide => packing(Packing::SideBySide, false),
        StereoName::SideBySideHalf => packing(Packing::SideBySide, true),
        StereoName::TopBottom => packing(Packing::TopBottom, false),
        StereoName::TopBottomHalf => packing(Packing::TopBottom, true),
        StereoName::Autostereogram => autostereogram(autostereogram_section, at)?,
    })
}

/// The autostereogram options of `[camera.autostereogram]`, if given.
fn autostereogram(
    section: Option<Spanned<AutostereogramSection>>,
    at: At,
) -> Result<Stereo, SceneFileError> {
    let (a, a_span) = match section {
        Some(a) => {
            let span = a.span();
            (a.into_inner(), Some(span))
        }
        None => (
            AutostereogramSection {
                eye_separation_px: None,
                depth_of_field: None,
                near: None,
                far: None,
                colour: true,
            },
            None,
        ),
    };
    let near = a.near.map(|n| n.0);
    let far = a.far.map(|f| f.0);
    if let (Some(n), Some(f)) = (near, far)
        && n >= f
    {
        return Err(at(
            a_span,
            &format!("autostereogram near ({n}) must be less than far ({f})"),
        ));
    }
    let depth_of_field = a.depth_of_field.unwrap_or(1.0 / 3.0);
    if !(depth_of_field > 0.0 && depth_of_field < 1.0) {
        return Err(at(
            a_span,
            &format!("autostereogram depth_of_field must be between 0 and 1, got {depth_of_field}"),
        ));
    }
    Ok(Stereo::Autostereogram {
        eye_separation_px: a.eye_separation_px,
        depth_of_field,
        colour: a.colour,
        near,
        far,
    })
}
