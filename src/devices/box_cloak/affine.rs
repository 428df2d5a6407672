//! What the affine box cloaks (the octahedral and the prismatic, Dr TIM's
//! `OctahedralBoxCloakMaker` and `PrismaticBoxCloakMaker`, and its `EditableGCLAsCloak`) share:
//! regions seen from outside through affine maps, the gCLA interfaces between them, and the
//! cube's frames. All work in the cloak's own coordinates (centre at the origin, half the side
//! the unit of length; see [`BoxCloakParameters::place`]).

use glam::DVec3;

use super::{Axis, BoxCloakParameters};
use crate::devices::affine_regions::{Region, affine, imaging_between};
use crate::devices::{Edges, Part};
use crate::surfaces::metatoys::Transmission;
use crate::surfaces::{ConfocalLensletArrays, Surface};

/// Which of a cloak's faces and frames (by name and their vertices in the cloak's own
/// coordinates) a device keeps.
pub(super) type Keep<'a> = &'a dyn Fn(&str, &[DVec3]) -> bool;

impl BoxCloakParameters {
    /// The inner volume's vertex on the axis `n`, in physical (`em` false) or electromagnetic
    /// space.
    pub(super) fn apex(&self, n: DVec3, em: bool) -> DVec3 {
        let size = if em {
            self.inner_volume_size_factor_em
        } else {
            self.inner_volume_size_factor_p
        };
        size * n
    }

    /// The region whose map keeps the points `fixed` where they are and moves the inner
    /// volume's vertices on the axes `apexes` from physical to electromagnetic space (four
    /// points in all).
    pub(super) fn region(
        &self,
        fixed: &[DVec3],
        apexes: &[DVec3],
        name: &str,
    ) -> Result<Region, String> {
        let mut from: Vec<DVec3> = fixed.to_vec();
        let mut to = from.clone();
        from.extend(apexes.iter().map(|&n| self.apex(n, false)));
        to.extend(apexes.iter().map(|&n| self.apex(n, true)));
        let seen = affine(
            [from[0], from[1], from[2], from[3]],
            [to[0], to[1], to[2], to[3]],
        )
        .filter(|m| m.determinant().abs() > 1e-12)
        .ok_or_else(|| {
            format!(
                "inner_volume_size_factor_em = {} flattens the {name}: choose another",
                self.inner_volume_size_factor_em
            )
        })?;
        Ok(Region {
            seen,
            inside: from.iter().sum::<DVec3>() / from.len() as f64,
        })
    }

    /// Refuses an electromagnetic-space size within 10⁻⁴ of one of `flat`, the values that
    /// flatten a region of the cloak (its maps lose their accuracy near them).
    pub(super) fn check_em(&self, flat: &[f64]) -> Result<(), String> {
        let e = self.inner_volume_size_factor_em;
        match flat.iter().find(|&&k| (e - k).abs() < 1e-4) {
            Some(k) => Err(format!(
                "inner_volume_size_factor_em = {e} is within 1e-4 of {k}, which flattens the \
                 cloak's regions ({} all do): choose another",
                flat.iter()
                    .map(f64::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            None => Ok(()),
        }
    }

    /// The interface with these vertices (in order round it) between regions `r1` and `r2`,
    /// as gCLAs imaging the one behind it into the one in front.
    pub(super) fn gclas_interface(
        &self,
        name: String,
        vertices: Vec<DVec3>,
        r1: &Region,
        r2: &Region,
    ) -> Result<Part, String> {
        let place = self.place();
        let imaging = imaging_between(&vertices, r1, r2).transformed(&place);
        let vertices = vertices.iter().map(|&v| place.point(v)).collect();
        let transmission = Transmission::Constant(self.interface_transmission_coefficient);
        let arrays = ConfocalLensletArrays::imaging(imaging, transmission)
            .map_err(|e| format!("{name}: {e}"))?;
        self.face(name, vertices, Surface::ConfocalLensletArrays(arrays))
    }

    /// The cube's eight corners, each as its three axes: front or back, right or left, top or
    /// bottom.
    pub(super) fn corners(&self) -> [[Axis; 3]; 8] {
        let axes = self.axes();
        std::array::from_fn(|signs| {
            std::array::from_fn(|k| {
                if (signs >> k) & 1 == 0 {
                    axes[k]
                } else {
                    -axes[k]
                }
            })
        })
    }

    /// The cube's frames that `keep` keeps (by name and ends): `cube vertex top right front`,
    /// ... and `cube edge top right front to top right back`, ... (each edge from its end on
    /// the front, right or top side).
    pub(super) fn cube_frames(&self, e: &Edges, keep: Keep) -> Result<Vec<Part>, String> {
        let place = self.place();
        let mut parts = Vec::new();
        for corner in self.corners() {
            let (name, at) = (
                format!("cube vertex {}", corner_label(corner)),
                corner_position(corner),
            );
            if keep(&name, &[at]) {
                parts.push(e.vertex(name, place.point(at))?);
            }
            for k in 0..3 {
                if ["front", "right", "top"].contains(&corner[k].name) {
                    let mut there = corner;
                    there[k] = -corner[k];
                    let name = format!(
                        "cube edge {} to {}",
                        corner_label(corner),
                        corner_label(there)
                    );
                    let ends = [at, corner_position(there)];
                    if keep(&name, &ends) {
                        parts.push(e.part(name, place.point(ends[0]), place.point(ends[1]))?);
                    }
                }
            }
        }
        Ok(parts)
    }
}

/// A corner's position: the sum of its axes.
pub(super) fn corner_position(corner: [Axis; 3]) -> DVec3 {
    corner.iter().map(|a| a.v).sum()
}

/// A corner's name, `top right front`.
pub(super) fn corner_label(corner: [Axis; 3]) -> String {
    format!("{} {} {}", corner[2].name, corner[1].name, corner[0].name)
}
