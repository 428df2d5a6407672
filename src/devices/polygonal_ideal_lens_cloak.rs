//! The polygonal ideal-lens cloak (Dr TIM's `EditablePolygonalIdealLensCloak`): the
//! tetrahedral cloak (`ideal_lens_cloak.rs`) on a regular N-gon base of circumradius R, base
//! vertex i at angle 2πi/N from the back (towards the right), with the same inner vertices and
//! the same EM-space heights h₁′ and h₂′ (Dr TIM's focal lengths for this cloak imply the same
//! h₂′; the unit tests check them). Its lower inner pyramid has the N-gon as its base, so as a
//! lens simplicial complex it is cut into N tetrahedra about the base centre (an extra vertex
//! that stays put): the base lens becomes N coplanar triangles with one and the same lens,
//! and the cuts through the axis need no lens.
//!
//! Vertices: 0 … N − 1 the base, N its centre, N + 1 lower inner, N + 2 upper inner, N + 3 top.

use glam::DVec3;
use serde::Deserialize;

use super::ideal_lens_cloak::{CLOAK_FRAMES, CloakKeys, Layout, rename};
use super::{EdgeDefaults, Edges, IdealLensCloak, LensDevice, LensSimplicialComplex, Part};

#[derive(Debug, Clone, PartialEq)]
pub struct PolygonalIdealLensCloak {
    /// The tetrahedral cloak's parameters (its `base_radius` R is the distance of the base
    /// vertices from the base centre).
    pub cloak: IdealLensCloak,
    /// N ≥ 3.
    pub no_of_base_vertices: usize,
}

/// Most base vertices (Dr TIM's cloaks have a few).
const MAX_BASE_VERTICES: usize = 100;

impl LensDevice for PolygonalIdealLensCloak {
    /// The lenses, named as in Dr TIM (`outer lens #I`, `upper inner pyramid lens #I`, `lower
    /// inner pyramid lens #I`, `upper vertical lens #I`, `lower vertical lens #I` for I = 0 …
    /// N − 1, and the pieces `base outer lens #I`), and with `edges` its frames `edge I-J`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let n = self.no_of_base_vertices;
        if !(3..=MAX_BASE_VERTICES).contains(&n) {
            return Err(format!(
                "no_of_base_vertices must be from 3 to {MAX_BASE_VERTICES}, got {n}"
            ));
        }
        let cloak = &self.cloak;
        let (h, h1, h2, h1e) = (
            cloak.height,
            cloak.height_lower_inner_vertex_p,
            cloak.height_upper_inner_vertex_p,
            cloak.height_lower_inner_vertex_e,
        );
        let Layout {
            front,
            right,
            top,
            h2e,
        } = cloak.layout()?;
        let c = cloak.base_centre;
        let r = cloak.base_radius;
        let above = |height: f64| c + height * top;
        let mut vertices: Vec<DVec3> = (0..n)
            .map(|i| {
                let (sin, cos) = (std::f64::consts::TAU * i as f64 / n as f64).sin_cos();
                c + r * sin * right - r * cos * front
            })
            .collect();
        vertices.extend([c, above(h1), above(h2), above(h)]);
        let (centre, lower, upper, tip) = (n, n + 1, n + 2, n + 3);
        let mut vertices_v = vertices.clone();
        vertices_v[lower] = above(h1e);
        vertices_v[upper] = above(h2e);
        let mut joined = vec![[lower, upper], [upper, tip], [centre, lower]];
        for i in 0..n {
            joined.extend([i, (i + 1) % n].map(|j| [i, j]).into_iter().skip(1));
            joined.extend([[i, centre], [i, lower], [i, upper], [i, tip]]);
        }
        let complex = LensSimplicialComplex {
            vertices,
            vertices_v,
            edges: joined,
            lens_transmission_coefficient: cloak.interface_transmission_coefficient,
            lens_type: cloak.lens_element_type,
            structure_v: None,
        };
        let mut parts = complex.parts(edges)?;
        // The base centre only cuts the complex into cells: Dr TIM's frames have no vertex there
        // and no edges to it.
        let cuts = [format!("vertex {centre}"), format!("edge {centre}-{lower}")];
        parts.retain(|p| {
            !cuts.contains(&p.name) && !(0..n).any(|i| p.name == format!("edge {i}-{centre}"))
        });
        let names = (0..n).flat_map(|i| {
            let next = (i + 1) % n;
            [
                ([i, next, centre], format!("base outer lens #{i}")),
                ([i, next, tip], format!("outer lens #{i}")),
                ([i, next, upper], format!("upper inner pyramid lens #{i}")),
                ([i, next, lower], format!("lower inner pyramid lens #{i}")),
                ([i, upper, tip], format!("upper vertical lens #{i}")),
                ([i, lower, upper], format!("lower vertical lens #{i}")),
            ]
        });
        rename(&mut parts, names);
        Ok(parts)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        CLOAK_FRAMES
    }
}

