//! Devices made of ideal thin lenses (issue 20, Part 2): each a pure function from the
//! parameters of Dr TIM's editable object to its parts, every face a lens (an ideal thin lens,
//! or what the device's lens type makes of it, [`LensType`]) with its positions in the device's
//! own coordinates, and the edges (Dr TIM's frames) cylinders. Every parameter Dr TIM's
//! editable object has a default for (its constructor `(SceneObject parent, Studio studio)`)
//! has the same default here, so that a device named by its type alone is Dr TIM's default
//! object.

mod affine_regions;
mod box_cloak;
mod chen_belin_black_hole;
mod clas;
mod coordinate_system;
mod four_pi_lens;
mod framed_gcla_mapping_goggles;
mod fresnel_lens;
mod fresnel_lens_surface;
mod homogeneous_planar_imaging_surface_simplicial_complex;
mod ideal_lens_cloak;
mod lens_simplicial_complex;
mod lens_star;
mod lens_type;
mod mirrored_space_cancelling_wedge;
mod negative_space_wedge_star;
mod net;
mod net_of_hypercube;
mod net_of_symmetric_4_simplex;
mod ninky_nonk_silhouette;
mod pinch_transformation_window;
mod platonic_lens;
mod polygonal_ideal_lens_cloak;
mod polyhedral_shell;
mod ray_rotation_sheet_star;
mod refractive_lens_surfaces;
mod refractive_lenslet_array;
mod refractive_view_rotator;
mod shifty_cloak;
mod space_cancelling_wedge;
mod star;
mod tetrahedral_shifty_cloak;
mod tim_head;
mod to_shifter;
mod triangular_thick_lens;

pub use box_cloak::{
    BoxCloak, BoxCloakKeys, BoxCloakParameters, GclasCloak, GclasCloakKeys, GclasTardisWindow,
    GclasTardisWindowKeys, OctahedralBoxCloak, PrismaticBoxCloak, RochesterCloak,
    RochesterCloakKeys,
};
pub use chen_belin_black_hole::{ChenBelinBlackHole, ChenBelinBlackHoleKeys};
pub use clas::{Clas, ClasKeys};
pub use coordinate_system::{CoordinateSystem, CoordinateSystemKeys};
pub use four_pi_lens::{FourPiLens, FourPiLensKeys};
pub use framed_gcla_mapping_goggles::{FramedGclaMappingGoggles, FramedGclaMappingGogglesKeys};
pub use fresnel_lens::{FresnelLens, FresnelLensKeys};
pub use fresnel_lens_surface::{FresnelLensSurface, FresnelLensSurfaceKeys, Sections};
pub use homogeneous_planar_imaging_surface_simplicial_complex::{
    HomogeneousPlanarImagingSurfaceSimplicialComplex,
    HomogeneousPlanarImagingSurfaceSimplicialComplexKeys,
};
pub use ideal_lens_cloak::{IdealLensCloak, IdealLensCloakKeys};
pub use lens_simplicial_complex::{LensSimplicialComplex, LensSimplicialComplexKeys};
pub use lens_star::{LensStar, LensStarKeys};
pub use lens_type::{Face, LensType, semitransparent_plane};
pub use negative_space_wedge_star::{NegativeSpaceWedgeStar, NegativeSpaceWedgeStarKeys};
pub use net_of_hypercube::{NetOfHypercube, NetOfHypercubeKeys};
pub use net_of_symmetric_4_simplex::{NetOfSymmetric4Simplex, NetOfSymmetric4SimplexKeys};
pub use ninky_nonk_silhouette::{NinkyNonkSilhouette, NinkyNonkSilhouetteKeys};
pub use pinch_transformation_window::{
    GclasPinchTransformationWindowKeys, PinchTransformationWindow, Wall,
};
pub use platonic_lens::{PlatonicLens, PlatonicLensKeys};
pub use polygonal_ideal_lens_cloak::{PolygonalIdealLensCloak, PolygonalIdealLensCloakKeys};
pub use ray_rotation_sheet_star::{RayRotationSheetStar, RayRotationSheetStarKeys};
pub use refractive_lens_surfaces::{RefractiveLensSurfaces, RefractiveLensSurfacesKeys};
pub use refractive_lenslet_array::{RefractiveLensletArray, RefractiveLensletArrayKeys};
pub use refractive_view_rotator::{RefractiveViewRotator, RefractiveViewRotatorKeys};
pub use shifty_cloak::{CubicShiftyCloakKeys, ShiftyCloak, SimpleTetrahedralShiftyCloakKeys};
pub use space_cancelling_wedge::{Gluing, SpaceCancellingWedge, SpaceCancellingWedgeKeys};
pub use tetrahedral_shifty_cloak::{TetrahedralShiftyCloak, TetrahedralShiftyCloakKeys};
pub use tim_head::{TimHead, TimHeadKeys};
pub use to_shifter::{ToShifterDevice, ToShifterKeys};
pub use triangular_thick_lens::{TriangularThickLens, TriangularThickLensKeys};

