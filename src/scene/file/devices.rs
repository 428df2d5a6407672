//! The `[[device]]` entries: devices made of ideal thin lenses (`crate::devices`), with the
//! parameters Dr TIM's editable objects take, each expanding into one scene object per part.

use glam::DVec3;
use serde::Deserialize;

use super::parts::Spanned;
use super::placement::{ArraySection, FrameName};
use crate::geometry::{PlatonicKind, TransformKeys};
use crate::devices::{
    CoordinateSystem, Edges, FourPiLens, IdealLensCloak, LensSimplicialComplex, LensStar, Part,
    PlatonicLens, PolygonalIdealLensCloak, TimHead,
};
use crate::keys::{Coefficient, Direction, Finite, NonZero, Positive, Vector};
use crate::math::Colour;
use crate::surfaces::{Coloured, Surface, SurfaceKeys};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DeviceSection {
    pub name: Option<String>,
    /// Whether the lenses throw shadows (edges always do).
    #[serde(default)]
    pub shadow_throwing: bool,
    pub frame: Option<FrameName>,
    pub transform: Option<Spanned<TransformKeys>>,
    pub array: Option<Spanned<ArraySection>>,
    lenses: Option<Spanned<LensesSection>>,
    aid: Option<Spanned<AidSection>>,
    #[serde(default)]
    show_edges: bool,
    edge_radius: Option<Positive>,
    edge_surface: Option<Spanned<SurfaceKeys>>,
}

/// Dr TIM's defaults for edges: radius 0.01, shiny red.
const EDGE_RADIUS: f64 = 0.01;

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum LensesSection {
    LensStar {
        number_of_lenses: u32,
        focal_length: NonZero,
        principal_point_distance: Option<Finite>,
        centre: Vector,
        intersection_direction: Direction,
        point_on_lens1: Vector,
        star_radius: Positive,
        star_length: Positive,
        lens_transmission_coefficient: Option<Coefficient>,
        shown_lenses_start_index: Option<i64>,
        number_of_shown_lenses: Option<u32>,
    },
    LensSimplicialComplex {
        vertices: Vec<Vector>,
        vertices_v: Vec<Vector>,
        edges: Vec<[usize; 2]>,
        lens_transmission_coefficient: Option<Coefficient>,
    },
    IdealLensCloak {
        #[serde(flatten)]
        cloak: CloakKeys,
    },
    PolygonalIdealLensCloak {
        #[serde(flatten)]
        cloak: CloakKeys,
        no_of_base_vertices: usize,
    },
    PlatonicLens {
        platonic_solid: PlatonicKind,
        centre: Vector,
        radius: Positive,
        basis_vector_1: Option<Direction>,
        basis_vector_2: Option<Direction>,
        focal_length: NonZero,
        lens_transmission_coefficient: Option<Coefficient>,
    },
    FourPiLens {
        principal_point: Vector,
        optical_axis_direction: Direction,
        focal_length_outwards: NonZero,
        transverse_direction1: Direction,
        transverse_direction2: Direction,
        radius: Positive,
        length: Positive,
        closer_inner_vertex_distance: Finite,
        farther_inner_vertex_distance: Finite,
        individual_lens_transmission_coefficient: Option<Coefficient>,
        show_l1: Option<bool>,
        show_r1: Option<bool>,
    },
}

/// Visual aids made of several coloured objects (Dr TIM's).
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum AidSection {
    TimHead {
        centre: Vector,
        radius: Option<Positive>,
        front_direction: Option<Direction>,
        top_direction: Option<Direction>,
    },
    CoordinateSystem {
        origin: Option<Vector>,
        axes: Option<[Direction; 3]>,
        length: Option<Positive>,
        shaft_radius: Option<Positive>,
    },
}