/// `lenses = { type = "polygonal-ideal-lens-cloak" }`: Dr TIM's
/// `EditablePolygonalIdealLensCloak`, the tetrahedral cloak's keys and `no_of_base_vertices`
/// (3, a tetrahedron, where not given).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolygonalIdealLensCloakKeys {
    #[serde(flatten)]
    cloak: CloakKeys,
    no_of_base_vertices: Option<usize>,
}

impl PolygonalIdealLensCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        Ok(Box::new(PolygonalIdealLensCloak {
            cloak: self.cloak.cloak(),
            no_of_base_vertices: self.no_of_base_vertices.unwrap_or(3),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every lens against the focal lengths and nodal points of Dr TIM's
    /// `EditablePolygonalIdealLensCloak.addLenses` (magnitudes, as in `ideal_lens_cloak.rs`).
    #[test]
    fn the_lenses_are_dr_tims() {
        for (n, h1e) in [(3, -1.0), (4, 0.1), (6, 0.3), (7, -0.5)] {
            let (h1, h2, h3, r) = (0.6, 1.3, 2.0, 1.5);
            let cloak = PolygonalIdealLensCloak {
                cloak: IdealLensCloak {
                    base_centre: DVec3::new(0.0, -1.0, 10.0),
                    front_direction: DVec3::new(0.0, 0.0, -1.0),
                    right_direction: DVec3::X,
                    top_direction: DVec3::Y,
                    base_radius: r,
                    height: h3,
                    height_lower_inner_vertex_p: h1,
                    height_upper_inner_vertex_p: h2,
                    height_lower_inner_vertex_e: h1e,
                    interface_transmission_coefficient: 1.0,
                    lens_element_type: super::super::LensType::IdealThinLens,
                },
                no_of_base_vertices: n,
            };
            let f00 = h1 * h1e / (h1e - h1);
            let pi_n = std::f64::consts::PI / n as f64;
            let x0 = r * pi_n.cos();
            let upper_outer = f00 * x0 * (h3 - h2) * (h3 - h1)
                / ((x0 * x0 + h3 * h3).sqrt() * h2 * -h1)
                + x0 * (h3 - h2) * h3 / ((x0 * x0 + h3 * h3).sqrt() * h2);
            let upper_inner =
                f00 * x0 * (h3 - h2) * (h2 - h1) / ((x0 * x0 + h2 * h2).sqrt() * h3 * h1);
            let lower_inner = f00 * x0 * (h3 - h1) * (h2 - h1)
                / ((x0 * x0 + h1 * h1).sqrt() * h3 * -h2)
                - x0 * (h1 - h2) * h1 / ((x0 * x0 + h1 * h1).sqrt() * h2);
            let r1 = h3 / pi_n.cos();
            let upper_vertical =
                -upper_outer / (2.0 * (pi_n.tan() * h3) / (r * r + r1 * r1).sqrt());
            let lower_vertical = upper_vertical * (h1 - h2) / (h3 - h2);
            let parts = cloak.parts(None).unwrap();
            for i in 0..n {
                for (name, f, nodal_height) in [
                    (format!("base outer lens #{i}"), f00, 0.0),
                    (format!("outer lens #{i}"), upper_outer, h3),
                    (format!("upper inner pyramid lens #{i}"), upper_inner, h2),
                    (format!("lower inner pyramid lens #{i}"), lower_inner, h1),
                    (format!("upper vertical lens #{i}"), upper_vertical, h3),
                    (format!("lower vertical lens #{i}"), lower_vertical, h1),
                ] {
                    let nodal = DVec3::new(0.0, -1.0 + nodal_height, 10.0);
                    let label = format!("n = {n}, h1e = {h1e}");
                    crate::devices::checks::lens(&parts, &name, f, nodal, &label);
                }
            }
            // Nothing else: the cuts through the axis need no lens.
            assert_eq!(parts.len(), 6 * n, "n = {n}");
        }
    }
}
