//! A window that changes ray directions like a Lorentz transformation (§6): looking through it
//! shows the scene as a camera moving with velocity β sees it (relativistic aberration, Eq 4).
//!
//! The paper gives no formula; this follows from its stated behaviour: the direction of each ray
//! traced back through the window changes as the camera's backwards-traced rays do on entering
//! the scene frame (§2.1, Eq 4), d′ ∝ d + (γ − 1)(β̂·d)β̂ − γ|d|β. The window changes only
//! directions, not times or positions, so unlike a moving camera it shows no light-travel-time
//! effects. The law is not reciprocal (aberration by β does not undo itself for reversed rays);
//! it is applied to rays arriving from either side, and the ray continues in the new direction
//! whichever side of the window that points to.

use crate::math::LorentzTransform;
use crate::render::{Interaction, Tracer};
use crate::surfaces::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct LorentzWindow {
    /// The boost of the virtual camera, velocity β (|β| < 1).
    pub boost: LorentzTransform,
    /// Fraction of the light transmitted, in [0, 1].
    pub transmission_coefficient: f64,
}

impl LorentzWindow {
    pub fn colour(&self, tracer: &Tracer, at: &Interaction) -> Colour {
        let out = self.boost.backwards_direction(at.ray.direction);
        self.transmission_coefficient * tracer.trace_from(at, out)
    }
}
