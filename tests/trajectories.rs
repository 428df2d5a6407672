//! Independent checks of ray-trajectory visualisation (`[[ray_trajectory]]`,
//! `timbre::trajectories::trace`, `timbre trace`): the recorded paths are compared with the
//! physics — Snell's law, the law of reflection, the Luneburg lens's focusing and its
//! elliptical ray paths, ray rotation, teleportation — worked out here from first principles,
//! not from the implementation. Every recorded surface point is checked against the implicit
//! equation of the shape written into the scene file by the test itself.

mod common;

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use timbre::scene::SceneDescription;
use timbre::trajectories::{self, Arrival, End, Trajectory};

use common::cli::{location, path_str, timbre, write};

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// The scene of `text` and its traced trajectories.
fn trace_text(text: &str) -> (SceneDescription, Vec<Trajectory>) {
    let description = common::images::parse(text);
    let traced = trajectories::trace(common::rays::device(), &description).expect("trace");
    (description, traced)
}

/// A TOML vector with every digit of the f64s.
fn v(p: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", p.x, p.y, p.z)
}

fn close_vec(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

/// The index of the object called `name` in the description.
#[track_caller]
fn index_of(d: &SceneDescription, name: &str) -> usize {
    let found: Vec<usize> = (0..d.objects.len())
        .filter(|&i| d.objects[i].name == name)
        .collect();
    assert_eq!(found.len(), 1, "objects named {name:?}: {found:?}");
    found[0]
}

/// `d` rotated by `angle` (radians) about the unit `axis`, right-handed (Rodrigues).
fn rotate(d: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    d * angle.cos() + axis.cross(d) * angle.sin() + axis * axis.dot(d) * (1.0 - angle.cos())
}

/// A unit vector perpendicular to unit `a`.
fn perpendicular(a: DVec3) -> DVec3 {
    let helper = if a.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    a.cross(helper).normalize()
}

/// Reflection of `d` in a surface of unit normal `n` (either orientation).
fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

/// Snell's law for `d` meeting a surface of outward unit normal `n` between an outside medium
/// and an inside of relative index `ratio` = n_inside / n_outside; total internal reflection
/// beyond the critical angle.
fn refract(d: DVec3, n: DVec3, ratio: f64) -> DVec3 {
    // `facing` is the normal on the side the ray comes from; `eta` = n_from / n_to.
    let (facing, eta) = if d.dot(n) < 0.0 {
        (n, 1.0 / ratio)
    } else {
        (-n, ratio)
    };
    let cos_i = -d.dot(facing);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        reflect(d, facing)
    } else {
        eta * d + (eta * cos_i - k.sqrt()) * facing
    }
}

/// The shapes the tests write into scene files, with their implicit equations.
#[derive(Debug, Clone, Copy)]
enum Geo {
    Sphere {
        centre: DVec3,
        radius: f64,
    },
    Plane {
        point: DVec3,
        normal: DVec3,
    },
    Parallelogram {
        corner: DVec3,
        u: DVec3,
        v: DVec3,
    },
    Disc {
        centre: DVec3,
        normal: DVec3,
        radius: f64,
    },
}

impl Geo {
    fn toml(&self) -> String {
        match *self {
            Geo::Sphere { centre, radius } => format!(
                "{{ type = \"sphere\", centre = {}, radius = {radius:?} }}",
                v(centre)
            ),
            Geo::Plane { point, normal } => format!(
                "{{ type = \"plane\", point = {}, normal = {} }}",
                v(point),
                v(normal)
            ),
            Geo::Parallelogram { corner, u, v: w } => format!(
                "{{ type = \"parallelogram\", corner = {}, span_u = {}, span_v = {} }}",
                v(corner),
                v(u),
                v(w)
            ),
            Geo::Disc {
                centre,
                normal,
                radius,
            } => format!(
                "{{ type = \"disc\", centre = {}, normal = {}, radius = {radius:?} }}",
                v(centre),
                v(normal)
            ),
        }
    }

    /// Outward unit normal at `p` (a point of the surface).
    fn normal(&self, p: DVec3) -> DVec3 {
        match *self {
            Geo::Sphere { centre, .. } => (p - centre).normalize(),
            Geo::Plane { normal, .. } | Geo::Disc { normal, .. } => normal.normalize(),
            Geo::Parallelogram { u, v, .. } => u.cross(v).normalize(),
        }
    }

    /// Whether `p` lies on the surface to `rel` relative to the scene's scale.
    fn contains(&self, p: DVec3, rel: f64) -> Result<(), String> {
        let scale = 1.0 + p.abs().max_element();
        let ok = |what: &str, err: f64, tol: f64| {
            if err.abs() <= tol {
                Ok(())
            } else {
                Err(format!("{p:?} is off {self:?}: {what} = {err:e}"))
            }
        };
        match *self {
            Geo::Sphere { centre, radius } => ok(
                "|p − c| − R",
                (p - centre).length() - radius,
                rel * (radius + scale),
            ),
            Geo::Plane { point, normal } => ok(
                "(p − p0)·n",
                (p - point).dot(normal.normalize()),
                rel * scale,
            ),
            Geo::Parallelogram { corner, u, v } => {
                let n = u.cross(v).normalize();
                ok("(p − corner)·n", (p - corner).dot(n), rel * scale)?;
                // Solve p − corner = α u + β v in the plane.
                let r = p - corner;
                let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
                let (ru, rv) = (r.dot(u), r.dot(v));
                let det = uu * vv - uv * uv;
                let alpha = (ru * vv - rv * uv) / det;
                let beta = (rv * uu - ru * uv) / det;
                let slack = rel * scale;
                if (-slack..=1.0 + slack).contains(&alpha) && (-slack..=1.0 + slack).contains(&beta)
                {
                    Ok(())
                } else {
                    Err(format!(
                        "{p:?} is outside the parallelogram {self:?}: α = {alpha}, β = {beta}"
                    ))
                }
            }
            Geo::Disc {
                centre,
                normal,
                radius,
            } => {
                ok(
                    "(p − c)·n",
                    (p - centre).dot(normal.normalize()),
                    rel * scale,
                )?;
                let rho = (p - centre).length();
                if rho <= radius + rel * scale {
                    Ok(())
                } else {
                    Err(format!("{p:?} is beyond the disc {self:?}: ρ = {rho}"))
                }
            }
        }
    }

    /// The corners of the bounding box, for bounded shapes.
    fn bounds(&self) -> Option<(DVec3, DVec3)> {
        match *self {
            Geo::Sphere { centre, radius } => Some((centre - radius, centre + radius)),
            Geo::Plane { .. } => None,
            Geo::Parallelogram { corner, u, v } => {
                let ps = [corner, corner + u, corner + v, corner + u + v];
                Some((
                    ps.iter().fold(DVec3::INFINITY, |m, &p| m.min(p)),
                    ps.iter().fold(DVec3::NEG_INFINITY, |m, &p| m.max(p)),
                ))
            }
            Geo::Disc { centre, radius, .. } => Some((centre - radius, centre + radius)),
        }
    }
}

/// What a surface does to a ray, as the tests work it out.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Law {
    /// A coloured surface: the ray ends on it.
    Absorbs,
    Mirror,
    /// `refractive` with this index ratio.
    Refracts(f64),
    /// A closed-form §3 lens on a sphere.
    Lens(Lens),
    /// `ray-rotating` about the surface normal by this angle (degrees).
    Rotates(f64),
}

/// §3's lenses, by their maps from entry (P, d) to exit (P′, d′), derived here for a lens of
/// centre C and radius R (n = 1 at the surface):
/// - Luneburg (n² = 2 − r²/R²): the rays are ellipses r(τ) − C = (P − C) cos(τ/R) +
///   R d sin(τ/R), which meet the surface again at τ/R = π/2: P′ = C + R d, d′ = (C − P)/R.
/// - Eaton: a retro-reflector, d′ = −d; the path is symmetric about its axis, which is then
///   the line through C along d, so P′ is P mirrored in that line.
/// - Maxwell fisheye (truncated at R): the rays are circle arcs from P to the antipode
///   P′ = 2C − P; the mirror plane through C perpendicular to P − C maps the circle onto itself
///   and P onto P′, reversing the direction of travel, so d′ = 2(d·P̂)P̂ − d.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Lens {
    Luneburg,
    Eaton,
    Maxwell,
}

impl Lens {
    fn map(self, centre: DVec3, radius: f64, p: DVec3, d: DVec3) -> (DVec3, DVec3) {
        let r = p - centre;
        let r_hat = r / radius;
        match self {
            Lens::Luneburg => (centre + radius * d, -r_hat),
            Lens::Eaton => (centre + 2.0 * r.dot(d) * d - r, -d),
            Lens::Maxwell => (centre - r, 2.0 * d.dot(r_hat) * r_hat - d),
        }
    }
}

/// An object of a test scene: its name, shape and law, and the TOML of its surface.
struct Obj {
    name: &'static str,
    geo: Geo,
    law: Law,
    surface: &'static str,
}

impl Obj {
    fn toml(&self) -> String {
        format!(
            "[[object]]\nname = \"{}\"\nshadow_throwing = false\nshape = {}\nsurface = {}\n\n",
            self.name,
            self.geo.toml(),
            self.surface
        )
    }
}

/// The `empty` studio's sky and floor, as its documentation describes them.
fn studio_objects() -> Vec<Obj> {
    vec![
        Obj {
            name: "sky",
            geo: Geo::Sphere {
                centre: DVec3::ZERO,
                radius: 1e5,
            },
            law: Law::Absorbs,
            surface: "",
        },
        Obj {
            name: "floor",
            geo: Geo::Plane {
                point: DVec3::new(0.0, -1.0001, 0.0),
                normal: DVec3::Y,
            },
            law: Law::Absorbs,
            surface: "",
        },
    ]
}

/// How many interactions of each law the check met.
#[derive(Debug, Default)]
struct Tally {
    absorbed: Vec<&'static str>,
    mirror: usize,
    refracted: usize,
    totally_reflected: usize,
    lens: usize,
    rotated: usize,
}

/// The direction the ray leaves point `k` of `t` in (to the next point, or the final direction).
fn leaving(t: &Trajectory, k: usize) -> DVec3 {
    match t.points.get(k + 1) {
        Some(next) => (next.position - t.points[k].position).normalize(),
        None => t.direction,
    }
}

