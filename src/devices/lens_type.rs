//! What each lens of a device is made of: Dr TIM's `ThinLensType` (the lens star, the CLAs),
//! `LensElementType` (the ideal-lens cloaks), `Editable4PiLens.LensType` and the lens simplicial
//! complex's `LensType`, one key each (`thin_lens_type`, `lenslet_array_type` and
//! `channeling_lenses_type`, `lens_element_type`, `lens_type`, `lens_type_representing_face`),
//! all read as [`LensType`]. A device works out each lens as
//! an ideal thin lens (its principal point, optical axis, focal length and transmission
//! coefficient) and [`LensType::part`] makes the face from it.
//!
//! The lens hologram is Dr TIM's `PhaseHologramOfLens`: a phase hologram whose phase,
//! −|r − P|²/(2f) about the principal point P, changes the tangential part of the unit ray
//! direction by −(S − P)ₜ/f where the ray meets the face at S. The ideal thin lens changes the
//! tangential part of d/|d·â| (the slope) by the same amount, so the two agree for paraxial rays
//! and differ by the hologram's spherical aberration away from the axis: a bundle along the
//! optical axis through a circle of radius ρ about P meets the axis at √(f² − ρ²) from the
//! face, not at f.

use glam::DVec3;
use serde::Deserialize;

use super::Part;
use crate::geometry::{ConvexPolygon, Parallelogram, Shape, TriangleMesh};
use crate::math::Colour;
use crate::surfaces::metatoys::{Phase, QuadraticPhase};
use crate::surfaces::{Coloured, Mix, PhaseHologram, Surface, ThinLens, Transparent, Weighted};

/// The kind of each lens of a device; Dr TIM's names of the same kind are aliases.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LensType {
    /// An ideal thin lens (Dr TIM's `IDEAL_THIN_LENS`, every device's default).
    #[default]
    IdealThinLens,
    /// A phase hologram of the lens (Dr TIM's `LENS_HOLOGRAM`, `PHASE_HOLOGRAM_OF_LENS` and
    /// `QUADRATIC_LENS_PHASE_HOLOGRAM`): the quadratic phase of the module comment, with the
    /// lens's transmission coefficient and lossless reflection where the wave is evanescent.
    #[serde(
        alias = "phase-hologram-of-lens",
        alias = "quadratic-lens-phase-hologram"
    )]
    LensHologram,
    /// A pane that passes the light on undeviated, with the lens's transmission coefficient
    /// (Dr TIM's `GLASS_PANE`, which Dr TIM's programs use to show the cloak's structure
    /// without its lenses).
    GlassPane,
    /// No face at all, only the edges (the lens simplicial complex's `NONE`).
    #[serde(rename = "none")]
    NoLens,
    /// Not a lens but a placeholder plane that shows where the lens is (Dr TIM's
    /// `SEMITRANSPARENT_PLANE`, `SemiTransparent.BLUE_SHINY_SEMITRANSPARENT`): 75 % of the light
    /// passes undeviated, 25 % is shiny blue ([`semitransparent_plane`]).
    #[serde(alias = "semi-transparent-plane")]
    SemitransparentPlane,
}

/// Dr TIM's `SemiTransparent.BLUE_SHINY_SEMITRANSPARENT`, what its `SEMITRANSPARENT_PLANE`
/// lens type puts in a lens's place, as timbre's `semi-transparent` surface makes it: of the
/// light, 0.75 passes undeviated and 0.25 is shiny blue (`SurfaceColour.BLUE_SHINY`: diffuse
/// blue, white specular). (Dr TIM adds all of the blue surface's light to 0.75 times the light
/// behind; timbre's fractions add up to 1, as its `semi-transparent` surface's do.)
pub fn semitransparent_plane() -> Surface {
    const T: f64 = 0.75;
    Surface::SemiTransparent(Mix {
        parts: Box::new([
            Weighted {
                weight: Colour::splat(1.0 - T),
                surface: Surface::Coloured(Coloured::shiny(Colour::new(0.0, 0.0, 1.0))),
            },
            Weighted {
                weight: Colour::splat(T),
                surface: Surface::Transparent(Transparent {
                    transmission_coefficient: 1.0,
                }),
            },
        ]),
    })
}

/// The flat face a lens of a device fills.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Face {
    /// The parallelogram with a corner at `corner` spanned by `span_u` and `span_v`.
    Parallelogram {
        corner: DVec3,
        span_u: DVec3,
        span_v: DVec3,
    },
    /// The triangle of three vertices.
    Triangle([DVec3; 3]),
}

impl Face {
    /// The face's shape: a triangle as one of Embree's triangles, or as a convex polygon where
    /// `flat_coordinates` are needed (a phase hologram's phase is given in them).
    fn shape(self, flat_coordinates: bool) -> Result<Shape, String> {
        let shape = match self {
            Face::Parallelogram {
                corner,
                span_u,
                span_v,
            } => Parallelogram::new(corner, span_u, span_v).map(Shape::Parallelogram),
            Face::Triangle(corners) if flat_coordinates => {
                ConvexPolygon::new(corners.to_vec()).map(Shape::ConvexPolygon)
            }
            Face::Triangle(corners) => {
                TriangleMesh::new(corners.to_vec(), vec![[0, 1, 2]]).map(Shape::TriangleMesh)
            }
        };
        shape.map_err(|e| e.to_string())
    }
}

