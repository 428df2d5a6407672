//! The net of a hypercube (Dr TIM's `EditableNetOfHypercube`): the tesseract's eight cubes
//! unfolded into 3D space, optically glued into its 3D surface. About the inner cube (side s,
//! centred on `centre`) sit six outer cubes, one on each face, and the eighth cube (the one
//! opposite the inner cube in 4D) cut into six square pyramids of height s/2, one on each
//! outer cube's outer face, their apices at the eighth cube's centre (2s from `centre`).
//!
//! The net closes up where space-cancelling wedges ([`SpaceCancellingWedge`]) remove the space
//! between faces that are one face of the tesseract: along each of the inner cube's 12 edges a
//! 90° wedge (legs s × `space_cancelling_wedge_leg_length_factor` along the two outer cubes'
//! facing sides) glues the outer cubes to each other, and a 180° wedge with its apex edge
//! twice as far from `centre` (legs √2 s × factor, in the plane of the two pyramids' facing
//! sides) glues those sides. A straight line in the tesseract's surface, e.g. from the inner
//! cube through an outer cube, the eighth cube and the opposite outer cube, is a ray that
//! closes on itself after 4s.

use glam::DVec3;
use serde::Deserialize;

use super::net::{self, CYAN_GLASS, NetFace};
use super::space_cancelling_wedge::{Gluing, SpaceCancellingWedge};
use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::keys::{Coefficient, Direction, Positive, Rgb, Vector, throughput};
use crate::math::Colour;

#[derive(Debug, Clone, PartialEq)]
pub struct NetOfHypercube {
    pub centre: DVec3,
    pub right_direction: DVec3,
    /// Made perpendicular to the right direction; must not be along it.
    pub up_direction: DVec3,
    pub side_length: f64,
    pub show_space_cancelling_wedges: bool,
    pub space_cancelling_wedge_leg_length_factor: f64,
    pub space_cancelling_wedge_surface_transmission_coefficient: f64,
    pub gluing: Gluing,
    pub number_of_negative_space_wedges: u32,
    pub distance_p1_p2: f64,
    /// Whether the wedges' edges are shown (Dr TIM's `showSpaceCancellingWedgeEdges`).
    pub show_space_cancelling_wedge_edges: bool,
    /// Their radius, where given (else 10⁻⁴ less than the net's edges').
    pub space_cancelling_wedge_edge_radius: Option<f64>,
    /// The colour filter of the net's faces, shown with its edges.
    pub net_face_transmission: Colour,
}

/// A direction with its name and its opposite's (Dr TIM's `NamedDirection`).
#[derive(Clone, Copy)]
struct Named(DVec3, &'static str, &'static str);

impl Named {
    fn reverse(self) -> Named {
        Named(-self.0, self.2, self.1)
    }
}

/// One of the six sides of the inner cube: its outward normal n̂ and the normals m̂ and ô of
/// two other sides.
#[derive(Clone, Copy)]
struct Side {
    n: Named,
    m: Named,
    o: Named,
}

impl NetOfHypercube {
    /// Dr TIM's six sides (n, m, o), from its right, up and front directions (front = up ×
    /// right).
    fn sides(&self) -> Result<[Side; 6], String> {
        let right = self.right_direction.normalize();
        let up = self.up_direction.reject_from_normalized(right);
        if up.length() <= 1e-12 * self.up_direction.length() {
            return Err(format!(
                "up_direction = {} is along right_direction = {}",
                self.up_direction, self.right_direction
            ));
        }
        let up = up.normalize();
        let (r, u, f) = (
            Named(right, "right", "left"),
            Named(up, "top", "bottom"),
            Named(up.cross(right), "front", "back"),
        );
        let side = |n, m, o| Side { n, m, o };
        Ok([
            side(r, u, f),
            side(r.reverse(), u, f.reverse()),
            side(u, f, r),
            side(u.reverse(), f, r.reverse()),
            side(f, r, u),
            side(f.reverse(), r, u.reverse()),
        ])
    }

    /// The two wedges along the inner cube's edge from `start` to `end`, with `edges`.
    fn wedges(
        &self,
        name: &str,
        start: DVec3,
        end: DVec3,
        edges: Option<&Edges>,
    ) -> Result<Vec<Part>, String> {
        let s = self.side_length;
        let k = self.space_cancelling_wedge_leg_length_factor;
        let mid = 0.5 * (start + end);
        let wedge =
            |apex_angle: f64, apex_edge_centre: DVec3, leg_length: f64| SpaceCancellingWedge {
                apex_angle,
                apex_edge_centre,
                apex_edge_direction: end - start,
                bisector_direction: mid - self.centre,
                leg_length,
                apex_edge_length: s,
                show_refracting_surfaces: self.show_space_cancelling_wedges,
                containment_mirrors_angle_with_sides: 91f64.to_radians(),
                surface_transmission_coefficient: self
                    .space_cancelling_wedge_surface_transmission_coefficient,
                gluing: self.gluing,
                number_of_negative_space_wedges: self.number_of_negative_space_wedges,
                distance_p1_p2: self.distance_p1_p2,
            };
        let mut parts = wedge(std::f64::consts::FRAC_PI_2, mid, s * k)
            .parts_named(&format!("90° wedge at {name}/"), edges)?;
        parts.extend(
            wedge(
                std::f64::consts::PI,
                self.centre + 2.0 * (mid - self.centre),
                std::f64::consts::SQRT_2 * s * k,
            )
            .parts_named(&format!("180° wedge at {name}/"), edges)?,
        );
        Ok(parts)
    }

