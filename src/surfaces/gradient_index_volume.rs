//! A gradient-index volume: the inside of any convex solid filled with a refractive-index
//! distribution n(x), through which light is traced by integrating the ray equation
//! d/ds (n dr/ds) = ∇n (Dr TIM's `SurfaceOfMetricSpace` with an isotropic index, as its
//! `SurfaceOfRadiallySymmetricRefractiveIndexDistribution` and `SurfaceOfLissajousLens` are;
//! its Hamiltonian H = k·n·k − det n (Schurig, Pendry & Smith, Opt. Express 14, 9794 (2006),
//! Eq. 40) for n = n 𝟙 gives the same rays, though Dr TIM's two measure the force from the
//! origin and the Lissajous lens's dn/dr is √2 times its index's), or through layers of constant index (Dr TIM's
//! `SurfaceOfVoxellatedRefractor` on its concentric spheres, coaxial cylinders or parallel
//! planes).
//!
//! The distributions are a constant n, or a profile n(ρ) of the distance ρ (in units of
//! `radius`) from a point (radial), a line (cylindrical: a gradient-index rod) or a plane
//! (planar: a layered medium, a mirage). As for the gradient-index lenses, with dτ = ds/n
//! and p = n dr/ds the ray equation is r″ = ∇(n²)/2 (′ = d/dτ), |p| = n, and the optical path
//! ∫n ds = ∫n² dτ; it is integrated in 3D by adaptive DOP853 steps (the lenses' tolerances)
//! until the ray reaches the solid's surface, located to rounding. With a layer separation
//! the profile is instead constant in each layer between the spheres, cylinders or planes at
//! ρ = k × separation, at its value in the layer's middle (Dr TIM's voxel index + ½), and light
//! goes straight in a layer and is refracted by Snell's law between layers, exactly. Light is
//! refracted by Snell's law into the index at the entry point and out of the index at the exit
//! (the index is relative to the surrounding medium); beyond the critical angle it is
//! reflected inside and traced on. A constant index is traced along straight chords, exactly.
//!
//! A ray that meets the surface from inside having started inside (a camera or trajectory
//! start within the volume) is integrated from its start, as Dr TIM does. Objects inside the
//! volume are not met by the curved rays (Dr TIM's `getInsideScene` is empty by default).

use glam::DVec3;
use serde::Deserialize;

use super::lenses::{IndexProfile, TableProfile};
use super::{Redirection, Surface, reflect, refract};
use crate::geometry::{ConvexSolid, Exit, Interaction, Shape, Span, Transform};
use crate::keys::{Coefficient, Direction, Finite, Positive, Vector, throughput};
use crate::math::{Colour, Phase};

/// Reflections inside (total internal reflection at the surface) after which a ray counts as
/// trapped, and no light comes back along it.
const MAX_REFLECTIONS: usize = 100;

/// Layer boundaries a ray may cross (or be reflected at) in one passage before it counts as
/// trapped.
const MAX_LAYER_CROSSINGS: usize = 1_000_000;

/// The thinnest layers, in units of the profile's radius: far thicker than the graze within
/// which a boundary counts as the surface, and few enough for a ray to cross quickly.
const MIN_LAYER_SEPARATION: f64 = 1e-4;

/// A graze, in units of the integration's length scale or of the profile's radius: a ray
/// entering with a straight chord shorter than this passes straight across (its exit cannot be
/// told from its entry); in layers, a ray this near a boundary is on it (and meets it again only
/// at its other crossing), its layer is the one this far ahead, and a boundary this near the
/// solid's surface is the surface.
const GRAZING: f64 = 1e-7;

/// What a profile's ρ is the distance from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Symmetry {
    /// A point (radial).
    Point(DVec3),
    /// The line through `point` along the unit `axis` (cylindrical).
    Line { point: DVec3, axis: DVec3 },
    /// The plane through `point` with unit `normal` (planar).
    Plane { point: DVec3, normal: DVec3 },
}

impl Symmetry {
    /// The displacement of `x` from the point, line or plane, whose length is the distance.
    fn displacement(&self, x: DVec3) -> DVec3 {
        match *self {
            Symmetry::Point(c) => x - c,
            Symmetry::Line { point, axis } => (x - point).reject_from_normalized(axis),
            Symmetry::Plane { point, normal } => (x - point).project_onto_normalized(normal),
        }
    }

    /// The coordinate whose level sets are the layer boundaries: the distance, or for a plane
    /// the signed distance along its normal.
    fn level(&self, x: DVec3) -> f64 {
        match *self {
            Symmetry::Plane { point, normal } => (x - point).dot(normal),
            _ => self.displacement(x).length(),
        }
    }

    /// The smallest t > 0 at which `x + t d` (d unit) has [`Self::level`] `level`; if `x` is
    /// on that level set (`on`), where the line meets it again (for a sphere or cylinder the
    /// other root, however near; a plane it never meets again).
    fn reaches(&self, x: DVec3, d: DVec3, level: f64, on: bool) -> Option<f64> {
        if let Symmetry::Plane { normal, .. } = *self {
            let t = (level - self.level(x)) / d.dot(normal);
            return (!on && t > 0.0 && t.is_finite()).then_some(t);
        }
        // |v + t w|² = level², v and w the parts of x and d across the line (all of them
        // about a point).
        let (v, w) = (
            self.displacement(x),
            self.displacement(x + d) - self.displacement(x),
        );
        let (a, half_b, c) = (
            w.length_squared(),
            v.dot(w),
            v.length_squared() - level * level,
        );
        let discriminant = half_b * half_b - a * c;
        if a == 0.0 || discriminant < 0.0 {
            return None;
        }
        if on {
            // The roots sum to −b/a, and one of them is 0.
            let t = -2.0 * half_b / a;
            return (t > 0.0).then_some(t);
        }
        // The roots without cancellation: q = −(b/2 + sign(b/2) √Δ), t = q/a and c/q.
        let q = -(half_b + discriminant.sqrt().copysign(half_b));
        let (t1, t2) = (q / a, c / q);
        [t1.min(t2), t1.max(t2)]
            .into_iter()
            .find(|&t| t > 0.0 && t.is_finite())
    }

