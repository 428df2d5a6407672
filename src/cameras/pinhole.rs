//! Pinhole camera, following TIM's convention: the detector lies at distance 1 behind the
//! pinhole (mirrored in front of it), and the horizontal view angle spans the *centres* of the
//! outermost pixel columns, so the pixel pitch is 2 tan(angle/2) / (width − 1). Pixels are
//! square; the rows are centred on the view direction.

use glam::DVec3;

use crate::math::Ray;

#[derive(Debug, Clone, PartialEq)]
pub struct PinholeCamera {
    position: DVec3,
    /// Unit view direction.
    view_direction: DVec3,
    /// Unit "right" on the detector (up × view).
    right: DVec3,
    /// Unit "up" on the detector, perpendicular to the view direction.
    up: DVec3,
    horizontal_view_angle: f64,
    /// Width of the detector between the centres of the outermost pixel columns: 2 tan(angle/2).
    detector_span: f64,
}

impl PinholeCamera {
    /// `up` need not be perpendicular to `view_direction`, only not parallel to it; both are
    /// normalised here. Returns `None` for parallel or zero vectors.
    pub fn new(
        position: DVec3,
        view_direction: DVec3,
        up: DVec3,
        horizontal_view_angle: f64,
    ) -> Option<PinholeCamera> {
        let view = view_direction.try_normalize()?;
        // With x right, y up and the view along +z (TIM's convention), right = up × view.
        let right = up.cross(view).try_normalize()?;
        let up = view.cross(right);
        let detector_span = 2.0 * (0.5 * horizontal_view_angle).tan();
        Some(PinholeCamera {
            position,
            view_direction: view,
            right,
            up,
            horizontal_view_angle,
            detector_span,
        })
    }

    pub fn position(&self) -> DVec3 {
        self.position
    }

    /// Unit view direction.
    pub fn view_direction(&self) -> DVec3 {
        self.view_direction
    }

    /// Horizontal view angle in radians, between the centres of the outermost pixel columns.
    pub fn horizontal_view_angle(&self) -> f64 {
        self.horizontal_view_angle
    }

    /// The ray through continuous detector position (x, y) in pixel units, (0, 0) being the
    /// centre of the top-left pixel, x to the right and y downwards.
    pub fn ray(&self, width: u32, height: u32, x: f64, y: f64) -> Ray {
        let pitch = self.detector_span / (width.max(2) - 1) as f64;
        let dx = (x - 0.5 * (width as f64 - 1.0)) * pitch;
        let dy = (0.5 * (height as f64 - 1.0) - y) * pitch;
        Ray::new(
            self.position,
            self.view_direction + dx * self.right + dy * self.up,
            0.0,
        )
    }
}