impl AidSection {
    fn parts(&self) -> Result<Vec<Part>, String> {
        match self {
            AidSection::TimHead {
                centre,
                radius,
                front_direction,
                top_direction,
            } => TimHead {
                centre: centre.0,
                radius: radius.map_or(1.0, |r| r.0),
                front_direction: front_direction.map_or(DVec3::NEG_Z, |d| d.0),
                top_direction: top_direction.map_or(DVec3::Y, |d| d.0),
            }
            .parts()
            .map_err(|e| format!("tim-head: {e}")),
            AidSection::CoordinateSystem {
                origin,
                axes,
                length,
                shaft_radius,
            } => {
                let length = length.map_or(1.0, |l| l.0);
                CoordinateSystem {
                    origin: origin.map_or(DVec3::ZERO, |o| o.0),
                    axes: axes.map_or([DVec3::X, DVec3::Y, DVec3::Z], |a| a.map(|d| d.0)),
                    names: ["x axis", "y axis", "z axis"],
                    length,
                    shaft_radius: shaft_radius.map_or(0.025 * length, |r| r.0),
                }
                .parts()
                .map_err(|e| format!("coordinate-system: {e}"))
            }
        }
    }
}

/// The keys of the tetrahedral and the polygonal ideal-lens cloak.
#[derive(Debug, Deserialize)]
struct CloakKeys {
    base_centre: Vector,
    front_direction: Direction,
    right_direction: Direction,
    top_direction: Direction,
    base_radius: Positive,
    height: Positive,
    height_lower_inner_vertex_p: Finite,
    height_upper_inner_vertex_p: Finite,
    height_lower_inner_vertex_e: Finite,
    interface_transmission_coefficient: Option<Coefficient>,
}

impl CloakKeys {
    fn cloak(&self) -> IdealLensCloak {
        IdealLensCloak {
            base_centre: self.base_centre.0,
            front_direction: self.front_direction.0,
            right_direction: self.right_direction.0,
            top_direction: self.top_direction.0,
            base_radius: self.base_radius.0,
            height: self.height.0,
            height_lower_inner_vertex_p: self.height_lower_inner_vertex_p.0,
            height_upper_inner_vertex_p: self.height_upper_inner_vertex_p.0,
            height_lower_inner_vertex_e: self.height_lower_inner_vertex_e.0,
            interface_transmission_coefficient: self
                .interface_transmission_coefficient
                .map_or(1.0, |c| c.0),
        }
    }
}

impl DeviceSection {
    /// Where the device's `lenses` or `aid` table is, for errors about the whole device.
    pub(super) fn span(&self) -> Option<std::ops::Range<usize>> {
        let aid = self.aid.as_ref().map(Spanned::span);
        self.lenses.as_ref().map(Spanned::span).or(aid)
    }