use crate::geometry::{Cylinder, Shape, Sphere};
use crate::keys::kinds;
use crate::math::Colour;
use crate::surfaces::{Coloured, Surface};

/// A device of ideal thin lenses, as its keys make it.
pub trait LensDevice: std::fmt::Debug {
    /// The device's parts, with its edges (Dr TIM's frames) where `edges` are shown.
    fn parts(&self, edges: Option<&Edges>) -> Result<Vec<Part>, String>;

    /// Dr TIM's defaults for the device's edges: by default those of `EditableLensStar`.
    fn edge_defaults(&self) -> EdgeDefaults {
        EdgeDefaults::HIDDEN_RED
    }

    /// Whether the device's lenses (or sheets) throw shadows where the `[[device]]` entry does
    /// not say: Dr TIM's `shadowThrowing` of them, by default `false`.
    fn shadow_throwing(&self) -> bool {
        false
    }
}

/// Whether a device's edges are shown, and their radius and (shiny) colour, where the
/// `[[device]]` entry does not say: Dr TIM's defaults for the device's frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeDefaults {
    pub shown: bool,
    pub radius: f64,
    /// The diffuse colour of the shiny surface (Dr TIM's `SurfaceColour` with a white specular
    /// colour: `RED_SHINY`, `GREY50_SHINY`, `BLUE_SHINY`).
    pub colour: Colour,
}

impl EdgeDefaults {
    /// Hidden, radius 0.01, `SurfaceColour.RED_SHINY` (Dr TIM's `EditableLensStar`).
    pub const HIDDEN_RED: EdgeDefaults = EdgeDefaults {
        shown: false,
        radius: 0.01,
        colour: Colour::new(1.0, 0.0, 0.0),
    };

    /// Shown, radius 0.01, `SurfaceColour.GREY50_SHINY` (Dr TIM's frames of its gCLA devices:
    /// the shifty cloaks and the mapping goggles).
    pub const SHOWN_GREY: EdgeDefaults = EdgeDefaults {
        shown: true,
        radius: 0.01,
        colour: Colour::new(0.5, 0.5, 0.5),
    };

    /// The shiny surface of the edges.
    pub fn surface(&self) -> Surface {
        Surface::Coloured(Coloured::shiny(self.colour))
    }
}