    /// The unit normal at `x` of the level set through it, towards higher levels.
    fn gradient(&self, x: DVec3) -> DVec3 {
        match *self {
            Symmetry::Plane { normal, .. } => normal,
            _ => self.displacement(x).normalize(),
        }
    }

    fn transformed(&self, t: &Transform) -> Symmetry {
        let unit = |v: DVec3| t.vector(v).normalize();
        match *self {
            Symmetry::Point(c) => Symmetry::Point(t.point(c)),
            Symmetry::Line { point, axis } => Symmetry::Line {
                point: t.point(point),
                axis: unit(axis),
            },
            Symmetry::Plane { point, normal } => Symmetry::Plane {
                point: t.point(point),
                normal: unit(normal),
            },
        }
    }
}

/// A profile n(ρ) of the distance from a point, line or plane, smooth or in layers.
#[derive(Debug, Clone, PartialEq)]
pub struct Profiled {
    pub about: Symmetry,
    /// R, the distance at which ρ = 1.
    pub radius: f64,
    pub profile: IndexProfile,
    /// The layers' thickness in ρ (Dr TIM's voxellation's separation over R), if in layers.
    pub layer_separation: Option<f64>,
}

impl Profiled {
    /// n² and the force n∇n = ∇(n²)/2 of the smooth profile at `x`: the profile's φ v/R in
    /// units of R (see [`IndexProfile::n_squared_and_force`]) is φ v/R² in the scene's.
    fn n_squared_and_force(&self, x: DVec3) -> (f64, DVec3) {
        let v = self.about.displacement(x);
        let r2 = self.radius * self.radius;
        let rho2 = v.length_squared() / r2;
        if let IndexProfile::Table(_) = self.profile
            && rho2 > 1.0
        {
            // Beyond its last entry a table's index stays at its value there.
            return (self.profile.n(1.0).powi(2), DVec3::ZERO);
        }
        let (n2, force) = self.profile.n_squared_and_force(rho2);
        (n2, force / r2 * v)
    }

    /// The layer a ray at `x` going in direction `d` (unit) is in, or enters if `x` lies on
    /// a boundary (or within a graze of one).
    fn layer(&self, x: DVec3, d: DVec3, separation: f64) -> i64 {
        let ahead = x + GRAZING * self.radius * d;
        (self.about.level(ahead) / (self.radius * separation)).floor() as i64
    }

    /// The index of layer k: the profile's in its middle.
    fn layer_index(&self, k: i64, separation: f64) -> Option<f64> {
        let rho = ((k as f64 + 0.5) * separation).abs();
        let rho = match self.profile {
            IndexProfile::Table(_) => rho.min(1.0),
            _ => rho,
        };
        let n = self.profile.n(rho);
        (n > 0.0).then_some(n)
    }
}

/// The refractive index inside the volume, relative to the surrounding medium.
#[derive(Debug, Clone, PartialEq)]
pub enum IndexDistribution {
    Constant(f64),
    Profiled(Profiled),
}

impl IndexDistribution {
    /// Where a ray going in direction `d` (unit) starts or enters at `x`: n² there (the
    /// layer's, in layers, −1 for a layer without an index), and its layer (0 but in layers).
    fn start(&self, x: DVec3, d: DVec3) -> (f64, i64) {
        match self {
            IndexDistribution::Constant(n) => (n * n, 0),
            IndexDistribution::Profiled(p) => match p.layer_separation {
                Some(separation) => {
                    let k = p.layer(x, d, separation);
                    let n = p.layer_index(k, separation);
                    (n.map_or(-1.0, |n| n * n), k)
                }
                None => (p.n_squared_and_force(x).0, 0),
            },
        }
    }

    /// The distribution of an object placed by `t`, which must keep angles (a rotation,
    /// uniform scaling and translation) for a profile to keep its symmetry.
    fn transformed(&self, t: &Transform) -> Result<IndexDistribution, String> {
        let IndexDistribution::Profiled(p) = self else {
            return Ok(self.clone());
        };
        let scale = t.uniform_scale().ok_or(
            "a gradient-index volume's index is symmetric about a point, line or plane, which \
             only rotations, uniform scaling and translations keep, so it cannot be scaled \
             non-uniformly",
        )?;
        Ok(IndexDistribution::Profiled(Profiled {
            about: p.about.transformed(t),
            radius: p.radius * scale,
            ..p.clone()
        }))
    }
}

/// The volume's law: its index distribution and the fraction of light passed through.
#[derive(Debug, Clone, PartialEq)]
pub struct GradientIndexVolume {
    pub index: IndexDistribution,
    pub transmission_coefficient: f64,
}

/// A ray inside the volume: position, optical direction vector p (|p| = n), and, in layers,
/// its layer.
#[derive(Debug, Clone, Copy)]
struct Inside {
    x: DVec3,
    p: DVec3,
    layer: i64,
}

/// Where a passage reaches the surface: the ray there, the part of the surface, and the
/// optical path.
type Reached = (Inside, u32, f64);