    /// The device's parts, or the span of the table at fault and what is wrong (`table`: the
    /// device's whole table).
    pub(super) fn parts(
        &mut self,
        table: std::ops::Range<usize>,
    ) -> Result<Vec<Part>, (std::ops::Range<usize>, String)> {
        let lenses = match (&self.lenses, &self.aid) {
            (Some(lenses), None) => lenses,
            (None, Some(aid)) => {
                if self.show_edges || self.edge_radius.is_some() || self.edge_surface.is_some() {
                    return Err((
                        aid.span(),
                        "edges (show_edges, edge_radius, edge_surface) belong to lens devices, \
                         not to visual aids"
                            .into(),
                    ));
                }
                return aid.get_ref().parts().map_err(|e| (aid.span(), e));
            }
            _ => {
                return Err((
                    table,
                    "a device needs exactly one of a `lenses` table (a device of lenses) and an \
                     `aid` table (a visual aid)"
                        .into(),
                ));
            }
        };
        let edges = if self.show_edges {
            let surface = match self.edge_surface.take() {
                Some(s) => {
                    let span = s.span();
                    if s.get_ref().destination().is_some() {
                        return Err((span, "edge_surface cannot be a teleporting surface".into()));
                    }
                    s.into_inner().build().map_err(|e| (span, e))?
                }
                None => Surface::Coloured(Coloured::shiny(Colour::new(1.0, 0.0, 0.0))),
            };
            Some(Edges {
                radius: self.edge_radius.as_ref().map_or(EDGE_RADIUS, |r| r.0),
                surface,
            })
        } else {
            None
        };
        let span = lenses.span();
        let lenses = lenses.get_ref();
        let device = match lenses {
            LensesSection::LensStar {
                number_of_lenses,
                focal_length,
                principal_point_distance,
                centre,
                intersection_direction,
                point_on_lens1,
                star_radius,
                star_length,
                lens_transmission_coefficient,
                shown_lenses_start_index,
                number_of_shown_lenses,
            } => LensStar {
                number_of_lenses: *number_of_lenses,
                focal_length: focal_length.0,
                principal_point_distance: principal_point_distance.map_or(0.0, |d| d.0),
                centre: centre.0,
                intersection_direction: intersection_direction.0,
                point_on_lens1: point_on_lens1.0,
                star_radius: star_radius.0,
                star_length: star_length.0,
                lens_transmission_coefficient: lens_transmission_coefficient.map_or(1.0, |c| c.0),
                shown_lenses: match (shown_lenses_start_index, number_of_shown_lenses) {
                    (None, None) => None,
                    (start, n) => Some((start.unwrap_or(0), n.unwrap_or(*number_of_lenses))),
                },
            }
            .parts(edges.as_ref()),
            LensesSection::LensSimplicialComplex {
                vertices,
                vertices_v,
                edges: joined,
                lens_transmission_coefficient,
            } => LensSimplicialComplex {
                vertices: vertices.iter().map(|v| v.0).collect(),
                vertices_v: vertices_v.iter().map(|v| v.0).collect(),
                edges: joined.clone(),
                lens_transmission_coefficient: lens_transmission_coefficient.map_or(1.0, |c| c.0),
            }
            .parts(edges.as_ref()),
            LensesSection::IdealLensCloak { cloak } => cloak.cloak().parts(edges.as_ref()),
            LensesSection::PolygonalIdealLensCloak {
                cloak,
                no_of_base_vertices,
            } => PolygonalIdealLensCloak {
                cloak: cloak.cloak(),
                no_of_base_vertices: *no_of_base_vertices,
            }
            .parts(edges.as_ref()),
            LensesSection::PlatonicLens {
                platonic_solid,
                centre,
                radius,
                basis_vector_1,
                basis_vector_2,
                focal_length,
                lens_transmission_coefficient,
            } => PlatonicLens {
                platonic_solid: *platonic_solid,
                centre: centre.0,
                radius: radius.0,
                basis_vector_1: basis_vector_1.map_or(DVec3::X, |b| b.0),
                basis_vector_2: basis_vector_2.map_or(DVec3::Y, |b| b.0),
                focal_length: focal_length.0,
                lens_transmission_coefficient: lens_transmission_coefficient.map_or(1.0, |c| c.0),
            }
            .parts(edges.as_ref()),
            LensesSection::FourPiLens {
                principal_point,
                optical_axis_direction,
                focal_length_outwards,
                transverse_direction1,
                transverse_direction2,
                radius,
                length,
                closer_inner_vertex_distance,
                farther_inner_vertex_distance,
                individual_lens_transmission_coefficient,
                show_l1,
                show_r1,
            } => FourPiLens {
                principal_point: principal_point.0,
                optical_axis_direction: optical_axis_direction.0,
                focal_length_outwards: focal_length_outwards.0,
                transverse_direction1: transverse_direction1.0,
                transverse_direction2: transverse_direction2.0,
                radius: radius.0,
                length: length.0,
                closer_inner_vertex_distance: closer_inner_vertex_distance.0,
                farther_inner_vertex_distance: farther_inner_vertex_distance.0,
                individual_lens_transmission_coefficient: individual_lens_transmission_coefficient
                    .map_or(1.0, |c| c.0),
                show_l1: show_l1.unwrap_or(true),
                show_r1: show_r1.unwrap_or(true),
            }
            .parts(edges.as_ref()),
        };
        device.map_err(|e| (span, format!("{}: {e}", lenses.name())))
    }
}

impl LensesSection {
    /// The device's `type`, for messages.
    fn name(&self) -> &'static str {
        match self {
            LensesSection::LensStar { .. } => "lens-star",
            LensesSection::LensSimplicialComplex { .. } => "lens-simplicial-complex",
            LensesSection::IdealLensCloak { .. } => "ideal-lens-cloak",
            LensesSection::PolygonalIdealLensCloak { .. } => "polygonal-ideal-lens-cloak",
            LensesSection::PlatonicLens { .. } => "platonic-lens",
            LensesSection::FourPiLens { .. } => "four-pi-lens",
        }
    }
}
