//! The Lorentz transformation from the camera frame into the scene frame (§2.1, Eqs 1–4), with
//! c = 1.
//!
//! The camera frame moves with velocity β (in units of c) through the scene frame. Eq 1 maps an
//! event (x, t) of the camera frame to its scene-frame position x′ and time t′; Eq 4 maps the
//! direction d of a *backwards-traced* ray (opposite to the light's direction of travel). The
//! term (γ − 1)/β² is evaluated as γ²/(γ + 1), which is the same for β ≠ 0 and stays finite
//! (the identity) for β = 0.

use glam::DVec3;

/// The inertial frame an object is at rest in (§2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceFrame {
    /// At rest in the scene (everything, usually).
    Scene,
    /// Moving with the camera: the camera-frame scene, which rays meet before they are
    /// Lorentz-transformed into the scene frame.
    Camera,
}

/// A boost by velocity β (|β| < 1): the scene-frame description of camera-frame events.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LorentzTransform {
    beta: DVec3,
    gamma: f64,
    /// (γ − 1)/β², written γ²/(γ + 1).
    k: f64,
}

impl LorentzTransform {
    /// The boost by velocity `beta`; `None` unless it is finite with |β| < 1.
    pub fn new(beta: DVec3) -> Option<LorentzTransform> {
        let b2 = beta.length_squared();
        if !b2.is_finite() || b2 >= 1.0 {
            return None;
        }
        let gamma = 1.0 / (1.0 - b2).sqrt();
        Some(LorentzTransform {
            beta,
            gamma,
            k: gamma * gamma / (gamma + 1.0),
        })
    }

    pub fn beta(&self) -> DVec3 {
        self.beta
    }

    /// The Lorentz factor γ = 1/√(1 − β²).
    pub fn gamma(&self) -> f64 {
        self.gamma
    }

    /// Whether this is the identity (β = 0).
    pub fn is_identity(&self) -> bool {
        self.beta == DVec3::ZERO
    }

    /// The boost back: velocity −β.
    pub fn inverse(&self) -> LorentzTransform {
        LorentzTransform {
            beta: -self.beta,
            ..*self
        }
    }

    /// Eq 1: the event at position `x` and time `t` in the camera frame, as (x′, t′) in the
    /// scene frame.
    pub fn event(&self, x: DVec3, t: f64) -> (DVec3, f64) {
        let bx = self.beta.dot(x);
        (
            x + self.k * bx * self.beta + self.gamma * t * self.beta,
            self.gamma * (t + bx),
        )
    }

    /// Eq 4: the direction d′ in the scene frame of a backwards-traced ray with direction `d` in
    /// the camera frame (not normalised: |d′| = γ(|d| − β·d)). The physical light travels along
    /// −d, hence the minus sign of the γβ|d| term.
    pub fn backwards_direction(&self, d: DVec3) -> DVec3 {
        d + self.k * self.beta.dot(d) * self.beta - self.gamma * d.length() * self.beta
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Minkowski interval t² − |x|².
    fn interval(x: DVec3, t: f64) -> f64 {
        t * t - x.length_squared()
    }

    fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
        (a - b).length() <= tol * (1.0 + b.length())
    }

    #[test]
    fn gamma_for_known_speeds() {
        for (beta, gamma) in [
            (0.0, 1.0),
            (0.6, 1.25),
            (0.8, 5.0 / 3.0),
            (0.99, 7.088_812_050_083_354),
        ] {
            let l = LorentzTransform::new(DVec3::new(0.0, beta, 0.0)).unwrap();
            assert!((l.gamma() - gamma).abs() < 1e-12, "{beta}: {}", l.gamma());
        }
        assert!(
            LorentzTransform::new(DVec3::new(0.6, 0.8, 0.0)).is_none(),
            "|β| = 1"
        );
        assert!(LorentzTransform::new(DVec3::new(f64::NAN, 0.0, 0.0)).is_none());
        assert!(LorentzTransform::new(DVec3::new(0.0, 0.0, -1.5)).is_none());
    }

    #[test]
    fn zero_velocity_is_exactly_the_identity() {
        let l = LorentzTransform::new(DVec3::ZERO).unwrap();
        let x = DVec3::new(1.5, -2.25, 1e9);
        assert_eq!(l.event(x, 3.5), (x, 3.5));
        assert_eq!(l.backwards_direction(x), x);
        assert!(l.is_identity());
    }

