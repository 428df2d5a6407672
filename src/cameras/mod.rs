//! Cameras: where primary rays start, in which directions and at what times.
//!
//! One camera type covers TIM's pinhole, finite-aperture ("any focus surface") and orthographic
//! cameras and Dr TIM's equirectangular panoramas (`SurroundAnaglyphCamera`), each optionally
//! moving at relativistic speed (§2). Rays are generated in the camera
//! frame; [`Camera::to_scene_frame`] Lorentz-transforms them (or, as an option, Galileo-
//! transforms them) into the scene frame. The two frames' coordinates coincide at time 0, and
//! the boost is taken about the camera position (the pupil centre): at t = 0 the camera is
//! where `position` says, in both frames. As an option beyond Dr TIM, the colour seen along a
//! ray is Doppler-shifted ([`doppler`]). A finite aperture may diffract its rays
//! ([`aperture_diffraction`], Dr TIM's `CircularApertureDiffraction`).

pub mod aperture_diffraction;
pub mod doppler;
mod lenticular_array;
mod positive_space_only;
mod shutter;

pub use lenticular_array::{LenticularArray, LenticularArrayKeys};
pub use positive_space_only::{PositiveSpaceOnly, PositiveSpaceOnlyKeys, Stretching};
pub use shutter::{LensType, Shutter, ShutterGeometry};

use std::fmt;

use glam::DVec3;

use crate::math::{Colour, LorentzTransform, Ray, galilean_backwards_direction, galilean_event};

/// How events and ray directions go from the camera frame into the scene frame (Dr TIM's
/// `SpaceTimeTransformationType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Transformation {
    /// Eqs 1 and 4 (Dr TIM's GUI's default).
    #[default]
    Lorentz,
    /// The Galilean transformation, light travelling at c in the scene frame
    /// ([`galilean_event`], [`galilean_backwards_direction`]).
    Galileo,
}

/// How detector positions map to chief rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Chief rays through the pupil centre, following TIM's convention: the detector lies at
    /// distance 1 behind the pinhole (mirrored in front of it), and the horizontal view angle
    /// spans the *centres* of the outermost pixel columns, so the pixel pitch is
    /// 2 tan(angle/2) / (width − 1). Pixels are square; the rows are centred on the view
    /// direction.
    Perspective { horizontal_view_angle: f64 },
    /// Chief rays parallel to the view direction, from the points of the plane through the
    /// camera position; `view_width` spans the centres of the outermost pixel columns. With
    /// `positive_space_only`, the points are those it maps each pixel's to, about the camera
    /// position, azimuth 0 along the camera's right ([`PositiveSpaceOnly`]).
    /// With `lenticular_array`, each pixel column looks along its own tilt towards the right
    /// ([`LenticularArray`]).
    Orthographic {
        view_width: f64,
        positive_space_only: Option<PositiveSpaceOnly>,
        lenticular_array: Option<LenticularArray>,
    },
    /// The whole sphere of directions, 360° by 180°, in equal steps of longitude and latitude
    /// (an equirectangular panorama, Dr TIM's `SurroundAnaglyphCamera` with its
    /// `StandardPanorama3DGeometry`): column x + ½ of W is at azimuth φ = 2π (x + ½) / W from
    /// straight behind, row y + ½ of H at polar angle θ = π (y + ½) / H from `up`; the view
    /// direction is the centre of the picture and the camera's right three quarters across.
    /// A stereo eye's offset turns with the azimuth (omnidirectional stereo), and the focus
    /// "plane" is the sphere of radius `focus_distance` about the camera.
    Equirectangular,
}

/// Where the images of the detector pixels are (TIM can focus on almost any surface).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Focus {
    /// The plane perpendicular to the view direction at this distance ahead of the pupil.
    Plane { distance: f64 },
    /// The scene's focus-surface objects, in the camera frame: a pixel's image is where its
    /// chief ray first meets them, or at infinity if it misses them.
    Surface,
}

/// Focus distance when none is given, in floor tiles.
pub const DEFAULT_FOCUS_DISTANCE: f64 = 10.0;

