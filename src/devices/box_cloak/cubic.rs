//! The cubic box cloak (Dr TIM's `EditableBoxCloak` with `BoxCloakType.CUBIC`, its
//! `CubicBoxCloakMaker`): a cube of glenses of side L about c round an inner cube of side
//! p L (p = `inner_volume_size_factor_p`), which, and anything in it, is seen from outside as a
//! cube of side e L (e = `inner_volume_size_factor_em`), while the space outside the cloak is
//! seen as it is: a non-affine cloak.
//!
//! Its faces are those of a [`Shell`]: the outer and inner cube's and the diagonal faces that
//! cut the shell between them into six frusta. Each region is seen from outside through a
//! projective map V ("electromagnetic space"): the identity outside, the scaling x ↦ c + (e/p)
//! (x − c) inside, and in the frustum on the face of outward normal n̂ (a distance r = L/2 from
//! c) the homology with centre c and the outer face as its axis that sends the inner face onto
//! its image, which sends the point c + t u (n̂·u = r) to
//!
//!   c + t u / (1 − (μ − 1)(t − 1)),   μ − 1 = (e − p)/(e (p − 1)).
//!
//! Neighbouring maps agree on the faces between them, so each face is the glens
//! ([`Glens::imaging`]) that images a point x behind it into V_front⁻¹(V_behind(x)) in front,
//! the glens Dr TIM's conjugate pairs give it.

use glam::{DMat4, DVec3, DVec4};

use super::BoxCloakParameters;
use crate::devices::polyhedral_shell::{AxisNames, Interface, Polyhedron, Region, Shell};
use crate::devices::{EdgeDefaults, Edges, LensDevice, Part};
use crate::surfaces::{Glens, Surface};

/// The cubic box cloak.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxCloak(pub BoxCloakParameters);

/// The box cloak's part names: `top right front`.
const NAMES: AxisNames = AxisNames {
    directions: [["top", "bottom"], ["right", "left"], ["front", "back"]],
    separator: " ",
};

impl BoxCloak {
    fn shell(&self) -> Result<Shell, String> {
        let BoxCloak(b) = self;
        b.check_precision()?;
        let (e, p) = (b.inner_volume_size_factor_em, b.inner_volume_size_factor_p);
        if e.abs() < 1e-4 || (e - 1.0).abs() < 1e-4 {
            return Err(format!(
                "inner_volume_size_factor_em = {e} is within 1e-4 of 0 or 1, which would show the \
                 inner cube as a point (0) or in the outer cube's faces (1): choose another"
            ));
        }
        Ok(Shell::new(
            Polyhedron::Cube,
            b.centre,
            [b.top, b.right, b.front],
            b.side_length,
            p * b.side_length,
            &NAMES,
        ))
    }

    /// The map V through which `region` is seen from outside, in homogeneous coordinates of
    /// the cloak's own: the centre at the origin, the half side 1.
    fn seen(&self, shell: &Shell, region: Region) -> DMat4 {
        let BoxCloak(b) = self;
        let (e, p) = (b.inner_volume_size_factor_em, b.inner_volume_size_factor_p);
        match region {
            Region::Outside => DMat4::IDENTITY,
            Region::Inside => DMat4::from_scale(DVec3::splat(e / p)),
            Region::Frustum(f) => {
                let n = shell.faces[f].normal;
                let mu_1 = (e - p) / (e * (p - 1.0));
                // (u, 1) ↦ (u, 1 − (μ − 1)(n̂·u − 1)).
                DMat4::from_cols(
                    DVec4::new(1.0, 0.0, 0.0, -mu_1 * n.x),
                    DVec4::new(0.0, 1.0, 0.0, -mu_1 * n.y),
                    DVec4::new(0.0, 0.0, 1.0, -mu_1 * n.z),
                    DVec4::new(0.0, 0.0, 0.0, 1.0 + mu_1),
                )
            }
        }
    }

    /// A face of the shell as the glens imaging the region behind it into the one in front,
    /// worked out in the cloak's own coordinates and placed.
    fn interface(&self, shell: &Shell, face: Interface) -> Result<Part, String> {
        let BoxCloak(b) = self;
        let h = 0.5 * b.side_length;
        let imaging = self.seen(shell, face.front).inverse() * self.seen(shell, face.behind);
        let placed = b.place();
        let glens = Glens::imaging(
            (face.vertices[0] - b.centre) / h,
            face.normal,
            imaging,
            b.interface_transmission_coefficient,
        )
        .and_then(|g| g.transformed(&placed))
        .map_err(|e| format!("{}: {e}", face.name))?;
        b.face(face.name, face.vertices, Surface::Glens(glens))
    }
}

impl LensDevice for BoxCloak {
    /// The glenses `outer face in front direction`, `inner face in front direction` (and
    /// `back`, `top`, `bottom`, `right`, `left`) and `diagonal face between the top and front
    /// faces`, ...; with `edges` Dr TIM's frames, `outer vertex top right front`, `inner vertex
    /// ...`, `outer edge ... to ...`, `inner edge ...` and `diagonal edge at top right front`.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        let shell = self.shell()?;
        let mut parts = shell
            .interfaces()
            .into_iter()
            .map(|face| self.interface(&shell, face))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(e) = edges {
            parts.extend(shell.frames(e)?);
        }
        Ok(parts)
    }

    fn edge_defaults(&self) -> EdgeDefaults {
        self.0.edge_defaults()
    }
}