impl GradientIndexVolume {
    pub fn redirect(
        &self,
        at: &Interaction,
        inside: &mut dyn FnMut(DVec3),
    ) -> Redirection<'static> {
        let Some(solid) = at.shape.analytic_solid() else {
            return Redirection::Lost;
        };
        let factor = Colour::splat(self.transmission_coefficient);
        let (p, d, normal) = (at.local_point(), at.ray.direction, at.normal());
        let show = &mut |x: DVec3| inside(x + at.offset);
        let (start, before) = if d.dot(normal) < 0.0 {
            // The layer inwards from the surface: along the inward normal.
            let (n2, layer) = self.index.start(p, -normal);
            let refracted = (n2 > 0.0).then(|| refract(d, normal, n2.sqrt())).flatten();
            let Some(refracted) = refracted else {
                // Reflected off the surface (a lower index inside, or n² ≤ 0 there).
                return Redirection::Leaves {
                    direction: reflect(d, normal),
                    factor,
                };
            };
            let start = Inside {
                x: p,
                p: n2.sqrt() * refracted,
                layer,
            };
            (start, 0.0)
        } else {
            // From inside: integrated from where the ray started, if that is inside.
            let origin = at.ray.origin - at.offset;
            let (n2, layer) = self.index.start(origin, d);
            if !solid.contains(origin) || n2 <= 0.0 {
                return Redirection::Leaves {
                    direction: d,
                    factor,
                };
            }
            let start = Inside {
                x: origin,
                p: n2.sqrt() * d,
                layer,
            };
            (start, at.hit.t)
        };
        if solid.chord(start.x, start.p.normalize()).is_none() {
            // A graze that rounding puts outside the solid passes on, as the lenses' do.
            return Redirection::Leaves {
                direction: d,
                factor,
            };
        }
        match self.traverse(at.shape, solid, start, show) {
            Some(exit) => Redirection::Crosses {
                exit: Exit {
                    point: exit.point + at.offset,
                    path: exit.path - before,
                    ..exit
                },
                factor,
            },
            None => Redirection::Lost,
        }
    }

    /// The ray from `start` inside the volume to where it leaves, refracted out, with the
    /// optical path from `start`; reflected inside beyond the critical angle. `None` for a
    /// trapped ray (more than [`MAX_REFLECTIONS`] reflections, or no exit within the
    /// integrator's step limit or [`MAX_LAYER_CROSSINGS`]), one that goes on for ever in an
    /// unbounded solid, or one whose line rounding puts outside the solid.
    fn traverse(
        &self,
        shape: &Shape,
        solid: &dyn ConvexSolid,
        mut ray: Inside,
        show: &mut dyn FnMut(DVec3),
    ) -> Option<Exit> {
        let mut path = 0.0;
        for _ in 0..=MAX_REFLECTIONS {
            let (leaving, part, optical) = match &self.index {
                IndexDistribution::Constant(_) => straight(solid, ray)?,
                IndexDistribution::Profiled(p) => match p.layer_separation {
                    Some(separation) => layered(p, separation, solid, ray, show)?,
                    None => integrated(p, shape, solid, ray, show)?,
                },
            };
            path += optical;
            let normal = shape.normal(leaving.x, part);
            let n = leaving.p.length();
            let d = leaving.p / n;
            if let Some(out) = refract(d, normal, n) {
                return Some(Exit {
                    point: leaving.x,
                    direction: out,
                    path,
                });
            }
            show(leaving.x);
            ray = Inside {
                p: reflect(leaving.p, normal),
                ..leaving
            };
        }
        None
    }

    /// The volume of an object placed by `t`.
    pub fn transformed(&self, t: &Transform) -> Result<GradientIndexVolume, String> {
        Ok(GradientIndexVolume {
            index: self.index.transformed(t)?,
            ..*self
        })
    }
}

/// The straight passage from `ray` to the surface.
fn straight(solid: &dyn ConvexSolid, ray: Inside) -> Option<Reached> {
    let d = ray.p.normalize();
    let (t, part) = solid.chord(ray.x, d)?.exit;
    if part == Span::NO_PART {
        // Never leaves an unbounded solid.
        return None;
    }
    let t = t.max(0.0);
    Some((
        Inside {
            x: ray.x + t * d,
            ..ray
        },
        part,
        ray.p.length() * t,
    ))
}