impl LensType {
    /// The part `name`: `face` filled with `lens` as this type makes it, or no part
    /// ([`LensType::NoLens`]).
    pub fn part(self, name: String, face: Face, lens: ThinLens) -> Result<Option<Part>, String> {
        let with_name = |e: String| format!("{name}: {e}");
        let (shape, surface) = match self {
            LensType::NoLens => return Ok(None),
            LensType::IdealThinLens => (
                face.shape(false).map_err(with_name)?,
                Surface::IdealThinLens(lens),
            ),
            LensType::GlassPane => (
                face.shape(false).map_err(with_name)?,
                Surface::Transparent(Transparent {
                    transmission_coefficient: lens.transmission_coefficient,
                }),
            ),
            LensType::SemitransparentPlane => (
                face.shape(false).map_err(with_name)?,
                semitransparent_plane(),
            ),
            LensType::LensHologram => {
                let shape = face.shape(true).map_err(with_name)?;
                let centre = shape
                    .plane_coordinates(lens.principal_point, 0)
                    .expect("a parallelogram and a convex polygon have plane coordinates");
                let phase = Phase::Quadratic(QuadraticPhase {
                    focal_length: lens.focal_length,
                    centre,
                });
                let hologram = PhaseHologram {
                    phase,
                    transmission_coefficient: lens.transmission_coefficient,
                    reflection_coefficient: 1.0,
                };
                (shape, Surface::PhaseHologram(hologram))
            }
        };
        Ok(Some(Part {
            name,
            shape,
            surface,
            edge: false,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surfaces::metatoys::hologram_direction;

    fn lens(f: f64) -> ThinLens {
        ThinLens {
            principal_point: DVec3::new(0.2, 0.3, 5.0),
            optical_axis: DVec3::Z,
            focal_length: f,
            gradient: None,
            transmission_coefficient: 0.7,
        }
    }

    const TRIANGLE: Face = Face::Triangle([
        DVec3::new(-2.0, -2.0, 5.0),
        DVec3::new(3.0, -1.0, 5.0),
        DVec3::new(0.0, 4.0, 5.0),
    ]);

    /// The hologram's kick at a point S of the face is −(S − P)/f, whichever way the face's
    /// coordinates run: a ray along the axis through S leaves with tangential part −(S − P)/f,
    /// as Dr TIM's `PhaseHologramOfLens` has it.
    #[test]
    fn the_lens_hologram_kicks_by_the_distance_from_the_principal_point_over_f() {
        let faces = [
            TRIANGLE,
            Face::Parallelogram {
                corner: DVec3::new(3.0, 2.0, 5.0),
                span_u: DVec3::new(-5.0, 1.0, 0.0),
                span_v: DVec3::new(0.0, -4.0, 0.0),
            },
        ];
        for face in faces {
            let part = LensType::LensHologram
                .part("lens".into(), face, lens(2.0))
                .unwrap()
                .unwrap();
            let Surface::PhaseHologram(h) = &part.surface else {
                panic!("{:?}", part.surface)
            };
            assert_eq!(h.transmission_coefficient, 0.7);
            let s = DVec3::new(0.7, -0.5, 5.0);
            let frame = part.shape.frame(s, 0);
            let r = part.shape.plane_coordinates(s, 0).unwrap();
            let local = |v: DVec3| DVec3::new(v.dot(frame.u), v.dot(frame.v), v.dot(frame.w));
            let out = hologram_direction(local(DVec3::Z), h.phase.gradient(r)).unwrap();
            let expected = local(-(s - lens(2.0).principal_point) / 2.0);
            assert!(
                (out.truncate() - expected.truncate()).length() < 1e-15,
                "{out} {expected}"
            );
        }
    }

    /// Dr TIM's `SemiTransparent.BLUE_SHINY_SEMITRANSPARENT` (`SurfaceColour.BLUE_SHINY`, 0.75
    /// of the light through) is timbre's `semi-transparent` surface of a shiny blue surface with
    /// its default transmission 0.75, whatever the lens.
    #[test]
    fn a_semitransparent_plane_is_a_shiny_blue_semi_transparent_surface() {
        let keys: crate::surfaces::SemiTransparentKeys =
            toml::from_str(r#"surface = { type = "shiny", colour = [0, 0, 1] }"#).unwrap();
        let expected = keys.build().unwrap();
        let Surface::SemiTransparent(mix) = &expected else {
            panic!("{expected:?}")
        };
        assert_eq!(mix.parts[1].weight, Colour::splat(0.75));
        for name in ["semitransparent-plane", "semi-transparent-plane"] {
            #[derive(Deserialize)]
            struct Keys {
                t: LensType,
            }
            let keys: Keys = toml::from_str(&format!("t = \"{name}\"")).unwrap();
            let part = keys
                .t
                .part("l".into(), TRIANGLE, lens(-3.0))
                .unwrap()
                .unwrap();
            assert_eq!(part.surface, expected);
            assert!(matches!(part.shape, Shape::TriangleMesh(_)));
        }
    }

    #[test]
    fn an_ideal_lens_a_glass_pane_and_no_lens() {
        let ideal = LensType::IdealThinLens
            .part("l".into(), TRIANGLE, lens(1.0))
            .unwrap()
            .unwrap();
        assert_eq!(ideal.surface, Surface::IdealThinLens(lens(1.0)));
        assert!(matches!(ideal.shape, Shape::TriangleMesh(_)));
        let pane = LensType::GlassPane
            .part("l".into(), TRIANGLE, lens(1.0))
            .unwrap()
            .unwrap();
        assert_eq!(
            pane.surface,
            Surface::Transparent(Transparent {
                transmission_coefficient: 0.7
            })
        );
        assert_eq!(
            LensType::NoLens.part("l".into(), TRIANGLE, lens(1.0)),
            Ok(None)
        );
    }
}
