//! Convex polyhedra: the intersection of half-spaces, one behind each face's plane.
//!
//! A line is clipped by every face's plane in turn (Cyrus–Beck, Kay–Kajiya): it is inside from
//! the last plane it crosses inwards to the first it crosses outwards, and the part crossed
//! there is that face's index. The solid shapes with flat faces (cuboid, parallelepiped,
//! triangular prism, wedge, Platonic solid) list their faces here and get [`AnalyticShape`]
//! and [`ConvexSolid`] from [`Polyhedral`].

use glam::{DVec2, DVec3};

use super::plane::plane_distance;
use super::{AnalyticShape, ConvexSolid, Span};
use crate::math::Frame;

/// One face: the plane through `corner` with outward normal `frame.w`. Its surface coordinates
/// are Cartesian, from the corner along u and v.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Face {
    corner: DVec3,
    frame: Frame,
}

impl Face {
    /// The face with the edges `first` and `second` leaving its vertex `vertex`, facing away
    /// from `inside` (a point inside the solid). u runs along `first`, v across the face
    /// towards `second`, from `vertex` or from the other end of `first`, whichever makes
    /// u, v, w right-handed.
    pub(super) fn new(vertex: DVec3, first: DVec3, second: DVec3, inside: DVec3) -> Face {
        // Scaled to a largest component of 1 first, so that tiny edges' product cannot
        // underflow.
        let scaled = |v: DVec3| v / v.abs().max_element();
        let n = scaled(first).cross(scaled(second));
        let (corner, n, u) = if n.dot(vertex - inside) >= 0.0 {
            (vertex, n, scaled(first))
        } else {
            (vertex + first, -n, -scaled(first))
        };
        Face {
            corner,
            frame: Frame::from_normal_and_u(n, u),
        }
    }
}

/// Whether the edges `a`, `b`, `c` leaving a vertex span no volume: one is zero or they are
/// coplanar (to 1e-12 of the box of their lengths).
pub(super) fn spans_no_volume(a: DVec3, b: DVec3, c: DVec3) -> bool {
    let volume = a.cross(b).dot(c).abs();
    volume.is_nan() || volume <= 1e-12 * a.length() * b.length() * c.length()
}

#[derive(Debug, Clone, PartialEq)]
pub struct Polyhedron {
    /// The faces, in the order of their parts.
    faces: Vec<Face>,
    bounds: (DVec3, DVec3),
}

impl Polyhedron {
    /// The convex solid behind `faces`, whose corners are `vertices`.
    pub(super) fn new(faces: Vec<Face>, vertices: &[DVec3]) -> Polyhedron {
        Polyhedron {
            faces,
            bounds: super::point_bounds(vertices),
        }
    }

    /// The number of faces (the parts are 0 to this − 1).
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }
}

impl AnalyticShape for Polyhedron {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        self.chord(origin, direction)?.nearest(t_min, t_max)
    }

    /// The face's frame: w its outward normal, u and v in its plane.
    fn frame(&self, _p: DVec3, part: u32) -> Frame {
        self.faces[part as usize].frame
    }

    /// Cartesian coordinates in the face's plane, from its corner along its u and v.
    fn coordinates(&self, p: DVec3, part: u32) -> DVec2 {
        let face = &self.faces[part as usize];
        let d = p - face.corner;
        DVec2::new(d.dot(face.frame.u), d.dot(face.frame.v))
    }

    /// The surface coordinates, which are Cartesian.
    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        Some(self.coordinates(p, part))
    }

    /// Every face has plane coordinates.
    fn is_charted(&self) -> bool {
        true
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        Some(self.bounds)
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        Some(self)
    }
}

impl ConvexSolid for Polyhedron {
    fn chord(&self, origin: DVec3, direction: DVec3) -> Option<Span> {
        let mut enter = (f64::NEG_INFINITY, Span::NO_PART);
        let mut exit = (f64::INFINITY, Span::NO_PART);
        for (i, face) in self.faces.iter().enumerate() {
            let n = face.frame.w;
            let Some(t) = plane_distance(face.corner, n, origin, direction) else {
                // Parallel to the face: inside its half-space throughout, or never.
                if (origin - face.corner).dot(n) > 0.0 {
                    return None;
                }
                continue;
            };
            if direction.dot(n) < 0.0 {
                if t > enter.0 {
                    enter = (t, i as u32);
                }
            } else if t < exit.0 {
                exit = (t, i as u32);
            }
        }
        (enter.0 < exit.0).then_some(Span { enter, exit })
    }

