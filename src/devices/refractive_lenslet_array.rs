//! Dr TIM's `RefractiveLensletArray` (surfaces/RefractiveLensletArray.java): a rectangular
//! array of refractive lenslets of one focal length, each a `RefractiveBoxLens` whose clear
//! aperture and principal point follow lattices of their own (`SurfaceOfGeneralRefractiveCLAs`;
//! with equal lattices Dr TIM's `SurfaceOfRefractiveCLAs`). Dr TIM traces it voxel by voxel
//! inside a bounding box; timbre traces the glass as one exact solid,
//! [`crate::geometry::LensletArray`], whose doc gives the construction. Two of them, confocal,
//! are refractive CLAs.

use serde::Deserialize;

use super::{Edges, LensDevice, Part};
use crate::geometry::{LensletArray, LensletArraySpec, RefractiveIndex, Shape};
use crate::keys::{Coefficient, NonNegative, NonZero, Positive, Vector};
use crate::surfaces::{Refractive, Surface};

#[derive(Debug, Clone, PartialEq)]
pub struct RefractiveLensletArray {
    pub spec: LensletArraySpec,
    pub transmission_coefficient: f64,
}

impl LensDevice for RefractiveLensletArray {
    /// `lenslets`, glass of index n; no edges.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String> {
        if edges.is_some() {
            return Err("a refractive lenslet array has no edges to show (show_edges)".into());
        }
        let shape = LensletArray::new(&self.spec).map_err(|e| e.to_string())?;
        Ok(vec![Part {
            name: "lenslets".into(),
            shape: Shape::LensletArray(shape),
            surface: Surface::Refractive(Refractive {
                index_ratio: self.spec.refractive_index,
                transmission_coefficient: self.transmission_coefficient,
            }),
            edge: false,
        }])
    }
}

/// `lenses = { type = "refractive-lenslet-array" }`: Dr TIM's `RefractiveLensletArray` (it has
/// no editable form, so its lattice, focal length and index are required).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefractiveLensletArrayKeys {
    centre: Vector,
    width: Positive,
    height: Positive,
    u_period_clear_aperture: Vector,
    v_period_clear_aperture: Vector,
    u_period_principal_point: Option<Vector>,
    v_period_principal_point: Option<Vector>,
    clear_aperture_centre: Option<Vector>,
    principal_point_centre: Option<Vector>,
    focal_length: NonZero,
    refractive_index: RefractiveIndex,
    thickness_at_thinnest_point: Option<NonNegative>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl RefractiveLensletArrayKeys {
    pub fn build(self) -> Result<Box<dyn LensDevice>, String> {
        let (u, v) = (
            self.u_period_clear_aperture.0,
            self.v_period_clear_aperture.0,
        );
        let clear_aperture_centre = self.clear_aperture_centre.map_or(self.centre.0, |c| c.0);
        let spec = LensletArraySpec {
            centre: self.centre.0,
            width: self.width.0,
            height: self.height.0,
            u_period_clear_aperture: u,
            v_period_clear_aperture: v,
            u_period_principal_point: self.u_period_principal_point.map_or(u, |p| p.0),
            v_period_principal_point: self.v_period_principal_point.map_or(v, |p| p.0),
            clear_aperture_centre,
            principal_point_centre: self
                .principal_point_centre
                .map_or(clear_aperture_centre, |p| p.0),
            focal_length: self.focal_length.0,
            refractive_index: self.refractive_index.0,
            thickness_at_thinnest_point: self.thickness_at_thinnest_point.map_or(0.0, |d| d.0),
        };
        // Refuse a lattice the glass cannot follow here, where the key's line is known.
        LensletArray::new(&spec).map_err(|e| e.to_string())?;
        Ok(Box::new(RefractiveLensletArray {
            spec,
            // Dr TIM's lenslets are `Refractive(n, 1, …)`.
            transmission_coefficient: self.transmission_coefficient.map_or(1.0, |c| c.0),
        }))
    }
}
