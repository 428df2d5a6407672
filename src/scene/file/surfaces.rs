//! Surface properties in scene files (`surface = { type = ..., ... }`).

use serde::Deserialize;

use glam::{DMat3, DVec2, DVec3};

use super::values::{
    Coefficient, Direction, Finite, InnerRadius, LensDistance, MetricTensor, NonNegative, NonZero,
    Positive, Rgb, Vector, Vector2,
};
use crate::geometry::Shape;
use crate::math::{Colour, LorentzTransform};
use crate::surfaces::lenses::{Ggrin, GradientIndex, IndexProfile, Lens, LensLaw, TableProfile};
use crate::surfaces::metatoys::{
    Basis, Conjugation, Phase, Refraction, RotationAxis, Teleportation,
};
use crate::surfaces::{
    Chequerboard, Coloured, ConfocalLensletArrays, Focus, Glens, LensletArray, LorentzWindow,
    MetricInterface, Mirror, PhaseConjugating, PhaseHologram, RayFlipping, RayRotating, Refractive,
    Surface, Teleporting, ThinLens, ThinMirror, Transparent,
};

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub(super) enum SurfaceSection {
    Coloured {
        diffuse: Rgb,
        specular: Option<Rgb>,
    },
    Shiny {
        colour: Rgb,
    },
    Matt {
        colour: Rgb,
    },
    #[serde(alias = "constant_colour")]
    ConstantColour {
        colour: Rgb,
    },
    Chequerboard {
        tile_width: Option<Positive>,
        surfaces: Box<[SurfaceSection; 2]>,
    },
    Mirror {
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    Refractive {
        index_ratio: Positive,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    Transparent {
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    #[serde(alias = "luneburg_lens")]
    LuneburgLens {
        method: Option<Method>,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(alias = "eaton_lens")]
    EatonLens {
        method: Option<Method>,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(alias = "maxwell_fisheye_lens")]
    MaxwellFisheyeLens {
        method: Option<Method>,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(alias = "ggrin_lens")]
    GgrinLens {
        r: LensDistance,
        r_prime: LensDistance,
        phi_deg: Finite,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(alias = "gradient_index_lens")]
    GradientIndexLens {
        rho: Vec<Finite>,
        n: Vec<Finite>,
        #[serde(flatten)]
        options: LensOptions,
    },
    #[serde(alias = "metric_interface")]
    MetricInterface {
        inside: Option<MetricTensor>,
        outside: Option<MetricTensor>,
        basis: Option<BasisName>,
        refraction: Option<RefractionName>,
        allow_imaginary: Option<bool>,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    #[serde(alias = "confocal_lenslet_arrays", alias = "gcla")]
    ConfocalLensletArrays {
        a: Direction,
        u: Direction,
        basis: Option<BasisName>,
        eta_u: NonZero,
        eta_v: NonZero,
        delta_u: Option<Finite>,
        delta_v: Option<Finite>,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    #[serde(alias = "ray_rotating")]
    RayRotating {
        angle_deg: Option<Finite>,
        axis: Option<Direction>,
        basis: Option<BasisName>,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    #[serde(alias = "ray_flipping")]
    RayFlipping {
        flip_axis_angle_deg: Option<Finite>,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    #[serde(alias = "phase_hologram")]
    PhaseHologram {
        phase: PhaseSection,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    #[serde(alias = "phase_conjugating")]
    PhaseConjugating {
        mode: Option<ConjugationName>,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    #[serde(alias = "lorentz_window")]
    LorentzWindow {
        beta: Vector,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    IdealThinLens {
        #[serde(flatten)]
        lens: ThinLensKeys,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    IdealThinCylindricalLens {
        #[serde(flatten)]
        lens: ThinLensKeys,
        gradient_direction: Direction,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    IdealThinMirror {
        #[serde(flatten)]
        lens: ThinLensKeys,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    IdealThinCylindricalMirror {
        #[serde(flatten)]
        lens: ThinLensKeys,
        gradient_direction: Direction,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
    IdealThinLensletArray {
        focal_length: NonZero,
        centre: Vector,
        u_direction: Direction,
        v_direction: Direction,
        period: [NonZero; 2],
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    Glens {
        optical_axis: Direction,
        principal_point: Option<Vector>,
        focal_length_negative: Option<NonZero>,
        focal_length_positive: Option<NonZero>,
        nodal_direction: Option<Direction>,
        focal_length_ratio: Option<NonZero>,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
    },
    Teleporting {
        destination: String,
        teleportation: Option<TeleportationName>,
        positional_error: Option<NonNegative>,
        angular_error_deg: Option<NonNegative>,
        #[serde(alias = "transmission")]
        transmission_coefficient: Option<Coefficient>,
        #[serde(alias = "reflection")]
        reflection_coefficient: Option<Coefficient>,
    },
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum BasisName {
    Global,
    Local,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum RefractionName {
    Positive,
    Negative,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum ConjugationName {
    Reflective,
    Transmissive,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum TeleportationName {
    Perfect,
    Holographic,
}

/// A phase hologram's phase function.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub(super) enum PhaseSection {
    Linear {
        gradient: Vector2,
    },
    Quadratic {
        focal_length: NonZero,
        centre: Option<Vector2>,
    },
    Lens {
        focal_length: NonZero,
        centre: Option<Vector2>,
    },
    Cylindrical {
        focal_length: NonZero,
        centre: Option<Vector2>,
        axis_angle_deg: Option<Finite>,
    },
}

impl PhaseSection {
    fn build(self) -> Phase {
        let centre = |c: Option<Vector2>| c.map_or(DVec2::ZERO, |c| c.0);
        match self {
            PhaseSection::Linear { gradient } => Phase::Linear {
                gradient: gradient.0,
            },
            PhaseSection::Quadratic {
                focal_length,
                centre: c,
            } => Phase::Quadratic {
                focal_length: focal_length.0,
                centre: centre(c),
            },
            PhaseSection::Lens {
                focal_length,
                centre: c,
            } => Phase::Lens {
                focal_length: focal_length.0,
                centre: centre(c),
            },
            PhaseSection::Cylindrical {
                focal_length,
                centre: c,
                axis_angle_deg,
            } => Phase::Cylindrical {
                focal_length: focal_length.0,
                centre: centre(c),
                axis_angle: axis_angle_deg.map_or(0.0, |a| a.0).to_radians(),
            },
        }
    }
}

/// A metric interface between the `inside` and `outside` metrics (Euclidean when not given);
/// in the local basis their tangential parts must be invertible.
fn metric_interface(
    inside: Option<MetricTensor>,
    outside: Option<MetricTensor>,
    basis: Basis,
    refraction: Option<RefractionName>,
    allow_imaginary: bool,
    [transmission_coefficient, reflection_coefficient]: [f64; 2],
) -> Result<Surface, String> {
    let euclidean = MetricTensor(DMat3::IDENTITY);
    let (g, h) = (
        inside.unwrap_or(euclidean).0,
        outside.unwrap_or(euclidean).0,
    );
    if basis == Basis::Local {
        check_tangential("inside", &g)?;
        check_tangential("outside", &h)?;
    }
    Ok(Surface::MetricInterface(MetricInterface {
        inside: g,
        outside: h,
        basis,
        refraction: match refraction {
            None | Some(RefractionName::Positive) => Refraction::Positive,
            Some(RefractionName::Negative) => Refraction::Negative,
        },
        allow_imaginary,
        transmission_coefficient,
        reflection_coefficient,
    }))
}

/// Generalised confocal lenslet arrays (Eq 39); the lenslets' `u` must not be along `a`.
fn confocal_lenslet_arrays(
    a: DVec3,
    u: DVec3,
    basis: Basis,
    eta: DVec2,
    delta: DVec2,
    [transmission_coefficient, reflection_coefficient]: [f64; 2],
) -> Result<Surface, String> {
    // Directions are unit vectors: a sine below 1e-9 is parallel.
    if a.cross(u).length() < 1e-9 {
        return Err(format!(
            "confocal-lenslet-arrays: u = {u} must not be parallel to a = {a}"
        ));
    }
    Ok(Surface::ConfocalLensletArrays(ConfocalLensletArrays {
        a,
        u,
        basis,
        eta,
        delta,
        transmission_coefficient,
        reflection_coefficient,
    }))
}

/// The keys of every ideal thin lens and mirror.
#[derive(Debug, Deserialize)]
pub(super) struct ThinLensKeys {
    focal_length: NonZero,
    principal_point: Vector,
    optical_axis: Direction,
}

impl ThinLensKeys {
    /// The lens, cylindrical if a gradient direction is given (made perpendicular to the
    /// optical axis, along which it must not lie).
    fn lens(
        self,
        name: &str,
        gradient: Option<Direction>,
        coefficient: f64,
    ) -> Result<ThinLens, String> {
        let a = self.optical_axis.0;
        let gradient = match gradient {
            None => None,
            Some(g) if a.cross(g.0).length() < 1e-9 => {
                return Err(format!(
                    "{name}: gradient_direction = {} must not be parallel to optical_axis = {a}",
                    g.0
                ));
            }
            Some(g) => Some((g.0 - g.0.dot(a) * a).normalize()),
        };
        Ok(ThinLens {
            principal_point: self.principal_point.0,
            optical_axis: a,
            focal_length: self.focal_length.0,
            gradient,
            transmission_coefficient: coefficient,
        })
    }
}

/// A glens's focus: finite focal lengths with a principal point, or (homogeneous) a nodal
/// direction and the ratio f₋/f₊; one set of keys, whole, and not the other.
fn glens_focus(
    axis: DVec3,
    finite: (Option<Vector>, Option<NonZero>, Option<NonZero>),
    homogeneous: (Option<Direction>, Option<NonZero>),
) -> Result<Focus, String> {
    match (finite, homogeneous) {
        ((Some(p), Some(f_neg), Some(f_pos)), (None, None)) => Ok(Focus::Finite {
            principal_point: p.0,
            focal_length_negative: f_neg.0,
            focal_length_positive: f_pos.0,
        }),
        ((None, None, None), (Some(n), Some(ratio))) => {
            // Directions are unit vectors: a cosine below 1e-9 is perpendicular.
            if n.0.dot(axis).abs() < 1e-9 {
                return Err(format!(
                    "glens: nodal_direction = {} must not lie in the glens's plane (perpendicular to optical_axis = {axis})",
                    n.0
                ));
            }
            Ok(Focus::Homogeneous {
                nodal_direction: n.0,
                ratio: ratio.0,
            })
        }
        _ => Err("glens: give principal_point, focal_length_negative and focal_length_positive (a glens with finite focal lengths), or nodal_direction and focal_length_ratio (a homogeneous glens), not a mixture".into()),
    }
}

/// A teleporting surface, linked to its destination once every object is placed. Errors
/// apply to perfect teleportation, hologram reflections to holographic.
fn teleporting(
    teleportation: Option<TeleportationName>,
    positional_error: f64,
    angular_error_deg: f64,
    transmission_coefficient: f64,
    reflection_coefficient: Option<Coefficient>,
) -> Result<Surface, String> {
    if angular_error_deg > 180.0 {
        return Err(format!(
            "teleporting: angular_error_deg = {angular_error_deg} is more than 180"
        ));
    }
    let teleportation = match teleportation {
        None | Some(TeleportationName::Perfect) => {
            if reflection_coefficient.is_some() {
                return Err("teleporting: reflection_coefficient applies to teleportation = \"holographic\" only (perfect teleportation reflects nothing)".into());
            }
            Teleportation::Perfect
        }
        Some(TeleportationName::Holographic) => {
            if positional_error > 0.0 || angular_error_deg > 0.0 {
                return Err("teleporting: positional_error and angular_error_deg apply to perfect teleportation only, not to teleportation = \"holographic\"".into());
            }
            Teleportation::Holographic
        }
    };
    Ok(Surface::Teleporting(Teleporting {
        destination: unlinked(),
        teleportation,
        positional_error,
        angular_error: angular_error_deg.to_radians(),
        transmission_coefficient,
        reflection_coefficient: coefficient(reflection_coefficient),
    }))
}

/// A phase-conjugating surface: a reflective one takes a reflection coefficient, a
/// transmissive one a transmission coefficient.
fn phase_conjugating(
    mode: Option<ConjugationName>,
    reflection_coefficient: Option<Coefficient>,
    transmission_coefficient: Option<Coefficient>,
) -> Result<Surface, String> {
    let (conjugation, coefficient, wrong) = match mode {
        None | Some(ConjugationName::Reflective) => (
            Conjugation::Reflective,
            reflection_coefficient,
            transmission_coefficient.map(|_| "a reflective one has a reflection_coefficient, not a transmission_coefficient"),
        ),
        Some(ConjugationName::Transmissive) => (
            Conjugation::Transmissive,
            transmission_coefficient,
            reflection_coefficient.map(|_| "a transmissive one (mode = \"transmissive\") has a transmission_coefficient, not a reflection_coefficient"),
        ),
    };
    if let Some(wrong) = wrong {
        return Err(format!("phase-conjugating: {wrong}"));
    }
    Ok(Surface::PhaseConjugating(PhaseConjugating {
        conjugation,
        coefficient: self::coefficient(coefficient),
    }))
}

fn basis(b: Option<BasisName>) -> Basis {
    match b {
        None | Some(BasisName::Global) => Basis::Global,
        Some(BasisName::Local) => Basis::Local,
    }
}

/// A coefficient, 1 (all the light) when not given.
fn coefficient(c: Option<Coefficient>) -> f64 {
    c.map_or(1.0, |c| c.0)
}

/// A law's transmission and (total internal) reflection coefficients.
fn coefficients(transmission: Option<Coefficient>, reflection: Option<Coefficient>) -> [f64; 2] {
    [coefficient(transmission), coefficient(reflection)]
}

/// The (u, v, w) components of h whose tangential part h₁₁h₂₂ − h₁₂² must not vanish.
fn check_tangential(name: &str, h: &DMat3) -> Result<(), String> {
    let det2 = h.x_axis.x * h.y_axis.y - h.y_axis.x * h.y_axis.x;
    let scale = h.x_axis.x.abs().max(h.y_axis.y.abs()).max(h.y_axis.x.abs());
    if det2.abs() <= 1e-12 * scale * scale {
        return Err(format!(
            "metric-interface: in the local basis, the {name} tensor's tangential part has g11 g22 - g12^2 = 0, so Eqs 27-28 have no unique solution"
        ));
    }
    Ok(())
}

/// How a Luneburg, Eaton or Maxwell-fisheye lens is rendered.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum Method {
    /// The paper's closed-form entry-to-exit map.
    #[default]
    Mapping,
    /// The ray equation integrated through the index profile.
    Integration,
}

/// The keys every lens has.
#[derive(Debug, Deserialize)]
pub(super) struct LensOptions {
    invisible_radius: Option<InnerRadius>,
    index_ratio: Option<Positive>,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl LensOptions {
    fn lens(self, law: LensLaw) -> Surface {
        Surface::Lens(Lens {
            law,
            invisible_radius: self.invisible_radius.map_or(0.0, |r| r.0),
            index_ratio: self.index_ratio.map_or(1.0, |n| n.0),
            transmission_coefficient: coefficient(self.transmission_coefficient),
        })
    }
}

impl Method {
    /// The closed-form `mapping`, or integration through `profile`.
    fn law(self, mapping: LensLaw, profile: IndexProfile) -> LensLaw {
        match self {
            Method::Mapping => mapping,
            Method::Integration => LensLaw::GradientIndex(GradientIndex { profile }),
        }
    }
}

impl SurfaceSection {
    /// The surface; an error for a table profile that is not one.
    pub(super) fn build(self) -> Result<Surface, String> {
        Ok(match self {
            SurfaceSection::Coloured { diffuse, specular } => Surface::Coloured(Coloured {
                diffuse: diffuse.0,
                specular: specular.map_or(Colour::ZERO, |s| s.0),
            }),
            SurfaceSection::Shiny { colour } => Surface::Coloured(Coloured::shiny(colour.0)),
            SurfaceSection::Matt { colour } => Surface::Coloured(Coloured::matt(colour.0)),
            SurfaceSection::ConstantColour { colour } => Surface::ConstantColour(colour.0),
            SurfaceSection::Chequerboard {
                tile_width,
                surfaces,
            } => {
                let [a, b] = *surfaces;
                if a.destination().is_some() || b.destination().is_some() {
                    return Err("a teleporting surface cannot be a chequerboard tile".into());
                }
                Surface::Chequerboard(Chequerboard {
                    tile_width: tile_width.map_or(1.0, |w| w.0),
                    surfaces: Box::new([a.build()?, b.build()?]),
                })
            }
            SurfaceSection::Mirror {
                reflection_coefficient,
            } => Surface::Mirror(Mirror {
                reflection_coefficient: coefficient(reflection_coefficient),
            }),
            SurfaceSection::Refractive {
                index_ratio,
                transmission_coefficient,
            } => Surface::Refractive(Refractive {
                index_ratio: index_ratio.0,
                transmission_coefficient: coefficient(transmission_coefficient),
            }),
            SurfaceSection::Transparent {
                transmission_coefficient,
            } => Surface::Transparent(Transparent {
                transmission_coefficient: coefficient(transmission_coefficient),
            }),
            SurfaceSection::LuneburgLens { method, options } => options.lens(
                method
                    .unwrap_or_default()
                    .law(LensLaw::Luneburg, IndexProfile::Luneburg),
            ),
            SurfaceSection::EatonLens { method, options } => options.lens(
                method
                    .unwrap_or_default()
                    .law(LensLaw::Eaton, IndexProfile::Eaton),
            ),
            SurfaceSection::MaxwellFisheyeLens { method, options } => options.lens(
                method
                    .unwrap_or_default()
                    .law(LensLaw::MaxwellFisheye, IndexProfile::MaxwellFisheye),
            ),
            SurfaceSection::GgrinLens {
                r,
                r_prime,
                phi_deg,
                options,
            } => options.lens(LensLaw::Ggrin(Ggrin {
                r: r.0,
                r_prime: r_prime.0,
                phi: phi_deg.0.to_radians(),
            })),
            SurfaceSection::GradientIndexLens { rho, n, options } => {
                let values = |v: Vec<Finite>| v.into_iter().map(|x| x.0).collect();
                let table = TableProfile::new(values(rho), values(n))
                    .map_err(|e| format!("gradient-index-lens profile: {e}"))?;
                options.lens(LensLaw::GradientIndex(GradientIndex {
                    profile: IndexProfile::Table(table),
                }))
            }
            SurfaceSection::MetricInterface {
                inside,
                outside,
                basis: b,
                refraction,
                allow_imaginary,
                transmission_coefficient,
                reflection_coefficient,
            } => metric_interface(
                inside,
                outside,
                basis(b),
                refraction,
                allow_imaginary.unwrap_or(false),
                coefficients(transmission_coefficient, reflection_coefficient),
            )?,
            SurfaceSection::ConfocalLensletArrays {
                a,
                u,
                basis: b,
                eta_u,
                eta_v,
                delta_u,
                delta_v,
                transmission_coefficient,
                reflection_coefficient,
            } => confocal_lenslet_arrays(
                a.0,
                u.0,
                basis(b),
                DVec2::new(eta_u.0, eta_v.0),
                DVec2::new(delta_u.map_or(0.0, |d| d.0), delta_v.map_or(0.0, |d| d.0)),
                coefficients(transmission_coefficient, reflection_coefficient),
            )?,
            SurfaceSection::RayRotating {
                angle_deg,
                axis,
                basis: b,
                transmission_coefficient,
                reflection_coefficient,
            } => {
                let axis = match (axis, b) {
                    (None, None) => RotationAxis::Normal,
                    (None, Some(_)) => {
                        return Err("ray-rotating: basis applies to an axis, but none is given".into());
                    }
                    (Some(a), b) => RotationAxis::Direction(a.0, basis(b)),
                };
                Surface::RayRotating(RayRotating {
                    angle: angle_deg.map_or(RayRotating::DEFAULT_ANGLE_DEG, |a| a.0).to_radians(),
                    axis,
                    transmission_coefficient: coefficient(transmission_coefficient),
                    reflection_coefficient: coefficient(reflection_coefficient),
                })
            }
            SurfaceSection::RayFlipping {
                flip_axis_angle_deg,
                transmission_coefficient,
            } => Surface::RayFlipping(RayFlipping {
                flip_axis_angle: flip_axis_angle_deg.map_or(0.0, |a| a.0).to_radians(),
                transmission_coefficient: coefficient(transmission_coefficient),
            }),
            SurfaceSection::PhaseHologram {
                phase,
                transmission_coefficient,
                reflection_coefficient,
            } => Surface::PhaseHologram(PhaseHologram {
                phase: phase.build(),
                transmission_coefficient: coefficient(transmission_coefficient),
                reflection_coefficient: coefficient(reflection_coefficient),
            }),
            SurfaceSection::PhaseConjugating {
                mode,
                reflection_coefficient,
                transmission_coefficient,
            } => phase_conjugating(mode, reflection_coefficient, transmission_coefficient)?,
            SurfaceSection::LorentzWindow {
                beta,
                transmission_coefficient,
            } => Surface::LorentzWindow(LorentzWindow {
                boost: LorentzTransform::new(beta.0).ok_or_else(|| {
                    format!(
                        "lorentz-window: beta = {} must have magnitude below 1 (the speed of light)",
                        beta.0
                    )
                })?,
                transmission_coefficient: coefficient(transmission_coefficient),
            }),
            SurfaceSection::IdealThinLens {
                lens,
                transmission_coefficient,
            } => Surface::IdealThinLens(lens.lens(
                "ideal-thin-lens",
                None,
                coefficient(transmission_coefficient),
            )?),
            SurfaceSection::IdealThinCylindricalLens {
                lens,
                gradient_direction,
                transmission_coefficient,
            } => Surface::IdealThinLens(lens.lens(
                "ideal-thin-cylindrical-lens",
                Some(gradient_direction),
                coefficient(transmission_coefficient),
            )?),
            SurfaceSection::IdealThinMirror {
                lens,
                reflection_coefficient,
            } => Surface::IdealThinMirror(ThinMirror {
                lens: lens.lens(
                    "ideal-thin-mirror",
                    None,
                    coefficient(reflection_coefficient),
                )?,
            }),
            SurfaceSection::IdealThinCylindricalMirror {
                lens,
                gradient_direction,
                reflection_coefficient,
            } => Surface::IdealThinMirror(ThinMirror {
                lens: lens.lens(
                    "ideal-thin-cylindrical-mirror",
                    Some(gradient_direction),
                    coefficient(reflection_coefficient),
                )?,
            }),
            SurfaceSection::IdealThinLensletArray {
                focal_length,
                centre,
                u_direction,
                v_direction,
                period,
                transmission_coefficient,
            } => {
                let (u, v) = (u_direction.0, v_direction.0);
                if period[0].0 <= 0.0 || period[1].0 <= 0.0 {
                    return Err(format!(
                        "ideal-thin-lenslet-array: period = [{}, {}] must be positive",
                        period[0].0, period[1].0
                    ));
                }
                if u.cross(v).length() < 1e-9 {
                    return Err(format!(
                        "ideal-thin-lenslet-array: v_direction = {v} must not be parallel to u_direction = {u}"
                    ));
                }
                Surface::IdealThinLensletArray(LensletArray {
                    centre: centre.0,
                    u,
                    v,
                    period: DVec2::new(period[0].0, period[1].0),
                    focal_length: focal_length.0,
                    transmission_coefficient: coefficient(transmission_coefficient),
                })
            }
            SurfaceSection::Glens {
                optical_axis,
                principal_point,
                focal_length_negative,
                focal_length_positive,
                nodal_direction,
                focal_length_ratio,
                transmission_coefficient,
            } => Surface::Glens(Glens {
                optical_axis: optical_axis.0,
                focus: glens_focus(
                    optical_axis.0,
                    (principal_point, focal_length_negative, focal_length_positive),
                    (nodal_direction, focal_length_ratio),
                )?,
                transmission_coefficient: coefficient(transmission_coefficient),
            }),
            SurfaceSection::Teleporting {
                destination: _,
                teleportation,
                positional_error,
                angular_error_deg,
                transmission_coefficient,
                reflection_coefficient,
            } => teleporting(
                teleportation,
                positional_error.map_or(0.0, |e| e.0),
                angular_error_deg.map_or(0.0, |a| a.0),
                coefficient(transmission_coefficient),
                reflection_coefficient,
            )?,
        })
    }

    /// The name of the object a teleporting surface leads to.
    pub(super) fn destination(&self) -> Option<&str> {
        match self {
            SurfaceSection::Teleporting { destination, .. } => Some(destination),
            _ => None,
        }
    }
}

/// The destination of a teleporting surface before it is linked: a point-sized sphere.
fn unlinked() -> Shape {
    Shape::Sphere(crate::geometry::Sphere::new(DVec3::ZERO, f64::MIN_POSITIVE).expect("valid"))
}
