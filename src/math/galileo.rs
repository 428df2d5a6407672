//! The Galilean transformation from the camera frame into the scene frame (Dr TIM's
//! `GalileanTransformation`, an alternative to Eqs 1–4 for comparison), with c = 1.
//!
//! The camera frame moves with velocity β through the scene frame, whose coordinates coincide
//! with the camera frame's at time 0. An event (x, t) is at x′ = x + βt at the same time
//! t′ = t. Light travels at c in the scene frame, where the scene's objects emit it (the
//! frame of a classical ether, or of the sources of an emission theory): light with unit
//! velocity −d̂′ there has velocity −d̂′ − β in the camera frame (classical velocity addition,
//! Bradley's aberration of starlight), so a backwards-traced camera-frame direction d maps to
//! the unit d̂′ with d̂′ + β ∥ d. That is Dr TIM's `getTransformedLightRayDirection` (its β is
//! −β here: it takes the scene's velocity in the camera frame). Galileo-boosting the
//! camera-frame ray itself instead (d′ ∝ d̂ − β, light at c in the camera frame) would be a
//! different, unphysical model for light the scene emits.

use glam::DVec3;

/// The scene-frame event (x′, t′) = (x + βt, t) of the camera-frame event (`x`, `t`).
pub fn galilean_event(beta: DVec3, x: DVec3, t: f64) -> (DVec3, f64) {
    (x + t * beta, t)
}

/// The unit scene-frame direction d̂′ of a backwards-traced ray with camera-frame direction
/// `d` (non-zero), for |β| < 1: d̂′ = s d̂ − β with s > 0 the root of |s d̂ − β| = 1,
/// s = d̂·β + √((d̂·β)² + 1 − β²).
pub fn galilean_backwards_direction(beta: DVec3, d: DVec3) -> DVec3 {
    let d = d.normalize();
    let b = d.dot(beta);
    let s = b + (b * b + 1.0 - beta.length_squared()).sqrt();
    s * d - beta
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_moves_with_velocity_beta_and_time_is_absolute() {
        let beta = DVec3::new(0.3, -0.2, 0.5);
        assert_eq!(galilean_event(beta, DVec3::ZERO, 2.0), (2.0 * beta, 2.0));
        assert_eq!(galilean_event(beta, DVec3::X, 0.0), (DVec3::X, 0.0));
    }

    /// Classical aberration, by adding velocities: a camera moving at β along z sees light
    /// that arrives in the scene frame from the angle θ to z (from the unit direction
    /// (sin θ, 0, cos θ)) with camera-frame velocity −(sin θ, 0, cos θ) − (0, 0, β), i.e.
    /// from the direction (sin θ, 0, cos θ + β), at tan θ_c = sin θ / (cos θ + β).
    #[test]
    fn aberration_by_adding_velocities() {
        let beta = 0.6;
        for theta_deg in [0.0_f64, 20.0, 45.0, 90.0, 120.0, 170.0] {
            let theta = theta_deg.to_radians();
            let camera = DVec3::new(theta.sin(), 0.0, theta.cos() + beta);
            let scene = galilean_backwards_direction(DVec3::new(0.0, 0.0, beta), camera);
            let expected = DVec3::new(theta.sin(), 0.0, theta.cos());
            assert!((scene - expected).length() < 1e-15, "{theta_deg}: {scene}");
            // The camera sees the point nearer the direction of motion.
            let theta_c = theta.sin().atan2(theta.cos() + beta);
            assert!(theta_c <= theta + 1e-15);
        }
    }

    #[test]
    fn scene_frame_light_has_unit_speed_and_zero_velocity_is_the_identity() {
        let beta = DVec3::new(-0.4, 0.5, 0.3);
        for d in [DVec3::Z, DVec3::new(1.0, 2.0, -3.0), -beta] {
            let dp = galilean_backwards_direction(beta, d);
            assert!((dp.length() - 1.0).abs() < 1e-15);
            // d̂′ + β is along d, forwards.
            assert!((dp + beta).normalize().dot(d.normalize()) > 1.0 - 1e-15);
        }
        let d = DVec3::new(0.6, 0.0, 0.8);
        assert_eq!(galilean_backwards_direction(DVec3::ZERO, d), d);
    }
}