    #[test]
    fn inverse_undoes_the_boost_and_the_interval_is_invariant() {
        let l = LorentzTransform::new(DVec3::new(0.3, -0.5, 0.7)).unwrap();
        for (x, t) in [
            (DVec3::new(1.0, 2.0, 3.0), 0.5),
            (DVec3::new(-4.0, 0.1, 9.0), -7.0),
            (DVec3::ZERO, 2.0),
        ] {
            let (xp, tp) = l.event(x, t);
            let (xb, tb) = l.inverse().event(xp, tp);
            assert!(close(xb, x, 1e-13) && (tb - t).abs() < 1e-12, "{xb} {tb}");
            assert!((interval(xp, tp) - interval(x, t)).abs() < 1e-11 * (1.0 + x.length_squared()));
        }
    }

    #[test]
    fn the_camera_moves_with_velocity_beta() {
        // The camera-frame origin at time t is at βt′ in the scene frame, t′ = γt (time dilation).
        let beta = DVec3::new(0.2, 0.0, 0.97);
        let l = LorentzTransform::new(beta).unwrap();
        let (x, t) = l.event(DVec3::ZERO, 2.0);
        assert!((t - 2.0 * l.gamma()).abs() < 1e-12);
        assert!(close(x, beta * t, 1e-14));
    }

    #[test]
    fn collinear_boosts_compose_by_relativistic_velocity_addition() {
        let axis = DVec3::new(1.0, 2.0, -2.0) / 3.0;
        let (u, v) = (0.6, 0.7);
        let both = |x, t| {
            let (x, t) = LorentzTransform::new(u * axis).unwrap().event(x, t);
            LorentzTransform::new(v * axis).unwrap().event(x, t)
        };
        let w = LorentzTransform::new((u + v) / (1.0 + u * v) * axis).unwrap();
        for (x, t) in [
            (DVec3::new(0.3, -1.0, 2.0), 1.0),
            (DVec3::new(5.0, 0.0, 0.0), -3.0),
        ] {
            let (xa, ta) = both(x, t);
            let (xb, tb) = w.event(x, t);
            assert!(close(xa, xb, 1e-13) && (ta - tb).abs() < 1e-12, "{xa} {xb}");
        }
    }

    #[test]
    fn directions_follow_from_transforming_two_events() {
        // Eqs 2–3: x₂ = x₁ − d at t₂ = t₁ + |d| maps to x₁′ − d′.
        let l = LorentzTransform::new(DVec3::new(-0.4, 0.3, 0.5)).unwrap();
        let (x1, t1) = (DVec3::new(1.0, -2.0, 0.5), 0.25);
        let d = DVec3::new(0.3, 0.4, -1.2);
        let (x1p, _) = l.event(x1, t1);
        let (x2p, _) = l.event(x1 - d, t1 + d.length());
        assert!(close(x1p - x2p, l.backwards_direction(d), 1e-14));
        // The light travels at c in both frames: |d′| = γ(|d| − β·d).
        let dp = l.backwards_direction(d);
        let expected = l.gamma() * (d.length() - l.beta().dot(d));
        assert!((dp.length() - expected).abs() < 1e-14 * expected);
    }

    #[test]
    fn aberration_formula_for_the_light_direction() {
        // For the light's own direction −d at angle θ to β, the scene-frame angle θ′ obeys
        // cos θ′ = (cos θ + β)/(1 + β cos θ).
        let beta = 0.9;
        let l = LorentzTransform::new(DVec3::new(0.0, 0.0, beta)).unwrap();
        for theta_deg in [0.0_f64, 10.0, 45.0, 90.0, 135.0, 179.0] {
            let theta = theta_deg.to_radians();
            let d = -DVec3::new(theta.sin(), 0.0, theta.cos());
            let light = -l.backwards_direction(d).normalize();
            let expected = (theta.cos() + beta) / (1.0 + beta * theta.cos());
            assert!(
                (light.z - expected).abs() < 1e-13,
                "{theta_deg}: {} {expected}",
                light.z
            );
        }
    }

    #[test]
    fn a_camera_moving_forwards_sees_a_wider_scene_in_the_same_field_of_view() {
        // Backwards-traced rays at 10° to the direction of motion leave at a larger angle in
        // the scene frame: the scene ahead looks smaller (the forward field of view shrinks).
        let l = LorentzTransform::new(DVec3::new(0.0, 0.0, 0.99)).unwrap();
        let d = DVec3::new(10f64.to_radians().sin(), 0.0, 10f64.to_radians().cos());
        let dp = l.backwards_direction(d).normalize();
        let angle = dp.z.acos().to_degrees();
        // tan(θ′/2) = tan(θ/2) √((1 + β)/(1 − β)) for the backwards-traced ray.
        let expected = 2.0 * ((5f64.to_radians().tan()) * (1.99f64 / 0.01).sqrt()).atan();
        assert!((angle - expected.to_degrees()).abs() < 1e-9, "{angle}");
        assert!(angle > 80.0);
    }
}