    fn contains(&self, p: DVec3) -> bool {
        self.faces
            .iter()
            .all(|f| (p - f.corner).dot(f.frame.w) <= 0.0)
    }
}

/// A shape that is a convex polyhedron: it is intersected, framed and bounded as its
/// [`Polyhedron`].
pub trait Polyhedral {
    fn polyhedron(&self) -> &Polyhedron;
}

impl<T: Polyhedral> AnalyticShape for T {
    fn intersect(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        self.polyhedron().intersect(origin, direction, t_min, t_max)
    }

    fn frame(&self, p: DVec3, part: u32) -> Frame {
        self.polyhedron().frame(p, part)
    }

    fn coordinates(&self, p: DVec3, part: u32) -> DVec2 {
        self.polyhedron().coordinates(p, part)
    }

    fn plane_coordinates(&self, p: DVec3, part: u32) -> Option<DVec2> {
        self.polyhedron().plane_coordinates(p, part)
    }

    fn is_charted(&self) -> bool {
        self.polyhedron().is_charted()
    }

    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.polyhedron().bounds()
    }

    fn solid(&self) -> Option<&dyn ConvexSolid> {
        Some(self.polyhedron())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube [0, 1]³ from its three faces at the origin and three at (1, 1, 1).
    fn unit_cube() -> Polyhedron {
        let inside = DVec3::splat(0.5);
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        let faces = vec![
            Face::new(DVec3::ZERO, y, z, inside),
            Face::new(DVec3::ONE, -y, -z, inside),
            Face::new(DVec3::ZERO, z, x, inside),
            Face::new(DVec3::ONE, -z, -x, inside),
            Face::new(DVec3::ZERO, x, y, inside),
            Face::new(DVec3::ONE, -x, -y, inside),
        ];
        Polyhedron::new(faces, &[DVec3::ZERO, DVec3::ONE])
    }

    #[test]
    fn a_line_enters_at_the_last_entering_face_and_leaves_at_the_first_leaving_one() {
        let cube = unit_cube();
        let d = DVec3::new(1.0, 0.5, 0.25);
        let s = cube.chord(DVec3::new(-1.0, 0.0, 0.2), d).unwrap();
        // x = 0 at t = 1 (y = 0.5, z = 0.45), x = 1 at t = 2 (y = 1, z = 0.7).
        assert_eq!(s.enter, (1.0, 0));
        assert_eq!(s.exit.0, 2.0);
        assert!(s.exit.1 == 1 || s.exit.1 == 3);
        // Parallel to the x faces and outside them: a miss; inside them: a chord along y.
        assert_eq!(cube.chord(DVec3::new(2.0, 0.5, 0.5), DVec3::Y), None);
        let s = cube.chord(DVec3::new(0.5, -1.0, 0.5), DVec3::Y).unwrap();
        assert_eq!((s.enter, s.exit), ((1.0, 2), (2.0, 3)));
    }

    #[test]
    fn faces_face_outwards_with_right_handed_frames_from_a_corner() {
        let cube = unit_cube();
        for part in 0..6 {
            let f = cube.frame(DVec3::ZERO, part);
            assert!((f.u.cross(f.v) - f.w).length() < 1e-15);
            // The centre is behind every face.
            let corner = cube.faces[part as usize].corner;
            assert!((DVec3::splat(0.5) - corner).dot(f.w) < 0.0);
        }
        // The face x = 0 (part 0) faces −x; u runs along −y from (0, 1, 0), v along +z.
        let f = cube.frame(DVec3::ZERO, 0);
        assert_eq!((f.u, f.v, f.w), (DVec3::NEG_Y, DVec3::Z, DVec3::NEG_X));
        let c = cube.coordinates(DVec3::new(0.0, 0.25, 0.5), 0);
        assert!((c - DVec2::new(0.75, 0.5)).length() < 1e-15);
    }

    #[test]
    fn spans_no_volume_finds_zero_and_coplanar_edges() {
        let (x, y) = (DVec3::X, DVec3::Y);
        assert!(!spans_no_volume(x, y, DVec3::Z));
        assert!(spans_no_volume(x, y, x + y));
        assert!(spans_no_volume(x, DVec3::ZERO, DVec3::Z));
        assert!(spans_no_volume(x, y, DVec3::new(0.0, 0.0, f64::NAN)));
    }
}
