//! Devices whose regions are seen from outside through affine maps, and whose faces are the
//! homogeneous planar imaging surfaces (gCLAs) that image the region behind each into the one
//! in front: the box cloaks of gCLAs and the pinch-transformation window.

use glam::{DMat4, DVec3};

use crate::surfaces::metatoys::HomogeneousPlanarImaging;

/// A region: its map V (seen from outside) and a point inside it.
pub struct Region {
    pub seen: DMat4,
    pub inside: DVec3,
}

impl Region {
    /// Space round a device centred at the origin, beyond its face of outward normal `n`
    /// (of length at most 1), seen as it is.
    pub fn outside(n: DVec3) -> Region {
        Region {
            seen: DMat4::IDENTITY,
            inside: 2.0 * n,
        }
    }
}

/// The affine map (homogeneous coordinates) that sends the points `from` to `to`, if `from`
/// spans space.
pub fn affine(from: [DVec3; 4], to: [DVec3; 4]) -> Option<DMat4> {
    let columns = |p: [DVec3; 4]| {
        DMat4::from_cols(
            p[0].extend(1.0),
            p[1].extend(1.0),
            p[2].extend(1.0),
            p[3].extend(1.0),
        )
    };
    let from = columns(from);
    let volume = from.determinant();
    (volume.abs()
        > 1e-12
            * from
                .abs()
                .to_cols_array()
                .iter()
                .fold(0.0, |m: f64, x| m.max(*x))
                .powi(3))
    .then(|| columns(to) * from.inverse())
}

/// The imaging surface of the face with these vertices (in order round it) between regions
/// `r1` and `r2`, which images the region behind it into the one in front: a point x behind is
/// seen, from in front, at V_front⁻¹(V_behind(x)).
pub fn imaging_between(vertices: &[DVec3], r1: &Region, r2: &Region) -> HomogeneousPlanarImaging {
    let normal = (vertices[1] - vertices[0])
        .cross(vertices[2] - vertices[0])
        .normalize();
    // The normal points to the region in front.
    let (front, behind) = if normal.dot(r1.inside - vertices[0]) > 0.0 {
        (r1, r2)
    } else {
        (r2, r1)
    };
    let inside_position = vertices[0] - normal;
    let image = front.seen.inverse() * behind.seen * inside_position.extend(1.0);
    HomogeneousPlanarImaging {
        point_on_plane: vertices[0],
        a: normal,
        inside_position,
        outside_position: image.truncate() / image.w,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec4;

    #[test]
    fn an_affine_map_from_four_pairs_sends_them() {
        let from = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let to = [
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(2.0, 2.0, 3.0),
            DVec3::new(1.0, 4.0, 3.0),
            DVec3::new(0.0, 0.0, 0.0),
        ];
        let m = affine(from, to).unwrap();
        for (f, t) in from.iter().zip(&to) {
            let image = m * f.extend(1.0);
            assert!((image - DVec4::from((*t, 1.0))).length() < 1e-12);
        }
        assert!(
            affine(
                [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)],
                to
            )
            .is_none()
        );
    }
}
