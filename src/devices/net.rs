//! What Dr TIM's nets of 4D polytopes share (`EditableNetOfHypercube`,
//! `EditableNetOfSymmetric4Simplex`): faces that are colour filters, shown with the net's edges,
//! and left out where a shown space-cancelling-wedge surface takes their place.

use glam::{DVec2, DVec3};

use super::{EdgeDefaults, Edges, Part};
use crate::geometry::{ConvexPolygon, Shape};
use crate::math::Colour;
use crate::surfaces::{ColourFilter, Coloured, Surface};

/// Dr TIM's `MyMath.TINY`, by which the wedges' edges are thinner than the net's.
pub const TINY: f64 = 1e-4;

/// Dr TIM's net structure (edges, and for the 4-simplex vertices): hidden, radius 0.02,
/// `SurfaceColour.BLUE_SHINY`.
pub const NET_EDGES: EdgeDefaults = EdgeDefaults {
    shown: false,
    radius: 0.02,
    colour: Colour::new(0.0, 0.0, 1.0),
};

/// Dr TIM's `ColourFilter.CYAN_GLASS`, the nets' faces by default: cyan (0, 198, 200)/255.
pub const CYAN_GLASS: Colour = Colour::new(0.0, 198.0 / 255.0, 200.0 / 255.0);

/// The edges of a net's wedges, if `shown`: shiny red (Dr TIM's `RED_SHINY`), of `radius` where
/// given, else (as Dr TIM's) [`TINY`] thinner than the net's edges, whose radius is 0.02 where
/// they are hidden.
pub fn wedge_edges(
    shown: bool,
    radius: Option<f64>,
    net_edges: Option<&Edges>,
) -> Result<Option<Edges>, String> {
    if !shown {
        return Ok(None);
    }
    let radius = match radius {
        Some(r) => r,
        None => {
            let net = net_edges.map_or(NET_EDGES.radius, |e| e.radius);
            if net <= TINY {
                return Err(format!(
                    "the wedges' edges are 1e-4 thinner than the net's, which are {net} thick: \
                     give space_cancelling_wedge_edge_radius"
                ));
            }
            net - TINY
        }
    };
    Ok(Some(Edges {
        radius,
        surface: Surface::Coloured(Coloured::shiny(Colour::new(1.0, 0.0, 0.0))),
    }))
}

/// A face of a net, with its centroid and unit normal.
pub struct NetFace {
    part: Part,
    centre: DVec3,
    normal: DVec3,
}

/// The face `name` with these corners (in order round it), a colour filter passing
/// `transmission` that throws no shadow (Dr TIM's `CYAN_GLASS` and its kind).
pub fn face(name: String, corners: Vec<DVec3>, transmission: Colour) -> Result<NetFace, String> {
    let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    let centre = corners.iter().sum::<DVec3>() / corners.len() as f64;
    let shape = ConvexPolygon::new(corners).map_err(|e| format!("{name}: {e}"))?;
    Ok(NetFace {
        part: Part {
            name,
            shape: Shape::ConvexPolygon(shape),
            surface: Surface::ColourFilter(ColourFilter { transmission }),
            edge: false,
        },
        centre,
        normal: normal.normalize(),
    })
}

impl NetFace {
    /// Whether the face's centre lies on the flat surface `shape`, in its plane.
    fn on(&self, shape: &Shape) -> bool {
        let Some(origin) = shape.point_at(DVec2::ZERO) else {
            return false;
        };
        let m = shape.frame(origin, 0).w;
        let scale = 1.0 + self.centre.abs().max_element() + origin.abs().max_element();
        self.normal.cross(m).length() < 1e-9
            && (self.centre - origin).dot(m).abs() < 1e-9 * scale
            && shape.point_at(shape.coordinates(self.centre, 0)).is_some()
    }
}

/// `parts` (a net's wedges and edges) with the `faces` whose centres lie on none of the
/// wedges' flat surfaces: such a surface stands in the face's place (a ray that met both would
/// meet only the one found first, the other being within its self-hit margin; Dr TIM traces
/// its trajectories with the faces hidden).
pub fn with_faces(mut parts: Vec<Part>, faces: Vec<NetFace>) -> Vec<Part> {
    let shown: Vec<Part> = faces
        .into_iter()
        .filter(|f| {
            !parts
                .iter()
                .any(|p| !p.edge && p.shape.is_flat() && f.on(&p.shape))
        })
        .map(|f| f.part)
        .collect();
    parts.extend(shown);
    parts
}
