//! Ray trajectories: TIM "can visualise ray trajectories" (the paper's program summary). Rays
//! start at a given point and direction (one ray, a cone of rays, or a parallel bundle), are
//! followed forwards through the scene by the same surface laws the renderer applies
//! ([`crate::surfaces::Redirection`]), and every point where they meet a surface is recorded.
//! The recorded paths are drawn into the scene as chains of thin capped cylinders.
//!
//! Trajectories are traced through the scene-frame objects, before the cylinders are added,
//! so no trajectory meets another's cylinders.

mod follow;
mod tubes;

pub use follow::trace;
pub use tubes::tubes;

use glam::DVec3;

use crate::math::{Frame, Ray};
use crate::surfaces::Colour;

/// Most points the trajectories of one scene may have in all (some 25 MB of points and, drawn,
/// about a gigabyte of cylinders at worst).
pub const MAX_POINTS: usize = 500_000;

/// Most points kept of a curved path through one lens, evenly spaced along the integrator's
/// steps (a typical crossing takes about a hundred).
pub const MAX_CURVED_POINTS: usize = 256;

/// A source of ray trajectories in a scene (`[[ray_trajectory]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct RayTrajectory {
    /// Names the cylinders it is drawn with.
    pub name: String,
    pub start: DVec3,
    /// Unit vector: the direction of the ray, or the axis of the cone or bundle.
    pub direction: DVec3,
    pub spread: Spread,
    /// Radius of the cylinders (and joint spheres) drawn along the paths.
    pub radius: f64,
    /// The cylinders' colour, which they emit whatever the lighting.
    pub colour: Colour,
    /// Most surfaces a ray may meet before it is no longer followed.
    pub max_interactions: u32,
    /// Whether spheres of the cylinders' radius round off the joints between them.
    pub joints: bool,
}

/// How the rays of a trajectory source spread about its direction. The azimuths are measured
/// from the part of the global x axis perpendicular to the direction (y if it is along x).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Spread {
    /// One ray along the direction.
    Single,
    /// `rays` rays from the start on the cone of half-angle `half_angle` (radians) about the
    /// direction, equally spaced in azimuth (TIM's ray-trajectory cone).
    Cone { half_angle: f64, rays: u32 },
    /// `rays` rays parallel to the direction through the disc of radius `radius` centred on the
    /// start and perpendicular to the direction, spread evenly over its area (Vogel's sunflower
    /// pattern: ray k at distance radius·√((k + ½)/rays) from the centre, k golden angles round);
    /// a bundle of one ray is the central ray.
    Bundle { radius: f64, rays: u32 },
}

impl RayTrajectory {
    /// The rays this source starts, at time 0.
    pub fn rays(&self) -> Vec<Ray> {
        let d = self.direction;
        let reference = if d.cross(DVec3::X).length() < 1e-6 {
            DVec3::Y
        } else {
            DVec3::X
        };
        let f = Frame::from_normal_and_u(d, reference);
        let across = |angle: f64| angle.cos() * f.u + angle.sin() * f.v;
        match self.spread {
            Spread::Single | Spread::Bundle { rays: 1, .. } => vec![Ray::new(self.start, d, 0.0)],
            Spread::Cone { half_angle, rays } => (0..rays)
                .map(|k| {
                    let azimuth = std::f64::consts::TAU * k as f64 / rays as f64;
                    let direction = half_angle.cos() * d + half_angle.sin() * across(azimuth);
                    Ray::new(self.start, direction, 0.0)
                })
                .collect(),
            Spread::Bundle { radius, rays } => {
                let golden_angle = std::f64::consts::PI * (3.0 - 5f64.sqrt());
                (0..rays)
                    .map(|k| {
                        let r = radius * ((k as f64 + 0.5) / rays as f64).sqrt();
                        let start = self.start + r * across(golden_angle * k as f64);
                        Ray::new(start, d, 0.0)
                    })
                    .collect()
            }
        }
    }
}

/// One ray's recorded path.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Index of the [`RayTrajectory`] in the scene that started it.
    pub source: usize,
    /// Which of the source's rays it is.
    pub ray: usize,
    /// The start, then every point where the ray met a surface (and the points of curved
    /// paths inside gradient-index lenses), in order.
    pub points: Vec<Point>,
    pub end: End,
    /// The unit direction the ray travels in after its last point (for an absorbed or lost ray,
    /// the direction it arrived in).
    pub direction: DVec3,
}

