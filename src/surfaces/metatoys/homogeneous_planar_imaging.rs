//! Homogeneous planar imaging surfaces (Dr TIM's `HomogeneousPlanarImagingSurface`; Oxburgh and
//! Courtial, "Perfect imaging with planar interfaces", JOSA A 30, 2334 (2013)): a plane with
//! outward unit normal â that images every point P of inside space to
//!
//!   P′ = P − a_P (δ_u û + δ_v v̂ + (1 − η) â),
//!
//! a_P being P's distance from the plane along â. This is an affine map that fixes the plane
//! point by point, so one pair of conjugate points off the plane fixes η, δ_u and δ_v. gCLAs with
//! axis â, η_u = η_v = η and these δ (Eq 39) realise it for every ray: a ray from P through a
//! point Q of the plane has slopes s = (Q − P)_uv / (−a_P), the ray through Q from (or towards)
//! P′ has slopes (s − δ)/η, which Eq 39 gives whatever P is.
//!
//! Since any invertible affine map T turns a map that fixes a plane into one that fixes the
//! image plane, the surface placed by T is again such a surface, imaging T P into T P′: its
//! points move with T and its normal as normals do. That is how the imaging surfaces of a device
//! move with it (`ConfocalLensletArrays::transformed`).

use glam::{DVec2, DVec3};

/// A plane imaging inside space to outside space, given by a pair of conjugate points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HomogeneousPlanarImaging {
    pub point_on_plane: DVec3,
    /// The outward normal (any length): outside space is the side it points to.
    pub a: DVec3,
    /// A point of inside space (off the plane) ...
    pub inside_position: DVec3,
    /// ... and its image in outside space.
    pub outside_position: DVec3,
}

/// The gCLAs parameters of an imaging surface: unit â and û (any unit vector in the plane), η
/// and (δ_u, δ_v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Telescopes {
    pub a_hat: DVec3,
    pub u_hat: DVec3,
    pub eta: f64,
    pub delta: DVec2,
}

impl HomogeneousPlanarImaging {
    /// η, δ_u and δ_v from the conjugate positions (Dr TIM's
    /// `setParametersFromConjugatePositions`); an error where the inside position lies in the
    /// plane (it fixes nothing) or the outside one does (η = 0: inside space would be imaged
    /// onto the plane).
    pub fn telescopes(&self) -> Result<Telescopes, String> {
        let a_hat = self
            .a
            .try_normalize()
            .ok_or("an imaging surface needs a non-zero normal")?;
        let u_hat = a_hat.any_orthonormal_vector();
        let v_hat = a_hat.cross(u_hat);
        let from_plane = self.inside_position - self.point_on_plane;
        let a_p = from_plane.dot(a_hat);
        if a_p.abs() <= 1e-12 * from_plane.length() || !a_p.is_finite() {
            return Err(format!(
                "the inside position {} lies in the imaging plane",
                self.inside_position
            ));
        }
        let image_to_object = self.inside_position - self.outside_position;
        let eta = 1.0 - image_to_object.dot(a_hat) / a_p;
        if eta.abs() <= 1e-12 || !eta.is_finite() {
            return Err(format!(
                "the outside position {} lies in the imaging plane (η = 0: the plane would \
                 image inside space onto itself)",
                self.outside_position
            ));
        }
        Ok(Telescopes {
            a_hat,
            u_hat,
            eta,
            delta: DVec2::new(image_to_object.dot(u_hat), image_to_object.dot(v_hat)) / a_p,
        })
    }

    /// The image of `p`, the affine map that fixes the plane and takes the inside position to
    /// the outside one (Dr TIM's `getImagePosition(p, OUTWARDS)`).
    pub fn image(&self, p: DVec3) -> DVec3 {
        let a_hat = self.a.normalize();
        let distance = |x: DVec3| (x - self.point_on_plane).dot(a_hat);
        p + distance(p) / distance(self.inside_position)
            * (self.outside_position - self.inside_position)
    }

    /// The surface placed by `t` (module notes): any invertible affine map.
    pub fn transformed(&self, t: &crate::geometry::Transform) -> HomogeneousPlanarImaging {
        HomogeneousPlanarImaging {
            point_on_plane: t.point(self.point_on_plane),
            a: t.normal(self.a),
            inside_position: t.point(self.inside_position),
            outside_position: t.point(self.outside_position),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surfaces::metatoys::Telescopelets;

    /// The gCLAs made from a conjugate pair send every ray from another inside point P through
    /// the plane on a line through P's image, worked out as the affine map that fixes the
    /// plane and takes the given inside position to the outside one.
    #[test]
    fn the_arrays_image_every_inside_point() {
        let imaging = HomogeneousPlanarImaging {
            point_on_plane: DVec3::new(0.1, 0.2, 1.0),
            a: DVec3::new(0.2, -0.1, 2.0),
            inside_position: DVec3::new(0.3, -0.4, 0.2),
            outside_position: DVec3::new(0.9, 0.1, -0.6),
        };
        let t = imaging.telescopes().unwrap();
        let arrays = Telescopelets::new(t.a_hat, t.u_hat, DVec2::splat(t.eta), t.delta).unwrap();
        let a_hat = imaging.a.normalize();
        let distance = |x: DVec3| (x - imaging.point_on_plane).dot(a_hat);
        // x ↦ x + (distance(x) / distance(inside)) (outside − inside).
        let shift = (imaging.outside_position - imaging.inside_position)
            / distance(imaging.inside_position);
        for p in [DVec3::new(-0.5, 0.7, 0.0), DVec3::new(0.2, 0.1, -1.5)] {
            let image = p + distance(p) * shift;
            for q in [DVec3::new(0.4, -0.3, 0.0), DVec3::new(-1.0, 0.5, 0.0)] {
                // A point of the plane.
                let q = q + imaging.point_on_plane;
                let q = q - distance(q) * a_hat;
                let out = arrays.refract((q - p).normalize(), a_hat).unwrap();
                let off_line = (image - q).reject_from(out).length();
                assert!(off_line < 1e-12, "p = {p}, q = {q}: {off_line}");
            }
        }
    }

    #[test]
    fn conjugates_in_the_plane_are_refused() {
        let on_plane = HomogeneousPlanarImaging {
            point_on_plane: DVec3::ZERO,
            a: DVec3::Z,
            inside_position: DVec3::new(1.0, 0.0, 0.0),
            outside_position: DVec3::new(1.0, 0.0, 1.0),
        };
        assert!(
            on_plane
                .telescopes()
                .unwrap_err()
                .contains("inside position")
        );
        let flattened = HomogeneousPlanarImaging {
            inside_position: DVec3::new(0.0, 0.0, -1.0),
            outside_position: DVec3::new(2.0, 0.0, 0.0),
            ..on_plane
        };
        assert!(flattened.telescopes().unwrap_err().contains("η = 0"));
    }
}
