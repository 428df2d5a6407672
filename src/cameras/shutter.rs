//! TIM's three shutter models (§2.1, Fig. 1): the time at which a backwards-traced ray leaves
//! the entrance pupil, which decides where a relativistic camera's ray starts in the scene frame.
//!
//! The shutter opens for an instant at time t_s, simultaneously (in the camera frame) across the
//! shutter surface. A ray leaves the pupil point E towards the image I of its pixel; P is the
//! pixel on the detector, C the pupil centre, with P, C and I on the pixel's undeviated chief
//! ray. The formulas are exactly the paper's, including its picture of the ray going from E to
//! I forwards in time (the focus-surface ray "passes through I at t_s"), although the traced
//! rays themselves run backwards in time (Eqs 2–3).

use glam::DVec3;

/// Where the shutter is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shutter {
    /// In the detector plane, a distance i behind the entrance pupil (a focal-plane shutter).
    DetectorPlane,
    /// Immediately in front of the lens, in the entrance-pupil disk.
    EntrancePupil,
    /// In the focus surface, where the images of the detector pixels are.
    FocusSurface,
}

/// The points that decide a ray's start time: pupil point E, pupil centre C, pixel P behind C,
/// and the pixel's image I (`None` when it is at infinity; `chief` is then the unit direction
/// of the chief ray).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShutterGeometry {
    pub pupil_point: DVec3,
    pub pupil_centre: DVec3,
    pub pixel: DVec3,
    pub image: Option<DVec3>,
    pub chief: DVec3,
}

impl Shutter {
    /// The scene-file name (`camera.shutter`).
    pub fn name(self) -> &'static str {
        match self {
            Shutter::DetectorPlane => "detector-plane",
            Shutter::EntrancePupil => "entrance-pupil",
            Shutter::FocusSurface => "focus-surface",
        }
    }

    /// The time the ray leaves E, for a shutter opening at `t_s`:
    /// entrance pupil t_s; focus surface t_s − |I − E|; detector plane
    /// t_s + |I − P| − |I − E|, with |I − P| = |P − C| + |I − C| since C lies between P and I.
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
            Shutter::DetectorPlane => t_s + (g.pixel - c).length() + path_difference,
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
        assert!((Shutter::DetectorPlane.start_time(2.0, &g) - (2.0 + 16.0 - ie)).abs() < 1e-14);
    }

    #[test]
    fn through_the_pupil_centre_the_models_differ_by_the_distances() {
        let g = geometry(DVec3::ZERO);
        assert_eq!(Shutter::EntrancePupil.start_time(0.0, &g), 0.0);
        assert_eq!(Shutter::FocusSurface.start_time(0.0, &g), -15.0);
        assert_eq!(Shutter::DetectorPlane.start_time(0.0, &g), 1.0);
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
        let t = Shutter::DetectorPlane.start_time(0.0, &infinite);
        assert!(
            (t - Shutter::DetectorPlane.start_time(0.0, &far)).abs() < 1e-6,
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
}