/// A point of a trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub position: DVec3,
    /// How the ray got here from the previous point.
    pub arrival: Arrival,
    /// The description index of the object whose surface the point lies on; `None` for the
    /// start, points inside a lens, a teleporter's destination and the end of an escaping ray.
    pub object: Option<usize>,
}

/// How a ray got from one recorded point to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrival {
    /// The first point.
    Start,
    /// In a straight line through space.
    Straight,
    /// Across a lens whose law maps entry to exit in closed form (§3): the straight chord
    /// stands for a path the law does not give.
    Chord,
    /// Along the integrated curved path through a gradient-index lens.
    Curved,
    /// Teleported: no path between.
    Teleported,
}

/// Why a trajectory ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// On a surface with a colour of its own (lit or emitting), at the last point.
    Absorbed,
    /// No light comes back along the ray: trapped in a lens, or teleported beyond the
    /// destination's edge (at the last point).
    Lost,
    /// It met nothing more; the last point is where the drawing of it stops (see [`follow`]).
    Escaped,
    /// It met `max_interactions` surfaces and would go on from the last point.
    MaxInteractions,
}

impl Arrival {
    pub fn name(self) -> &'static str {
        match self {
            Arrival::Start => "start",
            Arrival::Straight => "straight",
            Arrival::Chord => "chord",
            Arrival::Curved => "curved",
            Arrival::Teleported => "teleported",
        }
    }
}

impl End {
    pub fn name(self) -> &'static str {
        match self {
            End::Absorbed => "absorbed",
            End::Lost => "lost",
            End::Escaped => "escaped",
            End::MaxInteractions => "max-interactions",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn source(spread: Spread) -> RayTrajectory {
        RayTrajectory {
            name: "t".into(),
            start: DVec3::new(1.0, 2.0, 3.0),
            direction: DVec3::Z,
            spread,
            radius: 0.01,
            colour: Colour::X,
            max_interactions: 10,
            joints: true,
        }
    }

    #[test]
    fn cone_rays_lie_on_the_cone_equally_spaced_from_the_x_axis() {
        let half_angle = 0.3f64;
        let rays = source(Spread::Cone {
            half_angle,
            rays: 4,
        })
        .rays();
        assert_eq!(rays.len(), 4);
        for (k, r) in rays.iter().enumerate() {
            assert_eq!(r.origin, DVec3::new(1.0, 2.0, 3.0));
            assert!((r.direction.z - half_angle.cos()).abs() < 1e-15);
            let azimuth = r.direction.y.atan2(r.direction.x);
            let expected = std::f64::consts::FRAC_PI_2 * k as f64;
            let turn = (azimuth - expected).rem_euclid(std::f64::consts::TAU);
            assert!(turn.min(std::f64::consts::TAU - turn) < 1e-12, "ray {k}");
        }
    }

    #[test]
    fn azimuths_start_from_the_x_axis_or_from_y_for_rays_along_x() {
        let first = |direction: DVec3| {
            let mut s = source(Spread::Cone {
                half_angle: 0.5,
                rays: 3,
            });
            s.direction = direction.normalize();
            s.rays()[0].direction - s.direction * 0.5f64.cos()
        };
        let across = first(DVec3::new(0.0, 1.0, 1.0));
        assert!((across.normalize() - DVec3::X).length() < 1e-12, "{across}");
        let across = first(DVec3::NEG_X);
        assert!((across.normalize() - DVec3::Y).length() < 1e-12, "{across}");
    }

    #[test]
    fn bundle_rays_are_parallel_and_fill_the_disc_evenly() {
        let rays = source(Spread::Bundle {
            radius: 2.0,
            rays: 1000,
        })
        .rays();
        let centre = DVec3::new(1.0, 2.0, 3.0);
        let inner = rays
            .iter()
            .filter(|r| r.origin.distance(centre) < 2.0 / 2f64.sqrt())
            .count();
        assert!(rays.iter().all(|r| r.direction == DVec3::Z));
        assert!(rays.iter().all(|r| r.origin.distance(centre) < 2.0));
        assert!(rays.iter().all(|r| r.origin.z == 3.0));
        assert_eq!(inner, 500, "half the rays within half the area");
    }
}