#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// Centre of the entrance pupil (the pinhole).
    position: DVec3,
    /// Unit view direction, perpendicular to the pupil disk.
    view_direction: DVec3,
    /// Unit "right" on the detector (up × view).
    right: DVec3,
    /// Unit "up" on the detector, perpendicular to the view direction.
    up: DVec3,
    projection: Projection,
    /// Detector pitch per pixel at unit distance (perspective) or in length (orthographic),
    /// times (width − 1).
    span: f64,
    aperture_radius: f64,
    focus: Focus,
    shutter: Shutter,
    shutter_time: f64,
    /// Distance i of the detector plane behind the pupil (detector-plane shutter).
    detector_distance: f64,
    /// Camera velocity.
    boost: LorentzTransform,
    transformation: Transformation,
    /// Whether colours are Doppler-shifted and brightened (Lorentz only).
    doppler: bool,
    /// Offset of this eye's pupil from `position` (stereo views); zero for a single camera.
    eye: DVec3,
    /// The wavelength with which the aperture diffracts, if it does.
    diffraction: Option<f64>,
}

impl Camera {
    /// A camera with this projection and no aperture, at rest, shutter in the entrance pupil at
    /// t = 0, focused at [`DEFAULT_FOCUS_DISTANCE`]. `up` need not be
    /// perpendicular to `view_direction`, only not parallel to it; both are normalised here.
    /// Returns `None` for parallel or zero vectors.
    pub fn new(
        position: DVec3,
        view_direction: DVec3,
        up: DVec3,
        projection: Projection,
    ) -> Option<Camera> {
        let view = view_direction.try_normalize()?;
        // With x right, y up and the view along +z (TIM's convention), right = up × view.
        let right = up.cross(view).try_normalize()?;
        let up = view.cross(right);
        let span = match projection {
            Projection::Perspective {
                horizontal_view_angle,
            } => 2.0 * (0.5 * horizontal_view_angle).tan(),
            Projection::Orthographic { view_width, .. } => view_width,
            Projection::Equirectangular => 0.0,
        };
        Some(Camera {
            position,
            view_direction: view,
            right,
            up,
            projection,
            span,
            aperture_radius: 0.0,
            focus: Focus::Plane {
                distance: DEFAULT_FOCUS_DISTANCE,
            },
            shutter: Shutter::EntrancePupil,
            shutter_time: 0.0,
            detector_distance: 1.0,
            boost: LorentzTransform::new(DVec3::ZERO).expect("zero velocity"),
            transformation: Transformation::Lorentz,
            doppler: false,
            eye: DVec3::ZERO,
            diffraction: None,
        })
    }

    /// A pinhole camera with the given horizontal view angle (radians).
    pub fn pinhole(
        position: DVec3,
        view_direction: DVec3,
        up: DVec3,
        horizontal_view_angle: f64,
    ) -> Option<Camera> {
        Camera::new(
            position,
            view_direction,
            up,
            Projection::Perspective {
                horizontal_view_angle,
            },
        )
    }

    /// A finite entrance pupil of this radius (0: a pinhole), focused on `focus`.
    pub fn with_aperture(self, radius: f64, focus: Focus) -> Camera {
        Camera {
            aperture_radius: radius,
            focus,
            ..self
        }
    }

    /// The shutter model, its opening time t_s and the detector distance i behind the pupil.
    pub fn with_shutter(self, shutter: Shutter, time: f64, detector_distance: f64) -> Camera {
        Camera {
            shutter,
            shutter_time: time,
            detector_distance,
            ..self
        }
    }

    /// The camera moving with velocity `boost` through the scene.
    pub fn with_velocity(self, boost: LorentzTransform) -> Camera {
        Camera { boost, ..self }
    }

    /// The transformation into the scene frame (Lorentz by default).
    pub fn with_transformation(self, transformation: Transformation) -> Camera {
        Camera {
            transformation,
            ..self
        }
    }

    /// Whether colours are Doppler-shifted and brightened by the camera's motion
    /// ([`doppler`]; with the Lorentz transformation, off by default).
    pub fn with_doppler(self, doppler: bool) -> Camera {
        Camera { doppler, ..self }
    }

