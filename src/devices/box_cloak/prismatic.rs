//! The prismatic box cloak (Dr TIM's `EditableBoxCloak` with `BoxCloakType.PRISMATIC`, its
//! `PrismaticBoxCloakMaker`, and the "square prismatic" `EditableGCLAsCloak`): the octahedral
//! cloak's construction in the plane perpendicular to the top direction, extruded along it. A
//! cube of side L = 2h about c holds a central square prism, its vertical edges p h from c
//! along the front, right, back and left axes, which, and anything in it, is seen as the prism
//! with its edges e h from c (its height unchanged), while the space round the cloak is seen
//! as it is.
//!
//! The cube is cut into the central prism, a triangular prism behind each of the four side
//! faces (the face and the central prism's edge on its axis) and one at each vertical edge of
//! the cube (that edge and the central prism's two edges next to it). Each region is seen
//! through an affine map that keeps the top direction: the identity outside, x ↦ c + (e/p)
//! (x − c)⊥ + ((x − c)·t̂) t̂ inside, and in each triangular prism the map that keeps its cube
//! edges where they are and moves its central-prism edges from p h to e h. Each face is the
//! gCLAs that image the region behind it into the one in front: Dr TIM's exterior faces,
//! interior interfaces and innermost interfaces.
//!
//! Like Dr TIM's, the cloak has no top or bottom faces: it is a slice of an infinitely long
//! prismatic cloak, and works for light that crosses only its side faces.

use glam::DVec3;

use super::{Axis, BoxCloakParameters};
use crate::devices::affine_regions::Region;
use crate::devices::{EdgeDefaults, Edges, LensDevice, Part};

/// The prismatic box cloak.
#[derive(Debug, Clone, PartialEq)]
pub struct PrismaticBoxCloak(pub BoxCloakParameters);

impl PrismaticBoxCloak {
    /// The side axes in order round the top direction (front, right, back, left), and the top
    /// direction.
    fn axes(&self) -> ([Axis; 4], Axis) {
        let [front, right, top] = self.0.axes();
        ([front, right, -front, -right], top)
    }

    /// The names of side axes `n` and `m`, front or back first.
    fn names(n: Axis, m: Axis) -> (&'static str, &'static str) {
        if matches!(n.name, "front" | "back") {
            (n.name, m.name)
        } else {
            (m.name, n.name)
        }
    }

    /// The name of the vertical cube edge between side axes `n` and `m`: `front right`.
    fn pair(n: Axis, m: Axis) -> String {
        let (a, b) = Self::names(n, m);
        format!("{a} {b}")
    }
}

impl LensDevice for PrismaticBoxCloak {
    /// The gCLAs `exterior face front` (and right, back, left), `interface between the front
    /// prism and the front right edge prism`, ... and `innermost interface front right`, ...;
    /// with `edges` Dr TIM's frames: `cube vertex top right front`, `cuboid vertex top front`,
    /// `cube edge ...`, `cuboid edge top front to top right`, `cuboid edge front` (vertical)
    /// and `star edge from the top right front corner to the top front cuboid vertex`, ...
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let b = &self.0;
        b.check_precision()?;
        // e = 0 shows the central prism as a line, e = 1 its edges in the cube's faces, e = 2
        // flattens the prisms at the cube's vertical edges.
        b.check_em(&[0.0, 1.0, 2.0])?;
        let (sides, top) = self.axes();
        let t = top.v;
        let inside = b.region(&[t], &[sides[0].v, sides[1].v, sides[2].v], "central prism")?;
        let edge_prism = |n: Axis, m: Axis| {
            b.region(
                &[n.v + m.v + t, n.v + m.v - t],
                &[n.v, m.v],
                &format!("{} edge prism", Self::pair(n, m)),
            )
        };
        let mut parts = Vec::new();
        for (i, &n) in sides.iter().enumerate() {
            let (next, previous) = (sides[(i + 1) % 4], sides[(i + 3) % 4]);
            let face = [
                n.v + previous.v + t,
                n.v + next.v + t,
                n.v + next.v - t,
                n.v + previous.v - t,
            ];
            let prism = b.region(&face[..3], &[n.v], &format!("{} prism", n.name))?;
            parts.push(b.gclas_interface(
                format!("exterior face {}", n.name),
                face.to_vec(),
                &Region::outside(n.v),
                &prism,
            )?);
            let apex = b.apex(n.v, false);
            for m in [next, previous] {
                parts.push(b.gclas_interface(
                    format!(
                        "interface between the {} prism and the {} edge prism",
                        n.name,
                        Self::pair(n, m)
                    ),
                    vec![apex + t, n.v + m.v + t, n.v + m.v - t, apex - t],
                    &prism,
                    &edge_prism(n, m)?,
                )?);
            }
            let apex_next = b.apex(next.v, false);
            parts.push(b.gclas_interface(
                format!("innermost interface {}", Self::pair(n, next)),
                vec![apex + t, apex_next + t, apex_next - t, apex - t],
                &edge_prism(n, next)?,
                &inside,
            )?);
        }
        if let Some(e) = edges {
            parts.extend(self.frames(e)?);
        }
        Ok(parts)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        self.0.edge_defaults()
    }
}

impl PrismaticBoxCloak {
    /// Dr TIM's frames: spheres at the cube's and the central prism's ("cuboid's") vertices,
    /// cylinders along their edges and from each cube corner to the central prism's two
    /// vertices next to it.
    fn frames(&self, e: &Edges) -> Result<Vec<Part>, String> {
        let b = &self.0;
        let (sides, top) = self.axes();
        let place = b.place();
        let edge = |name: String, a: DVec3, c: DVec3| e.part(name, place.point(a), place.point(c));
        let cuboid = |n: Axis, level: Axis| b.apex(n.v, false) + level.v;
        let mut parts = b.cube_frames(e, &|_, _| true)?;
        for (i, &n) in sides.iter().enumerate() {
            let next = sides[(i + 1) % 4];
            for level in [top, -top] {
                parts.push(e.vertex(
                    format!("cuboid vertex {} {}", level.name, n.name),
                    place.point(cuboid(n, level)),
                )?);
                parts.push(edge(
                    format!(
                        "cuboid edge {} {} to {} {}",
                        level.name, n.name, level.name, next.name
                    ),
                    cuboid(n, level),
                    cuboid(next, level),
                )?);
                let corner = n.v + next.v + level.v;
                let (front_back, right_left) = Self::names(n, next);
                for m in [n, next] {
                    parts.push(edge(
                        format!(
                            "star edge from the {} {right_left} {front_back} corner to the {} {} \
                             cuboid vertex",
                            level.name, level.name, m.name
                        ),
                        corner,
                        cuboid(m, level),
                    )?);
                }
            }
            parts.push(edge(
                format!("cuboid edge {}", n.name),
                cuboid(n, top),
                cuboid(n, -top),
            )?);
        }
        Ok(parts)
    }
}
