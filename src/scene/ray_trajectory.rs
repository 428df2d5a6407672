//! Sources of ray trajectories (`[[ray_trajectory]]`): where rays start and how they spread;
//! `trajectories` follows them and draws their paths.

use glam::DVec3;

use crate::math::{Colour, Frame, Ray};

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
    /// `rays` skew rays that rule a hyperboloid of one sheet about the direction (Dr TIM's
    /// `RayTrajectoryHyperboloid`): ray k starts at azimuth φ_k = 2πk/rays on the waist, the
    /// circle of radius `waist_radius` about the start perpendicular to the direction, and
    /// leaves it at `half_angle` to the direction, tilted along the circle (towards increasing
    /// azimuth). At distance z along the direction the rays are √(w² + z² tan²α) from the axis.
    Hyperboloid {
        half_angle: f64,
        waist_radius: f64,
        rays: u32,
    },
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
            Spread::Hyperboloid {
                half_angle,
                waist_radius,
                rays,
            } => (0..rays)
                .map(|k| {
                    let azimuth = std::f64::consts::TAU * k as f64 / rays as f64;
                    let along = std::f64::consts::FRAC_PI_2 + azimuth;
                    let direction = half_angle.cos() * d + half_angle.sin() * across(along);
                    Ray::new(self.start + waist_radius * across(azimuth), direction, 0.0)
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

    /// Every point of every ray satisfies x² + y² − z² tan²α = w² (the hyperboloid of one
    /// sheet about the start, for the axis along z), the rays pass the waist circle at its
    /// radius at z = 0, and no two of them meet (skew lines: their common normal is not 0).
    #[test]
    fn hyperboloid_rays_rule_the_hyperboloid_of_one_sheet_and_are_skew() {
        let (half_angle, waist_radius) = (0.35f64, 0.8);
        let rays = source(Spread::Hyperboloid {
            half_angle,
            waist_radius,
            rays: 7,
        })
        .rays();
        let centre = DVec3::new(1.0, 2.0, 3.0);
        assert_eq!(rays.len(), 7);
        for r in &rays {
            assert!((r.direction.length() - 1.0).abs() < 1e-15);
            assert!((r.direction.z - half_angle.cos()).abs() < 1e-15);
            for t in [-3.0, 0.0, 0.5, 4.0] {
                let p = r.origin + t * r.direction - centre;
                let residual = p.x * p.x + p.y * p.y
                    - (p.z * half_angle.tan()).powi(2)
                    - waist_radius * waist_radius;
                assert!(residual.abs() < 1e-12, "{residual}");
            }
        }
        for (i, a) in rays.iter().enumerate() {
            for b in &rays[i + 1..] {
                let normal = a.direction.cross(b.direction).normalize();
                assert!((b.origin - a.origin).dot(normal).abs() > 1e-3);
            }
        }
        // The first ray starts on the x axis's side and turns towards +y (Dr TIM's sense).
        assert!((rays[0].origin - centre - DVec3::new(waist_radius, 0.0, 0.0)).length() < 1e-15);
        assert!(rays[0].direction.y > 0.0 && rays[0].direction.x.abs() < 1e-15);
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
