//! Dr TIM's `RefractiveLensSurfaces` (sceneObjects/RefractiveLensSurfaces.java): "the optical
//! surfaces of a symmetric refractive lens" of glass of refractive index n, focal length f and
//! centre thickness d: two spherical surfaces of the same radius R, the lens biconvex for
//! R > 0 and biconcave for R < 0.
//!
//! R solves the thick-lens lensmaker's equation with radii R and −R,
//! 1/f = (n − 1) (2/R − (n − 1) d/(n R²)), which is n R² − 2 n (n − 1) f R + (n − 1)² f d = 0;
//! Dr TIM takes the root R = f (n − 1) + sign(f) √(f (n − 1)² n (f n − d))/n, the one that
//! tends to the thin lens's 2 f (n − 1) as d → 0. With the centre C, the unit axis â and
//! c = R − d/2, the spheres are centred at C ± c â, so the vertices are at C ± (d/2) â:
//!
//! - R > 0 (biconvex): the intersection of the two balls; it needs R ≥ d/2 (Dr TIM: "cannot
//!   be made"), and f n ≥ d for R to exist;
//! - R < 0 (biconcave): the cylinder of radius |R| about the axis between the spheres'
//!   centres, less the two balls (Dr TIM's cylinder mantle, whose ends lie inside the balls).
//!
//! Its surface is `refractive` with index ratio n, its only part `lens`.

use glam::DVec3;
use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{Csg, CsgOperation, Cylinder, GeometryError, RefractiveIndex, Shape, Sphere};
use crate::keys::{Coefficient, Direction, NonZero, Positive, Vector};
use crate::surfaces::{Refractive, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct RefractiveLensSurfaces {
    /// Half-way between the vertices.
    pub centre: DVec3,
    /// From the vertex of surface 1 to that of surface 2 (unit).
    pub normalised_optical_axis_direction: DVec3,
    /// f ≠ 0.
    pub focal_length: f64,
    /// n > 1.
    pub refractive_index: f64,
    /// d > 0.
    pub centre_thickness: f64,
    pub surface_transmission_coefficient: f64,
}

impl RefractiveLensSurfaces {
    /// Dr TIM's `calculateRFromLensmakersEquation`: R, or `None` if no symmetric lens of this
    /// focal length, index and thickness exists.
    pub fn radius_of_curvature(&self) -> Option<f64> {
        let (f, n, d) = (
            self.focal_length,
            self.refractive_index,
            self.centre_thickness,
        );
        let root = f * (n - 1.0) * (n - 1.0) * n * (f * n - d);
        (root >= 0.0).then(|| f * (n - 1.0) + f.signum() * root.sqrt() / n)
    }

    /// The lens as one solid.
    pub fn shape(&self) -> Result<Shape, String> {
        let (f, n, d) = (
            self.focal_length,
            self.refractive_index,
            self.centre_thickness,
        );
        let r = self.radius_of_curvature().ok_or_else(|| {
            format!(
                "no symmetric lens of focal length {f}, refractive index {n} and centre \
                 thickness {d} exists (a converging one needs f n ≥ d)"
            )
        })?;
        if r > 0.0 && r < 0.5 * d {
            return Err(format!(
                "the lens cannot be made: its radius of curvature {r} is less than half its \
                 centre thickness {d}"
            ));
        }
        let (c, axis) = (self.centre, self.normalised_optical_axis_direction);
        let lens = solid(c + (r - 0.5 * d) * axis, c - (r - 0.5 * d) * axis, r)
            .map_err(|e| e.to_string())?;
        Ok(Shape::Csg(lens))
    }
}

/// The biconvex intersection of the balls of radius R about `one` and `two` (R > 0), or the
/// cylinder between them less the balls (R < 0).
fn solid(one: DVec3, two: DVec3, r: f64) -> Result<Csg, GeometryError> {
    let balls = [Sphere::new(one, r.abs())?, Sphere::new(two, r.abs())?].map(Shape::Sphere);
    if r > 0.0 {
        Csg::new(CsgOperation::Intersection, balls.into())
    } else {
        let rim = Shape::Cylinder(Cylinder::new(one, two, r.abs())?);
        Csg::new(CsgOperation::Difference, [vec![rim], balls.into()].concat())
    }
}

impl LensDevice for RefractiveLensSurfaces {
    /// `lens`; no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("refractive lens surfaces have no edges to show (show_edges)".into());
        }
        Ok(vec![Part {
            name: "lens".into(),
            shape: self.shape()?,
            surface: Surface::Refractive(Refractive {
                index_ratio: self.refractive_index,
                transmission_coefficient: self.surface_transmission_coefficient,
            }),
            edge: false,
        }])
    }
}

/// `lenses = { type = "refractive-lens-surfaces" }`: Dr TIM's `RefractiveLensSurfaces` (no
/// defaults: it has no editable form; the transmission coefficient, if left out, is 1).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefractiveLensSurfacesKeys {
    centre: Vector,
    normalised_optical_axis_direction: Direction,
    focal_length: NonZero,
    refractive_index: RefractiveIndex,
    centre_thickness: Positive,
    surface_transmission_coefficient: Option<Coefficient>,
}

impl RefractiveLensSurfacesKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(RefractiveLensSurfaces {
            centre: self.centre.0,
            normalised_optical_axis_direction: self.normalised_optical_axis_direction.0,
            focal_length: self.focal_length.0,
            refractive_index: self.refractive_index.0,
            centre_thickness: self.centre_thickness.0,
            surface_transmission_coefficient: crate::keys::coefficient(
                self.surface_transmission_coefficient,
            ),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lens(f: f64, d: f64) -> RefractiveLensSurfaces {
        RefractiveLensSurfaces {
            centre: DVec3::new(0.0, 0.0, 5.0),
            normalised_optical_axis_direction: DVec3::Z,
            focal_length: f,
            refractive_index: 1.5,
            centre_thickness: d,
            surface_transmission_coefficient: 1.0,
        }
    }

    #[test]
    fn the_radius_solves_the_thick_lensmakers_equation() {
        for (f, d) in [(1.0, 0.1), (3.0, 0.5), (-1.0, 0.1), (-2.0, 0.4)] {
            let l = lens(f, d);
            let r = l.radius_of_curvature().unwrap();
            let n = 1.5;
            let inverse = (n - 1.0) * (2.0 / r - (n - 1.0) * d / (n * r * r));
            assert!((1.0 / inverse - f).abs() < 1e-12 * f.abs(), "f {f}: {r}");
            // The vertices are d apart on the axis.
            let s = l.shape().unwrap();
            let o = DVec3::new(0.0, 0.0, -1.0);
            let (t, _) = s.intersect(o, DVec3::Z, 0.0, 100.0).unwrap();
            assert!((t - (6.0 - 0.5 * d)).abs() < 1e-12, "f {f}: {t}");
        }
    }

    #[test]
    fn impossible_lenses_are_refused() {
        // f n < d: no converging lens.
        assert!(
            lens(0.1, 0.2)
                .shape()
                .unwrap_err()
                .contains("no symmetric lens")
        );
        // f n = d: R = f (n − 1) = 0.5 < d/2 = 0.75.
        assert!(
            lens(1.0, 1.5)
                .shape()
                .unwrap_err()
                .contains("cannot be made")
        );
    }
}
