//! TIM's shutter models (§2.1, Fig. 1, and Dr TIM's `shutterModels`): the time at which a
//! backwards-traced ray leaves the entrance pupil, which decides where a relativistic camera's
//! ray starts in the scene frame.
//!
//! The shutter opens for an instant at time t_s, simultaneously (in the camera frame) across the
//! shutter surface. A ray leaves the pupil point E towards the image I of its pixel; P is the
//! pixel on the detector, C the pupil centre, with P, C and I on the pixel's undeviated chief
//! ray. The formulas are exactly the paper's, including its picture of the ray going from E to
//! I forwards in time (the focus-surface ray "passes through I at t_s"), although the traced
//! rays themselves run backwards in time (Eqs 2–3). The detector plane's lens types follow the
//! same picture. The two models the paper does not describe, Dr TIM's arbitrary-plane and
//! fixed-point-surface shutters, follow the light instead (as Dr TIM's code does): the light
//! crosses the shutter plane at t_s, or passes I at the time the boost leaves I in place.

use glam::DVec3;

/// Where the shutter is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shutter {
    /// In the detector plane, a distance i behind the entrance pupil (a focal-plane shutter).
    DetectorPlane(LensType),
    /// Immediately in front of the lens, in the entrance-pupil disk.
    EntrancePupil,
    /// In the focus surface, where the images of the detector pixels are.
    FocusSurface,
    /// In the plane through `point` with unit normal `normal` (camera-frame coordinates, which
    /// are the scene's at t = 0; Dr TIM's `ArbitraryPlaneShutterModel`).
    ArbitraryPlane { point: DVec3, normal: DVec3 },
    /// Timed so that the boost leaves every point of the focus surface in place: the focus
    /// surface looks undistorted (Dr TIM's `FixedPointSurfaceShutterModel`; no opening time).
    FixedPointSurface,
}

/// The camera lens of the detector-plane shutter (Dr TIM's `LensType`): what delay the lens
/// adds to a ray through the pupil point E.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LensType {
    /// All rays from a pixel P reach its image I at the same time (the paper's assumption 2):
    /// the lens delays each by |I − P| − |E − P| − |I − E| (Dr TIM's GUI's default).
    #[default]
    IdealLens,
    /// A lens hologram, which adds no delay: a ray takes |E − P| from the pixel to E.
    LensHologram,
}

/// The points that decide a ray's start time: pupil point E, pupil centre C, pixel P behind C,
/// and the pixel's image I (`None` when it is at infinity; `chief` is then the unit direction
/// of the chief ray); `fixed_time` is the camera-frame time at which the boost leaves I in
/// place (used by the fixed-point-surface shutter only, which needs a finite I).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShutterGeometry {
    pub pupil_point: DVec3,
    pub pupil_centre: DVec3,
    pub pixel: DVec3,
    pub image: Option<DVec3>,
    pub chief: DVec3,
    pub fixed_time: f64,
}