/// The passage from `ray` to the surface through the smooth profile, integrated.
fn integrated(
    profile: &Profiled,
    shape: &Shape,
    solid: &dyn ConvexSolid,
    ray: Inside,
    show: &mut dyn FnMut(DVec3),
) -> Option<Reached> {
    let d = ray.p.normalize();
    let (t, _) = solid.chord(ray.x, d)?.exit;
    // Lengths in units of L, the solid's half-diagonal (or the profile's radius where the
    // solid is unbounded), from its centre (or the start): τ scales with them, p stays as it
    // is and the force is L times its own.
    let (origin, length) = match shape.bounds() {
        Some((lo, hi)) => (0.5 * (lo + hi), 0.5 * lo.distance(hi)),
        None => (ray.x, profile.radius),
    };
    if t < GRAZING * length {
        return straight(solid, ray);
    }
    // A point well inside, from which the surface is seen in every direction: the solid's
    // centre, or else the middle of the ray's straight chord (at most L in).
    let inner = if solid.contains(origin) && shape.bounds().is_some() {
        origin
    } else {
        ray.x + 0.5 * t.min(length) * d
    };
    // Where the line from `inner` through x leaves the solid: the point, and the surface's
    // normal there.
    let surface_towards = |x: DVec3| {
        let u = (x - inner).try_normalize().unwrap_or(d);
        let (s, part) = solid.chord(inner, u)?.exit;
        let at = inner + s * u;
        Some((at, part, shape.normal(at, part), u))
    };
    let world = |x: &[f64; 3]| origin + length * DVec3::from_array(*x);
    let field = |x: &[f64; 3]| {
        let (n2, force) = profile.n_squared_and_force(world(x));
        ((length * force).to_array(), n2)
    };
    // g: how far beyond the surface x lies along the line from `inner` (in units of L), which
    // crosses zero upwards where the ray leaves, smoothly also where it leaves at a graze;
    // dg/dτ = (m·p)/(m·u) there, m the surface's normal and u the line's direction.
    let event = |y: &Phase<3>| {
        let (x, v) = (world(&y.x), DVec3::from_array(y.v));
        match surface_towards(x) {
            Some((at, _, m, u)) => {
                let beyond = (x - inner).length() - (at - inner).length();
                (beyond / length, m.dot(v) / m.dot(u))
            }
            None => (1.0, v.length()),
        }
    };
    let start = Phase {
        x: ((ray.x - origin) / length).to_array(),
        v: ray.p.to_array(),
        q: 0.0,
    };
    // The first step covers an eighth of the straight chord, or of L (|dx/dτ| = |p| = n in
    // units of L), so that it ends before the ray can leave.
    let h0 = 0.125 * (t / length).min(1.0) / ray.p.length();
    let step = |y: &Phase<3>| show(world(&y.x));
    let y = profile
        .profile
        .solver()
        .integrate_until(field, start, h0, event, step)?;
    // Onto the surface along the line from `inner`.
    let (at, part, _, _) = surface_towards(world(&y.x))?;
    let p = DVec3::from_array(y.v);
    Some((Inside { x: at, p, ..ray }, part, length * y.q))
}