kinds! {
    /// A device's `lenses` table: its `type` names the device, its other keys are the device's
    /// own (read by the device's `...Keys`, in the device's file).
    pub enum LensesKeys -> Result<Box<dyn LensDevice>, String> {
        LensStar(LensStarKeys),
        RayRotationSheetStar(RayRotationSheetStarKeys),
        NegativeSpaceWedgeStar(NegativeSpaceWedgeStarKeys),
        SpaceCancellingWedge(SpaceCancellingWedgeKeys),
        NetOfHypercube(NetOfHypercubeKeys),
        NetOfSymmetricFourSimplex(NetOfSymmetric4SimplexKeys),
        LensSimplicialComplex(LensSimplicialComplexKeys),
        HomogeneousPlanarImagingSurfaceSimplicialComplex(HomogeneousPlanarImagingSurfaceSimplicialComplexKeys),
        IdealLensCloak(IdealLensCloakKeys),
        PolygonalIdealLensCloak(PolygonalIdealLensCloakKeys),
        BoxCloak(BoxCloakKeys),
        RochesterCloak(RochesterCloakKeys),
        GclasCloak(GclasCloakKeys),
        GclasTardisWindow(GclasTardisWindowKeys),
        GclasPinchTransformationWindow(GclasPinchTransformationWindowKeys),
        CubicShiftyCloak(CubicShiftyCloakKeys),
        SimpleTetrahedralShiftyCloak(SimpleTetrahedralShiftyCloakKeys),
        TetrahedralShiftyCloak(TetrahedralShiftyCloakKeys),
        FramedGclaMappingGoggles(FramedGclaMappingGogglesKeys),
        PlatonicLens(PlatonicLensKeys),
        FourPiLens(FourPiLensKeys),
        FresnelLens(FresnelLensKeys),
        FresnelLensSurface(FresnelLensSurfaceKeys),
        RefractiveLensSurfaces(RefractiveLensSurfacesKeys),
        TriangularThickLens(TriangularThickLensKeys),
        RefractiveLensletArray(RefractiveLensletArrayKeys),
        RefractiveViewRotator(RefractiveViewRotatorKeys),
        Clas(ClasKeys),
        ChenBelinBlackHole(ChenBelinBlackHoleKeys),
        ToShifter(ToShifterKeys),
    }
}

kinds! {
    /// A device's `aid` table: a visual aid made of several coloured objects (Dr TIM's).
    pub enum AidKeys -> Result<Vec<Part>, String> {
        TimHead(TimHeadKeys),
        CoordinateSystem(CoordinateSystemKeys),
        NinkyNonkSilhouette(NinkyNonkSilhouetteKeys),
    }
}

/// Checks for the cloaks' unit tests.
#[cfg(test)]
pub(crate) mod checks {
    use glam::DVec3;

    use super::Part;
    use crate::surfaces::Surface;

    /// The part `name` of `parts` is an ideal thin lens of focal length ±`f` (each cloak picks
    /// its own face orientation) with its principal point at the nodal point `nodal`, to 1e-9;
    /// `label` names the case in messages.
    #[track_caller]
    pub fn lens(parts: &[Part], name: &str, f: f64, nodal: DVec3, label: &str) {
        let part = parts
            .iter()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("{label}: no {name}"));
        let Surface::IdealThinLens(lens) = &part.surface else {
            panic!("{label}: {name} is no lens")
        };
        assert!(
            (lens.focal_length.abs() - f.abs()).abs() < 1e-9 * f.abs().max(1.0),
            "{label}, {name}: f = {}, Dr TIM's {f}",
            lens.focal_length
        );
        assert!(
            (lens.principal_point - nodal).length() < 1e-9,
            "{label}, {name}: principal point {}",
            lens.principal_point
        );
    }
}

/// One scene object of a device.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// The part's name within the device, e.g. `lens 1`.
    pub name: String,
    pub shape: Shape,
    pub surface: Surface,
    /// Not a lens but part of the device's frame (an edge, a vertex; the faces of the Platonic
    /// lens's solid): it throws shadows whatever the device's `shadow_throwing` says.
    pub edge: bool,
}

/// How a device's edges are drawn, if they are shown: cylinders of this radius and surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Edges {
    pub radius: f64,
    pub surface: Surface,
}

impl Edges {
    /// The edge from `start` to `end`, named `name`.
    fn part(&self, name: String, start: glam::DVec3, end: glam::DVec3) -> Result<Part, String> {
        Ok(Part {
            name: name.clone(),
            shape: Shape::Cylinder(
                Cylinder::new(start, end, self.radius).map_err(|e| format!("{name}: {e}"))?,
            ),
            surface: self.surface.clone(),
            edge: true,
        })
    }

    /// A sphere of the edges' radius at the vertex `at`, named `name` (Dr TIM's frames round
    /// off their corners with these).
    fn vertex(&self, name: String, at: glam::DVec3) -> Result<Part, String> {
        Ok(Part {
            name: name.clone(),
            shape: Shape::Sphere(Sphere::new(at, self.radius).map_err(|e| format!("{name}: {e}"))?),
            surface: self.surface.clone(),
            edge: true,
        })
    }
}