    /// The parts Dr TIM's `addSceneObjectsForSide` adds for `side`: the wedges along two of
    /// the inner cube's edges, and with `edges` the net's edges of the outer cube and the
    /// pyramid on that side, and their faces (added to `faces`).
    fn side(
        &self,
        side: Side,
        edges: Option<&Edges>,
        wedge_edges: Option<&Edges>,
        faces: &mut Vec<NetFace>,
    ) -> Result<Vec<Part>, String> {
        let h = 0.5 * self.side_length;
        let s = self.side_length;
        let Side { n, m, o } = side;
        let (nn, mn, on) = (n.1, m.1, o.1);
        let (mo, oo) = (m.2, o.2);
        let corner = |along_n: f64, o_sign: f64, m_sign: f64| {
            self.centre + along_n * n.0 + o_sign * h * o.0 + m_sign * h * m.0
        };
        let inner = |os, ms| corner(h, os, ms);
        let outer = |os, ms| corner(3.0 * h, os, ms);
        let apex = self.centre + 2.0 * s * n.0;
        let mut parts = Vec::new();
        parts.extend(self.wedges(
            &format!("inner cube's {nn} {on} edge"),
            inner(1.0, -1.0),
            inner(1.0, 1.0),
            wedge_edges,
        )?);
        parts.extend(self.wedges(
            &format!("inner cube's {nn} {oo} edge"),
            inner(-1.0, -1.0),
            inner(-1.0, 1.0),
            wedge_edges,
        )?);
        let Some(edges) = edges else {
            return Ok(parts);
        };
        let cube = format!("{nn} outer cube");
        let mut cylinders = vec![
            (
                format!("inner cube's {nn} {on} edge"),
                inner(1.0, -1.0),
                inner(1.0, 1.0),
            ),
            (
                format!("inner cube's {nn} {oo} edge"),
                inner(-1.0, -1.0),
                inner(-1.0, 1.0),
            ),
            (
                format!("{cube}'s outer {on} edge"),
                outer(1.0, -1.0),
                outer(1.0, 1.0),
            ),
            (
                format!("{cube}'s outer {oo} edge"),
                outer(-1.0, -1.0),
                outer(-1.0, 1.0),
            ),
            (
                format!("{cube}'s outer {mn} edge"),
                outer(1.0, 1.0),
                outer(-1.0, 1.0),
            ),
            (
                format!("{cube}'s outer {mo} edge"),
                outer(1.0, -1.0),
                outer(-1.0, -1.0),
            ),
        ];
        for (os, o_name) in [(1.0, on), (-1.0, oo)] {
            for (ms, m_name) in [(1.0, mn), (-1.0, mo)] {
                cylinders.push((
                    format!("{cube}'s {o_name} {m_name} edge"),
                    inner(os, ms),
                    outer(os, ms),
                ));
                cylinders.push((
                    format!("{cube}'s outer {o_name} {m_name} corner to the eighth cube's centre"),
                    apex,
                    outer(os, ms),
                ));
            }
        }
        for (name, start, end) in cylinders {
            parts.push(edges.part(name, start, end)?);
        }
        let face = |name: String, corners: Vec<DVec3>| {
            net::face(name, corners, self.net_face_transmission)
        };
        let square = |name: String, corner: DVec3, u: DVec3, v: DVec3| {
            face(name, vec![corner, corner + u, corner + u + v, corner + v])
        };
        let triangle = |name: String, a: DVec3, b: DVec3| face(name, vec![a, b, apex]);
        let (sn, sm, so) = (s * n.0, s * m.0, s * o.0);
        let sixth = format!("{nn} sixth of the eighth cube");
        faces.extend([
            square(
                format!("{nn} face of the inner cube"),
                inner(1.0, 1.0),
                -sm,
                -so,
            )?,
            square(format!("{mn} face of the {cube}"), inner(1.0, 1.0), sn, -so)?,
            square(
                format!("{mo} face of the {cube}"),
                inner(1.0, -1.0),
                sn,
                -so,
            )?,
            square(format!("{on} face of the {cube}"), inner(1.0, 1.0), sn, -sm)?,
            square(
                format!("{oo} face of the {cube}"),
                inner(-1.0, 1.0),
                sn,
                -sm,
            )?,
            square(
                format!("{nn} face of the {cube}"),
                outer(1.0, 1.0),
                -sm,
                -so,
            )?,
            triangle(
                format!("{mn} face of the {sixth}"),
                outer(1.0, 1.0),
                outer(-1.0, 1.0),
            )?,
            triangle(
                format!("{mo} face of the {sixth}"),
                outer(1.0, -1.0),
                outer(-1.0, -1.0),
            )?,
            triangle(
                format!("{on} face of the {sixth}"),
                outer(1.0, 1.0),
                outer(1.0, -1.0),
            )?,
            triangle(
                format!("{oo} face of the {sixth}"),
                outer(-1.0, 1.0),
                outer(-1.0, -1.0),
            )?,
        ]);
        Ok(parts)
    }
}