/// The passage from `ray` to the surface through the profile's layers: straight within a
/// layer, refracted by Snell's law (or reflected) at each boundary between layers.
fn layered(
    profile: &Profiled,
    separation: f64,
    solid: &dyn ConvexSolid,
    mut ray: Inside,
    show: &mut dyn FnMut(DVec3),
) -> Option<Reached> {
    let about = profile.about;
    let width = profile.radius * separation;
    let graze = GRAZING * profile.radius;
    // The boundary the ray is on (within a graze), by its level k, at k × width.
    let nearest = (about.level(ray.x) / width).round();
    let mut on = ((about.level(ray.x) - nearest * width).abs() <= graze).then_some(nearest as i64);
    let mut path = 0.0;
    for _ in 0..MAX_LAYER_CROSSINGS {
        let (d, n, k) = (ray.p.normalize(), ray.p.length(), ray.layer);
        let (to_surface, part) = solid.chord(ray.x, d)?.exit;
        // The layer's boundaries ahead: its inner one (none at the centre or axis) and outer.
        let boundary = [(k, k - 1), (k + 1, k + 1)]
            .into_iter()
            .filter(|&(level, _)| level > 0 || matches!(about, Symmetry::Plane { .. }))
            .filter_map(|(level, next)| {
                let t = about.reaches(ray.x, d, level as f64 * width, on == Some(level))?;
                Some((t, level, next))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        // A boundary at the surface (within a graze) is the surface.
        let Some((t, level, next)) = boundary.filter(|&(t, _, _)| t < to_surface - graze) else {
            if part == Span::NO_PART {
                return None;
            }
            let t = to_surface.max(0.0);
            let x = ray.x + t * d;
            return Some((Inside { x, ..ray }, part, path + n * t));
        };
        let x = ray.x + t * d;
        path += n * t;
        show(x);
        on = Some(level);
        // Across into layer `next`, by Snell's law between the lower and the upper layer
        // about the boundary's normal towards the upper one; a layer without an index (n² ≤ 0)
        // reflects.
        let gradient = about.gradient(x);
        let (lower, upper) = (k.min(next), k.max(next));
        let indices = (
            profile.layer_index(lower, separation),
            profile.layer_index(upper, separation),
        );
        let crossed = match indices {
            (Some(low), Some(high)) => refract(d, gradient, low / high)
                .map(|direction| (direction, if next == upper { high } else { low })),
            _ => None,
        };
        ray = match crossed {
            Some((direction, n)) => Inside {
                x,
                p: n * direction,
                layer: next,
            },
            None => Inside {
                x,
                p: reflect(ray.p, gradient),
                layer: k,
            },
        };
    }
    None
}

/// A profile by name: `"luneburg"`, n = √(2 − ρ²) (the index of Dr TIM's
/// `SurfaceOfLissajousLens` with β = radius), or `"maxwell-fisheye"`, n = 2/(1 + ρ²).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "kebab-case")]
enum ProfileName {
    Luneburg,
    MaxwellFisheye,
}

/// `index = { type = ... }`: a constant `n`, or a profile about a point, line or plane.
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum IndexKeys {
    Constant {
        n: Positive,
    },
    Radial {
        centre: Vector,
        radius: Option<Positive>,
        profile: Option<ProfileName>,
        rho: Option<Vec<Finite>>,
        n: Option<Vec<Finite>>,
        layer_separation: Option<Positive>,
    },
    Cylindrical {
        point: Vector,
        axis: Direction,
        radius: Option<Positive>,
        profile: Option<ProfileName>,
        rho: Option<Vec<Finite>>,
        n: Option<Vec<Finite>>,
        layer_separation: Option<Positive>,
    },
    Planar {
        point: Vector,
        normal: Direction,
        radius: Option<Positive>,
        profile: Option<ProfileName>,
        rho: Option<Vec<Finite>>,
        n: Option<Vec<Finite>>,
        layer_separation: Option<Positive>,
    },
}

/// A profiled distribution from its keys: the profile by name, or a table of n at the
/// distances `rho` (in units of the radius, from 0 to 1).
fn profiled(
    about: Symmetry,
    radius: Option<Positive>,
    name: Option<ProfileName>,
    table: (Option<Vec<Finite>>, Option<Vec<Finite>>),
    layer_separation: Option<Positive>,
) -> Result<IndexDistribution, String> {
    let values = |v: Vec<Finite>| v.into_iter().map(|x| x.0).collect();
    let profile = match (name, table) {
        (Some(ProfileName::Luneburg), (None, None)) => IndexProfile::Luneburg,
        (Some(ProfileName::MaxwellFisheye), (None, None)) => IndexProfile::MaxwellFisheye,
        (None, (Some(rho), Some(n))) => TableProfile::new(values(rho), values(n))
            .map(IndexProfile::Table)
            .map_err(|e| format!("gradient-index-volume profile: {e}"))?,
        _ => {
            return Err(
                "gradient-index-volume: give the index's `profile` (\"luneburg\" or \
                        \"maxwell-fisheye\") or a table of `rho` and `n`, not both"
                    .into(),
            );
        }
    };
    if let Some(s) = layer_separation
        && s.0 < MIN_LAYER_SEPARATION
    {
        return Err(format!(
            "gradient-index-volume: layer_separation = {} is below {MIN_LAYER_SEPARATION:e} \
             (at most 10 000 layers per radius): thinner layers approach the smooth profile, \
             which leaving layer_separation out traces exactly",
            s.0
        ));
    }
    Ok(IndexDistribution::Profiled(Profiled {
        about,
        radius: radius.map_or(1.0, |r| r.0),
        profile,
        layer_separation: layer_separation.map(|s| s.0),
    }))
}

/// `type = "gradient-index-volume"`: `index` (required: Dr TIM has no editable object for it)
/// and `transmission_coefficient` (0.96, Dr TIM's default).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GradientIndexVolumeKeys {
    index: IndexKeys,
    #[serde(alias = "transmission")]
    transmission_coefficient: Option<Coefficient>,
}

impl GradientIndexVolumeKeys {
    pub fn build(self) -> Result<Surface, String> {
        let index = match self.index {
            IndexKeys::Constant { n } => IndexDistribution::Constant(n.0),
            IndexKeys::Radial {
                centre,
                radius,
                profile,
                rho,
                n,
                layer_separation,
            } => profiled(
                Symmetry::Point(centre.0),
                radius,
                profile,
                (rho, n),
                layer_separation,
            )?,
            IndexKeys::Cylindrical {
                point,
                axis,
                radius,
                profile,
                rho,
                n,
                layer_separation,
            } => profiled(
                Symmetry::Line {
                    point: point.0,
                    axis: axis.0,
                },
                radius,
                profile,
                (rho, n),
                layer_separation,
            )?,
            IndexKeys::Planar {
                point,
                normal,
                radius,
                profile,
                rho,
                n,
                layer_separation,
            } => profiled(
                Symmetry::Plane {
                    point: point.0,
                    normal: normal.0,
                },
                radius,
                profile,
                (rho, n),
                layer_separation,
            )?,
        };
        Ok(Surface::GradientIndexVolume(GradientIndexVolume {
            index,
            transmission_coefficient: throughput(self.transmission_coefficient),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Cuboid, Cylinder};
    use crate::surfaces::tests::{crosses, meet};

    /// Snell's law in vector form, written out here: the direction after crossing from index
    /// `n1` into `n2` through a surface of unit normal `normal` (either side).
    fn snell(d: DVec3, normal: DVec3, n1: f64, n2: f64) -> DVec3 {
        let normal = if d.dot(normal) > 0.0 { -normal } else { normal };
        let (eta, cos_i) = (n1 / n2, -d.dot(normal));
        let cos_t = (1.0 - eta * eta * (1.0 - cos_i * cos_i)).sqrt();
        eta * d + (eta * cos_i - cos_t) * normal
    }

    /// The first τ > 0 at which `inside(τ)` turns false, by sampling every `step` and
    /// bisecting to rounding.
    fn first_exit(inside: impl Fn(f64) -> bool, step: f64) -> f64 {
        let mut hi = step;
        while inside(hi) {
            hi += step;
        }
        let mut lo = hi - step;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if inside(mid) { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    }

    /// A Luneburg profile n² = 2 − |x − c|²/R² makes the ray equation x″ = −(x − c)/R² (in
    /// τ) a harmonic oscillator: x(τ) = c + A cos(τ/R) + R B sin(τ/R), with A = x₀ − c and B
    /// = p₀, the optical direction vector just inside. Its optical path ∫n² dτ integrates in
    /// closed form. Rays entering a cuboid (off the profile's centre) from several directions
    /// leave where the ellipse first leaves the cuboid, refracted by Snell's law, and their
    /// curved paths lie on the ellipse.
    #[test]
    fn a_luneburg_profile_in_a_cuboid_sends_rays_along_ellipses() {
        let (box_centre, half) = (DVec3::new(0.2, -0.1, 3.0), DVec3::new(1.0, 0.8, 0.6));
        let shape = Shape::Cuboid(Cuboid::new(box_centre, 2.0 * half).unwrap());
        let (c, r) = (DVec3::new(0.3, 0.1, 3.1), 1.3);
        let law = GradientIndexVolume {
            index: IndexDistribution::Profiled(Profiled {
                about: Symmetry::Point(c),
                radius: r,
                profile: IndexProfile::Luneburg,
                layer_separation: None,
            }),
            transmission_coefficient: 0.9,
        };
        let n = |x: DVec3| (2.0 - (x - c).length_squared() / (r * r)).sqrt();
        let inside_box = |x: DVec3| ((x - box_centre).abs() - half).max_element() < 0.0;
        for (origin, target) in [
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.1, 0.0, 2.5)),
            (DVec3::new(-2.0, 1.0, 2.5), DVec3::new(0.0, 0.2, 3.2)),
            (DVec3::new(1.5, -2.0, 4.0), DVec3::new(0.5, -0.3, 2.9)),
            (DVec3::new(0.25, 0.3, 6.0), DVec3::new(0.2, 0.35, 3.0)),
        ] {
            let at = meet(&shape, origin, target - origin);
            let entry = at.point();
            let mut curve = Vec::new();
            let (exit, factor) = crosses(law.redirect(&at, &mut |x| curve.push(x)));
            assert_eq!(factor, 0.9);
            // By hand: refract in, follow the ellipse, refract out.
            let d_in = snell(at.ray.direction, at.normal(), 1.0, n(entry));
            let (a, b) = (entry - c, n(entry) * d_in);
            let x = |tau: f64| c + a * (tau / r).cos() + r * b * (tau / r).sin();
            let p = |tau: f64| -a / r * (tau / r).sin() + b * (tau / r).cos();
            let tau = first_exit(|t| inside_box(x(t)), 1e-3);
            let leaving = x(tau);
            let outward = {
                let q = (leaving - box_centre) / half;
                let i = q.abs().max_position();
                DVec3::select(DVec3::AXES[i].cmpeq(DVec3::ONE), q.signum(), DVec3::ZERO)
            };
            let d_out = snell(p(tau).normalize(), outward, n(leaving), 1.0);
            assert!(
                exit.point.distance(leaving) < 1e-9,
                "{} vs {leaving}",
                exit.point
            );
            assert!(
                exit.direction.distance(d_out) < 1e-9,
                "{} vs {d_out}",
                exit.direction
            );
            // ∫(2 − |x − c|²/R²) dτ, with ∫cos² = τ/2 + sin(2ω τ)/(4ω), ∫sin cos = sin²(ωτ)/(2ω).
            let w = 1.0 / r;
            let (s2, sc) = (
                (2.0 * w * tau).sin() / (4.0 * w),
                (w * tau).sin().powi(2) / (2.0 * w),
            );
            let squared = a.length_squared() * (0.5 * tau + s2)
                + r * r * b.length_squared() * (0.5 * tau - s2)
                + 2.0 * r * a.dot(b) * sc;
            let path = 2.0 * tau - squared / (r * r);
            assert!((exit.path - path).abs() < 1e-9, "{} vs {path}", exit.path);
            // The curve drawn: on the ellipse, in the plane of A and B, at (A·e) cos + ... :
            // each point x has x − c = A cos s + R B sin s for some s.
            assert!(curve.len() > 3);
            let normal = a.cross(b).normalize();
            for point in &curve {
                assert!((point - c).dot(normal).abs() < 1e-9);
                assert!(inside_box(*point));
            }
        }
    }

    /// A gradient-index rod (Dr TIM's cylindrical Luneburg profile, n² = 2 − ρ²/R² with ρ the
    /// distance from the axis): across the axis the ray oscillates harmonically, along it it
    /// runs uniformly in τ. A ray entering the rod's end leaves where that closed form first
    /// leaves the rod.
    #[test]
    fn a_gradient_index_rod_sends_rays_along_sinusoids() {
        let (start, end, rod) = (DVec3::ZERO, DVec3::new(0.0, 0.0, 3.0), 0.5);
        let shape = Shape::Cylinder(Cylinder::new(start, end, rod).unwrap());
        let r = 0.6;
        let law = GradientIndexVolume {
            index: IndexDistribution::Profiled(Profiled {
                about: Symmetry::Line {
                    point: DVec3::new(0.05, 0.0, 0.0),
                    axis: DVec3::Z,
                },
                radius: r,
                profile: IndexProfile::Luneburg,
                layer_separation: None,
            }),
            transmission_coefficient: 1.0,
        };
        let axis_point = DVec3::new(0.05, 0.0, 0.0);
        let across = |x: DVec3| (x - axis_point).reject_from_normalized(DVec3::Z);
        let n = |x: DVec3| (2.0 - across(x).length_squared() / (r * r)).sqrt();
        let inside_rod = |x: DVec3| x.z > 0.0 && x.z < 3.0 && x.truncate().length() < rod;
        for origin in [
            DVec3::new(0.2, 0.1, -1.0),
            DVec3::new(-0.3, 0.3, -2.0),
            DVec3::new(0.0, -0.1, -0.5),
        ] {
            let target = DVec3::new(0.1, 0.0, 0.0);
            let at = meet(&shape, origin, target - origin);
            let entry = at.point();
            let (exit, _) = crosses(law.redirect(&at, &mut |_| {}));
            let b = n(entry) * snell(at.ray.direction, at.normal(), 1.0, n(entry));
            let a = across(entry);
            let x = |tau: f64| {
                axis_point
                    + a * (tau / r).cos()
                    + r * b.reject_from_normalized(DVec3::Z) * (tau / r).sin()
                    + DVec3::Z * (entry.z + b.z * tau)
            };
            let tau = first_exit(|t| inside_rod(x(t)), 1e-3);
            assert!(
                exit.point.distance(x(tau)) < 1e-9,
                "{} vs {}",
                exit.point,
                x(tau)
            );
        }
    }

    /// A mirage: the half-space z > 5 with the planar Luneburg profile n² = 2 − s² about its
    /// surface (s = z − 5). In τ the height oscillates, s = p_s sin τ, so a ray entering at
    /// s = 0 comes back out at τ = π, having gone π p_x along x, where p_x = sin θᵢ (Snell:
    /// n sin θ is the tangential part of p); it leaves mirrored.
    #[test]
    fn a_planar_profile_in_a_half_space_turns_rays_back_as_a_mirage() {
        let shape = Shape::Plane(
            crate::geometry::Plane::new(DVec3::new(0.0, 0.0, 5.0), DVec3::NEG_Z, DVec3::X).unwrap(),
        );
        let law = GradientIndexVolume {
            index: IndexDistribution::Profiled(Profiled {
                about: Symmetry::Plane {
                    point: DVec3::new(0.0, 0.0, 5.0),
                    normal: DVec3::Z,
                },
                radius: 1.0,
                profile: IndexProfile::Luneburg,
                layer_separation: None,
            }),
            transmission_coefficient: 1.0,
        };
        let d = DVec3::new(0.5, 0.0, 1.0).normalize();
        let at = meet(&shape, DVec3::ZERO, d);
        let (exit, _) = crosses(law.redirect(&at, &mut |_| {}));
        let x = 2.5 + std::f64::consts::PI * d.x;
        assert!(
            exit.point.distance(DVec3::new(x, 0.0, 5.0)) < 1e-10,
            "{}",
            exit.point
        );
        assert!(exit.direction.distance(DVec3::new(d.x, 0.0, -d.z)) < 1e-10);
    }

    /// Grazing entries: a Luneburg profile filling its sphere focuses a parallel beam on the
    /// far pole (Eqs 5–6), also for rays entering within 10⁻⁸ to 10⁻¹³ of the rim, whose exit
    /// the event must find where the path leaves the surface at a graze.
    #[test]
    fn grazing_rays_through_a_luneburg_sphere_reach_its_pole() {
        let shape =
            Shape::Sphere(crate::geometry::Sphere::new(DVec3::new(0.0, 0.0, 5.0), 1.0).unwrap());
        let law = GradientIndexVolume {
            index: IndexDistribution::Profiled(Profiled {
                about: Symmetry::Point(DVec3::new(0.0, 0.0, 5.0)),
                radius: 1.0,
                profile: IndexProfile::Luneburg,
                layer_separation: None,
            }),
            transmission_coefficient: 1.0,
        };
        for epsilon in [1e-2, 1e-8, 1e-10, 1e-12, 1e-13] {
            let at = meet(&shape, DVec3::new(1.0 - epsilon, 0.0, 0.0), DVec3::Z);
            let (exit, _) = crosses(law.redirect(&at, &mut |_| {}));
            assert!(
                exit.point.distance(DVec3::new(0.0, 0.0, 6.0)) < 1e-7,
                "{epsilon}: {}",
                exit.point
            );
        }
    }

    /// Parallel layers keep a ray's tangential optical momentum n sin θ (Snell's law at each
    /// plane), so a ray through a slab of planar layers, in and out through faces parallel to
    /// them, leaves along the direction it came in: also where a face lies within a graze
    /// (5 × 10⁻⁸) outside a boundary, which counts as the face (this checks that the layer
    /// a ray enters is the one its index was taken from).
    #[test]
    fn parallel_layers_pass_rays_on_parallel() {
        let law = GradientIndexVolume {
            index: IndexDistribution::Profiled(Profiled {
                about: Symmetry::Plane {
                    point: DVec3::new(0.0, 0.0, 5.0),
                    normal: DVec3::Z,
                },
                radius: 1.0,
                profile: IndexProfile::Luneburg,
                layer_separation: Some(0.1),
            }),
            transmission_coefficient: 1.0,
        };
        for top in [6.0, 6.0 + 5e-8, 5.95] {
            let (bottom, size) = (5.05, DVec3::new(10.0, 10.0, top - 5.05));
            let centre = DVec3::new(0.0, 0.0, 0.5 * (top + bottom));
            let shape = Shape::Cuboid(Cuboid::new(centre, size).unwrap());
            for d in [
                DVec3::new(0.95, 0.0, -0.3122498999),
                DVec3::new(0.3, 0.2, -1.0),
                DVec3::new(0.6, 0.5, -0.4),
            ] {
                let at = meet(&shape, DVec3::new(-3.0, 0.0, 8.0), d);
                let (exit, _) = crosses(law.redirect(&at, &mut |_| {}));
                assert!(
                    exit.direction.distance(at.ray.direction) < 1e-12,
                    "top {top}, {d}: {}",
                    exit.direction
                );
            }
        }
    }

    /// Reflection between layers: in a slab z ∈ [5.05, 6.55] of planar Luneburg layers
    /// (separation 0.1 about z = 5), the layer above z = 6.4 has no real index (its middle
    /// lies beyond ρ = √2). A ray entering the bottom climbs through layers 0 to 13 keeping its
    /// tangential optical momentum p_t = sin θᵢ, is reflected there and comes down the same
    /// way: it leaves the bottom mirrored, 2 Σ h_k p_t/√(n_k² − p_t²) further along, with
    /// optical path 2 Σ h_k n_k²/√(n_k² − p_t²) (h_k the height crossed in layer k).
    #[test]
    fn a_layer_without_an_index_reflects() {
        let shape = Shape::Cuboid(
            Cuboid::new(DVec3::new(0.0, 0.0, 5.8), DVec3::new(20.0, 20.0, 1.5)).unwrap(),
        );
        let law = GradientIndexVolume {
            index: IndexDistribution::Profiled(Profiled {
                about: Symmetry::Plane {
                    point: DVec3::new(0.0, 0.0, 5.0),
                    normal: DVec3::Z,
                },
                radius: 1.0,
                profile: IndexProfile::Luneburg,
                layer_separation: Some(0.1),
            }),
            transmission_coefficient: 1.0,
        };
        let d = DVec3::new(0.2, 0.1, 1.0).normalize();
        let at = meet(&shape, DVec3::new(0.0, 0.0, 4.0), d);
        let mut reflections = Vec::new();
        let (exit, _) = crosses(law.redirect(&at, &mut |x| reflections.push(x)));
        let p_t = d.truncate().length();
        let (mut along, mut path) = (0.0, 0.0);
        for k in 0..14 {
            let h = if k == 0 { 0.05 } else { 0.1 };
            let n2 = 2.0 - ((k as f64 + 0.5) * 0.1).powi(2);
            let root = (n2 - p_t * p_t).sqrt();
            along += 2.0 * h * p_t / root;
            path += 2.0 * h * n2 / root;
        }
        let leaving = at.point() + along * d.truncate().normalize().extend(0.0);
        assert!(
            exit.point.distance(leaving) < 1e-12,
            "{} vs {leaving}",
            exit.point
        );
        assert!(exit.direction.distance(DVec3::new(d.x, d.y, -d.z)) < 1e-12);
        assert!((exit.path - path).abs() < 1e-12, "{} vs {path}", exit.path);
        // Every boundary twice, and the reflection at z = 6.4 once.
        assert_eq!(reflections.len(), 27);
        assert!(reflections.iter().any(|x| (x.z - 6.4).abs() < 1e-12));
    }

    /// A ray starting inside (a camera in the volume) is integrated from its start: along the
    /// ellipse from there, to where it leaves.
    #[test]
    fn rays_starting_inside_are_integrated_from_their_start() {
        let shape = Shape::Cuboid(Cuboid::new(DVec3::ZERO, DVec3::splat(2.0)).unwrap());
        let law = GradientIndexVolume {
            index: IndexDistribution::Profiled(Profiled {
                about: Symmetry::Point(DVec3::ZERO),
                radius: 1.0,
                profile: IndexProfile::Luneburg,
                layer_separation: None,
            }),
            transmission_coefficient: 1.0,
        };
        let origin = DVec3::new(0.2, -0.1, 0.3);
        let d = DVec3::new(0.3, 0.2, 1.0).normalize();
        let at = meet(&shape, origin, d);
        let (exit, _) = crosses(law.redirect(&at, &mut |_| {}));
        let b = (2.0 - origin.length_squared()).sqrt() * d;
        let x = |tau: f64| origin * tau.cos() + b * tau.sin();
        let tau = first_exit(|t| x(t).abs().max_element() < 1.0, 1e-3);
        assert!(exit.point.distance(x(tau)) < 1e-9, "{}", exit.point);
    }

    /// A constant index is a block of glass: straight chords, Snell's law at both faces, and
    /// inside reflection beyond the critical angle; the optical path is n times the chord.
    #[test]
    fn a_constant_index_refracts_as_glass() {
        let shape = Shape::Cuboid(Cuboid::new(DVec3::ZERO, DVec3::splat(2.0)).unwrap());
        let law = GradientIndexVolume {
            index: IndexDistribution::Constant(1.5),
            transmission_coefficient: 1.0,
        };
        let origin = DVec3::new(-0.5, 0.2, -3.0);
        let at = meet(&shape, origin, DVec3::new(0.3, 0.1, 1.0));
        let (exit, _) = crosses(law.redirect(&at, &mut |_| {}));
        let inside = snell(at.ray.direction, DVec3::NEG_Z, 1.0, 1.5);
        let chord = 2.0 / inside.z;
        let leaving = at.point() + chord * inside;
        assert!(exit.point.distance(leaving) < 1e-12);
        assert!(exit.direction.distance(at.ray.direction) < 1e-12);
        assert!((exit.path - 1.5 * chord).abs() < 1e-12);
        // Into the top face y = 1 at x = 0.5, 80° from its normal: inside at θ = asin(sin 80°
        // / 1.5) = 41.0°, it meets the side x = 1 at 49.0° from its normal, beyond the
        // critical angle (41.8°), and is reflected; it leaves through the bottom y = −1 at θ,
        // so at 80° again, mirrored in x.
        let (sin, cos) = (80f64.to_radians().sin(), 80f64.to_radians().cos());
        let grazing = DVec3::new(sin, -cos, 0.0);
        let at = meet(&shape, DVec3::new(0.5, 1.0, 0.1) - 3.0 * grazing, grazing);
        assert!(at.point().distance(DVec3::new(0.5, 1.0, 0.1)) < 1e-12);
        let mut reflections = Vec::new();
        let (exit, _) = crosses(law.redirect(&at, &mut |x| reflections.push(x)));
        let inside = DVec3::new(sin / 1.5, -(1.0 - (sin / 1.5).powi(2)).sqrt(), 0.0);
        let wall = DVec3::new(0.5, 1.0, 0.1) + 0.5 / inside.x * inside;
        let bottom = wall + (wall.y + 1.0) / -inside.y * DVec3::new(-inside.x, inside.y, 0.0);
        assert_eq!(reflections.len(), 1);
        assert!(reflections[0].distance(wall) < 1e-12, "{}", reflections[0]);
        assert!(exit.point.distance(bottom) < 1e-12, "{}", exit.point);
        assert!(exit.direction.distance(DVec3::new(-sin, -cos, 0.0)) < 1e-12);
        let chords = (0.5 / inside.x) + (wall.y + 1.0) / -inside.y;
        assert!((exit.path - 1.5 * chords).abs() < 1e-12);
    }
}