    /// An aperture that diffracts light of wavelength `lambda` (in the scene's units of length;
    /// `None`: none), as Dr TIM's `AnyFocusSurfaceCamera` with `diffractiveAperture`
    /// ([`Self::diffracted`]). Meant for a finite aperture: a pinhole's would lose every ray.
    pub fn with_diffraction(self, lambda: Option<f64>) -> Camera {
        Camera {
            diffraction: lambda,
            ..self
        }
    }

    /// The view of an eye whose pupil is `offset` from this camera's, imaging each pixel onto
    /// the same point of the focus surface (both eyes converge there). The eyes lie in the
    /// pupil plane: the offset's component along the view direction is dropped.
    pub fn eye(&self, offset: DVec3) -> Camera {
        Camera {
            eye: offset.reject_from_normalized(self.view_direction),
            ..self.clone()
        }
    }

    pub fn position(&self) -> DVec3 {
        self.position
    }

    /// Unit view direction.
    pub fn view_direction(&self) -> DVec3 {
        self.view_direction
    }

    /// Unit right and up directions of the detector.
    pub fn right_up(&self) -> (DVec3, DVec3) {
        (self.right, self.up)
    }

    pub fn projection(&self) -> Projection {
        self.projection
    }

    pub fn aperture_radius(&self) -> f64 {
        self.aperture_radius
    }

    pub fn focus(&self) -> Focus {
        self.focus
    }

    /// The wavelength with which the aperture diffracts, if it does.
    pub fn diffraction(&self) -> Option<f64> {
        self.diffraction
    }

    pub fn shutter(&self) -> (Shutter, f64) {
        (self.shutter, self.shutter_time)
    }

    pub fn boost(&self) -> &LorentzTransform {
        &self.boost
    }

    pub fn transformation(&self) -> Transformation {
        self.transformation
    }

    /// Whether the colours are Doppler-shifted.
    pub fn doppler(&self) -> bool {
        self.doppler && !self.boost.is_identity()
    }

    /// The undeviated chief ray of continuous detector position (x, y) in pixel units, (0, 0)
    /// being the centre of the top-left pixel, x to the right and y downwards: its pupil centre
    /// (ignoring the eye offset) and direction (not normalised).
    #[inline]
    pub fn chief_ray(&self, width: u32, height: u32, x: f64, y: f64) -> (DVec3, DVec3) {
        match self.projection {
            Projection::Perspective { .. } => (
                self.position,
                self.view_direction + self.across(width, height, x, y),
            ),
            Projection::Orthographic {
                positive_space_only,
                lenticular_array,
                ..
            } => {
                let across = self.across(width, height, x, y);
                let across = match positive_space_only {
                    None => across,
                    Some(p) => {
                        let (x, y) = p.remap(across.dot(self.right), across.dot(self.up));
                        x * self.right + y * self.up
                    }
                };
                let direction = match lenticular_array {
                    None => self.view_direction,
                    Some(l) => {
                        let pitch = self.span / (width.max(2) - 1) as f64;
                        let (cos, sin) = l.tilt((x + 0.5).floor() as i64, pitch);
                        cos * self.view_direction + sin * self.right
                    }
                };
                (self.position + across, direction)
            }
            Projection::Equirectangular => {
                let phi = std::f64::consts::TAU * (x + 0.5) / width as f64;
                let theta = std::f64::consts::PI * (y + 0.5) / height as f64;
                let (sin_phi, cos_phi) = phi.sin_cos();
                let (sin_theta, cos_theta) = theta.sin_cos();
                // φ = 0 straight behind (Dr TIM's phi0 = −view), φ = 90° to the left.
                let around = -cos_phi * self.view_direction - sin_phi * self.right;
                (self.position, cos_theta * self.up + sin_theta * around)
            }
        }
    }

    /// The offset across the view direction of detector position (x, y) of a perspective or
    /// orthographic camera: at unit distance, or in length.
    #[inline]
    fn across(&self, width: u32, height: u32, x: f64, y: f64) -> DVec3 {
        let pitch = self.span / (width.max(2) - 1) as f64;
        let dx = (x - 0.5 * (width as f64 - 1.0)) * pitch;
        let dy = (0.5 * (height as f64 - 1.0) - y) * pitch;
        dx * self.right + dy * self.up
    }