impl LensDevice for NetOfHypercube {
    /// For each inner-cube edge (e.g. `inner cube's right front edge`) its wedges' parts,
    /// `90° wedge at EDGE/PART` and `180° wedge at EDGE/PART`; with `edges`, the net's edges
    /// and faces (`right face of the inner cube`, `top face of the right outer cube`,
    /// `top face of the right sixth of the eighth cube`, ...), but for those a shown wedge
    /// surface stands in for (see `devices/net.rs`).
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        // Dr TIM's containment mirrors, at 91° to the sides, meet the long legs only in
        // negative-space wedges under 89°: the 180° wedges need at least two.
        if self.gluing == Gluing::NegativeSpaceWedgesWithContainmentMirrors
            && self.number_of_negative_space_wedges < 2
        {
            return Err(
                "gluing_type = \"negative-space-wedges-with-containment-mirrors\" needs \
                        number_of_negative_space_wedges = 2 or more in a net of a hypercube (the \
                        containment mirrors of its 180° wedges, at 91° to the sides, meet the \
                        long legs only in negative-space wedges under 89°)"
                    .into(),
            );
        }
        let wedge_edges = net::wedge_edges(
            self.show_space_cancelling_wedge_edges,
            self.space_cancelling_wedge_edge_radius,
            edges,
        )?;
        let (mut parts, mut faces) = (Vec::new(), Vec::new());
        for side in self.sides()? {
            parts.extend(self.side(side, edges, wedge_edges.as_ref(), &mut faces)?);
        }
        Ok(net::with_faces(parts, faces))
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        net::NET_EDGES
    }
}

/// `lenses = { type = "net-of-hypercube" }`: Dr TIM's `EditableNetOfHypercube`, with the
/// defaults of its constructor `EditableNetOfHypercube(parent, studio)`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetOfHypercubeKeys {
    centre: Option<Vector>,
    right_direction: Option<Direction>,
    up_direction: Option<Direction>,
    side_length: Option<Positive>,
    show_space_cancelling_wedges: Option<bool>,
    space_cancelling_wedge_leg_length_factor: Option<Positive>,
    space_cancelling_wedge_surface_transmission_coefficient: Option<Coefficient>,
    gluing_type: Option<Gluing>,
    number_of_negative_space_wedges: Option<u32>,
    distance_p1_p2: Option<Positive>,
    show_space_cancelling_wedge_edges: Option<bool>,
    space_cancelling_wedge_edge_radius: Option<Positive>,
    net_face_transmission: Option<Rgb>,
}

impl NetOfHypercubeKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let net = NetOfHypercube {
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            right_direction: self.right_direction.map_or(DVec3::X, |d| d.0),
            up_direction: self.up_direction.map_or(DVec3::Y, |d| d.0),
            side_length: self.side_length.map_or(1.0, |s| s.0),
            show_space_cancelling_wedges: self.show_space_cancelling_wedges.unwrap_or(true),
            space_cancelling_wedge_leg_length_factor: self
                .space_cancelling_wedge_leg_length_factor
                .map_or(1.0, |k| k.0),
            space_cancelling_wedge_surface_transmission_coefficient: throughput(
                self.space_cancelling_wedge_surface_transmission_coefficient,
            ),
            gluing: self.gluing_type.unwrap_or(Gluing::Perfect),
            number_of_negative_space_wedges: self.number_of_negative_space_wedges.unwrap_or(1),
            distance_p1_p2: self.distance_p1_p2.map_or(1.0, |d| d.0),
            show_space_cancelling_wedge_edges: self
                .show_space_cancelling_wedge_edges
                .unwrap_or(false),
            space_cancelling_wedge_edge_radius: self
                .space_cancelling_wedge_edge_radius
                .map(|r| r.0),
            net_face_transmission: self.net_face_transmission.map_or(CYAN_GLASS, |t| t.0),
        };
        Ok(Box::new(net))
    }
}
