//! Shifty cloaks (Dr TIM's `EditableCubicShiftyCloak` and `EditableSimpleTetrahedralShiftyCloak`,
//! "realised using homogeneous GCLAs"): a polyhedral shell of homogeneous planar imaging
//! surfaces round an empty inner polyhedron, the outer one scaled about the centre, that makes
//! the inner polyhedron, and anything in it, appear shifted by δ, while the space outside the
//! cloak is seen as it is.
//!
//! The shell is cut into frusta, one on each outer face, by the diagonal faces joining each outer
//! edge to the inner one in front of it. Each region is seen from outside through an affine map
//! V (its "virtual space"): outside V(x) = x, inside V(x) = x + δ, and in the frustum on the face
//! of outward unit normal n̂, a distance r from the centre c,
//!
//!   V(x) = x + (d(x)/h) δ,   d(x) = r − n̂·(x − c),   h = (1 − k) r,
//!
//! k being the ratio of the inner to the outer side length: d is the distance from the outer
//! face, h that of the inner face. Neighbouring maps agree on the faces between them (on a
//! diagonal face, which contains c, the two frusta's d/h are equal), so each face is the
//! homogeneous planar imaging surface ([`HomogeneousPlanarImaging`]) that images a point x of the
//! region behind it into V_front⁻¹(V_behind(x)) in front; Dr TIM's conjugate pairs (other
//! points) give its faces the same maps. A frustum's map is singular where n̂·δ = h (the inner face would appear in
//! the outer face's plane): refused.

use glam::DVec3;
use serde::Deserialize;

use super::polyhedral_shell::{AxisNames, Interface, Polyhedron, Region, Shell};
use super::{EdgeDefaults, Edges, LensDevice, Part};
use crate::geometry::{ConvexPolygon, Shape};
use crate::keys::{Coefficient, Direction, Positive, Vector, throughput};
use crate::surfaces::metatoys::{HomogeneousPlanarImaging, Transmission};
use crate::surfaces::{ConfocalLensletArrays, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct ShiftyCloak {
    pub polyhedron: Polyhedron,
    pub centre: DVec3,
    pub u_direction: DVec3,
    pub v_direction: DVec3,
    pub side_length_outside: f64,
    pub side_length_inside: f64,
    /// δ: the inner polyhedron's apparent shift.
    pub delta: DVec3,
    pub show_interfaces: bool,
    pub interface_transmission_coefficient: f64,
}

/// The cloak worked out: its shell and the ratio k of the inner to the outer side length.
struct Layout<'a> {
    cloak: &'a ShiftyCloak,
    shell: Shell,
    k: f64,
}

/// The shifty cloaks' part names: `+u-v+w`.
const NAMES: AxisNames = AxisNames {
    directions: [["+u", "-u"], ["+v", "-v"], ["+w", "-w"]],
    separator: "",
};

impl ShiftyCloak {
    fn layout(&self) -> Result<Layout<'_>, String> {
        let (outside, inside) = (self.side_length_outside, self.side_length_inside);
        if inside >= outside {
            return Err(format!(
                "side_length_inside ({inside}) must be less than side_length_outside ({outside})"
            ));
        }
        // Dr TIM's `calculateUVWHats`.
        let u = self.u_direction.normalize();
        let v = self.v_direction.reject_from_normalized(u);
        if v.length() <= 1e-12 {
            return Err("v_direction must not be along u_direction".into());
        }
        let v = v.normalize();
        let shell = Shell::new(
            self.polyhedron,
            self.centre,
            [u, v, u.cross(v)],
            outside,
            inside,
            &NAMES,
        );
        let k = inside / outside;
        for face in &shell.faces {
            // h − n̂·δ, relative to h: the frustum's map is singular at 0.
            let h = (1.0 - k) * face.distance;
            if ((h - face.normal.dot(self.delta)) / h).abs() <= 1e-9 {
                let label = &face.label;
                return Err(format!(
                    "delta's component along the {label} face's normal equals the distance \
                     between the outer and inner {label} faces, {h}: the inner face would \
                     appear in the outer face's plane"
                ));
            }
        }
        Ok(Layout {
            cloak: self,
            shell,
            k,
        })
    }
}