    /// The offset of this eye's pupil for a chief ray along `chief`: the offset given, or for
    /// the equirectangular camera that offset turned about `up` with the azimuth, so that the
    /// eyes lie across each chief ray as a turning head's do (Dr TIM's
    /// `StandardPanorama3DGeometry`: the left eye at −½ IPD (up × d̂) for a horizontal d̂). Its
    /// component along `right` turns to the horizontal perpendicular to the chief ray; straight
    /// up or down, where that is undefined, it stays `right`.
    fn eye_offset(&self, chief: DVec3) -> DVec3 {
        if self.projection != Projection::Equirectangular || self.eye == DVec3::ZERO {
            return self.eye;
        }
        let across = self.eye.dot(self.right);
        let right = self.up.cross(chief).try_normalize().unwrap_or(self.right);
        across * right + (self.eye - across * self.right)
    }

    /// Where the chief ray from `centre` along the unit `chief` meets the focus plane
    /// `distance` ahead, or for the equirectangular camera the focus sphere of that radius;
    /// none at an infinite distance (the equirectangular camera's default).
    fn focus_point(&self, centre: DVec3, chief: DVec3, distance: f64) -> Option<DVec3> {
        match self.projection {
            Projection::Equirectangular => distance.is_finite().then(|| centre + distance * chief),
            _ => Some(centre + distance / chief.dot(self.view_direction) * chief),
        }
    }

    /// The camera-frame ray of one sample of detector position (x, y): it leaves a point E of
    /// the entrance-pupil disk, chosen by the two uniform numbers `pupil`, towards the pixel's
    /// image I, at the time the shutter model gives. `focus_surface(origin, direction)` is the
    /// distance along a chief ray to the focus surface (used with [`Focus::Surface`]).
    #[inline(always)]
    pub fn ray(
        &self,
        width: u32,
        height: u32,
        (x, y): (f64, f64),
        pupil: [f64; 2],
        focus_surface: &dyn Fn(DVec3, DVec3) -> Option<f64>,
    ) -> Ray {
        let (centre, direction) = self.chief_ray(width, height, x, y);
        // A single pinhole with the shutter in the pupil needs no image point: its rays are the
        // chief rays themselves, leaving at t_s. (Inlined: returning the ray through memory
        // stalled the render loop.)
        if self.aperture_radius == 0.0
            && self.eye == DVec3::ZERO
            && self.shutter == Shutter::EntrancePupil
        {
            return Ray::new(centre, direction, self.shutter_time);
        }
        self.ray_through_pupil(centre, direction, pupil, focus_surface)
    }

    /// [`Self::ray`] of a finite aperture, an eye of a stereo pair or a shutter away from the
    /// pupil, from the pixel's chief ray (from the pupil centre `centre` along `direction`).
    #[inline(never)]
    fn ray_through_pupil(
        &self,
        centre: DVec3,
        direction: DVec3,
        pupil: [f64; 2],
        focus_surface: &dyn Fn(DVec3, DVec3) -> Option<f64>,
    ) -> Ray {
        let chief = direction.normalize();
        let image = match self.focus {
            Focus::Plane { distance } => self.focus_point(centre, chief, distance),
            Focus::Surface => focus_surface(centre, chief).map(|t| centre + t * chief),
        };
        // This eye's pupil centre.
        let eye_centre = centre + self.eye_offset(chief);
        let pupil_point = if self.aperture_radius > 0.0 {
            let r = self.aperture_radius * pupil[0].sqrt();
            let (s, c) = (std::f64::consts::TAU * pupil[1]).sin_cos();
            eye_centre + r * (c * self.right + s * self.up)
        } else {
            eye_centre
        };
        // A pinhole's rays are the chief rays themselves, exactly.
        let direction = match image {
            _ if pupil_point == centre => direction,
            Some(i) => i - pupil_point,
            None => chief,
        };
        // A shutter in the pupil opens at t_s for every ray: no shutter geometry to compute.
        let time = if self.shutter == Shutter::EntrancePupil {
            self.shutter_time
        } else {
            // This eye's chief ray (through the common image point).
            let eye_chief = match image {
                Some(i) if self.eye != DVec3::ZERO => (i - eye_centre).normalize(),
                _ => chief,
            };
            let fixed_time = match (self.shutter, image) {
                (Shutter::FixedPointSurface, Some(i)) => self.fixed_time(i),
                _ => 0.0,
            };
            let geometry = ShutterGeometry {
                pupil_point,
                pupil_centre: eye_centre,
                pixel: eye_centre
                    - self.detector_distance / eye_chief.dot(self.view_direction) * eye_chief,
                image,
                chief: eye_chief,
                fixed_time,
            };
            self.shutter.start_time(self.shutter_time, &geometry)
        };
        Ray::new(pupil_point, direction, time)
    }

