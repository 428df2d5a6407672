//! Property tests of the curved shapes (cone, paraboloid, ellipsoid, spherical cap, elliptic
//! cylinder, open cylinder, tube), each built from a scene file, against an independent f64
//! reference written here (none of timbre's geometry is reused).
//!
//! # The reference
//!
//! A shape is a list of *pieces* (a cone's mantle and base, a tube's two mantles and two
//! annular ends). Each piece has a function F that is zero on its surface and positive on its
//! outward side, written differently from timbre's quadratics (a cone's mantle is
//! ρ cos α − z sin α, an ellipsoid |(p − c)/s| − 1), with a bound on its slope (Lipschitz
//! constant), and a *margin* that is positive where the piece is part of the shape (for a
//! closed convex solid, − the largest F of the other pieces; for an open one, the distance
//! from the rim along the axis or the sphere).
//!
//! Along a ray, F is sampled on 2048 intervals over the stretch inside a sphere around the
//! shape; a sign change is bisected to a crossing, and an interval without one is split
//! until the slope bound shows that F cannot reach zero in it (|F(a)| + |F(b)| > L |d| (b − a))
//! or it is shorter than 1e-11 of the shape's size (a *tangency*: the ray grazes the piece).
//! So no crossing is missed, however close two are, unless the ray is tangent.
//!
//! A crossing is *decisive* if it is more than 1e-6 (of the shape's size) inside its piece's
//! margin, the ray meets the surface at more than 1e-2 from grazing (|n̂·d̂| > 1e-2, with n̂ the
//! reference's normal from central differences of F), and it is not at t_min or t_max. Timbre
//! must report the first decisive crossing (to 1e-9 of the scale over |d| cos), and every hit
//! it reports must be a crossing of the reference, or a tangency, or on a rim. At decisive hits
//! the part must be the piece's and the frame's w its normal (to 1e-6), with the frame
//! orthonormal and right-handed.

mod common;

use std::f64::consts::PI;
use std::rc::Rc;

use glam::{DVec2, DVec3};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

use common::{config, log_uniform, point_in, unit_from, unit_vector};
use timbre::geometry::{
    Csg, CsgOperation, Ellipsoid, Plane, SceneGeometry, Shape, Sphere, Transform,
};
use timbre::math::Frame;
use timbre::scene::file;

// ---------------------------------------------------------------------------------------------
// The shapes' parameters, and the shapes built from them through scene files
// ---------------------------------------------------------------------------------------------

/// How a spherical cap's size is given.
#[derive(Debug, Clone, Copy)]
enum CapSize {
    Aperture(f64),
    AngleDeg(f64),
}

#[derive(Debug, Clone)]
enum Params {
    Cone {
        apex: DVec3,
        axis: DVec3,
        half_angle_deg: f64,
        height: f64,
        open: bool,
    },
    Paraboloid {
        vertex: DVec3,
        axis: DVec3,
        focal_length: f64,
        height: f64,
        open: bool,
    },
    Ellipsoid {
        centre: DVec3,
        semi_axes: DVec3,
    },
    Cap {
        sphere_centre: DVec3,
        cap_centre: DVec3,
        size: CapSize,
    },
    Elliptic {
        start: DVec3,
        end: DVec3,
        semi_axes: DVec2,
        a_direction: Option<DVec3>,
        open: bool,
    },
    OpenCylinder {
        start: DVec3,
        end: DVec3,
        radius: f64,
    },
    Tube {
        start: DVec3,
        end: DVec3,
        outer: f64,
        inner: f64,
    },
}