/// Checks every point of `t` against the objects `objs` of `d` (found by name): points on
/// objects lie on their surfaces, every surface applies its law, the trajectory ends as its
/// last surface says, and an escaping ray is drawn on beyond the bounding box of the bounded
/// objects. Returns what it met.
fn check_trajectory(
    d: &SceneDescription,
    objs: &[Obj],
    t: &Trajectory,
    tally: &mut Tally,
) -> Result<(), String> {
    let tol = 1e-9;
    let pts = &t.points;
    let ctx = |m: String| format!("trajectory {} ray {}: {m}\n{t:#?}", t.source, t.ray);
    if pts.len() < 2 {
        return Err(ctx("fewer than two points".into()));
    }
    if pts[0].arrival != Arrival::Start || pts[0].object.is_some() {
        return Err(ctx("the first point is not a plain start".into()));
    }
    if (t.direction.length() - 1.0).abs() > 1e-12 {
        return Err(ctx("final direction not a unit vector".into()));
    }
    let by_index = |i: usize| -> &Obj {
        let name = &d.objects[i].name;
        objs.iter()
            .find(|o| o.name == name)
            .unwrap_or_else(|| panic!("object {i} ({name}) is not one of the test's"))
    };
    let mut k = 1;
    while k < pts.len() {
        let p = &pts[k];
        let last = k + 1 == pts.len();
        match (p.arrival, p.object) {
            (Arrival::Straight, None) => {
                // Only the drawn end of an escaping ray.
                if !last || t.end != End::Escaped {
                    return Err(ctx(format!("point {k} is on no object")));
                }
                let from = pts[k - 1].position;
                let length = p.position.distance(from);
                let along = (p.position - from) / length;
                if !close_vec(along, t.direction, tol) {
                    return Err(ctx("escape point not along the final direction".into()));
                }
                if length < 1.0 - 1e-12 {
                    return Err(ctx(format!("escape drawn only {length} long")));
                }
                let boxes: Vec<_> = objs.iter().filter_map(|o| o.geo.bounds()).collect();
                if let Some(&(lo0, hi0)) = boxes.first() {
                    let (lo, hi) = boxes
                        .iter()
                        .fold((lo0, hi0), |(a, b), &(l, h)| (a.min(l), b.max(h)));
                    for c in 0..8 {
                        let corner = DVec3::new(
                            if c & 1 == 0 { lo.x } else { hi.x },
                            if c & 2 == 0 { lo.y } else { hi.y },
                            if c & 4 == 0 { lo.z } else { hi.z },
                        );
                        if from.distance(corner) > length * (1.0 + 1e-12) {
                            return Err(ctx(format!(
                                "escape point {:?} not beyond the bounding box corner {corner:?}",
                                p.position
                            )));
                        }
                    }
                }
            }
            (Arrival::Straight, Some(i)) => {
                let obj = by_index(i);
                obj.geo.contains(p.position, tol).map_err(ctx)?;
                let d_in = (p.position - pts[k - 1].position).normalize();
                let n = obj.geo.normal(p.position);
                let expected = match obj.law {
                    Law::Absorbs => {
                        if !last || t.end != End::Absorbed {
                            return Err(ctx(format!(
                                "point {k} on {} (coloured) does not end it as absorbed",
                                obj.name
                            )));
                        }
                        tally.absorbed.push(obj.name);
                        d_in
                    }
                    Law::Mirror => {
                        tally.mirror += 1;
                        reflect(d_in, n)
                    }
                    Law::Refracts(ratio) => {
                        let out = refract(d_in, n, ratio);
                        if out.dot(n).signum() == d_in.dot(n).signum() {
                            tally.refracted += 1;
                        } else {
                            tally.totally_reflected += 1;
                        }
                        out
                    }
                    Law::Rotates(deg) => {
                        tally.rotated += 1;
                        let axis = if d_in.dot(n) > 0.0 { n } else { -n };
                        rotate(d_in, axis, deg.to_radians())
                    }
                    Law::Lens(lens) => {
                        let Geo::Sphere { centre, radius } = obj.geo else {
                            unreachable!()
                        };
                        tally.lens += 1;
                        // Entry from outside; the exit is the next point, reached by a chord.
                        if d_in.dot(n) >= 0.0 {
                            return Err(ctx(format!("point {k}: lens met from inside")));
                        }
                        let Some(exit) = pts.get(k + 1) else {
                            if t.end == End::MaxInteractions {
                                break;
                            }
                            return Err(ctx(format!("no exit after lens entry {k}")));
                        };
                        if exit.arrival != Arrival::Chord || exit.object != Some(i) {
                            return Err(ctx(format!("point {} is not a chord exit", k + 1)));
                        }
                        let (exit_point, out) = lens.map(centre, radius, p.position, d_in);
                        if !close_vec(exit.position, exit_point, tol * radius) {
                            return Err(ctx(format!(
                                "{lens:?} lens exit {:?}, expected {exit_point:?}",
                                exit.position
                            )));
                        }
                        let got = leaving(t, k + 1);
                        if !close_vec(got, out, tol) {
                            return Err(ctx(format!(
                                "leaves the lens along {got:?}, expected {out:?}"
                            )));
                        }
                        k += 2;
                        continue;
                    }
                };
                let got = leaving(t, k);
                if !close_vec(got, expected, tol) {
                    return Err(ctx(format!(
                        "point {k} on {}: leaves along {got:?}, expected {expected:?} ({:?})",
                        obj.name, obj.law
                    )));
                }
            }
            (arrival, object) => {
                return Err(ctx(format!(
                    "unexpected point {k}: {arrival:?} on {object:?}"
                )));
            }
        }
        k += 1;
    }
    // The end kind matches the last point.
    let last = pts.last().unwrap();
    let expected_end_ok = match t.end {
        End::Escaped => last.object.is_none(),
        End::Absorbed => last.object.is_some_and(|i| by_index(i).law == Law::Absorbs),
        End::MaxInteractions => last.object.is_some(),
        End::Lost => false,
    };
    if !expected_end_ok {
        return Err(ctx(format!("end {:?} does not fit the last point", t.end)));
    }
    Ok(())
}

/// The scene text of `objs` (without the studio's) and trajectory tables `rays`.
fn scene_text(studio: &str, objs: &[Obj], rays: &str) -> String {
    let mut text = format!("studio = \"{studio}\"\n\n");
    for o in objs.iter().filter(|o| !o.surface.is_empty()) {
        text += &o.toml();
    }
    text + rays
}

// ---------------------------------------------------------------------------------------------
// 1. A refractive slab displaces a ray without turning it
// ---------------------------------------------------------------------------------------------

#[test]
fn slab_displaces_rays_by_the_textbook_amount_and_keeps_their_direction() {
    let n = 1.5;
    let thickness = 0.7;
    let axis = DVec3::new(0.3, -0.2, 1.0).normalize();
    let across = perpendicular(axis);
    let other = axis.cross(across);
    let front_point = DVec3::new(0.1, 0.2, 5.0);
    let back_point = front_point + thickness * axis;
    let objs = vec![
        Obj {
            name: "front",
            geo: Geo::Plane {
                point: front_point,
                normal: -axis,
            },
            law: Law::Refracts(n),
            surface: "{ type = \"refractive\", index_ratio = 1.5 }",
        },
        Obj {
            name: "back",
            geo: Geo::Plane {
                point: back_point,
                normal: axis,
            },
            law: Law::Refracts(n),
            surface: "{ type = \"refractive\", index_ratio = 1.5 }",
        },
    ];
    let angles = [0.0f64, 5.0, 20.0, 35.0, 50.0, 65.0, 80.0];
    let mut rays = String::new();
    let mut incident = Vec::new();
    for (k, deg) in angles.iter().enumerate() {
        let theta = deg.to_radians();
        // Alternate the plane of incidence, to cover more than one azimuth.
        let side = if k % 2 == 0 {
            across
        } else {
            (across + other).normalize()
        };
        let direction = theta.cos() * axis + theta.sin() * side;
        let start = front_point - 2.0 * axis + 0.3 * k as f64 * other;
        rays += &format!(
            "[[ray_trajectory]]\nstart = {}\ndirection = {}\n\n",
            v(start),
            v(direction)
        );
        incident.push((start, direction, theta));
    }
    let (d, traced) = trace_text(&scene_text("none", &objs, &rays));
    assert_eq!(traced.len(), angles.len());
    let (front, back) = (index_of(&d, "front"), index_of(&d, "back"));
    let mut tally = Tally::default();
    for (t, &(start, direction, theta)) in traced.iter().zip(&incident) {
        check_trajectory(&d, &objs, t, &mut tally).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(t.end, End::Escaped, "{t:#?}");
        let objects: Vec<_> = t.points.iter().map(|p| p.object).collect();
        assert_eq!(objects, [None, Some(front), Some(back), None], "{t:#?}");
        let [p0, p1, p2, _] = [0, 1, 2, 3].map(|i| t.points[i].position);
        assert!(close_vec(p0, start, 1e-15));
        // The same direction after the slab.
        assert!(
            close_vec(t.direction, direction, 1e-12),
            "θ = {}°: leaves along {:?}, came along {direction:?}",
            theta.to_degrees(),
            t.direction
        );
        // Snell's law inside.
        let theta_in = (theta.sin() / n).asin();
        let inside = (p2 - p1).normalize();
        assert!(
            (inside.dot(axis) - theta_in.cos()).abs() < 1e-12,
            "θ = {}°: inside angle {}°, expected {}°",
            theta.to_degrees(),
            inside.dot(axis).acos().to_degrees(),
            theta_in.to_degrees()
        );
        // The lateral displacement between the incident and the emerging line.
        let expected = thickness * (theta - theta_in).sin() / theta_in.cos();
        let displacement = (p2 - p0).cross(direction).length();
        assert!(
            (displacement - expected).abs() < 1e-12,
            "θ = {}°: displaced by {displacement}, expected {expected}",
            theta.to_degrees()
        );
        // The entry is on the incident line.
        assert!((p1 - p0).cross(direction).length() < 1e-12);
    }
    assert_eq!(tally.refracted, 2 * angles.len());
}

// ---------------------------------------------------------------------------------------------
// 2. A mirror at 45° turns a ray by 90°
// ---------------------------------------------------------------------------------------------