impl Shutter {
    /// The scene-file name (`camera.shutter`).
    pub fn name(self) -> &'static str {
        match self {
            Shutter::DetectorPlane(LensType::IdealLens) => "detector-plane",
            Shutter::DetectorPlane(LensType::LensHologram) => "detector-plane (lens hologram)",
            Shutter::EntrancePupil => "entrance-pupil",
            Shutter::FocusSurface => "focus-surface",
            Shutter::ArbitraryPlane { .. } => "arbitrary-plane",
            Shutter::FixedPointSurface => "fixed-point-surface",
        }
    }

    /// The time the ray leaves E, for a shutter opening at `t_s`:
    /// entrance pupil t_s; focus surface t_s − |I − E|; detector plane with an ideal lens
    /// t_s + |I − P| − |I − E|, with |I − P| = |P − C| + |I − C| since C lies between P and I,
    /// and with a lens hologram t_s + |E − P|; arbitrary plane t_s + μ, where μ is the signed
    /// distance from E along the ray's unit direction d̂ to the plane (the light crosses the
    /// plane at t_s; a ray parallel to the plane, which never crosses it, leaves at t_s);
    /// fixed-point surface t_I + |I − E|, t_I being `fixed_time` (the light passes I at t_I;
    /// t_I alone where I is at infinity, which the scene file does not allow).
    ///
    /// For an image at infinity the rays of a pixel are parallel and |I − E| is infinite; the
    /// infinite delay |I − C| is then dropped, leaving its finite limit
    /// |I − C| − |I − E| → (E − C)·chief. With the focus-surface shutter that delay is not
    /// common to pixels whose images are finite, so a moving camera focused on shapes that do
    /// not cover the whole view shows a seam where the chief rays start missing them.
    pub fn start_time(self, t_s: f64, g: &ShutterGeometry) -> f64 {
        let (c, e) = (g.pupil_centre, g.pupil_point);
        // |I − C| − |I − E|: the path difference from I to the pupil centre and to E.
        let path_difference = match g.image {
            Some(i) => (i - c).length() - (i - e).length(),
            None => (e - c).dot(g.chief),
        };
        match self {
            Shutter::EntrancePupil => t_s,
            Shutter::FocusSurface => match g.image {
                Some(i) => t_s - (i - e).length(),
                None => t_s + path_difference,
            },
            Shutter::DetectorPlane(LensType::IdealLens) => {
                t_s + (g.pixel - c).length() + path_difference
            }
            Shutter::DetectorPlane(LensType::LensHologram) => t_s + (e - g.pixel).length(),
            Shutter::ArbitraryPlane { point, normal } => {
                let d = g.image.map_or(g.chief, |i| (i - e).normalize());
                let across = d.dot(normal);
                if across == 0.0 {
                    t_s
                } else {
                    t_s + (point - e).dot(normal) / across
                }
            }
            Shutter::FixedPointSurface => g.fixed_time + g.image.map_or(0.0, |i| i.distance(e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry(e: DVec3) -> ShutterGeometry {
        // Pupil centre at the origin, detector 1 behind, image 15 ahead on the axis.
        ShutterGeometry {
            pupil_point: e,
            pupil_centre: DVec3::ZERO,
            pixel: DVec3::new(0.0, 0.0, -1.0),
            image: Some(DVec3::new(0.0, 0.0, 15.0)),
            chief: DVec3::Z,
            fixed_time: 0.0,
        }
    }

    #[test]
    fn start_times_are_the_papers_formulas() {
        let e = DVec3::new(0.3, 0.4, 0.0);
        let g = geometry(e);
        let ie = (15f64 * 15.0 + 0.25).sqrt();
        assert_eq!(Shutter::EntrancePupil.start_time(2.0, &g), 2.0);
        assert!((Shutter::FocusSurface.start_time(2.0, &g) - (2.0 - ie)).abs() < 1e-14);
        // |I − P| = 16.
        assert!(
            (Shutter::DetectorPlane(LensType::IdealLens).start_time(2.0, &g) - (2.0 + 16.0 - ie))
                .abs()
                < 1e-14
        );
    }

    #[test]
    fn through_the_pupil_centre_the_models_differ_by_the_distances() {
        let g = geometry(DVec3::ZERO);
        assert_eq!(Shutter::EntrancePupil.start_time(0.0, &g), 0.0);
        assert_eq!(Shutter::FocusSurface.start_time(0.0, &g), -15.0);
        assert_eq!(
            Shutter::DetectorPlane(LensType::IdealLens).start_time(0.0, &g),
            1.0
        );
    }

    #[test]
    fn an_image_at_infinity_is_the_limit_of_a_distant_one() {
        let e = DVec3::new(0.3, 0.0, 0.0);
        let chief = DVec3::new(0.6, 0.0, 0.8);
        let far = ShutterGeometry {
            image: Some(1e7 * chief),
            chief,
            ..geometry(e)
        };
        let infinite = ShutterGeometry { image: None, ..far };
        let t = Shutter::DetectorPlane(LensType::IdealLens).start_time(0.0, &infinite);
        assert!(
            (t - Shutter::DetectorPlane(LensType::IdealLens).start_time(0.0, &far)).abs() < 1e-6,
            "{t}"
        );
        assert!((t - (1.0 + 0.18)).abs() < 1e-15);
        // The focus-surface times lose the common infinite delay, keeping the differences.
        let a = Shutter::FocusSurface.start_time(0.0, &infinite);
        let b = Shutter::FocusSurface.start_time(
            0.0,
            &ShutterGeometry {
                pupil_point: DVec3::ZERO,
                ..infinite
            },
        );
        let fa = Shutter::FocusSurface.start_time(0.0, &far);
        let fb = Shutter::FocusSurface.start_time(
            0.0,
            &ShutterGeometry {
                pupil_point: DVec3::ZERO,
                ..far
            },
        );
        assert!(((a - b) - (fa - fb)).abs() < 1e-6);
    }

    #[test]
    fn a_lens_hologram_adds_no_delay_from_the_pixel() {
        // E = (0.3, 0.4, 0), P = (0, 0, −1): |E − P| = √1.25. Through the centre both lens
        // types take |P − C| = 1.
        let hologram = Shutter::DetectorPlane(LensType::LensHologram);
        let e = DVec3::new(0.3, 0.4, 0.0);
        assert!((hologram.start_time(2.0, &geometry(e)) - (2.0 + 1.25f64.sqrt())).abs() < 1e-15);
        assert_eq!(hologram.start_time(2.0, &geometry(DVec3::ZERO)), 3.0);
    }

    #[test]
    fn the_light_crosses_an_arbitrary_shutter_plane_at_the_opening_time() {
        // A plane tilted by 45° about y through (0, 0, 4): x + z = 4, normal (1, 0, 1)/√2.
        let plane = Shutter::ArbitraryPlane {
            point: DVec3::new(0.0, 0.0, 4.0),
            normal: DVec3::new(1.0, 0.0, 1.0) / 2f64.sqrt(),
        };
        // The ray from E = (0.3, 0, 0) towards I = (0, 0, 15): direction (−0.3, 0, 15)/|…|.
        // It meets x + z = 4 where 0.3 − 0.3s + 15s = 4, s = 3.7/14.7, after the distance
        // s·|I − E|; the backwards-traced ray runs back in time, so it left E that much later.
        let e = DVec3::new(0.3, 0.0, 0.0);
        let s = 3.7 / 14.7;
        let distance = s * (0.09f64 + 225.0).sqrt();
        let t = plane.start_time(1.0, &geometry(e));
        assert!((t - (1.0 + distance)).abs() < 1e-14, "{t}");
        // A plane through the pupil centre perpendicular to the axis is the entrance pupil's.
        let pupil = Shutter::ArbitraryPlane {
            point: DVec3::ZERO,
            normal: DVec3::Z,
        };
        assert_eq!(
            pupil.start_time(1.0, &geometry(DVec3::new(0.3, 0.4, 0.0))),
            1.0
        );
        // Behind the pupil, in the detector plane z = −1: the light crosses it after leaving
        // E, which it therefore left 1/cos earlier.
        let detector = Shutter::ArbitraryPlane {
            point: DVec3::new(0.0, 0.0, -1.0),
            normal: DVec3::Z,
        };
        let g = geometry(e);
        let cos = 15.0 / (0.09f64 + 225.0).sqrt();
        assert!((detector.start_time(0.0, &g) + 1.0 / cos).abs() < 1e-14);
        // Parallel to the plane: never crosses it, leaves at t_s.
        let parallel = Shutter::ArbitraryPlane {
            point: DVec3::new(5.0, 0.0, 0.0),
            normal: DVec3::X,
        };
        assert_eq!(parallel.start_time(0.5, &geometry(DVec3::ZERO)), 0.5);
    }

    #[test]
    fn the_fixed_point_shutter_times_the_light_to_pass_the_image_at_its_fixed_time() {
        let g = ShutterGeometry {
            fixed_time: -0.75,
            ..geometry(DVec3::new(0.0, 3.0, 0.0))
        };
        // |I − E| = √(15² + 3²).
        let t = Shutter::FixedPointSurface.start_time(123.0, &g);
        assert!((t - (-0.75 + 234f64.sqrt())).abs() < 1e-14);
    }
}