    /// A camera-frame ray of [`Self::ray`] diffracted by the aperture (Dr TIM's
    /// `CircularApertureDiffraction.getDiffractedLightRayDirection`), or `None` where the
    /// diffracted light is evanescent (the sample sees black, as in Dr TIM). Its direction's
    /// component perpendicular to the view direction (the pupil's normal) changes by
    /// sin θ = x λ / (2π r) in the azimuth `random[1]` (turns from the camera's right towards
    /// its up), x drawn by `random[0]` from the Airy pattern
    /// ([`aperture_diffraction::airy_x`]); its normal component is what keeps it a unit vector,
    /// as a phase hologram's. Origin and time are the undiffracted ray's (Dr TIM's shutter
    /// models time the ray before diffraction too). Without diffraction, `ray` itself.
    pub fn diffracted(&self, ray: Ray, random: [f64; 2]) -> Option<Ray> {
        let Some(lambda) = self.diffraction else {
            return Some(ray);
        };
        let n = self.view_direction;
        let along = ray.direction.dot(n);
        let across = ray.direction - along * n;
        // sin θ per unit x; the ray stays non-evanescent only while the change is below
        // 1 + |across| (the new tangential component's length being below 1).
        let scale = lambda / (std::f64::consts::TAU * self.aperture_radius);
        let x_max = (1.0 + across.length()) / scale;
        let x = aperture_diffraction::airy_x(random[0], x_max)?;
        let (s, c) = (std::f64::consts::TAU * random[1]).sin_cos();
        let across = across + x * scale * (c * self.right + s * self.up);
        let normal = 1.0 - across.length_squared();
        (normal > 0.0).then(|| {
            let direction = across + along.signum() * normal.sqrt() * n;
            Ray::new(ray.origin, direction, ray.time)
        })
    }

    /// The camera-frame time at which the Lorentz transformation leaves the point `x` where
    /// it is (Dr TIM's `FixedPointSurfaceShutterModel.getTimeWhenPositionIsStationary`): with
    /// x − position = r, Eq 1's x′ = x needs (γ − 1)(β̂·r)β̂ + γtβ = 0, so
    /// t = −(γ − 1)(β·r)/(γβ²); 0 at rest. (The scene file refuses this shutter with the
    /// Galilean transformation, under which light does not travel at c in the camera frame.)
    fn fixed_time(&self, x: DVec3) -> f64 {
        let b = self.boost.beta();
        if b == DVec3::ZERO {
            return 0.0;
        }
        let gamma = self.boost.gamma();
        -(gamma - 1.0) * b.dot(x - self.position) / (gamma * b.length_squared())
    }

    /// The scene-frame ray of a camera-frame ray: its origin event (Eq 1, about the camera
    /// position) and its backwards-traced direction (Eq 4), or their Galilean counterparts.
    /// Exactly `ray` at rest.
    #[inline]
    pub fn to_scene_frame(&self, ray: &Ray) -> Ray {
        if self.boost.is_identity() {
            return *ray;
        }
        let r = ray.origin - self.position;
        let ((x, t), direction) = match self.transformation {
            Transformation::Lorentz => (
                self.boost.event(r, ray.time),
                self.boost.backwards_direction(ray.direction),
            ),
            Transformation::Galileo => {
                let beta = self.boost.beta();
                (
                    galilean_event(beta, r, ray.time),
                    galilean_backwards_direction(beta, ray.direction),
                )
            }
        };
        Ray::new(self.position + x, direction, t)
    }

    /// The Doppler factor D = ν_camera/ν_scene = γ(1 + β·d̂′) of light arriving along a ray
    /// whose unit scene-frame (backwards-traced) direction is `scene_direction`.
    pub fn doppler_factor(&self, scene_direction: DVec3) -> f64 {
        self.boost.gamma() * (1.0 + self.boost.beta().dot(scene_direction))
    }