/// A TOML array.
fn arr(v: DVec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// Parses `text`, panicking with the error if it is rejected.
#[track_caller]
fn parse(text: &str) -> timbre::scene::SceneDescription {
    file::parse(text, "s.toml").unwrap_or_else(|e| panic!("{e}\nin:\n{text}"))
}

/// A scene with one object of shape `shape` (an inline table).
fn scene_with(shape: &str) -> String {
    format!(
        "studio = \"none\"\n[[object]]\nname = \"it\"\nshape = {shape}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
    )
}

impl Params {
    /// The shape's table in a scene file.
    fn table(&self) -> String {
        match self {
            Params::Cone {
                apex,
                axis,
                half_angle_deg,
                height,
                open,
            } => format!(
                "{{ type = \"cone\", apex = {}, axis = {}, half_angle_deg = {half_angle_deg}, height = {height}, open = {open} }}",
                arr(*apex),
                arr(*axis)
            ),
            Params::Paraboloid {
                vertex,
                axis,
                focal_length,
                height,
                open,
            } => format!(
                "{{ type = \"paraboloid\", vertex = {}, axis = {}, focal_length = {focal_length}, height = {height}, open = {open} }}",
                arr(*vertex),
                arr(*axis)
            ),
            Params::Ellipsoid { centre, semi_axes } => format!(
                "{{ type = \"ellipsoid\", centre = {}, semi_axes = {} }}",
                arr(*centre),
                arr(*semi_axes)
            ),
            Params::Cap {
                sphere_centre,
                cap_centre,
                size,
            } => {
                let size = match size {
                    CapSize::Aperture(r) => format!("aperture_radius = {r}"),
                    CapSize::AngleDeg(a) => format!("half_angle_deg = {a}"),
                };
                format!(
                    "{{ type = \"spherical-cap\", sphere_centre = {}, cap_centre = {}, {size} }}",
                    arr(*sphere_centre),
                    arr(*cap_centre)
                )
            }
            Params::Elliptic {
                start,
                end,
                semi_axes,
                a_direction,
                open,
            } => format!(
                "{{ type = \"elliptic-cylinder\", start = {}, end = {}, semi_axes = [{}, {}], {}open = {open} }}",
                arr(*start),
                arr(*end),
                semi_axes.x,
                semi_axes.y,
                a_direction.map_or(String::new(), |a| format!("a_direction = {}, ", arr(a)))
            ),
            Params::OpenCylinder { start, end, radius } => format!(
                "{{ type = \"cylinder\", start = {}, end = {}, radius = {radius}, open = true }}",
                arr(*start),
                arr(*end)
            ),
            Params::Tube {
                start,
                end,
                outer,
                inner,
            } => format!(
                "{{ type = \"tube\", start = {}, end = {}, outer_radius = {outer}, inner_radius = {inner} }}",
                arr(*start),
                arr(*end)
            ),
        }
    }

    /// The shape, as a scene file builds it.
    fn shape(&self) -> Shape {
        parse(&scene_with(&self.table())).objects[0].shape.clone()
    }

    fn is_solid(&self) -> bool {
        match self {
            Params::Cone { open, .. }
            | Params::Paraboloid { open, .. }
            | Params::Elliptic { open, .. } => !open,
            Params::Ellipsoid { .. } | Params::Tube { .. } => true,
            Params::Cap { .. } | Params::OpenCylinder { .. } => false,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The reference
// ---------------------------------------------------------------------------------------------

type Field = Rc<dyn Fn(DVec3) -> f64>;

fn field(f: impl Fn(DVec3) -> f64 + 'static) -> Field {
    Rc::new(f)
}

/// A piece of surface: F (zero on it, positive outwards), a bound on |∇F| near the shape, the
/// margin (positive on the piece), and the part timbre should report there.
#[derive(Clone)]
struct Piece {
    f: Field,
    lipschitz: f64,
    margin: Field,
    part: u32,
}

struct Reference {
    pieces: Vec<Piece>,
    /// A sphere around the shape.
    centre: DVec3,
    radius: f64,
    /// The shape's size, for tolerances.
    scale: f64,
}

/// The orthonormal basis of Duff et al. ("Building an orthonormal basis, revisited") for the
/// unit vector n, as docs/SCENE_FORMAT.md gives it for discs: (û, v̂) with û × v̂ = n.
fn disc_axes(n: DVec3) -> (DVec3, DVec3) {
    let s = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        DVec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// Coordinates of p about an axis through `origin` along the unit `axis`: distance along it
/// and distance from it.
fn along_and_from(origin: DVec3, axis: DVec3, p: DVec3) -> (f64, f64) {
    let q = p - origin;
    let z = q.dot(axis);
    (z, (q - z * axis).length())
}

/// Pieces of a solid whose inside is where all its constraints F are ≤ 0 (a convex solid, or a
/// tube), given with slope bounds and parts: each piece's margin is − the largest of the other
/// constraints.
fn from_constraints(constraints: Vec<(Field, f64, u32)>) -> Vec<Piece> {
    let all: Vec<Field> = constraints.iter().map(|c| c.0.clone()).collect();
    constraints
        .into_iter()
        .enumerate()
        .map(|(i, (f, lipschitz, part))| {
            let others: Vec<Field> = all
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, g)| g.clone())
                .collect();
            let margin =
                field(move |p: DVec3| others.iter().map(|g| -g(p)).fold(f64::INFINITY, f64::min));
            Piece {
                f,
                lipschitz,
                margin,
                part,
            }
        })
        .collect()
}

/// The constraints (F ≤ 0 inside, slope bound, part) of a closed shape: the pieces of its
/// surface, extended to the whole space.
fn constraints(params: &Params) -> Vec<(Field, f64, u32)> {
    match params.clone() {
        Params::Cone {
            apex,
            axis,
            half_angle_deg,
            height,
            ..
        } => {
            let a = axis.normalize();
            let (s, c) = half_angle_deg.to_radians().sin_cos();
            vec![
                (
                    field(move |p: DVec3| {
                        let (z, rho) = along_and_from(apex, a, p);
                        rho * c - z * s
                    }),
                    1.0,
                    0,
                ),
                (field(move |p: DVec3| (p - apex).dot(a) - height), 1.0, 1),
            ]
        }
        Params::Paraboloid {
            vertex,
            axis,
            focal_length: f,
            height,
            ..
        } => {
            let a = axis.normalize();
            // Near the shape (within 4 times its size of the vertex) ρ is at most that.
            let reach = 4.0 * (height + 2.0 * (f * height).sqrt());
            vec![
                (
                    field(move |p: DVec3| {
                        let (z, rho) = along_and_from(vertex, a, p);
                        rho * rho / (4.0 * f) - z
                    }),
                    (1.0 + (reach / (2.0 * f)).powi(2)).sqrt(),
                    0,
                ),
                (field(move |p: DVec3| (p - vertex).dot(a) - height), 1.0, 1),
            ]
        }
        Params::Ellipsoid { centre, semi_axes } => vec![(
            field(move |p: DVec3| ((p - centre) / semi_axes).length() - 1.0),
            1.0 / semi_axes.min_element(),
            0,
        )],
        Params::Elliptic {
            start,
            end,
            semi_axes,
            a_direction,
            ..
        } => {
            let length = (end - start).length();
            let h = (end - start) / length;
            let ua = match a_direction {
                Some(a) => (a - a.dot(h) * h).normalize(),
                None => disc_axes(h).0,
            };
            let ub = h.cross(ua);
            vec![
                (
                    field(move |p: DVec3| {
                        let q = p - start;
                        DVec2::new(q.dot(ua) / semi_axes.x, q.dot(ub) / semi_axes.y).length() - 1.0
                    }),
                    1.0 / semi_axes.min_element(),
                    0,
                ),
                (field(move |p: DVec3| -(p - start).dot(h)), 1.0, 1),
                (field(move |p: DVec3| (p - start).dot(h) - length), 1.0, 2),
            ]
        }
        Params::Tube {
            start,
            end,
            outer,
            inner,
        } => {
            let length = (end - start).length();
            let h = (end - start) / length;
            vec![
                (
                    field(move |p: DVec3| along_and_from(start, h, p).1 - outer),
                    1.0,
                    0,
                ),
                (
                    field(move |p: DVec3| inner - along_and_from(start, h, p).1),
                    1.0,
                    1 << 16,
                ),
                (field(move |p: DVec3| -(p - start).dot(h)), 1.0, 0),
                (field(move |p: DVec3| (p - start).dot(h) - length), 1.0, 0),
            ]
        }
        Params::Cap { .. } | Params::OpenCylinder { .. } => unreachable!("open shapes"),
    }
}

impl Params {
    fn reference(&self) -> Reference {
        let (centre, radius, scale) = self.bounding_sphere();
        let pieces = match self.clone() {
            Params::Cone {
                apex,
                axis,
                height,
                open: true,
                ..
            } => {
                let a = axis.normalize();
                let mantle = constraints(self).swap_remove(0);
                vec![Piece {
                    f: mantle.0,
                    lipschitz: 1.0,
                    margin: field(move |p: DVec3| {
                        let z = (p - apex).dot(a);
                        z.min(height - z)
                    }),
                    part: 0,
                }]
            }
            Params::Paraboloid {
                vertex,
                axis,
                height,
                open: true,
                ..
            } => {
                let a = axis.normalize();
                let mantle = constraints(self).swap_remove(0);
                vec![Piece {
                    f: mantle.0,
                    lipschitz: mantle.1,
                    margin: field(move |p: DVec3| height - (p - vertex).dot(a)),
                    part: 0,
                }]
            }
            Params::Elliptic {
                start,
                end,
                open: true,
                ..
            } => {
                let (length, h) = ((end - start).length(), (end - start).normalize());
                let mantle = constraints(self).swap_remove(0);
                vec![Piece {
                    f: mantle.0,
                    lipschitz: mantle.1,
                    margin: field(move |p: DVec3| {
                        let z = (p - start).dot(h);
                        z.min(length - z)
                    }),
                    part: 0,
                }]
            }
            Params::OpenCylinder { start, end, radius } => {
                let (length, h) = ((end - start).length(), (end - start).normalize());
                vec![Piece {
                    f: field(move |p: DVec3| along_and_from(start, h, p).1 - radius),
                    lipschitz: 1.0,
                    margin: field(move |p: DVec3| {
                        let z = (p - start).dot(h);
                        z.min(length - z)
                    }),
                    part: 0,
                }]
            }
            Params::Cap {
                sphere_centre,
                cap_centre,
                size,
            } => {
                let r = (cap_centre - sphere_centre).length();
                let n = (cap_centre - sphere_centre) / r;
                // The rim's plane: at R cos θ₀ from the centre, or (R² − a²)^½ for aperture a.
                let rim = match size {
                    CapSize::Aperture(a) => (r * r - a * a).sqrt(),
                    CapSize::AngleDeg(angle) => r * angle.to_radians().cos(),
                };
                vec![Piece {
                    f: field(move |p: DVec3| (p - sphere_centre).length() - r),
                    lipschitz: 1.0,
                    margin: field(move |p: DVec3| (p - sphere_centre).dot(n) - rim),
                    part: 0,
                }]
            }
            _ => from_constraints(constraints(self)),
        };
        Reference {
            pieces,
            centre,
            radius,
            scale,
        }
    }

    /// A sphere around the shape (centre, radius), and the shape's size.
    fn bounding_sphere(&self) -> (DVec3, f64, f64) {
        let (centre, radius) = match *self {
            Params::Cone {
                apex,
                axis,
                half_angle_deg,
                height,
                ..
            } => {
                let r = height * half_angle_deg.to_radians().tan();
                (
                    apex + 0.5 * height * axis.normalize(),
                    (0.25 * height * height + r * r).sqrt(),
                )
            }
            Params::Paraboloid {
                vertex,
                axis,
                focal_length,
                height,
                ..
            } => (
                vertex + 0.5 * height * axis.normalize(),
                (0.25 * height * height + 4.0 * focal_length * height).sqrt(),
            ),
            Params::Ellipsoid { centre, semi_axes } => (centre, semi_axes.max_element()),
            Params::Cap {
                sphere_centre,
                cap_centre,
                ..
            } => (sphere_centre, (cap_centre - sphere_centre).length()),
            Params::Elliptic {
                start,
                end,
                semi_axes,
                ..
            } => (
                0.5 * (start + end),
                (0.25 * (end - start).length_squared() + semi_axes.max_element().powi(2)).sqrt(),
            ),
            Params::OpenCylinder { start, end, radius }
            | Params::Tube {
                start,
                end,
                outer: radius,
                ..
            } => (
                0.5 * (start + end),
                (0.25 * (end - start).length_squared() + radius * radius).sqrt(),
            ),
        };
        (centre, 1.01 * radius + 1e-9, radius)
    }
}

/// A crossing found by the reference.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    t: f64,
    part: u32,
    margin: f64,
    /// |n̂·d̂|: 1 head-on, 0 grazing.
    cos: f64,
    normal: DVec3,
}

/// What the reference finds along a ray.
#[derive(Debug, Default)]
struct Found {
    crossings: Vec<Crossing>,
    /// Where the ray is tangent to a piece (within 1e-11 of the shape's size).
    tangencies: Vec<f64>,
}

/// The normalised gradient of f at p by central differences with step h.
fn gradient(f: &Field, p: DVec3, h: f64) -> DVec3 {
    let g = DVec3::new(
        f(p + h * DVec3::X) - f(p - h * DVec3::X),
        f(p + h * DVec3::Y) - f(p - h * DVec3::Y),
        f(p + h * DVec3::Z) - f(p - h * DVec3::Z),
    );
    g.normalize_or_zero()
}

impl Reference {
    /// The t where the line o + t d is inside the bounding sphere (textbook quadratic: the
    /// sphere is a generous one, so precision does not matter).
    fn window(&self, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
        let oc = o - self.centre;
        let (a, b, c) = (
            d.length_squared(),
            oc.dot(d),
            oc.length_squared() - self.radius * self.radius,
        );
        let disc = b * b - a * c;
        (disc > 0.0).then(|| ((-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a))
    }

    /// Every crossing of every piece's surface (on the piece or not) in (lo, hi), and the
    /// tangencies.
    fn find(&self, o: DVec3, d: DVec3, lo: f64, hi: f64) -> Found {
        let mut found = Found::default();
        let Some((w0, w1)) = self.window(o, d) else {
            return found;
        };
        let (lo, hi) = (lo.max(w0), hi.min(w1));
        if lo >= hi {
            return found;
        }
        const N: usize = 2048;
        for piece in &self.pieces {
            let f = |t: f64| (piece.f)(o + t * d);
            let ts: Vec<f64> = (0..=N)
                .map(|i| lo + (hi - lo) * i as f64 / N as f64)
                .collect();
            let fs: Vec<f64> = ts.iter().map(|&t| f(t)).collect();
            for i in 0..N {
                self.search(
                    piece,
                    o,
                    d,
                    (ts[i], fs[i]),
                    (ts[i + 1], fs[i + 1]),
                    &mut found,
                );
            }
        }
        found.crossings.sort_by(|a, b| a.t.total_cmp(&b.t));
        found
    }

    /// The crossings of `piece` between a and b (with F's values there).
    fn search(
        &self,
        piece: &Piece,
        o: DVec3,
        d: DVec3,
        (a, fa): (f64, f64),
        (b, fb): (f64, f64),
        found: &mut Found,
    ) {
        let f = |t: f64| (piece.f)(o + t * d);
        let step = d.length() * (b - a);
        if (fa > 0.0) != (fb > 0.0) {
            let (mut x, mut y) = (a, b);
            for _ in 0..200 {
                let m = 0.5 * (x + y);
                if m <= x || m >= y {
                    break;
                }
                if (f(m) > 0.0) == (fa > 0.0) {
                    x = m;
                } else {
                    y = m;
                }
            }
            let t = 0.5 * (x + y);
            let p = o + t * d;
            let normal = gradient(&piece.f, p, 1e-6 * self.scale);
            found.crossings.push(Crossing {
                t,
                part: piece.part,
                margin: (piece.margin)(p),
                cos: normal.dot(d.normalize()).abs(),
                normal,
            });
        } else if fa.abs() + fb.abs() <= 1.0001 * piece.lipschitz * step {
            if step < 1e-11 * self.scale {
                found.tangencies.push(0.5 * (a + b));
                return;
            }
            let m = 0.5 * (a + b);
            let fm = f(m);
            self.search(piece, o, d, (a, fa), (m, fm), found);
            self.search(piece, o, d, (m, fm), (b, fb), found);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Checking a shape against the reference
// ---------------------------------------------------------------------------------------------

#[derive(Debug, Clone)]
struct Case {
    params: Params,
    origin: DVec3,
    direction: DVec3,
    t_min: f64,
    t_max: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    /// A decisive hit, or a miss with no crossing near the shape.
    Decisive,
    /// A grazing ray, a rim, or a crossing at t_min or t_max.
    Marginal,
}

/// Margin below which a crossing is at a rim (times the scale).
const RIM: f64 = 1e-6;
/// |n̂·d̂| below which a crossing is grazing.
const GRAZING: f64 = 1e-2;

fn check_frame(f: &Frame, normal: DVec3) -> Result<(), String> {
    let unit = |v: DVec3| (v.length() - 1.0).abs() < 1e-12;
    if !(unit(f.u) && unit(f.v) && unit(f.w)) {
        return Err(format!("frame not unit: {f:?}"));
    }
    if f.u.dot(f.v).abs() > 1e-12 || f.u.dot(f.w).abs() > 1e-12 || f.v.dot(f.w).abs() > 1e-12 {
        return Err(format!("frame not orthogonal: {f:?}"));
    }
    if (f.u.cross(f.v) - f.w).length() > 1e-12 {
        return Err(format!("frame not right-handed: {f:?}"));
    }
    if (f.w - normal).length() > 1e-6 {
        return Err(format!(
            "normal {} differs from the reference's {normal}",
            f.w
        ));
    }
    Ok(())
}

/// Compares `shape`'s nearest hit with the reference's crossings.
fn check_hit(shape: &Shape, reference: &Reference, case: &Case) -> Result<Outcome, String> {
    let (o, d) = (case.origin, case.direction);
    let (t_min, t_max) = (case.t_min, case.t_max);
    let scale = reference.scale;
    let found = reference.find(o, d, t_min, t_max);
    let tol =
        |cos: f64| 1e-9 * (scale + (o - reference.centre).length()) / (d.length() * cos.max(1e-3));
    let at_ends = |c: &Crossing| c.t - t_min <= tol(c.cos) || t_max - c.t <= tol(c.cos);
    let decisive = |c: &Crossing| c.margin > RIM * scale && c.cos > GRAZING && !at_ends(c);
    let on_shape: Vec<&Crossing> = found
        .crossings
        .iter()
        .filter(|c| c.margin >= -RIM * scale)
        .collect();
    let first = on_shape.iter().find(|c| decisive(c));
    match shape.intersect(o, d, t_min, t_max) {
        None => match first {
            Some(c) => Err(format!("missed the crossing {c:?}")),
            None if on_shape.is_empty() && found.tangencies.is_empty() => Ok(Outcome::Decisive),
            None => Ok(Outcome::Marginal),
        },
        Some((t, part)) => {
            if !(t > t_min && t < t_max) {
                return Err(format!("hit at {t} outside ({t_min}, {t_max})"));
            }
            if let Some(c) = first
                && t > c.t + tol(c.cos)
            {
                return Err(format!("hit at {t} beyond the crossing {c:?}"));
            }
            let matched = on_shape.iter().find(|c| (c.t - t).abs() <= tol(c.cos));
            match matched {
                Some(c) if decisive(c) => {
                    if part != c.part {
                        return Err(format!("hit at {t} reports part {part}, not {}", c.part));
                    }
                    check_frame(&shape.frame(o + t * d, part), c.normal)
                        .map_err(|e| format!("hit at {t} ({c:?}): {e}"))?;
                    Ok(Outcome::Decisive)
                }
                Some(_) => Ok(Outcome::Marginal),
                None if found
                    .tangencies
                    .iter()
                    .any(|&g| (g - t).abs() <= 1e-6 * (1.0 + t.abs())) =>
                {
                    Ok(Outcome::Marginal)
                }
                None => {
                    // Not a crossing of the reference: only a rim (where a piece ends at
                    // another, or an open shape's edge) may differ by rounding.
                    let p = o + t * d;
                    let rim = reference.pieces.iter().any(|piece| {
                        (piece.f)(p).abs() <= 1e-9 * piece.lipschitz * scale
                            && (piece.margin)(p).abs() <= RIM * scale
                    });
                    if rim {
                        Ok(Outcome::Marginal)
                    } else {
                        Err(format!(
                            "hit at {t} (part {part}) where the reference has no crossing; it has {:?}",
                            found.crossings
                        ))
                    }
                }
            }
        }
    }
}

fn run_case(case: &Case) -> Result<Outcome, String> {
    check_hit(&case.params.shape(), &case.params.reference(), case)
}

// ---------------------------------------------------------------------------------------------
// Random shapes and rays
// ---------------------------------------------------------------------------------------------

fn cone() -> impl Strategy<Value = Params> {
    (
        point_in(3.0),
        unit_vector(),
        5.0..80.0f64,
        log_uniform(0.1, 3.0),
        any::<bool>(),
        log_uniform(0.2, 5.0),
    )
        .prop_map(|(apex, a, half_angle_deg, height, open, l)| Params::Cone {
            apex,
            axis: a * l,
            half_angle_deg,
            height,
            open,
        })
}

fn paraboloid() -> impl Strategy<Value = Params> {
    (
        point_in(3.0),
        unit_vector(),
        log_uniform(0.05, 2.0),
        log_uniform(0.1, 3.0),
        any::<bool>(),
        log_uniform(0.2, 5.0),
    )
        .prop_map(
            |(vertex, a, focal_length, height, open, l)| Params::Paraboloid {
                vertex,
                axis: a * l,
                focal_length,
                height,
                open,
            },
        )
}

fn ellipsoid() -> impl Strategy<Value = Params> {
    (
        point_in(3.0),
        log_uniform(0.1, 3.0),
        log_uniform(0.1, 3.0),
        log_uniform(0.1, 3.0),
    )
        .prop_map(|(centre, a, b, c)| Params::Ellipsoid {
            centre,
            semi_axes: DVec3::new(a, b, c),
        })
}

fn cap() -> impl Strategy<Value = Params> {
    (
        point_in(3.0),
        unit_vector(),
        log_uniform(0.1, 3.0),
        any::<bool>(),
        0.05..1.0f64,
        1.0..179.0f64,
    )
        .prop_map(|(centre, n, r, by_aperture, fraction, angle)| Params::Cap {
            sphere_centre: centre,
            cap_centre: centre + r * n,
            size: if by_aperture {
                CapSize::Aperture(fraction * r)
            } else {
                CapSize::AngleDeg(angle)
            },
        })
}

fn elliptic() -> impl Strategy<Value = Params> {
    (
        point_in(3.0),
        unit_vector(),
        log_uniform(0.1, 4.0),
        log_uniform(0.05, 2.0),
        log_uniform(0.05, 2.0),
        prop::option::of(unit_vector()),
        any::<bool>(),
    )
        .prop_filter_map(
            "a_direction along the axis",
            |(start, h, length, a, b, a_direction, open)| {
                if a_direction.is_some_and(|u| u.cross(h).length() < 0.05) {
                    return None;
                }
                Some(Params::Elliptic {
                    start,
                    end: start + length * h,
                    semi_axes: DVec2::new(a, b),
                    a_direction,
                    open,
                })
            },
        )
}

fn open_cylinder() -> impl Strategy<Value = Params> {
    (
        point_in(3.0),
        unit_vector(),
        log_uniform(0.1, 4.0),
        log_uniform(0.05, 2.0),
    )
        .prop_map(|(start, h, length, radius)| Params::OpenCylinder {
            start,
            end: start + length * h,
            radius,
        })
}

fn tube() -> impl Strategy<Value = Params> {
    (
        point_in(3.0),
        unit_vector(),
        log_uniform(0.1, 4.0),
        log_uniform(0.05, 2.0),
        0.1..0.9f64,
    )
        .prop_map(|(start, h, length, outer, fraction)| Params::Tube {
            start,
            end: start + length * h,
            outer,
            inner: fraction * outer,
        })
}

/// A ray for `params` from twelve uniform numbers: from within four sizes of the shape aimed
/// at a point within half its bounding sphere's radius of that sphere's centre (a spherical
/// cap's: of the midpoint of its sphere's centre and its pole) (modes 0 and 1),
/// from inside that sphere in any direction (2), or from anywhere near in any direction (3);
/// the direction of length 0.1 to 10; t_min 0 or a random distance, t_max ∞ or a random one.
fn make_case(params: Params, mode: u8, u: [f64; 12]) -> Case {
    let (centre, radius, _) = params.bounding_sphere();
    let inside = |a: f64, b: f64, c: f64| centre + radius * c.cbrt() * unit_from(a, b);
    let (origin, direction) = match mode {
        0 | 1 => {
            let origin = centre + 4.0 * radius * unit_from(u[0], u[1]) * (0.3 + u[2]);
            // A cap's rays are aimed at the cap's side of its sphere.
            let middle = match params {
                Params::Cap {
                    sphere_centre,
                    cap_centre,
                    ..
                } => 0.5 * (sphere_centre + cap_centre),
                _ => centre,
            };
            let aim = middle + 0.5 * radius * u[5].cbrt() * unit_from(u[3], u[4]);
            (origin, aim - origin)
        }
        2 => (inside(u[0], u[1], u[2]), unit_from(u[3], u[4])),
        _ => (
            centre + 4.0 * radius * unit_from(u[0], u[1]) * u[2],
            unit_from(u[3], u[4]),
        ),
    };
    let length = (0.1f64.ln() + u[6] * 100f64.ln()).exp();
    let direction = direction.normalize() * length;
    let reach = 8.0 * radius / length;
    let t_min = if u[7] < 0.7 { 0.0 } else { u[8] * reach };
    let t_max = if u[9] < 0.7 {
        f64::INFINITY
    } else {
        t_min + u[10] * reach
    };
    Case {
        params,
        origin,
        direction,
        t_min,
        t_max,
    }
}

fn cases(params: impl Strategy<Value = Params>) -> impl Strategy<Value = Case> {
    (params, 0..4u8, prop::array::uniform12(0.0..1.0f64))
        .prop_map(|(p, mode, u)| make_case(p, mode, u))
}

proptest! {
    #![proptest_config(config(512))]

    #[test]
    fn cones_match_the_reference(case in cases(cone())) {
        run_case(&case).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn paraboloids_match_the_reference(case in cases(paraboloid())) {
        run_case(&case).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn ellipsoids_match_the_reference(case in cases(ellipsoid())) {
        run_case(&case).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn spherical_caps_match_the_reference(case in cases(cap())) {
        run_case(&case).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn elliptic_cylinders_match_the_reference(case in cases(elliptic())) {
        run_case(&case).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn open_cylinders_match_the_reference(case in cases(open_cylinder())) {
        run_case(&case).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn tubes_match_the_reference(case in cases(tube())) {
        run_case(&case).map_err(TestCaseError::fail)?;
    }
}

/// Draws `n` cases from `strategy` with a fixed seed.
fn draw(strategy: impl Strategy<Value = Case>, n: usize) -> Vec<Case> {
    let mut runner = TestRunner::deterministic();
    (0..n)
        .map(|_| strategy.new_tree(&mut runner).unwrap().current())
        .collect()
}

#[allow(clippy::type_complexity)]
fn all_strategies() -> Vec<(&'static str, BoxedStrategy<Case>)> {
    vec![
        ("cone", cases(cone()).boxed()),
        ("paraboloid", cases(paraboloid()).boxed()),
        ("ellipsoid", cases(ellipsoid()).boxed()),
        ("spherical cap", cases(cap()).boxed()),
        ("elliptic cylinder", cases(elliptic()).boxed()),
        ("open cylinder", cases(open_cylinder()).boxed()),
        ("tube", cases(tube()).boxed()),
    ]
}

/// The property tests would pass vacuously if every case were marginal (or a miss): most random
/// cases must be decisive, and a good share of them hits.
#[test]
fn random_cases_are_mostly_decisive_and_often_hit() {
    for (name, strategy) in all_strategies() {
        let cases = draw(strategy, 300);
        let mut decisive = 0;
        let mut hits = 0;
        for case in &cases {
            let outcome = run_case(case).unwrap_or_else(|e| panic!("{name}: {e}\n{case:?}"));
            decisive += usize::from(outcome == Outcome::Decisive);
            let shape = case.params.shape();
            hits += usize::from(
                shape
                    .intersect(case.origin, case.direction, case.t_min, case.t_max)
                    .is_some(),
            );
        }
        eprintln!("{name}: {decisive} decisive, {hits} hits");
        assert!(decisive >= 290, "{name}: only {decisive} of 300 decisive");
        assert!(hits >= 60, "{name}: only {hits} of 300 hit");
    }
}

/// The checks reject shapes whose size is off by one part in a million: the reference is
/// built from the true parameters, the shape from slightly wrong ones.
#[test]
fn checks_reject_slightly_wrong_shapes() {
    let grow = 1.0 + 1e-6;
    for (name, strategy) in all_strategies() {
        let cases = draw(strategy, 200);
        let rejected = cases
            .iter()
            .filter(|case| {
                let wrong = match case.params.clone() {
                    Params::Cone {
                        apex,
                        axis,
                        half_angle_deg,
                        height,
                        open,
                    } => Params::Cone {
                        apex,
                        axis,
                        half_angle_deg: half_angle_deg * grow,
                        height,
                        open,
                    },
                    Params::Paraboloid {
                        vertex,
                        axis,
                        focal_length,
                        height,
                        open,
                    } => Params::Paraboloid {
                        vertex,
                        axis,
                        focal_length: focal_length * grow,
                        height,
                        open,
                    },
                    Params::Ellipsoid { centre, semi_axes } => Params::Ellipsoid {
                        centre,
                        semi_axes: semi_axes * DVec3::new(grow, 1.0, 1.0),
                    },
                    Params::Cap {
                        sphere_centre,
                        cap_centre,
                        size,
                    } => Params::Cap {
                        sphere_centre,
                        cap_centre: sphere_centre + (cap_centre - sphere_centre) * grow,
                        size,
                    },
                    Params::Elliptic {
                        start,
                        end,
                        semi_axes,
                        a_direction,
                        open,
                    } => Params::Elliptic {
                        start,
                        end,
                        semi_axes: semi_axes * DVec2::new(1.0, grow),
                        a_direction,
                        open,
                    },
                    Params::OpenCylinder { start, end, radius } => Params::OpenCylinder {
                        start,
                        end,
                        radius: radius * grow,
                    },
                    Params::Tube {
                        start,
                        end,
                        outer,
                        inner,
                    } => Params::Tube {
                        start,
                        end,
                        outer: outer * grow,
                        inner: inner * grow,
                    },
                };
                check_hit(&wrong.shape(), &case.params.reference(), case).is_err()
            })
            .count();
        eprintln!("{name}: {rejected} rejected");
        assert!(
            rejected >= 20,
            "{name}: only {rejected} of 200 cases notice a size wrong by 1e-6"
        );
    }
}

proptest! {
    #![proptest_config(config(256))]

    /// Seen from 10³ to 10⁵ times its size away, a shape's hit points are still within
    /// 1e-13 of that distance of its surface: the quadratics are solved about the line's point
    /// nearest the shape (the textbook formula loses about (distance / size)² ε).
    #[test]
    fn hits_from_afar_are_backward_accurate(
        params in any_shape(),
        far in log_uniform(1e3, 1e5),
        u in prop::array::uniform12(0.0..1.0f64),
    ) {
        let (centre, radius, scale) = params.bounding_sphere();
        let reference = params.reference();
        let aim = centre + 0.5 * radius * u[2].cbrt() * unit_from(u[0], u[1]);
        let origin = aim + far * scale * unit_from(u[3], u[4]);
        let direction = (aim - origin).normalize() * (0.5 + u[5]);
        let shape = params.shape();
        if let Some((t, part)) = shape.intersect(origin, direction, 0.0, f64::INFINITY) {
            let p = origin + t * direction;
            let off = reference
                .pieces
                .iter()
                .filter(|piece| (piece.margin)(p) >= -1e-9 * far * scale)
                .map(|piece| (piece.f)(p).abs() / piece.lipschitz)
                .fold(f64::INFINITY, f64::min);
            prop_assert!(off <= 1e-13 * far * scale, "hit (part {}) {} off the surface, {} away", part, off, far * scale);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Solids: contains and chord
// ---------------------------------------------------------------------------------------------

/// The reference's inside margin of a closed shape: − the largest constraint.
fn inside_margin(params: &Params, p: DVec3) -> f64 {
    constraints(params)
        .iter()
        .map(|(f, _, _)| -f(p))
        .fold(f64::INFINITY, f64::min)
}

/// Whether `shape` (a convex solid or a CSG shape) says p is inside.
fn contains(shape: &Shape, p: DVec3) -> bool {
    match shape {
        Shape::Csg(c) => c.contains(p),
        other => other
            .analytic_solid()
            .expect("a closed shape is a solid")
            .contains(p),
    }
}

fn closed(strategy: impl Strategy<Value = Params>) -> impl Strategy<Value = Params> {
    strategy.prop_filter("closed", Params::is_solid)
}

fn any_closed() -> impl Strategy<Value = Params> {
    prop_oneof![
        closed(cone()),
        closed(paraboloid()),
        ellipsoid(),
        closed(elliptic()),
        tube(),
    ]
}

proptest! {
    #![proptest_config(config(128))]

    /// `contains` agrees with the implicit inequalities, away from the surface.
    #[test]
    fn contains_agrees_with_the_inequalities(params in any_closed(), u in prop::array::uniform12(0.0..1.0f64)) {
        let shape = params.shape();
        let (centre, radius, scale) = params.bounding_sphere();
        prop_assert!(shape.is_solid());
        for k in 0..4 {
            let p = centre + 1.2 * radius * u[3 * k].cbrt() * unit_from(u[3 * k + 1], u[3 * k + 2]);
            let m = inside_margin(&params, p);
            if m.abs() > 1e-9 * scale {
                prop_assert_eq!(contains(&shape, p), m > 0.0, "at {} (margin {})", p, m);
            }
        }
    }

    /// A convex solid's chord has the first and last crossings of the whole line as its ends,
    /// with their parts, and `intersect` finds them.
    #[test]
    fn chords_end_at_the_crossings(case in cases(prop_oneof![closed(cone()), closed(paraboloid()), ellipsoid(), closed(elliptic())])) {
        let (o, d) = (case.origin, case.direction);
        let shape = case.params.shape();
        let reference = case.params.reference();
        let found = reference.find(o, d, f64::NEG_INFINITY, f64::INFINITY);
        let on: Vec<&Crossing> = found.crossings.iter().filter(|c| c.margin >= -RIM * reference.scale).collect();
        let clean = on.iter().all(|c| c.margin > RIM * reference.scale && c.cos > GRAZING) && found.tangencies.is_empty();
        let chord = shape.analytic_solid().unwrap().chord(o, d);
        if !clean {
            return Ok(());
        }
        let tol = |c: &Crossing| 1e-9 * (reference.scale + (o - reference.centre).length()) / (d.length() * c.cos);
        match (chord, on.first(), on.last()) {
            (None, None, _) => {}
            (Some(span), Some(first), Some(last)) => {
                prop_assert!(on.len() == 2, "a convex solid is crossed twice: {:?}", on);
                prop_assert!((span.enter.0 - first.t).abs() <= tol(first) && span.enter.1 == first.part, "{:?} vs {:?}", span, first);
                prop_assert!((span.exit.0 - last.t).abs() <= tol(last) && span.exit.1 == last.part, "{:?} vs {:?}", span, last);
                prop_assert_eq!(shape.intersect(o, d, f64::NEG_INFINITY, f64::INFINITY), Some(span.enter));
                prop_assert_eq!(shape.intersect(o, d, span.enter.0, f64::INFINITY), Some(span.exit));
                let mid = o + 0.5 * (span.enter.0 + span.exit.0) * d;
                prop_assert!(contains(&shape, mid));
            }
            (chord, _, _) => prop_assert!(false, "chord {:?}, crossings {:?}", chord, on),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Constructive solid geometry with the closed shapes
// ---------------------------------------------------------------------------------------------

/// A closed shape cut by the half-space behind a plane through a point near its middle.
#[derive(Debug, Clone)]
struct Cut {
    params: Params,
    point: DVec3,
    normal: DVec3,
}

fn cut_cases() -> impl Strategy<Value = (Cut, Case)> {
    (
        any_closed(),
        unit_vector(),
        unit_vector(),
        0.0..0.5f64,
        0..3u8,
        prop::array::uniform12(0.0..1.0f64),
    )
        .prop_map(|(params, off, normal, k, mode, u)| {
            let (centre, radius, _) = params.bounding_sphere();
            let cut = Cut {
                params: params.clone(),
                point: centre + k * radius * off,
                normal,
            };
            (cut, make_case(params, mode, u))
        })
}

impl Cut {
    fn shape(&self) -> Shape {
        let plane = Plane::new(self.point, self.normal, self.normal.any_orthogonal_vector());
        Shape::Csg(
            Csg::new(
                CsgOperation::Intersection,
                vec![self.params.shape(), Shape::Plane(plane.unwrap())],
            )
            .unwrap(),
        )
    }

    /// The shape's constraints and the plane's (the plane is the CSG's last leaf).
    fn reference(&self) -> Reference {
        let (centre, radius, scale) = self.params.bounding_sphere();
        let mut all = constraints(&self.params);
        let leaf = if matches!(self.params, Params::Tube { .. }) {
            2
        } else {
            1
        };
        let (point, normal) = (self.point, self.normal);
        all.push((
            field(move |p: DVec3| (p - point).dot(normal)),
            1.0,
            leaf << 16,
        ));
        Reference {
            pieces: from_constraints(all),
            centre,
            radius,
            scale,
        }
    }
}

proptest! {
    #![proptest_config(config(192))]

    /// Each closed shape cut by a plane: hits match the reference, and the inside changes
    /// across each decisive hit as `Csg::contains` says.
    #[test]
    fn closed_shapes_cut_by_a_plane_match_the_reference((cut, case) in cut_cases()) {
        let shape = cut.shape();
        let reference = cut.reference();
        let outcome = check_hit(&shape, &reference, &case).map_err(TestCaseError::fail)?;
        if outcome == Outcome::Decisive
            && let Some((t, _)) = shape.intersect(case.origin, case.direction, case.t_min, case.t_max)
        {
            let delta = 1e-6 * reference.scale / case.direction.length();
            let at = |t: f64| case.origin + t * case.direction;
            let (before, after) = (contains(&shape, at(t - delta)), contains(&shape, at(t + delta)));
            prop_assert!(before != after, "inside before and after the hit at {}: {}", t, before);
            let inside = |p: DVec3| inside_margin(&cut.params, p).min(-(p - cut.point).dot(cut.normal));
            prop_assert_eq!(after, inside(at(t + delta)) > 0.0);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Ellipsoids and scaled spheres
// ---------------------------------------------------------------------------------------------

/// The nearest hits of two shapes agree: both miss, or both hit at distances within 1e-9
/// relative with normals within 1e-9, unless the ray grazes (|n̂·d̂| < 1e-3, where one may miss).
fn same_hits(a: &Shape, b: &Shape, o: DVec3, d: DVec3) -> Result<(), String> {
    let (ha, hb) = (
        a.intersect(o, d, 0.0, f64::INFINITY),
        b.intersect(o, d, 0.0, f64::INFINITY),
    );
    let grazing = |s: &Shape, (t, part): (f64, u32)| {
        s.frame(o + t * d, part).w.dot(d.normalize()).abs() < 1e-3
    };
    match (ha, hb) {
        (None, None) => Ok(()),
        (Some((ta, pa)), Some((tb, pb))) => {
            let (na, nb) = (a.frame(o + ta * d, pa).w, b.frame(o + tb * d, pb).w);
            if grazing(a, (ta, pa)) {
                return Ok(());
            }
            if (ta - tb).abs() > 1e-9 * ta.abs().max(1.0) || (na - nb).length() > 1e-9 {
                return Err(format!("hits at {ta} and {tb}, normals {na} and {nb}"));
            }
            Ok(())
        }
        (Some(h), None) if grazing(a, h) => Ok(()),
        (None, Some(h)) if grazing(b, h) => Ok(()),
        (ha, hb) => Err(format!("{ha:?} vs {hb:?}")),
    }
}

proptest! {
    #![proptest_config(config(256))]

    /// An ellipsoid hits like the unit sphere scaled by its semi-axes and moved to its centre
    /// (a transformed sphere, traced in the sphere's space), also when both are turned.
    #[test]
    fn ellipsoids_hit_like_scaled_spheres(
        centre in point_in(3.0),
        a in log_uniform(0.1, 3.0),
        b in log_uniform(0.1, 3.0),
        c in log_uniform(0.1, 3.0),
        axis in unit_vector(),
        angle in -PI..PI,
        u in prop::array::uniform12(0.0..1.0f64),
    ) {
        let s = DVec3::new(a, b, c);
        let ellipsoid = Shape::Ellipsoid(Ellipsoid::new(centre, s).unwrap());
        let unit = Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
        let scaled = Transform::new(s, DVec3::Z, 0.0, centre).unwrap().shape(&unit).unwrap();
        prop_assert!(matches!(scaled, Shape::Transformed(_)));
        let params = Params::Ellipsoid { centre, semi_axes: s };
        let case = make_case(params, (u[11] * 4.0) as u8, u);
        same_hits(&ellipsoid, &scaled, case.origin, case.direction).map_err(TestCaseError::fail)?;

        let at_origin = Shape::Ellipsoid(Ellipsoid::new(DVec3::ZERO, s).unwrap());
        let turned_ellipsoid = Transform::new(DVec3::ONE, axis, angle, centre).unwrap().shape(&at_origin).unwrap();
        let turned_sphere = Transform::new(s, axis, angle, centre).unwrap().shape(&unit).unwrap();
        same_hits(&turned_ellipsoid, &turned_sphere, case.origin, case.direction).map_err(TestCaseError::fail)?;
    }
}

// ---------------------------------------------------------------------------------------------
// Surface coordinates
// ---------------------------------------------------------------------------------------------

/// Surface coordinates as docs/SCENE_FORMAT.md defines them, computed here for a point `p` of
/// the shape's part 0.
fn documented_coordinates(params: &Params, p: DVec3) -> DVec2 {
    match *params {
        Params::Cone {
            apex,
            axis,
            half_angle_deg,
            height,
            ..
        } => {
            let h = axis.normalize();
            let (u, v) = disc_axes(h);
            let q = p - apex;
            let r = height * half_angle_deg.to_radians().tan();
            DVec2::new(r * q.dot(v).atan2(q.dot(u)), q.dot(h))
        }
        Params::Paraboloid { vertex, axis, .. } => {
            let (u, v) = disc_axes(axis.normalize());
            DVec2::new((p - vertex).dot(u), (p - vertex).dot(v))
        }
        Params::Ellipsoid { centre, semi_axes } => {
            let e = (p - centre) / semi_axes;
            let rho = (semi_axes.x * semi_axes.y * semi_axes.z).cbrt();
            rho * DVec2::new(e.x.atan2(e.z), e.y.clamp(-1.0, 1.0).acos())
        }
        Params::Cap {
            sphere_centre,
            cap_centre,
            ..
        } => {
            let r = (cap_centre - sphere_centre).length();
            let n = (cap_centre - sphere_centre) / r;
            let (u, v) = disc_axes(n);
            let q = p - sphere_centre;
            r * DVec2::new(
                q.dot(v).atan2(q.dot(u)),
                (q.dot(n) / r).clamp(-1.0, 1.0).acos(),
            )
        }
        Params::Elliptic {
            start,
            end,
            semi_axes,
            a_direction,
            ..
        } => {
            let h = (end - start).normalize();
            let ua = match a_direction {
                Some(a) => (a - a.dot(h) * h).normalize(),
                None => disc_axes(h).0,
            };
            let q = p - start;
            let (x, y) = (q.dot(ua) / semi_axes.x, q.dot(h.cross(ua)) / semi_axes.y);
            DVec2::new((semi_axes.x * semi_axes.y).sqrt() * y.atan2(x), q.dot(h))
        }
        Params::OpenCylinder { start, end, radius }
        | Params::Tube {
            start,
            end,
            outer: radius,
            ..
        } => {
            let h = (end - start).normalize();
            let (u, v) = disc_axes(h);
            let q = p - start;
            DVec2::new(radius * q.dot(v).atan2(q.dot(u)), q.dot(h))
        }
    }
}

fn any_shape() -> impl Strategy<Value = Params> {
    prop_oneof![
        cone(),
        paraboloid(),
        ellipsoid(),
        cap(),
        elliptic(),
        open_cylinder(),
        tube()
    ]
}

/// Whether the angle components of two coordinate pairs are so near the seam (±π times the
/// scale) that they may differ by a full turn.
fn near_seam(a: DVec2, b: DVec2) -> bool {
    (a.x.abs() - b.x.abs()).abs() < 1e-6 * (1.0 + a.x.abs()) && a.x * b.x < 0.0
}

proptest! {
    #![proptest_config(config(256))]

    /// At decisive hits on part 0 the surface coordinates are the documented ones, and
    /// `point_at` takes them back to the hit point (where the shape has it).
    #[test]
    fn coordinates_are_as_documented_and_point_at_inverts_them(case in cases(any_shape())) {
        let shape = case.params.shape();
        let reference = case.params.reference();
        let (o, d) = (case.origin, case.direction);
        if run_case(&case).map_err(TestCaseError::fail)? != Outcome::Decisive {
            return Ok(());
        }
        let Some((t, part)) = shape.intersect(o, d, case.t_min, case.t_max) else {
            return Ok(());
        };
        if part != 0 {
            return Ok(());
        }
        let p = o + t * d;
        let c = shape.coordinates(p, part);
        let expected = documented_coordinates(&case.params, p);
        let scale = reference.scale;
        if !near_seam(c, expected) {
            prop_assert!((c - expected).length() <= 1e-9 * scale, "coordinates {} vs documented {}", c, expected);
        }
        if matches!(case.params, Params::Tube { .. }) {
            return Ok(()); // a CSG shape: no inverse
        }
        let back = shape.point_at(c);
        prop_assert!(back.is_some(), "point_at({}) is None", c);
        prop_assert!((back.unwrap() - p).length() <= 1e-9 * (scale + p.length()), "point_at({}) = {:?}, not {}", c, back, p);
    }

    /// `point_at` gives surface points (on part 0) for coordinates in range, and none beyond.
    #[test]
    fn point_at_gives_surface_points(params in any_shape(), x in -0.99..0.99f64, y in 0.0..1.0f64) {
        if matches!(params, Params::Tube { .. }) {
            return Ok(());
        }
        let shape = params.shape();
        let reference = params.reference();
        let scale = reference.scale;
        // The coordinates' range: the angle's scale and v's range.
        let (angle_scale, v_max) = match params {
            Params::Cone { half_angle_deg, height, .. } => (height * half_angle_deg.to_radians().tan(), height),
            Params::Paraboloid { .. } => (0.0, 0.0),
            Params::Ellipsoid { semi_axes, .. } => {
                let rho = semi_axes.element_product().cbrt();
                (rho, rho * PI)
            }
            Params::Cap { sphere_centre, cap_centre, size } => {
                let r = (cap_centre - sphere_centre).length();
                let angle = match size {
                    CapSize::Aperture(a) => (a / r).asin(),
                    CapSize::AngleDeg(a) => a.to_radians(),
                };
                (r, r * angle)
            }
            Params::Elliptic { start, end, semi_axes, .. } => ((semi_axes.x * semi_axes.y).sqrt(), (end - start).length()),
            Params::OpenCylinder { start, end, radius } => (radius, (end - start).length()),
            Params::Tube { .. } => unreachable!(),
        };
        let c = match params {
            Params::Paraboloid { focal_length, height, .. } => {
                // Cartesian within the rim's radius.
                let rim = 2.0 * (focal_length * height).sqrt();
                rim * y.sqrt() * DVec2::new((PI * x).cos(), (PI * x).sin())
            }
            _ => DVec2::new(PI * x * angle_scale, y * v_max),
        };
        let p = shape.point_at(c).unwrap_or_else(|| panic!("point_at({c}) is None"));
        let piece = &reference.pieces[0];
        prop_assert!((piece.f)(p).abs() <= 1e-9 * piece.lipschitz * scale, "{} is off the surface by {}", p, (piece.f)(p));
        prop_assert!((piece.margin)(p) >= -1e-9 * scale, "{} is beyond the rim", p);
        let back = shape.coordinates(p, 0);
        prop_assert!((back - c).length() <= 1e-9 * scale, "coordinates({}) = {}, not {}", p, back, c);
        // Beyond the range: nothing.
        let beyond = match params {
            Params::Paraboloid { focal_length, height, .. } => DVec2::new(2.01 * (focal_length * height).sqrt(), 0.0),
            _ => DVec2::new(0.0, v_max * 1.01 + 1e-9),
        };
        prop_assert_eq!(shape.point_at(beyond), None);
    }
}

// ---------------------------------------------------------------------------------------------
// Bounds
// ---------------------------------------------------------------------------------------------

/// Points of the shape's surface on a 120 × 120 grid of its own parametrisation (written here),
/// for each piece.
fn surface_grid(params: &Params) -> Vec<DVec3> {
    const N: usize = 120;
    let grid = |f: &dyn Fn(f64, f64) -> DVec3| -> Vec<DVec3> {
        (0..=N)
            .flat_map(|i| (0..=N).map(move |j| (i as f64 / N as f64, j as f64 / N as f64)))
            .map(|(a, b)| f(a, b))
            .collect()
    };
    let ring = |c: DVec3, h: DVec3, r: f64, a: f64| {
        let (u, v) = disc_axes(h);
        c + r * ((2.0 * PI * a).cos() * u + (2.0 * PI * a).sin() * v)
    };
    match *params {
        Params::Cone {
            apex,
            axis,
            half_angle_deg,
            height,
            ..
        } => {
            let h = axis.normalize();
            let r = height * half_angle_deg.to_radians().tan();
            let mut all = grid(&|a, b| ring(apex + b * height * h, h, b * r, a));
            all.extend(grid(&|a, b| ring(apex + height * h, h, b * r, a)));
            all
        }
        Params::Paraboloid {
            vertex,
            axis,
            focal_length,
            height,
            ..
        } => {
            let h = axis.normalize();
            let rim = 2.0 * (focal_length * height).sqrt();
            grid(&|a, b| {
                let z = b * b * height;
                ring(vertex + z * h, h, (4.0 * focal_length * z).sqrt(), a)
            })
            .into_iter()
            .chain(grid(&|a, b| ring(vertex + height * h, h, b * rim, a)))
            .collect()
        }
        Params::Ellipsoid { centre, semi_axes } => grid(&|a, b| {
            let (phi, theta) = (2.0 * PI * a, PI * b);
            centre
                + semi_axes
                    * DVec3::new(
                        theta.sin() * phi.cos(),
                        theta.cos(),
                        theta.sin() * phi.sin(),
                    )
        }),
        Params::Cap {
            sphere_centre,
            cap_centre,
            size,
        } => {
            let r = (cap_centre - sphere_centre).length();
            let n = (cap_centre - sphere_centre) / r;
            let angle = match size {
                CapSize::Aperture(a) => (a / r).asin(),
                CapSize::AngleDeg(a) => a.to_radians(),
            };
            grid(&|a, b| {
                let theta = b * angle;
                ring(sphere_centre + r * theta.cos() * n, n, r * theta.sin(), a)
            })
        }
        Params::Elliptic {
            start,
            end,
            semi_axes,
            a_direction,
            ..
        } => {
            let h = (end - start).normalize();
            let ua = match a_direction {
                Some(a) => (a - a.dot(h) * h).normalize(),
                None => disc_axes(h).0,
            };
            let ub = h.cross(ua);
            let ellipse = move |c: DVec3, a: f64, s: f64| {
                let phi = 2.0 * PI * a;
                c + s * (semi_axes.x * phi.cos() * ua + semi_axes.y * phi.sin() * ub)
            };
            let mut all = grid(&|a, b| ellipse(start + b * (end - start), a, 1.0));
            all.extend(grid(&|a, b| ellipse(start, a, b)));
            all.extend(grid(&|a, b| ellipse(end, a, b)));
            all
        }
        Params::OpenCylinder { start, end, radius }
        | Params::Tube {
            start,
            end,
            outer: radius,
            ..
        } => {
            let h = (end - start).normalize();
            grid(&|a, b| ring(start + b * (end - start), h, radius, a))
        }
    }
}

proptest! {
    #![proptest_config(config(64))]

    /// The bounds contain the surface, and are tight: each face of the box is touched (to the
    /// grid's resolution).
    #[test]
    fn bounds_contain_the_surface_tightly(params in any_shape()) {
        let (lo, hi) = params.shape().bounds().expect("bounded");
        let scale = params.bounding_sphere().2;
        let points = surface_grid(&params);
        let (mut plo, mut phi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for p in &points {
            prop_assert!(p.cmpge(lo - 1e-12 * (scale + p.length())).all() && p.cmple(hi + 1e-12 * (scale + p.length())).all(),
                "{} outside the bounds {} .. {}", p, lo, hi);
            plo = plo.min(*p);
            phi = phi.max(*p);
        }
        let slack = 2e-3 * scale;
        prop_assert!((plo - lo).max_element() <= slack && (hi - phi).max_element() <= slack,
            "bounds {} .. {} are loose around {} .. {}", lo, hi, plo, phi);
    }
}

proptest! {
    #![proptest_config(config(32))]

    /// Embree's BVH (built from the bounds) finds the same nearest hits as a plain loop over
    /// the shapes, in a scene of one random shape of each kind.
    #[test]
    fn embree_finds_every_hit(
        shapes in (cone(), paraboloid(), ellipsoid(), cap(), elliptic(), open_cylinder(), tube()),
        rays in prop::collection::vec(prop::array::uniform12(0.0..1.0f64), 64),
    ) {
        let params = [shapes.0, shapes.1, shapes.2, shapes.3, shapes.4, shapes.5, shapes.6];
        let objects: Vec<(Shape, bool)> = params.iter().map(|p| (p.shape(), true)).collect();
        let scene = SceneGeometry::build(common::rays::device(), objects, Vec::new()).unwrap();
        for (i, u) in rays.iter().enumerate() {
            let case = make_case(params[i % params.len()].clone(), (u[11] * 4.0) as u8, *u);
            let (o, d) = (case.origin, case.direction);
            let (embree, plain) = (
                scene.nearest(o, d, case.t_min, case.t_max),
                scene.nearest_brute_force(o, d, case.t_min, case.t_max),
            );
            prop_assert_eq!(embree, plain, "ray {:?}", case);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Tubes
// ---------------------------------------------------------------------------------------------

#[test]
fn a_tube_has_an_annular_end_and_no_cap_over_its_hole() {
    // Along z from 0 to 2, radii 1 and 0.5.
    let params = Params::Tube {
        start: DVec3::ZERO,
        end: DVec3::new(0.0, 0.0, 2.0),
        outer: 1.0,
        inner: 0.5,
    };
    let tube = params.shape();
    let down = DVec3::NEG_Z;
    // Down the hole, parallel to the axis: nothing (no cap over the hole, and the inner
    // mantle is parallel to the ray).
    for x in [0.0, 0.2, 0.49] {
        let o = DVec3::new(x, 0.0, 5.0);
        assert_eq!(tube.intersect(o, down, 0.0, f64::INFINITY), None, "x = {x}");
    }
    // Onto the ring: its end face, facing +z.
    for x in [0.51, 0.75, 0.99] {
        let o = DVec3::new(x, 0.0, 5.0);
        let (t, part) = tube.intersect(o, down, 0.0, f64::INFINITY).unwrap();
        assert!((t - 3.0).abs() < 1e-12, "x = {x}: t = {t}");
        assert!((tube.frame(o + t * down, part).w - DVec3::Z).length() < 1e-12);
        // And out through the other end face, facing −z.
        let (t, part) = tube.intersect(o, down, 3.0 + 1e-9, f64::INFINITY).unwrap();
        assert!((t - 5.0).abs() < 1e-12, "x = {x}: t = {t}");
        assert!((tube.frame(o + t * down, part).w - DVec3::NEG_Z).length() < 1e-12);
    }
    // Obliquely into the hole: the inner mantle, whose outward normal faces the axis.
    let o = DVec3::new(0.0, 0.0, 2.2);
    let d = DVec3::new(1.0, 0.0, -1.0);
    let (t, part) = tube.intersect(o, d, 0.0, f64::INFINITY).unwrap();
    assert!((t - 0.5).abs() < 1e-12, "t = {t}");
    assert!((tube.frame(o + t * d, part).w - DVec3::NEG_X).length() < 1e-12);
    // Across the wall from outside: the outer mantle, then the inner one.
    let o = DVec3::new(-3.0, 0.0, 1.0);
    let hits: Vec<f64> = std::iter::successors(
        tube.intersect(o, DVec3::X, 0.0, f64::INFINITY),
        |&(t, _)| tube.intersect(o, DVec3::X, t + 1e-9, f64::INFINITY),
    )
    .map(|h| h.0)
    .collect();
    assert_eq!(hits, [2.0, 2.5, 3.5, 4.0]);
}

// ---------------------------------------------------------------------------------------------
// Scene files: errors and kinds
// ---------------------------------------------------------------------------------------------

/// The error for a scene whose only object has shape `shape`, which must be at the shape's
/// line (4) and contain every one of `parts`.
#[track_caller]
fn assert_shape_error(shape: &str, parts: &[&str]) {
    let text = scene_with(shape);
    let message = match file::parse(&text, "s.toml") {
        Ok(_) => panic!("accepted: {shape}"),
        Err(e) => e.to_string(),
    };
    assert!(message.starts_with("s.toml:4:"), "{message}");
    for part in parts {
        assert!(message.contains(part), "lacks {part:?}: {message}");
    }
}

#[test]
fn bad_parameters_are_errors_naming_the_key() {
    let cone =
        |extra: &str| format!("{{ type = \"cone\", apex = [0, 0, 5], axis = [0, 0, 1], {extra} }}");
    assert_shape_error(
        &cone("half_angle_deg = 30, height = 0"),
        &["cone height must be a positive", "got 0"],
    );
    assert_shape_error(
        &cone("half_angle_deg = 30, height = -1"),
        &["cone height", "got -1"],
    );
    for angle in ["0", "90", "95", "-10"] {
        assert_shape_error(
            &cone(&format!("half_angle_deg = {angle}, height = 1")),
            &[
                "cone half_angle_deg must be between 0 and 90",
                &format!("got {angle}"),
            ],
        );
    }
    assert_shape_error(
        "{ type = \"cone\", apex = [0, 0, 5], axis = [0, 0, 0], half_angle_deg = 30, height = 1 }",
        &["cone axis must be a non-zero vector"],
    );
    let paraboloid = |f: &str, h: &str| {
        format!(
            "{{ type = \"paraboloid\", vertex = [0, 0, 5], axis = [0, 0, -1], focal_length = {f}, height = {h} }}"
        )
    };
    assert_shape_error(&paraboloid("0", "1"), &["paraboloid focal_length", "got 0"]);
    assert_shape_error(&paraboloid("1", "-2"), &["paraboloid height", "got -2"]);
    assert_shape_error(
        "{ type = \"paraboloid\", vertex = [0, 0, 5], axis = [0, 0, 0], focal_length = 1, height = 1 }",
        &["paraboloid axis must be a non-zero vector"],
    );
    for semi in ["[1, 0, 2]", "[1, -1, 1]"] {
        assert_shape_error(
            &format!("{{ type = \"ellipsoid\", centre = [0, 0, 5], semi_axes = {semi} }}"),
            &["ellipsoid semi_axes must all be positive", "got"],
        );
    }
    let elliptic = |extra: &str| {
        format!("{{ type = \"elliptic-cylinder\", start = [0, 0, 5], end = [0, 0, 6], {extra} }}")
    };
    assert_shape_error(
        &elliptic("semi_axes = [0, 1]"),
        &[
            "elliptic-cylinder semi_axes must all be positive",
            "got [0, 1]",
        ],
    );
    assert_shape_error(
        &elliptic("semi_axes = [1, 1], a_direction = [0, 0, 2]"),
        &["elliptic-cylinder a_direction must not be zero or parallel to the axis"],
    );
    assert_shape_error(
        "{ type = \"elliptic-cylinder\", start = [0, 0, 5], end = [0, 0, 5], semi_axes = [1, 1] }",
        &["elliptic-cylinder start and end coincide"],
    );
    let tube = |outer: &str, inner: &str| {
        format!(
            "{{ type = \"tube\", start = [0, 0, 5], end = [0, 0, 6], outer_radius = {outer}, inner_radius = {inner} }}"
        )
    };
    assert_shape_error(
        &tube("1", "1"),
        &["tube inner_radius must be less than outer_radius (1), got 1"],
    );
    assert_shape_error(&tube("1", "2"), &["tube inner_radius", "got 2"]);
    assert_shape_error(
        &tube("1", "0"),
        &["tube inner_radius must be a positive", "got 0"],
    );
    assert_shape_error(&tube("-1", "0.5"), &["tube outer_radius", "got -1"]);
    assert_shape_error(
        "{ type = \"tube\", start = [0, 0, 5], end = [0, 0, 5], outer_radius = 1, inner_radius = 0.5 }",
        &["cylinder start and end coincide"],
    );
    let cap = |extra: &str| {
        format!(
            "{{ type = \"spherical-cap\", sphere_centre = [0, 0, 5], cap_centre = [0, 0, 4], {extra} }}"
        )
    };
    assert_shape_error(
        &cap("aperture_radius = 2"),
        &[
            "spherical-cap aperture_radius must be at most the sphere's radius",
            "got 2",
        ],
    );
    assert_shape_error(
        &cap("aperture_radius = 0"),
        &["spherical-cap aperture_radius", "got 0"],
    );
    assert_shape_error(
        &cap("half_angle_deg = 0"),
        &[
            "spherical-cap half_angle_deg must be greater than 0 and at most 180",
            "got 0",
        ],
    );
    assert_shape_error(&cap("half_angle_deg = 181"), &["half_angle_deg", "got 181"]);
    assert_shape_error(
        &cap("half_angle_deg = 30, aperture_radius = 0.5"),
        &["one of aperture_radius and half_angle_deg, not both"],
    );
    assert_shape_error(
        "{ type = \"spherical-cap\", sphere_centre = [0, 0, 5], cap_centre = [0, 0, 5], half_angle_deg = 30 }",
        &["spherical-cap cap_centre and sphere_centre coincide"],
    );
}

#[test]
fn open_shapes_are_not_solids_and_say_why() {
    for (open, kind) in [
        (
            "{ type = \"cone\", apex = [0, 0, 5], axis = [0, 0, 1], half_angle_deg = 30, height = 1, open = true }",
            "(cone with open = true) does not enclose a solid",
        ),
        (
            "{ type = \"paraboloid\", vertex = [0, 0, 5], axis = [0, 0, 1], focal_length = 1, height = 1, open = true }",
            "(paraboloid with open = true) does not",
        ),
        (
            "{ type = \"cylinder\", start = [0, 0, 5], end = [0, 0, 6], radius = 1, open = true }",
            "(cylinder with open = true) does not",
        ),
        (
            "{ type = \"elliptic-cylinder\", start = [0, 0, 5], end = [0, 0, 6], semi_axes = [1, 2], open = true }",
            "(elliptic-cylinder with open = true) does not",
        ),
        (
            "{ type = \"spherical-cap\", sphere_centre = [0, 0, 5], cap_centre = [0, 0, 4], half_angle_deg = 30 }",
            "(spherical-cap) does not",
        ),
    ] {
        let union = format!(
            "{{ type = \"union\", of = [{open}, {{ type = \"sphere\", centre = [0, 0, 5], radius = 1 }}] }}"
        );
        assert_shape_error(&union, &["member 1 of the union", kind]);
        // Closed, each is a solid the union takes.
        if !open.contains("spherical-cap") {
            let closed = union.replace("open = true", "open = false");
            assert!(matches!(
                parse(&scene_with(&closed)).objects[0].shape,
                Shape::Csg(_)
            ));
        }
    }
}

#[test]
fn a_closed_cylinder_stays_the_cylinder_it_was() {
    // `open = false` (the default) gives the existing closed cylinder, not an elliptic one.
    for open in ["", ", open = false"] {
        let text = scene_with(&format!(
            "{{ type = \"cylinder\", start = [0, 0, 5], end = [0, 0, 6], radius = 1{open} }}"
        ));
        assert!(matches!(parse(&text).objects[0].shape, Shape::Cylinder(_)));
    }
}

#[test]
fn the_example_scene_has_every_curved_shape() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/curved-shapes.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = parse(&text);
    let kinds: Vec<&str> = scene.objects.iter().map(|o| o.shape.kind()).collect();
    for kind in [
        "cone",
        "ellipsoid",
        "paraboloid with open = true",
        "spherical-cap",
        "elliptic-cylinder",
        "cylinder with open = true",
        "tube",
    ] {
        assert!(kinds.contains(&kind), "no {kind} among {kinds:?}");
    }
}

#[test]
fn hostile_rays_do_not_panic() {
    let shapes: Vec<Shape> = draw(cases(any_shape()), 40)
        .into_iter()
        .map(|c| c.params.shape())
        .collect();
    let values = [
        0.0,
        -0.0,
        1.0,
        -1e300,
        1e300,
        f64::NAN,
        f64::INFINITY,
        f64::MIN_POSITIVE,
    ];
    for shape in &shapes {
        for &a in &values {
            for &b in &values {
                let o = DVec3::new(a, b, 0.5);
                for d in [DVec3::ZERO, DVec3::new(b, a, 1.0), DVec3::splat(a)] {
                    if let Some((t, part)) = shape.intersect(o, d, 0.0, f64::INFINITY) {
                        let _ = shape.frame(o + t * d, part);
                        let _ = shape.coordinates(o + t * d, part);
                    }
                }
            }
        }
    }
}