impl Layout<'_> {
    /// Where a point x of `region` is seen from outside, V(x).
    fn seen(&self, region: Region, x: DVec3) -> DVec3 {
        let delta = self.cloak.delta;
        match region {
            Region::Outside => x,
            Region::Inside => x + delta,
            Region::Frustum(f) => {
                let face = &self.shell.faces[f];
                let d = face.distance - face.normal.dot(x - self.cloak.centre);
                x + d / ((1.0 - self.k) * face.distance) * delta
            }
        }
    }

    /// The point of `region` seen at y, V⁻¹(y): in a frustum d(x)(1 − n̂·δ/h) = d(y).
    fn at(&self, region: Region, y: DVec3) -> DVec3 {
        let delta = self.cloak.delta;
        match region {
            Region::Outside => y,
            Region::Inside => y - delta,
            Region::Frustum(f) => {
                let face = &self.shell.faces[f];
                let h = (1.0 - self.k) * face.distance;
                let d_y = face.distance - face.normal.dot(y - self.cloak.centre);
                y - d_y / (h - face.normal.dot(delta)) * delta
            }
        }
    }

    /// A face of the shell as gCLAs imaging the region behind it into the one in front.
    fn interface(&self, face: Interface) -> Result<Part, String> {
        let Interface {
            name,
            vertices,
            normal,
            front,
            behind,
        } = face;
        let point_on_plane = vertices[0];
        let inside_position = point_on_plane - self.cloak.side_length_outside * normal;
        let imaging = HomogeneousPlanarImaging {
            point_on_plane,
            a: normal,
            inside_position,
            outside_position: self.at(front, self.seen(behind, inside_position)),
        };
        let transmission = Transmission::Constant(self.cloak.interface_transmission_coefficient);
        let arrays = ConfocalLensletArrays::imaging(imaging, transmission)
            .map_err(|e| format!("{name}: {e}"))?;
        Ok(Part {
            shape: Shape::ConvexPolygon(
                ConvexPolygon::new(vertices).map_err(|e| format!("{name}: {e}"))?,
            ),
            name,
            surface: Surface::ConfocalLensletArrays(arrays),
            edge: false,
        })
    }
}

impl LensDevice for ShiftyCloak {
    /// With `show_interfaces`, the faces `outer face in +u direction`, `inner face in +u
    /// direction`, `diagonal face between the +u and +v faces`, ... (the tetrahedron's
    /// `outer face in -u-v-w direction`, ...); with `edges` the frames `outer vertex +u+v+w`,
    /// `inner vertex ...`, `outer edge +u+v-w to +u+v+w`, `inner edge ...`, `diagonal edge at
    /// +u+v+w`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let layout = self.layout()?;
        let mut parts = if self.show_interfaces {
            (layout.shell.interfaces().into_iter())
                .map(|face| layout.interface(face))
                .collect::<Result<_, _>>()?
        } else {
            Vec::new()
        };
        if let Some(e) = edges {
            parts.extend(layout.shell.frames(e)?);
        }
        Ok(parts)
    }

    /// Dr TIM's frames: shown, radius 0.01, `SurfaceColour.GREY50_SHINY`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults::SHOWN_GREY
    }
}

/// The keys of both shifty cloaks, with the defaults of Dr TIM's constructors
/// `EditableCubicShiftyCloak(parent, studio)` and `EditableSimpleTetrahedralShiftyCloak(parent,
/// studio)` (the same): a cloak of side 1 about (0, 0, 10), its inner cube or tetrahedron of
/// side 0.5 seen shifted by (1, 0, 0).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShiftyCloakKeys {
    centre: Option<Vector>,
    u_direction: Option<Direction>,
    v_direction: Option<Direction>,
    side_length_outside: Option<Positive>,
    side_length_inside: Option<Positive>,
    delta: Option<Vector>,
    show_interfaces: Option<bool>,
    interface_transmission_coefficient: Option<Coefficient>,
}

impl ShiftyCloakKeys {
    fn cloak(self, polyhedron: Polyhedron) -> Result<Box<dyn LensDevice>, String> {
        let cloak = ShiftyCloak {
            polyhedron,
            centre: self.centre.map_or(DVec3::new(0.0, 0.0, 10.0), |c| c.0),
            u_direction: self.u_direction.map_or(DVec3::X, |d| d.0),
            v_direction: self.v_direction.map_or(DVec3::Y, |d| d.0),
            side_length_outside: self.side_length_outside.map_or(1.0, |s| s.0),
            side_length_inside: self.side_length_inside.map_or(0.5, |s| s.0),
            delta: self.delta.map_or(DVec3::X, |d| d.0),
            show_interfaces: self.show_interfaces.unwrap_or(true),
            interface_transmission_coefficient: throughput(self.interface_transmission_coefficient),
        };
        // Refuse bad parameters when the scene is read.
        cloak.layout()?;
        Ok(Box::new(cloak))
    }
}

/// `lenses = { type = "cubic-shifty-cloak" }`: Dr TIM's `EditableCubicShiftyCloak`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct CubicShiftyCloakKeys(ShiftyCloakKeys);

impl CubicShiftyCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        self.0.cloak(Polyhedron::Cube)
    }
}

/// `lenses = { type = "simple-tetrahedral-shifty-cloak" }`: Dr TIM's
/// `EditableSimpleTetrahedralShiftyCloak`.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
pub struct SimpleTetrahedralShiftyCloakKeys(ShiftyCloakKeys);

impl SimpleTetrahedralShiftyCloakKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        self.0.cloak(Polyhedron::Tetrahedron)
    }
}