#[test]
fn mirror_at_45_degrees_turns_rays_by_a_right_angle() {
    let mut rng = common::rng::Rng(0x7a11_2024);
    for case in 0..8 {
        let direction = rng.unit();
        let e = perpendicular(direction);
        let e = rotate(e, direction, rng.range(0.0, TAU));
        // The ray meets the mirror at 45° on its front (even cases) or its back (odd ones).
        let sign = if case % 2 == 0 { 1.0 } else { -1.0 };
        let normal = sign * -(direction + e).normalize();
        let hit = rng.point(3.0);
        let start = hit - rng.range(1.0, 4.0) * direction;
        let u = perpendicular(normal);
        let w = normal.cross(u);
        let objs = vec![Obj {
            name: "mirror",
            geo: Geo::Parallelogram {
                corner: hit - 0.5 * u - 0.5 * w,
                u,
                v: w,
            },
            law: Law::Mirror,
            surface: "{ type = \"mirror\" }",
        }];
        let rays = format!(
            "[[ray_trajectory]]\nstart = {}\ndirection = {}\n",
            v(start),
            v(direction)
        );
        let (d, traced) = trace_text(&scene_text("none", &objs, &rays));
        let t = &traced[0];
        let mut tally = Tally::default();
        check_trajectory(&d, &objs, t, &mut tally).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(tally.mirror, 1, "{t:#?}");
        assert_eq!(t.points.len(), 3, "{t:#?}");
        assert!(close_vec(t.points[1].position, hit, 1e-12), "{t:#?}");
        let turn = t.direction.dot(direction).clamp(-1.0, 1.0).acos();
        assert!(
            (turn - PI / 2.0).abs() < 1e-12,
            "case {case}: turned by {}°",
            turn.to_degrees()
        );
        // The reflected ray goes along the sheet's in-plane direction −e: in the plane of
        // incidence, away from the incident side.
        assert!(close_vec(t.direction, -e, 1e-12), "case {case}: {t:#?}");
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Points lie on surfaces, laws hold, ends are right
// ---------------------------------------------------------------------------------------------

/// A studio scene with glass, a Luneburg lens, a ray-rotating sheet, a mirror, a refracting
/// disc and a matt ball.
fn mixed_objects() -> Vec<Obj> {
    let mut objs = studio_objects();
    objs.extend([
        Obj {
            name: "glass ball",
            geo: Geo::Sphere {
                centre: DVec3::new(-0.7, 0.2, 6.0),
                radius: 0.5,
            },
            law: Law::Refracts(1.5),
            surface: "{ type = \"refractive\", index_ratio = 1.5 }",
        },
        Obj {
            name: "lens",
            geo: Geo::Sphere {
                centre: DVec3::new(0.8, 0.0, 6.0),
                radius: 0.6,
            },
            law: Law::Lens(Lens::Luneburg),
            surface: "{ type = \"luneburg-lens\" }",
        },
        Obj {
            name: "rotator",
            geo: Geo::Parallelogram {
                corner: DVec3::new(-1.5, -0.9, 9.0),
                u: DVec3::new(3.0, 0.0, 0.0),
                v: DVec3::new(0.0, 2.0, 0.0),
            },
            law: Law::Rotates(30.0),
            surface: "{ type = \"ray-rotating\", angle_deg = 30 }",
        },
        Obj {
            name: "mirror",
            geo: Geo::Parallelogram {
                corner: DVec3::new(-1.5, -1.0, 11.0),
                u: DVec3::new(3.0, 0.0, 0.0),
                v: DVec3::new(0.0, 2.0, 1.0),
            },
            law: Law::Mirror,
            surface: "{ type = \"mirror\" }",
        },
        Obj {
            name: "window",
            geo: Geo::Disc {
                centre: DVec3::new(0.0, 0.5, 3.0),
                normal: DVec3::new(0.0, 0.3, -1.0),
                radius: 0.4,
            },
            law: Law::Refracts(1.33),
            surface: "{ type = \"refractive\", index_ratio = 1.33 }",
        },
        Obj {
            name: "matt ball",
            geo: Geo::Sphere {
                centre: DVec3::new(0.0, -0.6, 4.5),
                radius: 0.3,
            },
            law: Law::Absorbs,
            surface: "{ type = \"matt\", colour = [0.2, 0.8, 0.2] }",
        },
    ]);
    objs
}

const MIXED_RAYS: &str = r#"
[[ray_trajectory]]
name = "cone"
start = [0, 0.1, 0]
direction = [0, 0, 1]
cone_half_angle_deg = 7
rays = 48
max_interactions = 40

[[ray_trajectory]]
name = "bundle"
start = [0.8, 0, 3]
direction = [0, 0, 1]
bundle_radius = 0.55
rays = 24

[[ray_trajectory]]
name = "down"
start = [0, 0, 0]
direction = [0, -0.5, 1]

[[ray_trajectory]]
name = "up"
start = [0, 0, 0]
direction = [0, 1, 0.2]

[[ray_trajectory]]
name = "wide cone"
start = [0, 0.2, 2]
direction = [0, -0.1, 1]
cone_half_angle_deg = 12
rays = 30

# From inside the glass ball, 0.35 R from its centre: rays across the radius meet the
# surface at sin θ = 0.7 > 1/1.5 and are trapped by total internal reflection.
[[ray_trajectory]]
name = "inside"
start = [-0.35, 0.2, 6]
direction = [0, 1, 0]
cone_half_angle_deg = 30
rays = 12
max_interactions = 25
"#;

#[test]
fn points_lie_on_their_surfaces_and_every_surface_applies_its_law() {
    let objs = mixed_objects();
    let (d, traced) = trace_text(&scene_text("empty", &objs, MIXED_RAYS));
    assert_eq!(d.objects[0].name, "sky");
    assert_eq!(d.objects[1].name, "floor");
    assert_eq!(traced.len(), 48 + 24 + 1 + 1 + 30 + 12);
    let mut tally = Tally::default();
    let mut errors = Vec::new();
    for t in &traced {
        if let Err(e) = check_trajectory(&d, &objs, t, &mut tally) {
            errors.push(e);
        }
        assert_ne!(t.end, End::Escaped, "nothing escapes the sky: {t:#?}");
    }
    assert!(
        errors.is_empty(),
        "{} of {} trajectories fail:\n{}",
        errors.len(),
        traced.len(),
        errors.join("\n\n")
    );
    // Each source and ray index appears once, in order.
    let ids: Vec<(usize, usize)> = traced.iter().map(|t| (t.source, t.ray)).collect();
    let mut expected = Vec::new();
    for (s, n) in [48, 24, 1, 1, 30, 12].into_iter().enumerate() {
        expected.extend((0..n).map(|k| (s, k)));
    }
    assert_eq!(ids, expected);
    // The test met every law (so it checked something).
    println!("{tally:?}");
    assert!(tally.mirror >= 3, "{tally:?}");
    assert!(tally.refracted >= 10, "{tally:?}");
    assert!(tally.lens >= 10, "{tally:?}");
    assert!(tally.totally_reflected >= 10, "{tally:?}");
    assert!(tally.rotated >= 10, "{tally:?}");
    for name in ["sky", "floor", "matt ball"] {
        assert!(tally.absorbed.contains(&name), "none absorbed by {name}");
    }
    // The ray aimed down ends on the floor, the one aimed up on the sky.
    let down = &traced[48 + 24];
    assert_eq!(down.end, End::Absorbed);
    assert_eq!(down.points.len(), 2, "{down:#?}");
    assert_eq!(down.points[1].object, Some(1));
    assert!(close_vec(
        down.points[1].position,
        DVec3::new(0.0, -1.0001, 2.0002),
        1e-12
    ));
    let up = &traced[48 + 24 + 1];
    assert_eq!(up.end, End::Absorbed);
    assert_eq!(up.points[1].object, Some(0));
    assert!((up.points[1].position.length() - 1e5).abs() < 1e-6);
    // The rays from inside the glass at 60° to 120° from the radius are trapped for good.
    let inside = &traced[48 + 24 + 1 + 1 + 30..];
    let trapped = inside
        .iter()
        .filter(|t| t.end == End::MaxInteractions)
        .count();
    assert!(trapped >= 2, "{trapped} trapped");
    for t in inside.iter().filter(|t| t.end == End::MaxInteractions) {
        assert_eq!(t.points.len(), 26);
        assert!(
            t.points[1..]
                .iter()
                .all(|p| p.object == Some(index_of(&d, "glass ball")))
        );
    }
}

#[test]
fn a_ray_that_meets_nothing_escapes_beyond_the_bounding_box() {
    let objs = vec![
        Obj {
            name: "ball",
            geo: Geo::Sphere {
                centre: DVec3::new(0.0, 0.0, 5.0),
                radius: 1.0,
            },
            law: Law::Refracts(1.5),
            surface: "{ type = \"refractive\", index_ratio = 1.5 }",
        },
        Obj {
            name: "far tile",
            geo: Geo::Parallelogram {
                corner: DVec3::new(20.0, 30.0, -40.0),
                u: DVec3::new(1.0, 0.0, 0.0),
                v: DVec3::new(0.0, 1.0, 0.0),
            },
            law: Law::Absorbs,
            surface: "{ type = \"matt\", colour = [1, 1, 1] }",
        },
    ];
    let rays = r#"
[[ray_trajectory]]
start = [0.3, 0.2, 0]
direction = [0, 0, 1]

[[ray_trajectory]]
start = [5, 0, 0]
direction = [0, 1, 0]
"#;
    let (d, traced) = trace_text(&scene_text("none", &objs, rays));
    let mut tally = Tally::default();
    for t in &traced {
        check_trajectory(&d, &objs, t, &mut tally).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(t.end, End::Escaped, "{t:#?}");
    }
    assert_eq!(traced[0].points.len(), 4, "{:#?}", traced[0]);
    assert_eq!(traced[1].points.len(), 2, "{:#?}", traced[1]);
    // Without any bounded object the drawn end is 1 away.
    let (_, traced) = trace_text(
        "studio = \"none\"\n[[ray_trajectory]]\nstart = [1, 2, 3]\ndirection = [0, 0, -2]\n",
    );
    let t = &traced[0];
    assert_eq!(t.end, End::Escaped);
    assert_eq!(t.points.len(), 2);
    assert!(
        close_vec(t.points[1].position, DVec3::new(1.0, 2.0, 2.0), 1e-12),
        "{t:#?}"
    );
    assert!(close_vec(t.direction, DVec3::NEG_Z, 1e-15));
}

#[test]
fn facing_mirrors_stop_a_ray_after_max_interactions() {
    let objs = vec![
        Obj {
            name: "left",
            geo: Geo::Plane {
                point: DVec3::new(-1.0, 0.0, 0.0),
                normal: DVec3::X,
            },
            law: Law::Mirror,
            surface: "{ type = \"mirror\" }",
        },
        Obj {
            name: "right",
            geo: Geo::Plane {
                point: DVec3::new(1.0, 0.0, 0.0),
                normal: DVec3::NEG_X,
            },
            law: Law::Mirror,
            surface: "{ type = \"mirror\" }",
        },
    ];
    for max in [1u32, 2, 7, 40] {
        let rays = format!(
            "[[ray_trajectory]]\nstart = [0, 0, 0]\ndirection = [1, 0.1, 0.05]\nmax_interactions = {max}\n"
        );
        let (d, traced) = trace_text(&scene_text("none", &objs, &rays));
        let t = &traced[0];
        let mut tally = Tally::default();
        check_trajectory(&d, &objs, t, &mut tally).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(t.end, End::MaxInteractions, "{t:#?}");
        assert_eq!(t.points.len(), max as usize + 1, "{t:#?}");
        assert_eq!(tally.mirror, max as usize);
        let (left, right) = (index_of(&d, "left"), index_of(&d, "right"));
        for (k, p) in t.points.iter().enumerate().skip(1) {
            // Alternately on the right and left mirror, 2 apart in x each time.
            let (object, x) = if k % 2 == 1 {
                (right, 1.0)
            } else {
                (left, -1.0)
            };
            assert_eq!(p.object, Some(object), "point {k}");
            let path = 1.0 + 2.0 * (k - 1) as f64;
            let expected = DVec3::new(x, 0.1 * path, 0.05 * path);
            assert!(close_vec(p.position, expected, 1e-12), "point {k}: {p:?}");
        }
    }
}

#[test]
fn teleported_rays_leave_the_destination_with_the_same_surface_coordinates() {
    // Source: 2 × 2 at z = 5, (u, v) = (x + 1, y + 1); destination: 1 × 1, facing −x, with
    // u along +z and v along +y.
    let rays = r#"
studio = "none"

[[object]]
name = "entrance"
shape = { type = "parallelogram", corner = [-1, -1, 5], span_u = [2, 0, 0], span_v = [0, 2, 0] }
surface = { type = "teleporting", destination = "exit" }

[[object]]
name = "exit"
shape = { type = "parallelogram", corner = [3, -0.5, 8], span_u = [0, 0, 1], span_v = [0, 1, 0] }
surface = { type = "transparent" }

[[ray_trajectory]]
start = [-0.5, -0.4, 0]
direction = [0.05, 0.1, 1]

[[ray_trajectory]]
start = [0.5, 0.5, 0]
direction = [0, 0, 1]
"#;
    let (d, traced) = trace_text(rays);
    let entrance = index_of(&d, "entrance");
    // Ray 0 meets the entrance at (−0.25, 0.1, 5): (u, v) = (0.75, 1.1), beyond the exit's
    // height of 1: lost.
    let t = &traced[0];
    assert_eq!(t.end, End::Lost, "{t:#?}");
    assert_eq!(t.points.len(), 2, "{t:#?}");
    assert_eq!(t.points[1].object, Some(entrance));
    assert!(close_vec(
        t.points[1].position,
        DVec3::new(-0.25, 0.1, 5.0),
        1e-12
    ));
    // Ray 1 meets it at (0.5, 0.5, 5): (u, v) = (1.5, 1.5), also beyond.
    assert_eq!(traced[1].end, End::Lost);
    // Moved to meet it at (−0.4, −0.7, 5): (u, v) = (0.6, 0.3), within the exit.
    let rays = rays.replace("start = [0.5, 0.5, 0]", "start = [-0.4, -0.7, 0]");
    let (_, traced) = trace_text(&rays);
    let t = &traced[1];
    let arrivals: Vec<Arrival> = t.points.iter().map(|p| p.arrival).collect();
    assert_eq!(
        arrivals,
        [
            Arrival::Start,
            Arrival::Straight,
            Arrival::Teleported,
            Arrival::Straight
        ],
        "{t:#?}"
    );
    assert_eq!(t.points[1].object, Some(entrance));
    assert_eq!(t.points[2].object, None);
    assert_eq!(t.end, End::Escaped);
    // (u, v) = (0.6, 0.3) on the exit: corner + 0.6 ẑ + 0.3 ŷ.
    assert!(
        close_vec(t.points[2].position, DVec3::new(3.0, -0.2, 8.6), 1e-12),
        "{t:#?}"
    );
    // Direction components along (u, v, w): (0, 0, 1) along (x̂, ŷ, ẑ) → along (ẑ, ŷ, −x̂).
    assert!(close_vec(t.direction, DVec3::NEG_X, 1e-12), "{t:#?}");
}

#[test]
fn chequerboard_tiles_and_array_copies_act_by_their_own_surfaces() {
    let text = r#"
studio = "none"

[[object]]
name = "mirrors"
shape = { type = "parallelogram", corner = [-0.5, -0.5, 5], span_u = [1, 0, 0], span_v = [0, 1, 1] }
surface = { type = "mirror" }
array = { vectors = [[2, 0, 0]], counts = [3] }

# (u, v) = (z, x): tiles with ⌊z⌋ + ⌊x⌋ even are mirrors, the others matt.
[[object]]
name = "tiles"
shape = { type = "plane", point = [0, -2, 0], normal = [0, 1, 0], u_direction = [0, 0, 1] }
surface = { type = "chequerboard", surfaces = [{ type = "mirror" }, { type = "matt", colour = [1, 1, 1] }] }

[[ray_trajectory]]
name = "third copy"
start = [4.2, 0.1, 0]
direction = [0, 0, 1]

[[ray_trajectory]]
name = "matt tile"
start = [0.5, -1, 0.2]
direction = [0, -1, 1]

[[ray_trajectory]]
name = "mirror tile"
start = [0.5, -1, -0.5]
direction = [0, -1, 1]
"#;
    let (d, traced) = trace_text(text);
    let (mirrors, tiles) = (index_of(&d, "mirrors"), index_of(&d, "tiles"));
    // The third copy of the mirror, 4 along x: the plane through (3.5, −0.5, 5) with normal
    // (0, −1, 1)/√2; met at z = 5.6, sent up along +y.
    let t = &traced[0];
    assert_eq!(t.points[1].object, Some(mirrors), "{t:#?}");
    assert!(
        close_vec(t.points[1].position, DVec3::new(4.2, 0.1, 5.6), 1e-12),
        "{t:#?}"
    );
    assert!(close_vec(t.direction, DVec3::Y, 1e-12), "{t:#?}");
    assert_eq!(t.end, End::Escaped);
    // A matt tile ((x, z) = (0.5, 1.2)) absorbs, a mirror tile ((0.5, 0.5)) reflects.
    let t = &traced[1];
    assert_eq!(t.end, End::Absorbed, "{t:#?}");
    assert_eq!(t.points.len(), 2);
    assert_eq!(t.points[1].object, Some(tiles));
    assert!(close_vec(
        t.points[1].position,
        DVec3::new(0.5, -2.0, 1.2),
        1e-12
    ));
    let t = &traced[2];
    assert_eq!(t.points[1].object, Some(tiles), "{t:#?}");
    assert!(close_vec(
        t.points[1].position,
        DVec3::new(0.5, -2.0, 0.5),
        1e-12
    ));
    assert!(
        close_vec(t.direction, DVec3::new(0.0, 1.0, 1.0).normalize(), 1e-12),
        "{t:#?}"
    );
    assert_ne!(t.end, End::Absorbed, "{t:#?}");
}

// ---------------------------------------------------------------------------------------------
// Lenses
// ---------------------------------------------------------------------------------------------

fn lens_scene(surface: &str, centre: DVec3, radius: f64, direction: DVec3) -> String {
    format!(
        r#"studio = "none"

[[object]]
name = "lens"
shape = {{ type = "sphere", centre = {}, radius = {radius:?} }}
surface = {surface}

[[ray_trajectory]]
start = {}
direction = {}
bundle_radius = {:?}
rays = 30
"#,
        v(centre),
        v(centre - 2.5 * radius * direction),
        v(direction),
        0.97 * radius
    )
}

#[test]
fn luneburg_lens_focuses_a_parallel_bundle_on_the_far_surface() {
    let centre = DVec3::new(0.2, -0.1, 5.0);
    let radius = 0.8;
    for direction in [DVec3::Z, DVec3::new(0.3, 0.2, 1.0).normalize()] {
        let text = lens_scene("{ type = \"luneburg-lens\" }", centre, radius, direction);
        let (_, traced) = trace_text(&text);
        assert_eq!(traced.len(), 30);
        let focus = centre + radius * direction;
        for t in &traced {
            let arrivals: Vec<Arrival> = t.points.iter().map(|p| p.arrival).collect();
            assert_eq!(
                arrivals,
                [
                    Arrival::Start,
                    Arrival::Straight,
                    Arrival::Chord,
                    Arrival::Straight
                ],
                "{t:#?}"
            );
            assert_eq!(t.points[1].object, Some(0));
            assert_eq!(t.points[2].object, Some(0));
            let entry = t.points[1].position;
            let exit = t.points[2].position;
            assert!(
                (entry.distance(centre) - radius).abs() < 1e-12,
                "entry off the sphere"
            );
            assert!(
                exit.distance(focus) < 1e-9 * radius,
                "exit {exit:?}, focus {focus:?}"
            );
            // From the focus, the ray goes on parallel to the line from the entry point to
            // the centre.
            let out = (centre - entry).normalize();
            assert!(close_vec(t.direction, out, 1e-9), "{t:#?}");
            assert_eq!(t.end, End::Escaped);
        }
    }
}

#[test]
fn eaton_and_maxwell_fisheye_lenses_map_entry_to_exit_in_closed_form() {
    let objs = vec![
        Obj {
            name: "eaton",
            geo: Geo::Sphere {
                centre: DVec3::new(-1.5, 0.0, 6.0),
                radius: 0.7,
            },
            law: Law::Lens(Lens::Eaton),
            surface: "{ type = \"eaton-lens\" }",
        },
        Obj {
            name: "maxwell",
            geo: Geo::Sphere {
                centre: DVec3::new(1.5, 0.0, 6.0),
                radius: 0.7,
            },
            law: Law::Lens(Lens::Maxwell),
            surface: "{ type = \"maxwell-fisheye-lens\" }",
        },
    ];
    let rays = r#"
[[ray_trajectory]]
name = "to eaton"
start = [-1.8, -0.15, 3]
direction = [0.1, 0.05, 1]
bundle_radius = 0.6
rays = 25

[[ray_trajectory]]
name = "to maxwell"
start = [1.5, 0.2, 3]
direction = [0, -0.05, 1]
cone_half_angle_deg = 8
rays = 25
"#;
    let (d, traced) = trace_text(&scene_text("none", &objs, rays));
    let mut tally = Tally::default();
    for t in &traced {
        check_trajectory(&d, &objs, t, &mut tally).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(t.end, End::Escaped);
    }
    assert!(tally.lens >= 40, "{tally:?}");
    // Every ray sent into the Eaton lens comes straight back.
    let back = DVec3::new(0.1, 0.05, 1.0).normalize();
    for t in traced.iter().filter(|t| t.source == 0) {
        assert_eq!(t.points[2].arrival, Arrival::Chord, "{t:#?}");
        assert!(close_vec(t.direction, -back, 1e-12), "{t:#?}");
    }
    // Every ray from the cone's apex that meets the Maxwell-fisheye lens leaves from the
    // antipode of its entry.
    let centre = DVec3::new(1.5, 0.0, 6.0);
    let mut crossing = 0;
    for t in traced
        .iter()
        .filter(|t| t.source == 1 && t.points.len() == 4)
    {
        let (entry, exit) = (t.points[1].position, t.points[2].position);
        assert!(close_vec(entry + exit, 2.0 * centre, 1e-9), "{t:#?}");
        crossing += 1;
    }
    assert!(
        crossing >= 20,
        "{crossing} rays cross the Maxwell-fisheye lens"
    );
}

/// Checks that the integrated path of `t` through a Luneburg lens (n² = 2 − (r/R)²) is the
/// analytic one. In Hamiltonian form, dr/dτ = p and dp/dτ = ∇(n²)/2 = −r/R², so inside the
/// lens r(τ) − C = (P − C) cos(τ/R) + R d sin(τ/R) with P the entry point and d the unit
/// entry direction (n = 1 at the surface, so p = d there): an ellipse centred on the lens
/// centre, in the plane of P − C and d, which meets the surface again at τ/R = π/2, at
/// C + R d, going along −(P − C)/R. `tol` is relative to R.
fn check_luneburg_ellipse(t: &Trajectory, centre: DVec3, radius: f64, tol: f64) -> usize {
    let pts = &t.points;
    assert_eq!(pts[1].arrival, Arrival::Straight, "{t:#?}");
    assert_eq!(pts[1].object, Some(0), "{t:#?}");
    let entry = pts[1].position;
    let d = (entry - pts[0].position).normalize();
    let a = (entry - centre) / radius;
    // The exit: the last Curved point, on the lens.
    let exit_k = pts
        .iter()
        .rposition(|p| p.arrival == Arrival::Curved)
        .unwrap_or_else(|| panic!("no curved points: {t:#?}"));
    assert_eq!(pts[exit_k].object, Some(0), "exit not on the lens: {t:#?}");
    assert_eq!(exit_k, pts.len() - 2, "{t:#?}");
    let inner = &pts[2..exit_k];
    assert!(inner.len() >= 3, "only {} inner points", inner.len());
    // Solve x = a cos s + d sin s for (cos s, sin s) in the plane of a and d.
    let (aa, ad, dd) = (a.dot(a), a.dot(d), d.dot(d));
    let det = aa * dd - ad * ad;
    let mut last_s = 0.0;
    for (k, p) in inner.iter().chain([&pts[exit_k]]).enumerate() {
        if k < inner.len() {
            assert_eq!(p.object, None, "inner point {k} on an object");
            assert_eq!(p.arrival, Arrival::Curved);
        }
        let x = (p.position - centre) / radius;
        let (xa, xd) = (x.dot(a), x.dot(d));
        let c = (xa * dd - xd * ad) / det;
        let s = (xd * aa - xa * ad) / det;
        let off_plane = (x - c * a - s * d).length();
        assert!(
            off_plane < tol,
            "point {k} leaves the plane of incidence by {off_plane:e} R"
        );
        assert!(
            (c * c + s * s - 1.0).abs() < tol,
            "point {k} is off the ellipse: cos² + sin² = {}",
            c * c + s * s
        );
        let angle = s.atan2(c);
        assert!(
            angle >= last_s - tol && angle <= PI / 2.0 + tol,
            "point {k}: parameter {angle} after {last_s}"
        );
        last_s = angle;
    }
    let exit = pts[exit_k].position;
    let focus = centre + radius * d;
    assert!(
        exit.distance(focus) < tol * radius,
        "exit {exit:?} misses the focus {focus:?} by {:e} R",
        exit.distance(focus) / radius
    );
    assert!(close_vec(t.direction, -a.normalize(), tol * 10.0), "{t:#?}");
    inner.len()
}

#[test]
fn integrated_luneburg_rays_follow_the_analytic_ellipses_to_the_focus() {
    let centre = DVec3::new(-0.3, 0.4, 6.0);
    let radius = 1.2;
    for direction in [DVec3::Z, DVec3::new(-0.2, 0.1, 1.0).normalize()] {
        let text = lens_scene(
            "{ type = \"luneburg-lens\", method = \"integration\" }",
            centre,
            radius,
            direction,
        );
        let (_, traced) = trace_text(&text);
        for t in &traced {
            assert_eq!(t.end, End::Escaped, "{t:#?}");
            check_luneburg_ellipse(t, centre, radius, 1e-9);
        }
    }
}

#[test]
fn tabulated_luneburg_profile_bends_rays_to_nearly_the_same_focus() {
    // A gradient-index lens with the Luneburg profile tabulated at 41 points: the spline
    // interpolation error is of order h⁴ ≈ 4e-7, so the paths are the ellipses to about 1e-6.
    let centre = DVec3::new(0.0, 0.0, 5.0);
    let radius = 1.0;
    let rho: Vec<f64> = (0..=40).map(|k| k as f64 / 40.0).collect();
    let n: Vec<f64> = rho.iter().map(|r| (2.0 - r * r).sqrt()).collect();
    let list = |xs: &[f64]| {
        let parts: Vec<String> = xs.iter().map(|x| format!("{x:?}")).collect();
        format!("[{}]", parts.join(", "))
    };
    let surface = format!(
        "{{ type = \"gradient-index-lens\", rho = {}, n = {} }}",
        list(&rho),
        list(&n)
    );
    let text = lens_scene(&surface, centre, radius, DVec3::Z);
    let (_, traced) = trace_text(&text);
    for t in &traced {
        assert_eq!(t.end, End::Escaped, "{t:#?}");
        check_luneburg_ellipse(t, centre, radius, 1e-5);
    }
}

// ---------------------------------------------------------------------------------------------
// Sources: cones and bundles
// ---------------------------------------------------------------------------------------------

#[test]
fn cone_rays_make_the_half_angle_with_the_axis_equally_spaced_round_it() {
    let axis = DVec3::new(0.2, -0.4, 1.0).normalize();
    let start = DVec3::new(0.5, 0.25, -1.0);
    for (axis, half_angle, rays) in [
        (axis, 25.0f64, 12usize),
        (axis, 90.0, 5),
        (axis, 150.0, 7),
        (DVec3::X, 10.0, 9),
        (DVec3::NEG_Y, 45.0, 4),
    ] {
        let text = format!(
            "studio = \"none\"\n[[ray_trajectory]]\nstart = {}\ndirection = {}\ncone_half_angle_deg = {half_angle:?}\nrays = {rays}\n",
            v(start),
            v(axis * 3.0)
        );
        let (_, traced) = trace_text(&text);
        assert_eq!(traced.len(), rays);
        let mut azimuths = Vec::new();
        let reference = perpendicular(axis);
        for t in &traced {
            assert!(close_vec(t.points[0].position, start, 1e-15));
            let d = t.direction;
            assert!(close_vec(
                d,
                (t.points[1].position - start).normalize(),
                1e-12
            ));
            let angle = d.dot(axis).clamp(-1.0, 1.0).acos().to_degrees();
            assert!(
                (angle - half_angle).abs() < 1e-9,
                "ray at {angle}° from the axis, not {half_angle}°"
            );
            let across = d - d.dot(axis) * axis;
            azimuths.push(
                across
                    .dot(axis.cross(reference))
                    .atan2(across.dot(reference)),
            );
        }
        // Equally spaced: sorted, successive azimuths are 360°/rays apart.
        azimuths.sort_by(f64::total_cmp);
        for k in 0..rays {
            let next = if k + 1 < rays {
                azimuths[k + 1]
            } else {
                azimuths[0] + TAU
            };
            let gap = next - azimuths[k];
            assert!(
                (gap - TAU / rays as f64).abs() < 1e-9,
                "azimuth gap {}°",
                gap.to_degrees()
            );
        }
    }
}

#[test]
fn bundle_rays_are_parallel_and_start_in_the_disc_across_the_direction() {
    let axis = DVec3::new(-0.3, 0.5, 0.8).normalize();
    let centre = DVec3::new(1.0, -2.0, 3.0);
    let text = format!(
        "studio = \"none\"\n[[ray_trajectory]]\nstart = {}\ndirection = {}\nbundle_radius = 0.4\nrays = 200\n",
        v(centre),
        v(axis)
    );
    let (_, traced) = trace_text(&text);
    assert_eq!(traced.len(), 200);
    let starts: Vec<DVec3> = traced.iter().map(|t| t.points[0].position).collect();
    for (t, &s) in traced.iter().zip(&starts) {
        assert!(close_vec(t.direction, axis, 1e-15));
        assert!(
            (s - centre).dot(axis).abs() < 1e-12,
            "start off the disc's plane"
        );
        assert!(s.distance(centre) <= 0.4 + 1e-12, "start beyond the disc");
    }
    // Distinct, and spread over the disc: some in each quadrant, a quarter within half the
    // radius (a quarter of the area), give or take a few.
    let (u, w) = (perpendicular(axis), axis.cross(perpendicular(axis)));
    let mut quadrants = [0; 4];
    for s in &starts {
        let r = *s - centre;
        quadrants[usize::from(r.dot(u) > 0.0) + 2 * usize::from(r.dot(w) > 0.0)] += 1;
    }
    assert!(quadrants.iter().all(|&q| q > 30), "{quadrants:?}");
    let inner = starts.iter().filter(|s| s.distance(centre) < 0.2).count();
    assert!(
        (40..=60).contains(&inner),
        "{inner} of 200 within half the radius"
    );
    for i in 0..starts.len() {
        for j in 0..i {
            assert!(
                starts[i].distance(starts[j]) > 1e-3,
                "rays {i} and {j} coincide"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Rendering: the trajectory is drawn in its colour, and nothing else is
// ---------------------------------------------------------------------------------------------

/// A ray from S bounces off a mirror seen edge-on by the camera (its plane contains the
/// camera's pinhole, so it covers no pixel and shows no reflection) and ends on a matt wall
/// that no light lights (black).
const RENDER_SCENE: &str = r#"
studio = "none"

[render]
width = 160
height = 120

[camera]
horizontal_view_angle_deg = 20

[[object]]
name = "edge-on mirror"
shape = { type = "parallelogram", corner = [0.28333333333333333, -0.5, 8.5], span_u = [0, 1, 0], span_v = [0.03333333333333333, 0, 1] }
surface = { type = "mirror" }

[[object]]
name = "wall"
shape = { type = "parallelogram", corner = [-5, -5, 12], span_u = [10, 0, 0], span_v = [0, 10, 0] }
surface = { type = "matt", colour = [1, 1, 1] }
"#;

const RENDER_TRAJECTORY: &str = r#"
[[ray_trajectory]]
name = "green"
start = [-0.8, 0.3, 7]
direction = [1.1, -0.3, 2]
radius = 0.06
colour = [0, 1, 0]
"#;

/// Pixel coordinates (x right, y down) of a point in front of the standard pinhole camera:
/// the pixel pitch at unit distance is 2 tan(angle/2)/(width − 1), and pixel (x, y)'s centre
/// is at ((x − (w − 1)/2) p, ((h − 1)/2 − y) p) on the detector at distance 1.
fn project(p: DVec3, width: u32, height: u32, angle_deg: f64) -> (f64, f64) {
    let pitch = 2.0 * (angle_deg.to_radians() / 2.0).tan() / (width - 1) as f64;
    (
        0.5 * (width - 1) as f64 + p.x / p.z / pitch,
        0.5 * (height - 1) as f64 - p.y / p.z / pitch,
    )
}

fn distance_to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (ux, uy) = (b.0 - a.0, b.1 - a.1);
    let (px, py) = (p.0 - a.0, p.1 - a.1);
    let s = ((px * ux + py * uy) / (ux * ux + uy * uy)).clamp(0.0, 1.0);
    ((px - s * ux).powi(2) + (py - s * uy).powi(2)).sqrt()
}

fn is_green(c: DVec3) -> bool {
    (c.y - 1.0).abs() < 1e-6 && c.x.abs() < 1e-6 && c.z.abs() < 1e-6
}

#[test]
fn a_trajectory_renders_in_its_colour_along_its_projected_path_only() {
    let text = format!("{RENDER_SCENE}{RENDER_TRAJECTORY}");
    let (d, traced) = trace_text(&text);
    let t = &traced[0];
    // The path: start, the mirror, the wall.
    assert_eq!(t.end, End::Absorbed, "{t:#?}");
    assert_eq!(t.points.len(), 3, "{t:#?}");
    assert_eq!(t.points[1].object, Some(index_of(&d, "edge-on mirror")));
    assert_eq!(t.points[2].object, Some(index_of(&d, "wall")));
    assert!(close_vec(
        t.points[1].position,
        DVec3::new(0.3, 0.0, 9.0),
        1e-9
    ));

    let image = common::images::render_text(&text);
    let (w, h) = (image.width, image.height);
    let projected: Vec<(f64, f64)> = t
        .points
        .iter()
        .map(|p| project(p.position, w, h, 20.0))
        .collect();
    // Along the path, sampled between its points (the tube is 3–5 pixels wide there).
    let mut sampled = 0;
    for seg in t.points.windows(2) {
        for k in 1..20 {
            let p = seg[0].position.lerp(seg[1].position, k as f64 / 20.0);
            let (x, y) = project(p, w, h, 20.0);
            let (x, y) = (x.round(), y.round());
            if x < 0.0 || y < 0.0 || x >= w as f64 || y >= h as f64 {
                continue;
            }
            sampled += 1;
            let c = image.pixel(x as u32, y as u32);
            assert!(
                is_green(c),
                "pixel ({x}, {y}) on the path of {p:?} is {c:?}"
            );
        }
    }
    assert!(sampled >= 30, "only {sampled} path samples in the picture");
    // Away from the path: black.
    let mut near = 0;
    for y in 0..h {
        for x in 0..w {
            let c = image.pixel(x, y);
            let distance = projected
                .windows(2)
                .map(|s| distance_to_segment((x as f64, y as f64), s[0], s[1]))
                .fold(f64::INFINITY, f64::min);
            if distance > 8.0 {
                assert!(
                    c.length() < 1e-9,
                    "pixel ({x}, {y}), {distance:.1} px from the path, is {c:?}"
                );
            } else if is_green(c) {
                near += 1;
            }
        }
    }
    assert!(near >= 100, "only {near} green pixels");
    // Without the trajectory, nothing is green.
    let plain = common::images::render_text(RENDER_SCENE);
    let green = plain.pixels.iter().filter(|c| c.y > 0.01).count();
    assert_eq!(green, 0, "green pixels without the trajectory");
}

/// A lit studio scene (floor lit by the studio's point light, which is above, right and behind
/// the camera) with something green just above the floor.
fn lit_scene(extra: &str) -> String {
    format!(
        r#"studio = "empty"

[render]
width = 160
height = 120

{extra}
"#
    )
}

#[test]
fn drawn_trajectories_emit_their_colour_and_throw_no_shadow() {
    let tube = r#"
[[ray_trajectory]]
start = [-0.3, -0.5, 4]
direction = [0, 0, 1]
radius = 0.05
colour = [0, 1, 0]
"#;
    // The same tube as a shadow-throwing object, to show that a shadow would be seen.
    let object = r#"
[[object]]
name = "solid tube"
shadow_throwing = true
shape = { type = "cylinder", start = [-0.3, -0.5, 4], end = [-0.3, -0.5, 40], radius = 0.05 }
surface = { type = "constant_colour", colour = [0, 1, 0] }
"#;
    let plain = common::images::render_text(&lit_scene(""));
    let drawn = common::images::render_text(&lit_scene(tube));
    let solid = common::images::render_text(&lit_scene(object));
    let changed = |image: &timbre::render::Image| -> (usize, usize) {
        let mut green = 0;
        let mut other = 0;
        for (a, b) in image.pixels.iter().zip(&plain.pixels) {
            if a != b {
                if is_green(*a) {
                    green += 1;
                } else {
                    other += 1;
                }
            }
        }
        (green, other)
    };
    let (green, other) = changed(&solid);
    assert!(
        green > 50 && other > 20,
        "the control shows no shadow: {green}, {other}"
    );
    // Every pixel the trajectory changes is its own colour, exactly: no shadow, no shading.
    let (green, other) = changed(&drawn);
    assert!(green > 50, "only {green} pixels of the trajectory");
    assert_eq!(
        other, 0,
        "pixels changed by the trajectory but not its colour"
    );
}

// ---------------------------------------------------------------------------------------------
// 5. Bad input
// ---------------------------------------------------------------------------------------------

#[test]
fn bad_trajectory_tables_are_rejected_with_the_line_of_the_mistake() {
    // (the table's keys after `start`, the line of the mistake, words the message must have)
    let cases: [(&str, usize, &[&str]); 9] = [
        ("direction = [0, 0, 0]", 5, &["direction", "zero"]),
        (
            "direction = [0, 0, 1]\nradius = -0.5",
            6,
            &["positive", "-0.5"],
        ),
        ("direction = [0, 0, 1]\nradius = 0", 6, &["positive"]),
        (
            "direction = [0, 0, 1]\nrays = 5",
            6,
            &["rays", "cone_half_angle_deg", "bundle_radius"],
        ),
        (
            "direction = [0, 0, 1]\nrays = 5\ncone_half_angle_deg = 10\nbundle_radius = 0.5",
            7,
            &["cone_half_angle_deg", "bundle_radius", "not both"],
        ),
        (
            "direction = [0, 0, 1]\nrays = 5\ncone_half_angle_deg = 180",
            7,
            &["cone_half_angle_deg", "180"],
        ),
        (
            "direction = [0, 0, 1]\nrays = 10001\nbundle_radius = 1",
            6,
            &["from 1 to 10000", "10001"],
        ),
        (
            "direction = [0, 0, 1]\nrays = 0",
            6,
            &["from 1 to 10000", "got 0"],
        ),
        (
            "direction = [0, 0, 1]\nmax_interactions = 0",
            6,
            &["from 1 to 10000", "got 0"],
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (k, (keys, line, needles)) in cases.iter().enumerate() {
        let text = format!("studio = \"none\"\n\n[[ray_trajectory]]\nstart = [0, 0, 0]\n{keys}\n");
        let name = format!("bad{k}.toml");
        let path = write(dir.path(), &name, &text);
        for command in ["trace", "check"] {
            let run = timbre(dir.path(), &[command, path_str(&path)]);
            run.assert_bad_input(needles);
            let (at, _) = location(&run.stderr, &path);
            assert_eq!(at, *line, "{command} {keys:?}: {}", run.stderr);
        }
    }
}

#[test]
fn trace_without_trajectories_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "plain.toml", "studio = \"none\"\n");
    timbre(dir.path(), &["trace", path_str(&path)]).assert_bad_input(&["ray_trajectory"]);
}

// ---------------------------------------------------------------------------------------------
// The command line: `timbre trace --json` is `trace()`
// ---------------------------------------------------------------------------------------------

const CLI_SCENE: &str = r#"
studio = "empty"

[[object]]
name = "glass"
shape = { type = "sphere", centre = [-0.5, 0, 5], radius = 0.5 }
surface = { type = "refractive", index_ratio = 1.5 }

[[object]]
name = "lens"
shape = { type = "sphere", centre = [0.7, 0, 5], radius = 0.5 }
surface = { type = "luneburg-lens" }

[[object]]
name = "mirror a"
shape = { type = "parallelogram", corner = [5, -1, 20], span_u = [0, 2, 0], span_v = [0, 0, 2] }
surface = { type = "mirror" }

[[object]]
name = "mirror b"
shape = { type = "parallelogram", corner = [7, -1, 20], span_u = [0, 0, 2], span_v = [0, 2, 0] }
surface = { type = "mirror" }

[[ray_trajectory]]
name = "cone"
start = [0, 0, 0]
direction = [0, 0, 1]
cone_half_angle_deg = 6
rays = 16

[[ray_trajectory]]
name = "trapped"
start = [6, 0, 21]
direction = [1, 0, 0]
max_interactions = 5

[[ray_trajectory]]
start = [0, 0, 0]
direction = [0, -1, 1]
"#;

#[test]
fn trace_json_lists_the_same_paths_as_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "scene.toml", CLI_SCENE);
    let run = timbre(dir.path(), &["trace", "--json", path_str(&path)]);
    run.assert_success();
    let json: serde_json::Value =
        serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("{e}: {}", run.stdout));
    let (d, traced) = trace_text(CLI_SCENE);
    assert_eq!(json["scene"].as_str(), Some(path_str(&path)));
    let rays = json["rays"].as_array().expect("a rays array");
    assert_eq!(rays.len(), traced.len());
    let ends: Vec<&str> = rays.iter().map(|r| r["end"].as_str().unwrap()).collect();
    assert!(
        ends.contains(&"absorbed") && ends.contains(&"max-interactions"),
        "{ends:?}"
    );
    let vector = |x: &serde_json::Value| -> DVec3 {
        let a = x.as_array().expect("a vector");
        assert_eq!(a.len(), 3);
        DVec3::new(
            a[0].as_f64().unwrap(),
            a[1].as_f64().unwrap(),
            a[2].as_f64().unwrap(),
        )
    };
    for (r, t) in rays.iter().zip(&traced) {
        let name = &d.trajectories[t.source].name;
        assert_eq!(r["trajectory"].as_str(), Some(name.as_str()));
        assert_eq!(r["ray"].as_u64(), Some(t.ray as u64));
        assert_eq!(r["end"].as_str(), Some(t.end.name()));
        assert!(close_vec(vector(&r["direction"]), t.direction, 1e-15));
        let points = r["points"].as_array().unwrap();
        assert_eq!(points.len(), t.points.len());
        for (jp, p) in points.iter().zip(&t.points) {
            let position = vector(&jp["position"]);
            assert!(close_vec(
                position,
                p.position,
                1e-14 * (1.0 + p.position.length())
            ));
            assert_eq!(jp["arrival"].as_str(), Some(p.arrival.name()));
            let object = p.object.map(|i| d.objects[i].name.as_str());
            assert_eq!(jp["object"].as_str(), object);
        }
    }
    assert_eq!(rays.last().unwrap()["trajectory"], "ray_trajectory 3");
    // The trapped ray: 5 points on the mirrors, alternately.
    let trapped = &rays[16];
    assert_eq!(trapped["end"], "max-interactions");
    let objects: Vec<&str> = trapped["points"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|p| p["object"].as_str())
        .collect();
    assert_eq!(
        objects,
        ["mirror b", "mirror a", "mirror b", "mirror a", "mirror b"]
    );
    // Kebab-case names.
    assert_eq!(End::MaxInteractions.name(), "max-interactions");
    assert_eq!(Arrival::Teleported.name(), "teleported");

    // --set changes the traced file.
    let run = timbre(
        dir.path(),
        &[
            "trace",
            "--json",
            path_str(&path),
            "--set",
            "ray_trajectory.2.direction=[0,1,0]",
        ],
    );
    run.assert_success();
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let last = json["rays"].as_array().unwrap().last().unwrap();
    assert_eq!(vector(&last["direction"]), DVec3::Y);
    assert_eq!(last["points"][1]["object"], "sky");

    // The plain listing names every ray and its end.
    let run = timbre(dir.path(), &["trace", path_str(&path)]);
    run.assert_success();
    for t in &traced {
        let name = &d.trajectories[t.source].name;
        let header = format!(
            "{name} ray {}: {} points, {}",
            t.ray,
            t.points.len(),
            t.end.name()
        );
        assert!(
            run.stdout.contains(&header),
            "no {header:?} in:\n{}",
            run.stdout
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Edge cases of the laws and limits
// ---------------------------------------------------------------------------------------------

/// An integrated Eaton lens, whose equations are regularised at the singular centre: a ray aimed
/// at the centre is integrated into it along the axis and straight back out of the point where
/// it entered (a crossing, not a reflection), drawn by the integrator's steps.
#[test]
fn a_ray_aimed_at_an_integrated_eaton_centre_goes_there_and_back() {
    let text = r#"studio = "none"
[[object]]
name = "lens"
shape = { type = "sphere", centre = [0, 0, 5], radius = 1 }
surface = { type = "eaton-lens", method = "integration" }
[[ray_trajectory]]
start = [0, 0, 2]
direction = [0, 0, 1]
"#;
    let (d, traced) = trace_text(text);
    let lens = index_of(&d, "lens");
    let p = &traced[0].points;
    let last = p.len() - 1;
    assert!(p.len() > 5, "{p:?}");
    assert_eq!(
        (p[1].position, p[1].object),
        (DVec3::new(0.0, 0.0, 4.0), Some(lens))
    );
    let inside = &p[2..last - 1];
    assert!(inside.iter().all(|q| q.arrival == Arrival::Curved
        && q.position.x == 0.0
        && q.position.y == 0.0
        && (4.0..=5.0).contains(&q.position.z)));
    let deepest = inside.iter().map(|q| q.position.z).fold(0.0, f64::max);
    assert!(deepest > 4.9, "{p:?}");
    assert_eq!(
        (p[last - 1].arrival, p[last - 1].object),
        (Arrival::Curved, Some(lens))
    );
    assert!(close_vec(p[last - 1].position, p[1].position, 1e-12));
    assert_eq!(traced[0].direction, DVec3::NEG_Z);
    assert_eq!(traced[0].end, End::Escaped);
}

/// A lens whose surface index is below the surroundings' reflects rays beyond the critical
/// angle off its surface, at a point: no crossing.
#[test]
fn a_lens_surface_beyond_the_critical_angle_reflects_at_a_point() {
    let text = r#"studio = "none"
[[object]]
name = "lens"
shape = { type = "sphere", centre = [0, 0, 5], radius = 1 }
surface = { type = "luneburg-lens", index_ratio = 0.5 }
[[ray_trajectory]]
start = [0.95, 0, 0]
direction = [0, 0, 1]
"#;
    let (d, traced) = trace_text(text);
    let t = &traced[0];
    assert_eq!(t.points.len(), 3, "{:?}", t.points);
    let hit = t.points[1].position;
    assert_eq!(
        (t.points[1].arrival, t.points[1].object),
        (Arrival::Straight, Some(index_of(&d, "lens")))
    );
    // sin θ = 0.95 > 0.5: totally reflected, the mirror image in the surface.
    let n = (hit - DVec3::new(0.0, 0.0, 5.0)).normalize();
    assert!(
        close_vec(t.direction, reflect(DVec3::Z, n), 1e-12),
        "{}",
        t.direction
    );
    assert_eq!(t.points[2].arrival, Arrival::Straight);
}

/// Meshes redirect trajectories like analytic shapes: a 45° mirror made of two triangles.
#[test]
fn a_mesh_mirror_at_45_degrees_turns_the_ray_by_a_right_angle() {
    let text = r#"studio = "none"
[[object]]
name = "mesh mirror"
shape = { type = "triangle_mesh", vertices = [[-1, -1, 4], [1, -1, 4], [1, 1, 6], [-1, 1, 6]], triangles = [[0, 1, 2], [0, 2, 3]] }
surface = { type = "mirror" }
[[ray_trajectory]]
start = [0.2, 0.1, 0]
direction = [0, 0, 1]
"#;
    let (d, traced) = trace_text(text);
    let t = &traced[0];
    assert_eq!(t.points[1].object, Some(index_of(&d, "mesh mirror")));
    assert!(close_vec(
        t.points[1].position,
        DVec3::new(0.2, 0.1, 5.1),
        1e-6
    ));
    assert!(close_vec(t.direction, DVec3::Y, 1e-6), "{}", t.direction);
}

/// A mirror that reflects nothing ends the trajectory there: no light goes on.
#[test]
fn a_coefficient_of_zero_loses_the_ray() {
    let mirror = |r: &str| {
        format!(
            "studio = \"none\"\n[[object]]\nshape = {{ type = \"plane\", point = [0, 0, 5], normal = [0, 1, -1] }}\nsurface = {{ type = \"mirror\", reflection = {r} }}\n[[ray_trajectory]]\nstart = [0, 0, 0]\ndirection = [0, 0, 1]\n"
        )
    };
    let (_, traced) = trace_text(&mirror("0"));
    assert_eq!((traced[0].end, traced[0].points.len()), (End::Lost, 2));
    let (_, traced) = trace_text(&mirror("0.01"));
    assert_eq!((traced[0].end, traced[0].points.len()), (End::Escaped, 3));
}

#[test]
fn too_many_points_in_all_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"studio = "none"
[[object]]
shape = { type = "plane", point = [0, 0, 0], normal = [0, 0, 1] }
surface = { type = "mirror" }
[[object]]
shape = { type = "plane", point = [0, 0, 1], normal = [0, 0, -1] }
surface = { type = "mirror" }
[[ray_trajectory]]
start = [0, 0, 0.5]
direction = [0.1, 0, 1]
bundle_radius = 0.1
rays = 100
max_interactions = 10000
"#;
    let path = write(dir.path(), "mirrors.toml", text);
    for command in ["trace", "render"] {
        timbre(dir.path(), &[command, path_str(&path)]).assert_bad_input(&[
            "mirrors.toml",
            "more than 500000 points",
            "max_interactions",
        ]);
    }
    let fewer = text.replace("rays = 100", "rays = 40");
    let path = write(dir.path(), "fewer.toml", fewer);
    timbre(dir.path(), &["trace", path_str(&path)]).assert_success();
}

#[test]
fn a_trajectory_starting_inside_a_lens_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"studio = "none"
[[object]]
name = "ball lens"
shape = { type = "sphere", centre = [0, 0, 5], radius = 1 }
surface = { type = "luneburg-lens" }
[[ray_trajectory]]
name = "inner ray"
start = [0, 0.5, 5]
direction = [0, 0, 1]
"#;
    let path = write(dir.path(), "inside.toml", text);
    let run = timbre(dir.path(), &["check", path_str(&path)]);
    run.assert_success();
    assert!(
        run.stderr
            .contains("ray trajectory 'inner ray': starts inside lens 'ball lens'"),
        "{}",
        run.stderr
    );
}

/// Trajectories are traced before any is drawn: a ray crossing another's path passes its
/// cylinder, both in the recorded points and in the scene that is rendered.
#[test]
fn trajectories_do_not_meet_each_others_cylinders() {
    let text = r#"studio = "none"
[[ray_trajectory]]
name = "across"
start = [-3, 0, 5]
direction = [1, 0, 0]
radius = 0.2
[[ray_trajectory]]
name = "along"
start = [0, 0, 0]
direction = [0, 0, 1]
"#;
    let (d, traced) = trace_text(text);
    for t in &traced {
        assert_eq!((t.end, t.points.len()), (End::Escaped, 2), "{t:?}");
    }
    let device = common::rays::device();
    assert!(
        matches!(
            timbre::scene::Scene::build(device, &d),
            Err(timbre::scene::BuildError::UndrawnTrajectories)
        ),
        "a scene is not built with its trajectories left out"
    );
    let drawn = trajectories::draw(device, &d).unwrap();
    assert!(drawn.trajectories.is_empty());
    let scene = timbre::scene::Scene::build(device, &drawn).unwrap();
    let drawn = &scene.scene_frame;
    assert!(drawn.objects.iter().any(|o| o.name == "across"));
    let hit = drawn
        .geometry
        .nearest(DVec3::ZERO, DVec3::Z, 0.0, f64::INFINITY)
        .expect("the drawn scene has the cylinders");
    assert_eq!(
        drawn.objects[hit.object].name, "along",
        "its own cylinder first"
    );
}

/// A hyperboloid of skew rays (Dr TIM's `RayTrajectoryHyperboloid`: waist radius w, angle α to
/// the axis) through an ideal thin lens of focal length f, a distance L beyond the waist, is
/// another hyperboloid of skew rays: worked out here in the transverse plane, a ray at the lens
/// is at p = w r̂ + L tan α φ̂ with slope s = tan α φ̂, and leaves with the slope s − p/f; it is
/// nearest the axis, at √(|p|² − (p·s′)²/|s′|²), a distance z* = −p·s′/|s′|² beyond the lens,
/// the same for every ray (they are the same ray turned about the axis). The rays start on the
/// waist circle.
#[test]
fn a_hyperboloid_of_skew_rays_is_imaged_by_a_lens_into_another() {
    let (w, alpha, f, l) = (0.3f64, 0.2f64, 1.5, 2.0);
    let text = format!(
        "studio = \"none\"\n\
         [[object]]\nname = \"lens\"\n\
         shape = {{ type = \"disc\", centre = [0, 0, {l}], normal = [0, 0, 1], radius = 5 }}\n\
         surface = {{ type = \"ideal-thin-lens\", focal_length = {f}, principal_point = [0, 0, {l}], optical_axis = [0, 0, 1], transmission_coefficient = 1 }}\n\
         [[ray_trajectory]]\nstart = [0, 0, 0]\ndirection = [0, 0, 1]\n\
         cone_half_angle_deg = {}\nwaist_radius = {w}\nrays = 6\n",
        alpha.to_degrees()
    );
    let (_, traced) = trace_text(&text);
    assert_eq!(traced.len(), 6);
    // In the transverse plane, the ray of azimuth 0 (all others are it turned).
    let p = glam::DVec2::new(w, l * alpha.tan());
    let s = glam::DVec2::new(0.0, alpha.tan()) - p / f;
    let z_star = -p.dot(s) / s.length_squared();
    let r_star = (p.length_squared() - p.dot(s).powi(2) / s.length_squared()).sqrt();
    for t in &traced {
        let start = t.points[0].position;
        assert!((start.truncate().length() - w).abs() < 1e-12 && start.z == 0.0);
        let lens = t.points[1].position;
        assert!((lens.z - l).abs() < 1e-9, "{lens}");
        // Nearest the axis along the ray after the lens.
        let d = t.direction;
        let (q, e) = (lens.truncate(), d.truncate());
        let along = -q.dot(e) / e.length_squared();
        let nearest = lens + along * d;
        assert!(
            (nearest.z - l - z_star).abs() < 1e-9,
            "waist at {} beyond the lens, expected {z_star}",
            nearest.z - l
        );
        assert!(
            (nearest.truncate().length() - r_star).abs() < 1e-9,
            "waist radius {}, expected {r_star}",
            nearest.truncate().length()
        );
    }
}

#[test]
fn a_waist_radius_needs_a_cone_angle() {
    let dir = tempfile::TempDir::new().unwrap();
    let scene = write(
        &dir,
        "bad.toml",
        "[[ray_trajectory]]\nstart = [0, 0, 0]\ndirection = [0, 0, 1]\nwaist_radius = 1\nrays = 4\n",
    );
    let run = timbre(dir.path(), &["check", path_str(&scene)]);
    run.assert_bad_input(&["waist_radius", "cone_half_angle_deg"]);
    assert_eq!(location(&run.stderr, &scene).0, 4, "{}", run.stderr);
}

// ---------------------------------------------------------------------------------------------
// `seen_by`: Dr TIM's programs trace their trajectories, then remove objects (or add some)
// before rendering. A trajectory meets an object only the trajectories see, and passes one
// only the camera sees as though it were not there; the picture is the other way round.
// ---------------------------------------------------------------------------------------------

/// A ray along +z at x = 0.1 meets a mirror at z = 5 (seen by the trajectories only) and comes
/// back by the law of reflection, through a ball at z = 2 that only the camera sees.
#[test]
fn trajectories_meet_what_only_they_see_and_pass_what_only_the_camera_sees() {
    let objects = |mirror: &str, ball: &str| {
        format!(
            "studio = \"none\"\n\
             [[object]]\nname = \"mirror\"\n{mirror}\
             shape = {{ type = \"disc\", centre = [0, 0, 5], normal = [0, 0, 1], radius = 1 }}\n\
             surface = {{ type = \"mirror\" }}\n\
             [[group]]\n{ball}\
             [[group.object]]\nname = \"ball\"\n\
             shape = {{ type = \"sphere\", centre = [0, 0, 2], radius = 0.3 }}\n\
             surface = {{ type = \"matt\", colour = [1, 0, 0] }}\n"
        )
    };
    let ray = "[[ray_trajectory]]\nstart = [0.1, 0, 0]\ndirection = [0, 0, 1]\n";
    let text = objects("seen_by = \"trajectories\"\n", "seen_by = \"camera\"\n") + ray;
    let (d, traced) = trace_text(&text);
    let t = &traced[0];
    // Straight through the ball to the mirror, reflected back along −z.
    assert_eq!(t.points[1].object, Some(index_of(&d, "mirror")));
    assert!(close_vec(
        t.points[1].position,
        DVec3::new(0.1, 0.0, 5.0),
        1e-12
    ));
    assert!(close_vec(t.direction, reflect(DVec3::Z, DVec3::Z), 1e-12));
    assert_eq!(t.end, End::Escaped);
    assert!(
        t.points
            .iter()
            .all(|p| p.object != Some(index_of(&d, "ball")))
    );
    // Seen by all, the ball absorbs it.
    let (d, traced) = trace_text(&(objects("", "") + ray));
    assert_eq!(traced[0].end, End::Absorbed);
    assert_eq!(traced[0].points[1].object, Some(index_of(&d, "ball")));

    // The picture leaves out what only the trajectories see: with the mirror only the
    // trajectories see and no trajectory, it is the picture without the mirror, byte for byte;
    // with the mirror seen by all (reflecting the sky dimmed by 0.96), it differs.
    let light = "[[light]]\ntype = \"point\"\nposition = [0, 3, 0]\ncolour = [1, 1, 1]\n\
                 [[object]]\nname = \"sky\"\n\
                 shape = { type = \"sphere\", centre = [0, 0, 0], radius = 100 }\n\
                 surface = { type = \"constant-colour\", colour = [0.5, 0.5, 1] }\n\
                 [camera]\nposition = [0, 0, -1]\nlook_at = [0, 0, 3]\n[render]\nwidth = 48\nheight = 36\n";
    let hidden =
        common::images::render_text(&(objects("seen_by = \"trajectories\"\n", "") + light));
    let without = {
        let text = objects("", "") + light;
        let start = text.find("[[object]]").unwrap();
        let end = text.find("[[group]]").unwrap();
        common::images::render_text(&format!("{}{}", &text[..start], &text[end..]))
    };
    assert_eq!(common::images::differing(&hidden, &without), 0);
    let shown = common::images::render_text(&(objects("", "") + light));
    assert!(
        common::images::differing(&shown, &without) > 0,
        "the mirror shows"
    );
}

/// A group's `seen_by` is its members' (a device's every part's) unless a member gives its own;
/// objects moving with the camera cannot be seen by trajectories only.
#[test]
fn seen_by_is_inherited_and_refused_where_no_ray_could_meet_the_object() {
    let d = common::images::parse(
        "studio = \"none\"\n[[group]]\nname = \"g\"\nseen_by = \"camera\"\n\
         [[group.object]]\nname = \"a\"\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\n\
         surface = { type = \"matt\", colour = [1, 0, 0] }\n\
         [[group.object]]\nname = \"b\"\nseen_by = \"all\"\n\
         shape = { type = \"sphere\", centre = [0, 0, 9], radius = 1 }\n\
         surface = { type = \"matt\", colour = [1, 0, 0] }\n\
         [[group.device]]\nname = \"star\"\nlenses = { type = \"lens-star\" }\n",
    );
    let seen = |name: &str| d.objects[index_of(&d, name)].seen_by;
    assert_eq!(seen("g/a"), timbre::scene::SeenBy::Camera);
    assert_eq!(seen("g/b"), timbre::scene::SeenBy::All);
    assert_eq!(seen("g/star/lens 1"), timbre::scene::SeenBy::Camera);
    let dir = tempfile::tempdir().unwrap();
    let text = "studio = \"none\"\n\n[[object]]\nframe = \"camera\"\nseen_by = \"trajectories\"\n\
                shape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\n\
                surface = { type = \"matt\", colour = [1, 0, 0] }\n";
    let path = write(dir.path(), "bad.toml", text);
    let run = timbre(dir.path(), &["check", path_str(&path)]);
    run.assert_bad_input(&["never met by the ray trajectories", "frame = \"camera\""]);
    assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
}

#[test]
fn seen_by_takes_one_of_its_three_values() {
    let dir = tempfile::tempdir().unwrap();
    let text = "studio = \"none\"\n\n[[object]]\nseen_by = \"nobody\"\n\
                shape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\n\
                surface = { type = \"matt\", colour = [1, 0, 0] }\n";
    let path = write(dir.path(), "bad.toml", text);
    let run = timbre(dir.path(), &["check", path_str(&path)]);
    run.assert_bad_input(&["nobody", "all", "camera", "trajectories"]);
    assert_eq!(location(&run.stderr, &path).0, 4, "{}", run.stderr);
}