    /// The colour the camera sees of light of scene-frame colour `colour` arriving along the
    /// unit scene-frame direction `scene_direction`: Doppler-shifted and brightened if the
    /// camera is asked to ([`Self::with_doppler`]), else `colour` itself.
    #[inline]
    pub fn seen(&self, colour: Colour, scene_direction: DVec3) -> Colour {
        if self.doppler() {
            doppler::doppler_shifted(colour, self.doppler_factor(scene_direction))
        } else {
            colour
        }
    }
}

/// A camera in words (see [`Camera::describe`]).
pub struct Description<'a> {
    camera: &'a Camera,
    focus_shapes: usize,
}

impl Camera {
    /// The camera in words, as `timbre check` prints it: projection, aperture and focus (for a
    /// finite aperture or a moving camera; `focus_shapes` counts the focus surface's shapes),
    /// velocity and shutter.
    pub fn describe(&self, focus_shapes: usize) -> Description<'_> {
        Description {
            camera: self,
            focus_shapes,
        }
    }
}

impl fmt::Display for Description<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let camera = self.camera;
        // Degrees to 9 decimals (20° comes back from radians as 19.999999999999996).
        let degrees = |a: f64| (a.to_degrees() * 1e9).round() / 1e9;
        match (camera.projection(), camera.aperture_radius()) {
            (
                Projection::Orthographic {
                    view_width,
                    positive_space_only,
                    lenticular_array,
                },
                _,
            ) => {
                write!(f, "orthographic, {view_width} wide")?;
                if let Some(l) = lenticular_array {
                    write!(
                        f,
                        ", for a lenticular array ({} pixels per lenslet of focal length {})",
                        l.pixels_per_cylindrical_lens, l.cylindrical_lenslet_focal_length
                    )?;
                }
                if let Some(p) = positive_space_only {
                    write!(
                        f,
                        ", positive space only ({} wedges, deficit {}°, {})",
                        p.number_of_negative_space_wedges,
                        degrees(p.deficit_angle),
                        match p.stretching {
                            crate::cameras::Stretching::StretchAngle => "stretching the angle",
                            crate::cameras::Stretching::StretchWidth => "stretching the width",
                        }
                    )?
                }
            }
            (Projection::Equirectangular, _) => write!(f, "equirectangular, 360° × 180°")?,
            (
                Projection::Perspective {
                    horizontal_view_angle: a,
                },
                0.0,
            ) => write!(f, "pinhole, {}°", degrees(a))?,
            (
                Projection::Perspective {
                    horizontal_view_angle: a,
                },
                r,
            ) => write!(f, "finite aperture (radius {r}), {}°", degrees(a))?,
        }
        if let Some(lambda) = camera.diffraction() {
            write!(f, "; diffracting (lambda = {lambda:e})")?;
        }
        let boost = camera.boost();
        if camera.aperture_radius() > 0.0 || !boost.is_identity() {
            match camera.focus() {
                Focus::Plane { distance } if distance.is_infinite() => {
                    write!(f, "; focused at infinity")?
                }
                Focus::Plane { distance } => write!(f, "; focused at {distance}")?,
                Focus::Surface => write!(f, "; focused on {} shapes", self.focus_shapes)?,
            }
        }
        if !boost.is_identity() {
            let (shutter, time) = camera.shutter();
            let b = boost.beta();
            write!(
                f,
                "; moving at beta = ({}, {}, {}) (gamma = {:.4}), {} shutter",
                b.x,
                b.y,
                b.z,
                boost.gamma(),
                shutter.name()
            )?;
            if shutter != Shutter::FixedPointSurface {
                write!(f, " at t = {time}")?;
            }
            if camera.transformation() == Transformation::Galileo {
                write!(f, "; Galilean transformation")?;
            }
            if camera.doppler() {
                write!(f, "; Doppler-shifted")?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::uniform;

    /// A finite aperture of radius 1e-4 looking along +z, diffracting light of wavelength λ.
    fn diffracting(lambda: f64) -> Camera {
        Camera::pinhole(DVec3::ZERO, DVec3::Z, DVec3::Y, 0.3)
            .unwrap()
            .with_aperture(1e-4, Focus::Plane { distance: 1.0 })
            .with_diffraction(Some(lambda))
    }

    /// The direction change is sin θ = x λ / (2π r) in the azimuth drawn, measured from the
    /// camera's right towards its up: the median x (P = ½) is 1.68022474619420 (mpmath).
    #[test]
    fn diffraction_turns_the_ray_by_the_airy_angle_in_the_drawn_azimuth() {
        let lambda = 632.8e-9;
        let camera = diffracting(lambda);
        let ray = Ray::new(DVec3::new(5e-5, 0.0, 0.0), DVec3::new(0.01, 0.0, 1.0), 0.25);
        let sin_theta = 1.680_224_746_194_2 * lambda / (std::f64::consts::TAU * 1e-4);
        for (azimuth, along) in [(0.0, DVec3::X), (0.25, DVec3::Y), (0.5, -DVec3::X)] {
            let out = camera.diffracted(ray, [0.5, azimuth]).unwrap();
            let change = out.direction - ray.direction;
            let across = change - change.dot(DVec3::Z) * DVec3::Z;
            assert!((across - sin_theta * along).length() < 1e-15, "{across}");
            assert!((out.direction.length() - 1.0).abs() < 1e-15);
            assert!(out.direction.z > 0.0);
            assert_eq!((out.origin, out.time), (ray.origin, ray.time));
        }
        // Without diffraction, the ray itself.
        let plain = camera.clone().with_diffraction(None);
        assert_eq!(plain.diffracted(ray, [0.5, 0.1]), Some(ray));
    }

    /// The azimuths are uniform: the mean change vanishes, and each quadrant gets a quarter.
    #[test]
    fn diffraction_azimuths_are_uniform() {
        let camera = diffracting(632.8e-9);
        let ray = Ray::new(DVec3::ZERO, DVec3::Z, 0.0);
        // (A few, 2/(π x_max) ≈ 0.06 %, are evanescent.)
        let directions: Vec<DVec3> = (0..40_000)
            .filter_map(|s| {
                let random = [uniform(9, 0, 0, s, 4), uniform(9, 0, 0, s, 5)];
                camera.diffracted(ray, random).map(|r| r.direction)
            })
            .collect();
        let n = directions.len();
        assert!(n > 39_900, "{n}");
        let mut quadrants = [0u32; 4];
        let mut mean = DVec3::ZERO;
        for d in directions {
            mean += DVec3::new(d.x, d.y, 0.0).normalize_or_zero() / n as f64;
            quadrants[usize::from(d.x < 0.0) + 2 * usize::from(d.y < 0.0)] += 1;
        }
        let sigma = (0.5 / n as f64).sqrt();
        assert!(mean.length() < 4.0 * sigma, "{mean}");
        for q in quadrants {
            let share = q as f64 / n as f64;
            assert!(
                (share - 0.25).abs() < 4.0 * (0.1875 / n as f64).sqrt(),
                "{share}"
            );
        }
    }

    /// Light whose direction change would leave no normal component is evanescent: no ray.
    #[test]
    fn evanescent_diffraction_loses_the_ray() {
        // x λ / (2π r) = 1.68 λ / (2π 10⁻⁴) > 2 for λ > 7.5e-4: beyond any tangential part.
        let camera = diffracting(1e-3);
        let ray = Ray::new(DVec3::ZERO, DVec3::new(0.3, 0.0, 1.0), 0.0);
        assert_eq!(camera.diffracted(ray, [0.5, 0.3]), None);
        // Turned back towards the view direction, a large change can still leave light.
        let camera = diffracting(1.2 * std::f64::consts::TAU * 1e-4 / 1.680_224_746_194_2);
        let (s, c) = (0.3f64.sin(), 0.3f64.cos());
        let tilted = Ray::new(DVec3::ZERO, DVec3::new(s, 0.0, c), 0.0);
        // sin θ = 1.2 along −x from sin 0.3 = 0.296 along +x: 0.904 along −x.
        let out = camera.diffracted(tilted, [0.5, 0.5]).unwrap();
        assert!(
            (out.direction.x + (1.2 - s)).abs() < 1e-12,
            "{}",
            out.direction
        );
    }
}
