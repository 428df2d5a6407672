//! Property tests of the polyhedra and flat shapes (cuboid, parallelepiped, triangular prism,
//! wedge, Platonic solids, convex polygon, bilinear surface) against independent f64
//! references written here (none of timbre's geometry is reused, but for the consistency of CSG
//! hits with `Csg::contains`, itself checked against point membership in tests/csg.rs):
//!
//! * **Polyhedra**: every face a loop of vertices worked out here from the shape's parameters
//!   (a wedge's by turning its bisector about its apex edge; a Platonic solid's vertices by
//!   ring formulas checked against Dr TIM's tables, its faces from the dual solid's vertex
//!   directions). A ray's reference hit is the nearest crossing of a face's plane whose point
//!   lies inside that face's polygon, edge by edge: a different algorithm from the shapes'
//!   slab clipping. A cuboid under a shear is checked against its sheared loops.
//! * **Convex polygon**: a fan of triangles, each intersected by Möller–Trumbore.
//! * **Bilinear surface**: Newton's method on p(α, β) = o + t d for (t, α, β), started from a
//!   grid of (α, β).
//!
//! Rays whose reference crossings come within 1e-7 (times the scene's scale) of an edge, or
//! that graze a curved surface, are *marginal* and skipped; every property also checks that
//! most of its rays are decisive and that many of them hit.
//!
//! Beyond that: `contains` and `chord` against the reference, the Platonic solids' counts,
//! circumspheres and dihedral angles, the cuboid's documented faces and coordinates,
//! polyhedra inside constructive solid geometry (hits against `Csg::contains` sampled along
//! the ray), and bad parameters in scene files.

mod common;

use std::f64::consts::{PI, TAU};

use glam::{DMat3, DVec2, DVec3};
use proptest::prelude::*;
use proptest::strategy::ValueTree;

use common::config;
use common::rng::Rng;
use proptest::array::uniform3;
use timbre::geometry::{
    AnalyticShape, BilinearSurface, ConvexPolygon, Csg, CsgOperation, Cuboid, Parallelepiped,
    PlatonicKind, PlatonicSolid, Polyhedral, Shape, Sphere, Transform, TriangularPrism, Wedge,
};
use timbre::math::Frame;
use timbre::scene::file;

/// Reference crossings this close to an edge (times the scale) are marginal.
const EDGE_TOL: f64 = 1e-7;
/// Hit distances agree to this, relative to scale + t.
const T_TOL: f64 = 1e-9;
/// Rays per random shape.
const RAYS: usize = 48;

// ---------------------------------------------------------------------------------------------
// What a check found
// ---------------------------------------------------------------------------------------------

#[derive(Debug, Default, Clone, Copy)]
struct Counts {
    hits: usize,
    misses: usize,
    marginal: usize,
}

impl Counts {
    fn add(&mut self, other: Counts) {
        self.hits += other.hits;
        self.misses += other.misses;
        self.marginal += other.marginal;
    }

    /// At least half the rays decisive, and some of them hits and some misses.
    fn assert_decisive(&self, what: &str) {
        let all = self.hits + self.misses + self.marginal;
        assert!(
            2 * self.marginal < all && self.hits * 10 > all && self.misses * 20 > all,
            "{what}: too few decisive rays: {self:?}"
        );
    }
}

/// Orthonormal and right-handed (u × v = w).
fn check_frame(f: &Frame) -> Result<(), String> {
    let e = 1e-12;
    let unit = |v: DVec3| (v.length() - 1.0).abs() <= e;
    if !(unit(f.u) && unit(f.v) && unit(f.w)) {
        return Err(format!("frame not unit: {f:?}"));
    }
    if f.u.dot(f.v).abs() > e || f.u.dot(f.w).abs() > e || f.v.dot(f.w).abs() > e {
        return Err(format!("frame not orthogonal: {f:?}"));
    }
    if (f.u.cross(f.v) - f.w).length() > e {
        return Err(format!("frame not right-handed: {f:?}"));
    }
    Ok(())
}

/// A ray from within `spread` of `centre`: half of them aimed at a point that `aim` draws,
/// half in a random direction.
fn random_ray(
    rng: &mut Rng,
    centre: DVec3,
    spread: f64,
    aim: impl Fn(&mut Rng) -> DVec3,
) -> (DVec3, DVec3) {
    let origin = centre + rng.point(spread);
    let direction = if rng.f() < 0.5 {
        (aim(rng) - origin).normalize()
    } else {
        rng.unit()
    };
    (origin, direction)
}

// ---------------------------------------------------------------------------------------------
// Reference polyhedra: faces as loops of vertices
// ---------------------------------------------------------------------------------------------

/// A convex polyhedron as loops of vertices (either winding), in the order of the shape's
/// parts.
struct RefSolid {
    faces: Vec<Vec<DVec3>>,
}

/// A crossing of a face's plane: where, which face, and how far inside the face's polygon.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    t: f64,
    face: usize,
    margin: f64,
}

impl RefSolid {
    fn centroid(&self) -> DVec3 {
        let all: Vec<DVec3> = self.faces.iter().flatten().copied().collect();
        all.iter().sum::<DVec3>() / all.len() as f64
    }

    /// 1 + the largest coordinate.
    fn scale(&self) -> f64 {
        1.0 + self
            .faces
            .iter()
            .flatten()
            .fold(0.0, |a: f64, v| a.max(v.abs().max_element()))
    }

    /// The unit normal of face `i` (Newell's), pointing away from the centroid.
    fn normal(&self, i: usize) -> DVec3 {
        let f = &self.faces[i];
        let n: DVec3 = (0..f.len())
            .map(|k| f[k].cross(f[(k + 1) % f.len()]))
            .sum::<DVec3>()
            .normalize();
        if n.dot(f[0] - self.centroid()) < 0.0 {
            -n
        } else {
            n
        }
    }

    /// The in-plane distance of `p` (on face i's plane) inside the face's polygon: the least
    /// distance to an edge's line, negative outside.
    fn margin(&self, i: usize, p: DVec3) -> f64 {
        let f = &self.faces[i];
        let n = self.normal(i);
        let middle = f.iter().sum::<DVec3>() / f.len() as f64;
        (0..f.len())
            .map(|k| {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                let mut m = n.cross(b - a).normalize();
                if m.dot(middle - a) < 0.0 {
                    m = -m;
                }
                m.dot(p - a)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Every crossing of a face's plane with t > t_min (planes the line is parallel to,
    /// to 1e-12, are left out: it cannot cross them).
    fn crossings(&self, o: DVec3, d: DVec3, t_min: f64) -> Vec<Crossing> {
        (0..self.faces.len())
            .filter_map(|face| {
                let n = self.normal(face);
                let dn = d.dot(n);
                if dn.abs() < 1e-12 {
                    return None;
                }
                let t = (self.faces[face][0] - o).dot(n) / dn;
                (t > t_min).then(|| Crossing {
                    t,
                    face,
                    margin: self.margin(face, o + t * d),
                })
            })
            .collect()
    }

    /// How far outside `p` is: the largest signed distance beyond a face's plane.
    fn outside_by(&self, p: DVec3) -> f64 {
        (0..self.faces.len())
            .map(|i| self.normal(i).dot(p - self.faces[i][0]))
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The loops of the parallelepiped about `c` with edges a, b, e in the documented order:
/// −a, +a, −b, +b, −e, +e.
fn ref_parallelepiped(c: DVec3, [a, b, e]: [DVec3; 3]) -> RefSolid {
    let corner = |i: f64, j: f64, k: f64| c + 0.5 * (i * a + j * b + k * e);
    let mut faces = Vec::new();
    for s in [-1.0, 1.0] {
        faces.push(vec![
            corner(s, -1.0, -1.0),
            corner(s, 1.0, -1.0),
            corner(s, 1.0, 1.0),
            corner(s, -1.0, 1.0),
        ]);
    }
    for s in [-1.0, 1.0] {
        faces.push(vec![
            corner(-1.0, s, -1.0),
            corner(1.0, s, -1.0),
            corner(1.0, s, 1.0),
            corner(-1.0, s, 1.0),
        ]);
    }
    for s in [-1.0, 1.0] {
        faces.push(vec![
            corner(-1.0, -1.0, s),
            corner(1.0, -1.0, s),
            corner(1.0, 1.0, s),
            corner(-1.0, 1.0, s),
        ]);
    }
    RefSolid { faces }
}

/// The loops of the prism A B C extruded by `e`, in the documented order: sides AB, BC, CA,
/// then the triangle and its copy.
fn ref_prism([a, b, c]: [DVec3; 3], e: DVec3) -> RefSolid {
    let side = |p: DVec3, q: DVec3| vec![p, q, q + e, p + e];
    RefSolid {
        faces: vec![
            side(a, b),
            side(b, c),
            side(c, a),
            vec![a, b, c],
            vec![a + e, b + e, c + e],
        ],
    }
}

/// `v` turned by `angle` about the unit axis `k` (Rodrigues' formula).
fn turned(v: DVec3, k: DVec3, angle: f64) -> DVec3 {
    v * angle.cos() + k.cross(v) * angle.sin() + k * k.dot(v) * (1.0 - angle.cos())
}

/// The wedge as Dr TIM builds it: the apex edge's lower end and the legs, the bisector turned
/// by ∓ half the apex angle about the edge; as a prism of (apex, −, +).
fn ref_wedge(
    centre: DVec3,
    edge: DVec3,
    bisector: DVec3,
    angle: f64,
    leg: f64,
    length: f64,
) -> RefSolid {
    let a = edge.normalize();
    let b = (bisector - bisector.dot(a) * a).normalize();
    let apex = centre - 0.5 * length * a;
    ref_prism(
        [
            apex,
            apex + leg * turned(b, a, -0.5 * angle),
            apex + leg * turned(b, a, 0.5 * angle),
        ],
        length * a,
    )
}

// ---------------------------------------------------------------------------------------------
// Reference Platonic solids
// ---------------------------------------------------------------------------------------------

const KINDS: [PlatonicKind; 5] = [
    PlatonicKind::Tetrahedron,
    PlatonicKind::Cube,
    PlatonicKind::Octahedron,
    PlatonicKind::Dodecahedron,
    PlatonicKind::Icosahedron,
];

/// Five points at height z on the unit sphere, at azimuths `first` + 72° k.
fn ring(z: f64, first_deg: f64) -> Vec<DVec3> {
    (0..5)
        .map(|k| {
            let phi = (first_deg + 72.0 * k as f64).to_radians();
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// The unit vertices in Dr TIM's orientation, by formulas of their own: the tetrahedron's
/// lower three at polar angle arccos(−1/3) and azimuths 0°, ±120°; the icosahedron's rings at
/// polar angles arctan 2 and π − arctan 2; the dodecahedron's four rings at
/// z = ±√((5 + 2√5)/15) (its inradius) and ±(√5 − 2) times that.
fn ref_vertices(kind: PlatonicKind) -> Vec<DVec3> {
    match kind {
        PlatonicKind::Tetrahedron => {
            let theta = (-1.0f64 / 3.0).acos();
            let mut v = vec![DVec3::Z];
            v.extend((0..3).map(|k| {
                let phi = TAU * k as f64 / 3.0;
                DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                )
            }));
            v
        }
        PlatonicKind::Cube => {
            let mut v = Vec::new();
            for x in [-1.0, 1.0] {
                for y in [-1.0, 1.0] {
                    for z in [-1.0, 1.0] {
                        v.push(DVec3::new(x, y, z) / 3f64.sqrt());
                    }
                }
            }
            v
        }
        PlatonicKind::Octahedron => vec![
            DVec3::X,
            DVec3::NEG_X,
            DVec3::Y,
            DVec3::NEG_Y,
            DVec3::Z,
            DVec3::NEG_Z,
        ],
        PlatonicKind::Icosahedron => {
            let z = 2f64.atan().cos();
            let mut v = vec![DVec3::Z, DVec3::NEG_Z];
            v.extend(ring(z, 0.0));
            v.extend(ring(-z, 36.0));
            v
        }
        PlatonicKind::Dodecahedron => {
            let z1 = ((5.0 + 2.0 * 5f64.sqrt()) / 15.0).sqrt();
            let z2 = (5f64.sqrt() - 2.0) * z1;
            [
                ring(z1, 36.0),
                ring(z2, 36.0),
                ring(-z2, 0.0),
                ring(-z1, 0.0),
            ]
            .concat()
        }
    }
}

/// The directions of the face normals: the dual solid's vertices.
fn ref_face_normals(kind: PlatonicKind) -> Vec<DVec3> {
    match kind {
        PlatonicKind::Tetrahedron => ref_vertices(kind).into_iter().map(|v| -v).collect(),
        PlatonicKind::Cube => ref_vertices(PlatonicKind::Octahedron),
        PlatonicKind::Octahedron => ref_vertices(PlatonicKind::Cube),
        PlatonicKind::Dodecahedron => ref_vertices(PlatonicKind::Icosahedron),
        PlatonicKind::Icosahedron => ref_vertices(PlatonicKind::Dodecahedron),
    }
}

/// (faces, vertices of a face, dihedral angle).
fn platonic_facts(kind: PlatonicKind) -> (usize, usize, f64) {
    match kind {
        PlatonicKind::Tetrahedron => (4, 3, (1.0f64 / 3.0).acos()),
        PlatonicKind::Cube => (6, 4, 0.5 * PI),
        PlatonicKind::Octahedron => (8, 3, (-1.0f64 / 3.0).acos()),
        PlatonicKind::Dodecahedron => (12, 5, (-1.0 / 5f64.sqrt()).acos()),
        PlatonicKind::Icosahedron => (20, 3, (-5f64.sqrt() / 3.0).acos()),
    }
}

/// The solid's faces: for each face normal, the vertices farthest along it, in order round it.
fn ref_platonic(kind: PlatonicKind, centre: DVec3, radius: f64) -> RefSolid {
    let v = ref_vertices(kind);
    let faces = ref_face_normals(kind)
        .into_iter()
        .map(|n| {
            let top = v.iter().map(|p| p.dot(n)).fold(f64::NEG_INFINITY, f64::max);
            let mut face: Vec<DVec3> = v
                .iter()
                .copied()
                .filter(|p| p.dot(n) > top - 1e-9)
                .collect();
            let middle = face.iter().sum::<DVec3>() / face.len() as f64;
            let e1 = n.any_orthonormal_vector();
            let e2 = n.cross(e1);
            let angle = |p: &DVec3| (p - middle).dot(e2).atan2((p - middle).dot(e1));
            face.sort_by(|p, q| angle(p).total_cmp(&angle(q)));
            face.into_iter().map(|p| centre + radius * p).collect()
        })
        .collect();
    RefSolid { faces }
}

#[test]
fn the_reference_platonic_solids_are_dr_tims() {
    // Dr TIM's tables (`PlatonicSolidType`, six digits from Mathematica).
    for (kind, vertex) in [
        (
            PlatonicKind::Tetrahedron,
            DVec3::new(-0.471405, 0.816497, -0.333333),
        ),
        (
            PlatonicKind::Icosahedron,
            DVec3::new(-0.723607, -0.525731, 0.447214),
        ),
        (
            PlatonicKind::Icosahedron,
            DVec3::new(0.723607, 0.525731, -0.447214),
        ),
        (
            PlatonicKind::Dodecahedron,
            DVec3::new(-0.303531, -0.934172, 0.187592),
        ),
        (
            PlatonicKind::Dodecahedron,
            DVec3::new(0.491123, 0.356822, 0.794654),
        ),
        (
            PlatonicKind::Dodecahedron,
            DVec3::new(0.607062, 0.0, -0.794654),
        ),
    ] {
        let nearest = ref_vertices(kind)
            .into_iter()
            .map(|p| p.distance(vertex))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-6, "{kind:?} {vertex}: {nearest}");
    }
    for kind in KINDS {
        let (faces, sides, _) = platonic_facts(kind);
        let r = ref_platonic(kind, DVec3::ZERO, 1.0);
        assert_eq!(r.faces.len(), faces, "{kind:?}");
        assert!(r.faces.iter().all(|f| f.len() == sides), "{kind:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Checking a polyhedral shape against its reference
// ---------------------------------------------------------------------------------------------

/// Rays, points and lines against the reference. `ordered`: the shape's parts are the
/// reference's faces in order (otherwise the hit face is recognised by its normal).
fn check_solid(
    shape: &Shape,
    reference: &RefSolid,
    ordered: bool,
    seed: u64,
) -> Result<Counts, String> {
    let mut rng = Rng(seed);
    let mut counts = Counts::default();
    let scale = reference.scale();
    let centre = reference.centroid();
    let size = reference
        .faces
        .iter()
        .flatten()
        .fold(0.0, |a: f64, v| a.max(v.distance(centre)));
    let solid = shape.analytic_solid().ok_or("not a solid")?;
    for _ in 0..RAYS {
        let (o, d) = random_ray(&mut rng, centre, 3.0 * size, |r| centre + r.point(size));
        let all = reference.crossings(o, d, f64::NEG_INFINITY);
        if all
            .iter()
            .any(|c| c.margin.abs() <= EDGE_TOL * scale || c.t.abs() <= EDGE_TOL * scale)
        {
            counts.marginal += 1;
            continue;
        }
        let inside: Vec<Crossing> = {
            let mut v: Vec<Crossing> = all.iter().copied().filter(|c| c.margin > 0.0).collect();
            v.sort_by(|a, b| a.t.total_cmp(&b.t));
            v
        };
        // The nearest hit beyond t = 0.
        let expected = inside.iter().find(|c| c.t > 0.0);
        let got = shape.intersect(o, d, 0.0, f64::INFINITY);
        let describe = || format!("ray {o} + t {d}: expected {expected:?}, got {got:?}");
        match (expected, got) {
            (None, None) => counts.misses += 1,
            (Some(e), Some((t, part))) => {
                if (t - e.t).abs() > T_TOL * (scale + t.abs()) {
                    return Err(format!("wrong distance: {}", describe()));
                }
                check_face(shape, reference, ordered, o + t * d, part, e.face)
                    .map_err(|m| format!("{m}: {}", describe()))?;
                counts.hits += 1;
            }
            _ => return Err(format!("hit and miss disagree: {}", describe())),
        }
        // The chord over the whole line: the reference's two crossings, or none.
        let chord = solid.chord(o, d);
        match (inside.as_slice(), chord) {
            ([], None) => {}
            ([enter, exit], Some(span)) => {
                for (c, (t, part)) in [(enter, span.enter), (exit, span.exit)] {
                    if (t - c.t).abs() > T_TOL * (scale + t.abs()) {
                        return Err(format!("chord {span:?} against {inside:?}: {}", describe()));
                    }
                    check_face(shape, reference, ordered, o + t * d, part, c.face)?;
                }
            }
            _ => {
                return Err(format!(
                    "chord {chord:?} against {inside:?}: {}",
                    describe()
                ));
            }
        }
        // Membership of a point near the solid.
        let p = centre + rng.point(1.2 * size);
        let outside_by = reference.outside_by(p);
        if outside_by.abs() > EDGE_TOL * scale && solid.contains(p) != (outside_by < 0.0) {
            return Err(format!(
                "contains({p}) = {}, but the point is {outside_by} outside",
                solid.contains(p)
            ));
        }
    }
    Ok(counts)
}

/// At point `p` of part `part`: the frame is right-handed and orthonormal, its normal face
/// `face`'s outward one (with the centroid behind it), and the plane coordinates Cartesian in
/// the face's plane (distances between the face's vertices kept); so are the surface
/// coordinates, but of a transformed shape, whose pattern stretches with it.
fn check_face(
    shape: &Shape,
    reference: &RefSolid,
    ordered: bool,
    p: DVec3,
    part: u32,
    face: usize,
) -> Result<(), String> {
    if ordered && part as usize != face {
        return Err(format!("part {part}, expected face {face}"));
    }
    let f = shape.frame(p, part);
    check_frame(&f)?;
    let n = reference.normal(face);
    if (f.w - n).length() > 1e-9 {
        return Err(format!(
            "normal {} on part {part}, face {face}'s is {n}",
            f.w
        ));
    }
    if (reference.centroid() - p).dot(f.w) >= 0.0 {
        return Err(format!("the centroid is in front of part {part}"));
    }
    let loop_ = &reference.faces[face];
    let scale = reference.scale();
    for (i, &a) in loop_.iter().enumerate() {
        let b = loop_[(i + 1) % loop_.len()];
        let plane = |p: DVec3| shape.plane_coordinates(p, part).unwrap_or(DVec2::NAN);
        let (ca, cb) = (plane(a), plane(b));
        let error = ((ca - cb).length() - a.distance(b)).abs();
        if error.is_nan() || error > 1e-9 * scale {
            return Err(format!(
                "part {part}'s plane coordinates are not Cartesian: {a} -> {ca}, {b} -> {cb}"
            ));
        }
        if !matches!(shape, Shape::Transformed(_)) && shape.coordinates(a, part) != ca {
            return Err(format!(
                "part {part}: plane coordinates differ from coordinates"
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Random polyhedra
// ---------------------------------------------------------------------------------------------

fn point(a: f64) -> impl Strategy<Value = DVec3> {
    (-a..a, -a..a, -a..a).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn length() -> impl Strategy<Value = f64> {
    (0.1f64.ln()..3f64.ln()).prop_map(f64::exp)
}

/// A vector of length 0.1 to 3 in a uniformly random direction.
fn vector() -> impl Strategy<Value = DVec3> {
    (0.0..1.0f64, 0.0..1.0f64, length()).prop_map(|(a, b, l)| l * common::unit_from(a, b))
}

/// Three edges spanning a volume (not nearly coplanar).
fn spanning() -> impl Strategy<Value = [DVec3; 3]> {
    uniform3(vector()).prop_filter("nearly coplanar", |[a, b, c]| {
        a.cross(*b).dot(*c).abs() > 0.15 * a.length() * b.length() * c.length()
    })
}

/// A triangle of some area and an extrusion well out of its plane.
fn prism_parts() -> impl Strategy<Value = ([DVec3; 3], DVec3)> {
    (uniform3(point(3.0)), vector()).prop_filter("thin triangle or flat prism", |([a, b, c], e)| {
        let n = (*b - *a).cross(*c - *a);
        n.length() > 0.2 * (*b - *a).length() * (*c - *a).length()
            && (*b - *a).length() > 0.1
            && (*c - *a).length() > 0.1
            && n.normalize().dot(*e).abs() > 0.2 * e.length()
    })
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn cuboids_match_the_reference(centre in point(3.0), size in uniform3(length()), seed: u64) {
        let size = DVec3::from_array(size);
        let shape = Shape::Cuboid(Cuboid::new(centre, size).unwrap());
        let edges = [size.x * DVec3::X, size.y * DVec3::Y, size.z * DVec3::Z];
        let counts = check_solid(&shape, &ref_parallelepiped(centre, edges), true, seed)
            .map_err(TestCaseError::fail)?;
        prop_assert!(counts.hits + counts.misses > 0);
    }

    /// A cuboid under a general linear map (a `Transformed` shape) against its mapped loops.
    #[test]
    fn sheared_cuboids_match_the_reference(
        centre in point(3.0),
        size in uniform3(length()),
        columns in spanning(),
        seed: u64,
    ) {
        let m = DMat3::from_cols(columns[0], columns[1], columns[2]);
        let size = DVec3::from_array(size);
        let cuboid = Shape::Cuboid(Cuboid::new(centre, size).unwrap());
        let shape = Transform::from_matrix(m).unwrap().shape(&cuboid).unwrap();
        prop_assert!(matches!(shape, Shape::Transformed(_)));
        let edges = [size.x * DVec3::X, size.y * DVec3::Y, size.z * DVec3::Z].map(|e| m * e);
        let reference = ref_parallelepiped(m * centre, edges);
        check_solid(&shape, &reference, true, seed).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn parallelepipeds_match_the_reference(centre in point(3.0), edges in spanning(), seed: u64) {
        let shape = Shape::Parallelepiped(Parallelepiped::new(centre, edges).unwrap());
        check_solid(&shape, &ref_parallelepiped(centre, edges), true, seed)
            .map_err(TestCaseError::fail)?;
    }

    #[test]
    fn triangular_prisms_match_the_reference((vertices, extrusion) in prism_parts(), seed: u64) {
        let shape = Shape::TriangularPrism(TriangularPrism::new(vertices, extrusion).unwrap());
        check_solid(&shape, &ref_prism(vertices, extrusion), true, seed)
            .map_err(TestCaseError::fail)?;
    }

    #[test]
    fn wedges_match_the_reference(
        centre in point(3.0),
        edge in vector(),
        bisector in vector(),
        angle_deg in 5.0..175.0f64,
        leg in length(),
        edge_length in length(),
        seed: u64,
    ) {
        prop_assume!(edge.normalize().cross(bisector.normalize()).length() > 0.2);
        let angle = angle_deg.to_radians();
        let shape = Shape::Wedge(Wedge::new(centre, edge, bisector, angle, leg, edge_length).unwrap());
        let reference = ref_wedge(centre, edge, bisector, angle, leg, edge_length);
        check_solid(&shape, &reference, true, seed).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn platonic_solids_match_the_reference(
        kind in (0..5usize).prop_map(|i| KINDS[i]),
        centre in point(3.0),
        radius in length(),
        seed: u64,
    ) {
        let shape = Shape::PlatonicSolid(PlatonicSolid::new(kind, centre, radius).unwrap());
        check_solid(&shape, &ref_platonic(kind, centre, radius), false, seed)
            .map_err(TestCaseError::fail)?;
    }
}

/// Over many shapes, most rays are decisive and many hit (so the properties above test
/// something).
#[test]
fn polyhedron_rays_are_mostly_decisive() {
    let mut rng = Rng(7);
    let mut counts = Counts::default();
    for i in 0..40u64 {
        let centre = rng.point(3.0);
        let shapes = [
            (
                Shape::Cuboid(Cuboid::new(centre, DVec3::new(0.5, 1.0, 2.0)).unwrap()),
                ref_parallelepiped(centre, [0.5 * DVec3::X, DVec3::Y, 2.0 * DVec3::Z]),
                true,
            ),
            (
                Shape::PlatonicSolid(
                    PlatonicSolid::new(KINDS[i as usize % 5], centre, 1.0).unwrap(),
                ),
                ref_platonic(KINDS[i as usize % 5], centre, 1.0),
                false,
            ),
        ];
        for (shape, reference, ordered) in shapes {
            counts.add(check_solid(&shape, &reference, ordered, i).unwrap());
        }
    }
    counts.assert_decisive("polyhedra");
}

// ---------------------------------------------------------------------------------------------
// Platonic solids, cuboid faces, CSG
// ---------------------------------------------------------------------------------------------

/// Face counts, vertices on the circumsphere, and the dihedral angles: every face meets its
/// neighbours (as many as it has sides) at the solid's dihedral angle.
#[test]
fn platonic_solids_have_their_faces_circumspheres_and_dihedral_angles() {
    let (centre, radius) = (DVec3::new(0.3, -1.0, 2.0), 1.7);
    for kind in KINDS {
        let (faces, sides, dihedral) = platonic_facts(kind);
        let solid = PlatonicSolid::new(kind, centre, radius).unwrap();
        assert_eq!(solid.polyhedron().face_count(), faces, "{kind:?}");
        for v in solid.vertices() {
            assert!(
                (v.distance(centre) - radius).abs() < 1e-12 * radius,
                "{kind:?} {v}"
            );
        }
        let normals: Vec<DVec3> = (0..faces as u32)
            .map(|i| solid.frame(centre, i).w)
            .collect();
        for (i, n) in normals.iter().enumerate() {
            let angles: Vec<f64> = normals
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, m)| n.dot(*m).clamp(-1.0, 1.0).acos())
                .collect();
            let neighbours = angles
                .iter()
                .filter(|&&a| (PI - a - dihedral).abs() < 1e-12)
                .count();
            assert_eq!(neighbours, sides, "{kind:?} face {i}: {angles:?}");
            assert!(
                angles.iter().all(|&a| a > PI - dihedral - 1e-12),
                "{kind:?}"
            );
        }
    }
}

/// The cuboid's faces as SCENE_FORMAT.md lists them: (outward normal, u, v, the corner their
/// coordinates start from, as signs of the half-sizes).
#[test]
fn cuboid_faces_and_coordinates_are_as_documented() {
    let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
    let table = [
        (-x, -y, z, [-1.0, 1.0, -1.0]),
        (x, y, z, [1.0, -1.0, -1.0]),
        (-y, -z, x, [-1.0, -1.0, 1.0]),
        (y, z, x, [-1.0, 1.0, -1.0]),
        (-z, -x, y, [1.0, -1.0, -1.0]),
        (z, x, y, [-1.0, -1.0, 1.0]),
    ];
    let (centre, size) = (DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.5, 1.5, 2.5));
    let cuboid = Cuboid::new(centre, size).unwrap();
    for (part, (w, u, v, corner)) in table.into_iter().enumerate() {
        let part = part as u32;
        let f = cuboid.frame(centre, part);
        assert_eq!((f.u, f.v, f.w), (u, v, w), "part {part}");
        let corner = centre + 0.5 * size * DVec3::from_array(corner);
        assert!(
            cuboid.coordinates(corner, part).length() < 1e-15,
            "part {part}"
        );
        // The face is the rectangle [0, size along u] × [0, size along v].
        let far = corner + u * u.abs().dot(size) + v * v.abs().dot(size);
        let c = cuboid.coordinates(far, part);
        assert!((c - DVec2::new(u.abs().dot(size), v.abs().dot(size))).length() < 1e-14);
        // A ray straight at the face's middle hits it.
        let middle = centre + 0.5 * w * w.abs().dot(size);
        let hit = cuboid.intersect(middle + w, -w, 0.0, f64::INFINITY);
        assert_eq!(hit, Some((1.0, part)));
    }
}

/// Polyhedra inside constructive solid geometry: along random rays, `Csg::contains` is constant
/// up to the first hit and changes there, and the normal there points out of the result.
#[test]
fn polyhedra_in_csg_agree_with_csg_contains() {
    let cuboid = Shape::Cuboid(Cuboid::new(DVec3::ZERO, DVec3::new(2.0, 1.5, 1.0)).unwrap());
    let ball = Shape::Sphere(Sphere::new(DVec3::new(1.0, 0.75, 0.5), 0.8).unwrap());
    let dodecahedron = Shape::PlatonicSolid(
        PlatonicSolid::new(PlatonicKind::Dodecahedron, DVec3::new(0.5, 0.2, 0.0), 1.0).unwrap(),
    );
    let wedge = Shape::Wedge(
        Wedge::new(
            DVec3::new(-0.5, 0.0, 0.0),
            DVec3::Y,
            DVec3::X,
            1.0,
            2.0,
            3.0,
        )
        .unwrap(),
    );
    let cases = [
        Csg::new(CsgOperation::Difference, vec![cuboid.clone(), ball.clone()]).unwrap(),
        Csg::new(
            CsgOperation::Intersection,
            vec![dodecahedron.clone(), cuboid.clone()],
        )
        .unwrap(),
        Csg::new(CsgOperation::Union, vec![wedge, dodecahedron, ball]).unwrap(),
    ];
    let mut rng = Rng(11);
    for csg in cases {
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..1500 {
            let (o, d) = random_ray(&mut rng, DVec3::ZERO, 5.0, |r| r.point(1.0));
            let hit = csg.intersect(o, d, 0.0, f64::INFINITY);
            let end = hit.map_or(20.0, |h| h.0);
            let start = csg.contains(o);
            let eps = 1e-7;
            for k in 1..2000 {
                let t = end * k as f64 / 2000.0;
                if t < end - eps && csg.contains(o + t * d) != start {
                    panic!(
                        "{:?}: the ray {o} + t {d} crosses at {t}, before its hit {hit:?}",
                        csg.operation()
                    );
                }
            }
            let Some((t, part)) = hit else {
                misses += 1;
                continue;
            };
            hits += 1;
            let p = o + t * d;
            assert_ne!(
                csg.contains(p + eps * d),
                start,
                "no crossing at {t}: {o} + t {d}"
            );
            let w = csg.frame(p, part).w;
            assert!(
                csg.contains(p - eps * w) && !csg.contains(p + eps * w),
                "{:?}: the normal {w} at {p} does not point out",
                csg.operation()
            );
        }
        assert!(hits > 300 && misses > 100, "{hits} hits, {misses} misses");
    }
}

// ---------------------------------------------------------------------------------------------
// Convex polygons
// ---------------------------------------------------------------------------------------------

/// Möller–Trumbore: the t where the line meets triangle (a, b, c), if inside it.
fn moller_trumbore(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then(|| e2.dot(q) / det)
}

/// The distance of `p` (in the polygon's plane) from the polygon's boundary.
fn boundary_distance(vertices: &[DVec3], p: DVec3) -> f64 {
    (0..vertices.len())
        .map(|i| {
            let (a, b) = (vertices[i], vertices[(i + 1) % vertices.len()]);
            let s = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            p.distance(a + s * (b - a))
        })
        .fold(f64::INFINITY, f64::min)
}

/// A convex polygon: 3 to 8 points in order round an ellipse in a random plane, counter-
/// clockwise about `normal` (or clockwise, and then the normal reversed).
fn polygon() -> impl Strategy<Value = (Vec<DVec3>, DVec3)> {
    (
        point(3.0),
        (0.0..1.0f64, 0.0..1.0f64),
        (length(), length()),
        prop::collection::vec(0.0..TAU, 3..9),
        any::<bool>(),
    )
        .prop_filter_map(
            "vertices too close",
            |(centre, (n0, n1), (a, b), mut angles, reverse)| {
                let n = common::unit_from(n0, n1);
                let e1 = n.any_orthonormal_vector();
                let e2 = n.cross(e1);
                angles.sort_by(f64::total_cmp);
                let mut gaps = (0..angles.len()).map(|i| {
                    let next = angles.get(i + 1).copied().unwrap_or(angles[0] + TAU);
                    next - angles[i]
                });
                if gaps.any(|g| g < 0.1) {
                    return None;
                }
                let mut vertices: Vec<DVec3> = angles
                    .iter()
                    .map(|t| centre + a * t.cos() * e1 + b * t.sin() * e2)
                    .collect();
                let normal = if reverse {
                    vertices.reverse();
                    -n
                } else {
                    n
                };
                Some((vertices, normal))
            },
        )
}

fn check_polygon(vertices: &[DVec3], normal: DVec3, seed: u64) -> Result<Counts, String> {
    let polygon =
        Shape::ConvexPolygon(ConvexPolygon::new(vertices.to_vec()).map_err(|e| e.to_string())?);
    let mut rng = Rng(seed);
    let mut counts = Counts::default();
    let centre = vertices.iter().sum::<DVec3>() / vertices.len() as f64;
    let size = vertices
        .iter()
        .fold(0.0, |a: f64, v| a.max(v.distance(centre)));
    let scale = 1.0
        + vertices
            .iter()
            .fold(0.0, |a: f64, v| a.max(v.abs().max_element()));
    for _ in 0..RAYS {
        // Aimed at points of the polygon's plane, most of them inside it.
        let aim = |r: &mut Rng| {
            let v = vertices[r.index(vertices.len())];
            centre + 1.3 * r.f() * (v - centre)
        };
        let (o, d) = random_ray(&mut rng, centre, 3.0 * size, aim);
        let dn = d.dot(normal);
        let t_plane = (vertices[0] - o).dot(normal) / dn;
        if dn.abs() < 1e-6
            || t_plane.abs() < EDGE_TOL * scale
            || boundary_distance(vertices, o + t_plane * d) < EDGE_TOL * scale
        {
            counts.marginal += 1;
            continue;
        }
        let expected = (1..vertices.len() - 1)
            .filter_map(|i| moller_trumbore(o, d, [vertices[0], vertices[i], vertices[i + 1]]))
            .find(|&t| t > 0.0);
        let got = polygon.intersect(o, d, 0.0, f64::INFINITY);
        match (expected, got) {
            (None, None) => counts.misses += 1,
            (Some(e), Some((t, part))) if (t - e).abs() <= T_TOL * (scale + t.abs()) => {
                let p = o + t * d;
                let f = polygon.frame(p, part);
                check_frame(&f)?;
                if (f.w - normal).length() > 1e-9
                    || (f.u - (vertices[1] - vertices[0]).normalize()).length() > 1e-9
                {
                    return Err(format!("frame {f:?}, normal {normal}"));
                }
                // Cartesian coordinates from vertex 0 along u and v, and back.
                let c = polygon.coordinates(p, part);
                let expected_c = DVec2::new((p - vertices[0]).dot(f.u), (p - vertices[0]).dot(f.v));
                let back = polygon.point_at(c);
                if (c - expected_c).length() > 1e-12 * scale
                    || polygon.plane_coordinates(p, part) != Some(c)
                    || back.is_none_or(|q| q.distance(p) > 1e-12 * scale)
                {
                    return Err(format!("coordinates {c} at {p}, back at {back:?}"));
                }
                counts.hits += 1;
            }
            _ => {
                return Err(format!(
                    "ray {o} + t {d}: expected {expected:?}, got {got:?}"
                ));
            }
        }
    }
    Ok(counts)
}

proptest! {
    #![proptest_config(config(128))]

    #[test]
    fn convex_polygons_match_the_reference((vertices, normal) in polygon(), seed: u64) {
        check_polygon(&vertices, normal, seed).map_err(TestCaseError::fail)?;
    }
}

#[test]
fn polygon_rays_are_mostly_decisive() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut counts = Counts::default();
    for seed in 0..100 {
        let (vertices, normal) = polygon().new_tree(&mut runner).unwrap().current();
        counts.add(check_polygon(&vertices, normal, seed).unwrap());
    }
    counts.assert_decisive("convex polygons");
}

// ---------------------------------------------------------------------------------------------
// Bilinear surfaces
// ---------------------------------------------------------------------------------------------

/// p(α, β) of corners (P00, P10, P11, P01) and its derivatives along α and β.
fn bilinear(c: &[DVec3; 4], a: f64, b: f64) -> (DVec3, DVec3, DVec3) {
    let p =
        (1.0 - a) * (1.0 - b) * c[0] + a * (1.0 - b) * c[1] + a * b * c[2] + (1.0 - a) * b * c[3];
    let pa = (1.0 - b) * (c[1] - c[0]) + b * (c[2] - c[3]);
    let pb = (1.0 - a) * (c[3] - c[0]) + a * (c[2] - c[1]);
    (p, pa, pb)
}

/// Every (t, α, β) with p(α, β) = o + t d that Newton's method reaches from a grid of starts
/// (α, β ∈ [−0.2, 1.2]).
fn bilinear_roots(c: &[DVec3; 4], o: DVec3, d: DVec3, scale: f64) -> Vec<(f64, DVec2)> {
    let mut roots: Vec<(f64, DVec2)> = Vec::new();
    for i in 0..=7 {
        for j in 0..=7 {
            let (mut a, mut b) = (-0.2 + 0.2 * i as f64, -0.2 + 0.2 * j as f64);
            let mut t = (bilinear(c, a, b).0 - o).dot(d);
            for _ in 0..40 {
                let (p, pa, pb) = bilinear(c, a, b);
                let residual = p - o - t * d;
                let jacobian = DMat3::from_cols(pa, pb, -d);
                if jacobian.determinant().abs() < 1e-300 {
                    break;
                }
                let step = jacobian.inverse() * residual;
                a -= step.x;
                b -= step.y;
                t -= step.z;
            }
            let (p, _, _) = bilinear(c, a, b);
            let converged =
                (p - o - t * d).length() < 1e-12 * scale && a.abs() < 10.0 && b.abs() < 10.0;
            let ab = DVec2::new(a, b);
            if converged && !roots.iter().any(|r| (r.1 - ab).length() < 1e-7) {
                roots.push((t, ab));
            }
        }
    }
    roots
}

/// A patch over a convex quadrilateral (corners 0, a, s(a + b), b about `centre`), its fourth
/// corner lifted by `h` out of the plane (h = 0 a fifth of the time: a flat patch).
fn patch() -> impl Strategy<Value = [DVec3; 4]> {
    (
        point(3.0),
        vector(),
        vector(),
        0.6..1.4f64,
        -0.8..0.8f64,
        0..5u8,
    )
        .prop_filter_map("nearly parallel sides", |(centre, a, b, s, h, flat)| {
            let n = a.cross(b);
            if n.length() < 0.35 * a.length() * b.length() {
                return None;
            }
            let h = if flat == 0 {
                0.0
            } else {
                h * a.length().min(b.length())
            };
            Some([
                centre,
                centre + a,
                centre + s * (a + b) + h * n.normalize(),
                centre + b,
            ])
        })
}

fn check_bilinear(corners: [DVec3; 4], seed: u64) -> Result<Counts, String> {
    let shape = Shape::BilinearSurface(BilinearSurface::new(corners).map_err(|e| e.to_string())?);
    let mut rng = Rng(seed);
    let mut counts = Counts::default();
    let centre = corners.iter().sum::<DVec3>() / 4.0;
    let size = corners
        .iter()
        .fold(0.0, |a: f64, v| a.max(v.distance(centre)));
    let scale = 1.0
        + corners
            .iter()
            .fold(0.0, |a: f64, v| a.max(v.abs().max_element()));
    let (len_a, len_b) = (
        (corners[1] - corners[0]).length(),
        (corners[3] - corners[0]).length(),
    );
    'rays: for _ in 0..RAYS {
        // Aimed at points of the saddle surface, most of them on the patch.
        let aim = |r: &mut Rng| bilinear(&corners, r.range(-0.2, 1.2), r.range(-0.2, 1.2)).0;
        let (o, d) = random_ray(&mut rng, centre, 3.0 * size, aim);
        let roots = bilinear_roots(&corners, o, d, scale);
        let mut on_patch = Vec::new();
        for &(t, ab) in &roots {
            let margin = ab.x.min(1.0 - ab.x).min(ab.y).min(1.0 - ab.y);
            let (_, pa, pb) = bilinear(&corners, ab.x, ab.y);
            let grazing = d.dot(pa.cross(pb).normalize()).abs() < 1e-3;
            if margin.abs() < EDGE_TOL || (margin > 0.0 && (grazing || t.abs() < EDGE_TOL * scale))
            {
                counts.marginal += 1;
                continue 'rays;
            }
            if margin > 0.0 {
                on_patch.push((t, ab));
            }
        }
        let expected = on_patch
            .iter()
            .filter(|r| r.0 > 0.0)
            .min_by(|x, y| x.0.total_cmp(&y.0));
        let got = shape.intersect(o, d, 0.0, f64::INFINITY);
        match (expected, got) {
            (None, None) => counts.misses += 1,
            (Some(&(e, ab)), Some((t, part))) if (t - e).abs() <= T_TOL * (scale + t.abs()) => {
                let p = o + t * d;
                let f = shape.frame(p, part);
                check_frame(&f)?;
                let (_, pa, pb) = bilinear(&corners, ab.x, ab.y);
                if (f.w - pa.cross(pb).normalize()).length() > 1e-8
                    || (f.u - pa.normalize()).length() > 1e-8
                {
                    return Err(format!(
                        "frame {f:?} at (α, β) = {ab}: ∂p/∂α {pa}, ∂p/∂β {pb}"
                    ));
                }
                let c = shape.coordinates(p, part);
                if (c - ab * DVec2::new(len_a, len_b)).length() > 1e-8 * scale {
                    return Err(format!("coordinates {c} at (α, β) = {ab}"));
                }
                counts.hits += 1;
            }
            _ => {
                return Err(format!(
                    "ray {o} + t {d}: expected {expected:?} (roots {roots:?}), got {got:?}"
                ));
            }
        }
    }
    Ok(counts)
}

proptest! {
    #![proptest_config(config(128))]

    #[test]
    fn bilinear_surfaces_match_the_reference(corners in patch(), seed: u64) {
        check_bilinear(corners, seed).map_err(TestCaseError::fail)?;
    }
}

#[test]
fn bilinear_rays_are_mostly_decisive() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut counts = Counts::default();
    for seed in 0..100 {
        let corners = patch().new_tree(&mut runner).unwrap().current();
        counts.add(check_bilinear(corners, seed).unwrap());
    }
    counts.assert_decisive("bilinear surfaces");
}

/// A bilinear patch with corners on a parabola-shaped saddle z = αβ: known hits, and the
/// normal (−β, −α, 1) normalised.
#[test]
fn a_saddle_is_hit_where_z_is_alpha_beta() {
    let corners = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 1.0), DVec3::Y];
    let saddle = BilinearSurface::new(corners).unwrap();
    for (x, y) in [(0.25, 0.5), (0.9, 0.1), (0.5, 0.5), (0.01, 0.99)] {
        let hit = saddle.intersect(DVec3::new(x, y, 5.0), DVec3::new(0.0, 0.0, -2.0), 0.0, 9.0);
        let (t, part) = hit.unwrap();
        assert!((t - (5.0 - x * y) / 2.0).abs() < 1e-14, "{x} {y}: {t}");
        let w = saddle.frame(DVec3::new(x, y, x * y), part).w;
        assert!(
            (w - DVec3::new(-y, -x, 1.0).normalize()).length() < 1e-14,
            "{w}"
        );
    }
    // Outside the patch (x > 1): a miss, although the saddle surface goes on.
    assert_eq!(
        saddle.intersect(DVec3::new(1.1, 0.5, 5.0), DVec3::NEG_Z, 0.0, 9.0),
        None
    );
}

// ---------------------------------------------------------------------------------------------
// Bad parameters in scene files
// ---------------------------------------------------------------------------------------------

/// The error for an object with `shape` (on line 2 of the file), which must name line 2.
fn shape_error(shape: &str) -> String {
    let text = format!(
        "[[object]]\nshape = {shape}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
    );
    match file::parse(&text, "s.toml") {
        Ok(_) => panic!("accepted: {shape}"),
        Err(e) => {
            let message = e.to_string();
            assert!(message.starts_with("s.toml:2:"), "{message}");
            message
        }
    }
}

#[test]
fn bad_parameters_are_clear_errors() {
    let cases = [
        (
            r#"{ type = "cuboid", centre = [0, 0, 5], size = [1, 0, 1] }"#,
            "expected a positive number",
        ),
        (
            r#"{ type = "cuboid", centre = [0, 0, 5], size = [1, 1] }"#,
            "an array of 3 values",
        ),
        (
            r#"{ type = "parallelepiped", centre = [0, 0, 5], edges = [[1, 0, 0], [0, 1, 0], [1, 1, 0]] }"#,
            "the parallelepiped's edges are coplanar",
        ),
        (
            r#"{ type = "parallelepiped", centre = [0, 0, 5], edges = [[1, 0, 0], [0, 0, 0], [0, 0, 1]] }"#,
            "parallelepiped edge must be a non-zero vector",
        ),
        (
            r#"{ type = "triangular-prism", vertices = [[0, 0, 5], [1, 1, 5], [2, 2, 5]], extrusion = [0, 0, 1] }"#,
            "vertices are repeated or collinear",
        ),
        (
            r#"{ type = "triangular-prism", vertices = [[0, 0, 5], [0, 0, 5], [1, 0, 5]], extrusion = [0, 0, 1] }"#,
            "vertices are repeated or collinear",
        ),
        (
            r#"{ type = "triangular-prism", vertices = [[0, 0, 5], [1, 0, 5], [0, 1, 5]], extrusion = [1, 1, 0] }"#,
            "extrusion is parallel to the plane of its vertices",
        ),
        (
            r#"{ type = "wedge", apex_edge_centre = [0, 0, 5], apex_edge_direction = [0, 1, 0], bisector_direction = [0, 2, 0], apex_angle_deg = 30, leg_length = 1, apex_edge_length = 1 }"#,
            "bisector direction is parallel to its apex edge",
        ),
        (
            r#"{ type = "wedge", apex_edge_centre = [0, 0, 5], apex_edge_direction = [0, 1, 0], bisector_direction = [1, 0, 0], apex_angle_deg = 180, leg_length = 1, apex_edge_length = 1 }"#,
            "apex angle must be between 0° and 180°, got 180°",
        ),
        (
            r#"{ type = "platonic-solid", solid = "dodecahedra", centre = [0, 0, 5], radius = 1 }"#,
            "unknown variant `dodecahedra`, expected one of `tetrahedron`, `cube`, `octahedron`, `dodecahedron`, `icosahedron`",
        ),
        (
            r#"{ type = "platonic-solid", solid = "cube", centre = [0, 0, 5], radius = -1 }"#,
            "expected a positive number",
        ),
        (
            r#"{ type = "convex-polygon", vertices = [[0, 0, 5], [1, 0, 5]] }"#,
            "a convex polygon needs at least 3 vertices, got 2",
        ),
        (
            r#"{ type = "convex-polygon", vertices = [[0, 0, 5], [1, 0, 5], [1, 1, 5.1], [0, 1, 5]] }"#,
            "off the plane of the others: the vertices must be coplanar",
        ),
        (
            r#"{ type = "convex-polygon", vertices = [[0, 0, 5], [2, 0, 5], [1, 0.5, 5], [2, 2, 5], [0, 2, 5]] }"#,
            "is not convex: it turns the other way at vertex 2",
        ),
        (
            r#"{ type = "convex-polygon", vertices = [[0, 0, 5], [1, 0, 5], [1, 0, 5], [0, 1, 5]] }"#,
            "convex polygon vertices 1 and 2 (counting from 0) coincide",
        ),
        (
            r#"{ type = "convex-polygon", vertices = [[0, 0, 5], [1, 0, 5], [2, 0, 5]] }"#,
            "collinear",
        ),
        (
            // A pentagram: every turn the same way, but twice round.
            r#"{ type = "convex-polygon", vertices = [[0, 1, 5], [0.588, -0.809, 5], [-0.951, 0.309, 5], [0.951, 0.309, 5], [-0.588, -0.809, 5]] }"#,
            "its edges cross",
        ),
        (
            r#"{ type = "bilinear-surface", corners = [[0, 0, 5], [0, 0, 5], [1, 1, 5], [0, 1, 5]] }"#,
            "the bilinear surface is degenerate",
        ),
        (
            // A bow tie: the corners in the wrong order fold the patch over.
            r#"{ type = "bilinear-surface", corners = [[0, 0, 5], [1, 0, 5], [0, 1, 5], [1, 1, 5]] }"#,
            "the bilinear surface is degenerate",
        ),
        (
            r#"{ type = "difference", of = [{ type = "cuboid", centre = [0, 0, 5], size = [1, 1, 1] }, { type = "convex-polygon", vertices = [[0, 0, 5], [1, 0, 5], [0, 1, 5]] }] }"#,
            "member 2 of the difference (convex-polygon) does not enclose a solid",
        ),
    ];
    for (shape, expected) in cases {
        let message = shape_error(shape);
        assert!(
            message.contains(expected),
            "{shape}:\n{message}\nlacks {expected:?}"
        );
    }
}

/// Every new shape reads from a scene file, and `kind()` names it by its type there.
#[test]
fn the_shapes_read_from_scene_files_are_named_by_their_type() {
    let shapes = [
        ("cuboid", r#"centre = [0, 0, 5], size = [1, 2, 3]"#),
        (
            "parallelepiped",
            r#"centre = [0, 0, 5], edges = [[1, 0, 0], [0.5, 1, 0], [0, 0, 1]]"#,
        ),
        (
            "triangular-prism",
            r#"vertices = [[0, 0, 5], [1, 0, 5], [0, 1, 5]], extrusion = [0.2, 0.1, 1]"#,
        ),
        (
            "wedge",
            r#"apex_edge_centre = [0, 0, 5], apex_edge_direction = [0, 1, 0], bisector_direction = [0, 0, 1], apex_angle_deg = 30, leg_length = 1, apex_edge_length = 1"#,
        ),
        (
            "platonic-solid",
            r#"solid = "icosahedron", centre = [0, 0, 5], radius = 1"#,
        ),
        (
            "convex-polygon",
            r#"vertices = [[0, 0, 5], [1, 0, 5], [1.5, 1, 5], [0, 1, 5]]"#,
        ),
        (
            "bilinear-surface",
            r#"corners = [[0, 0, 5], [1, 0, 5], [1, 1, 6], [0, 1, 5]]"#,
        ),
    ];
    for (kind, keys) in shapes {
        let text = format!(
            "[[object]]\nshape = {{ type = \"{kind}\", {keys} }}\nsurface = {{ type = \"matt\", colour = [1, 1, 1] }}\n"
        );
        let scene = file::parse(&text, "s.toml").unwrap_or_else(|e| panic!("{e}"));
        let shape = &scene.objects.last().unwrap().shape;
        assert_eq!(shape.kind(), kind);
        // Each is hit by a ray from the camera's side, straight at its bounds' middle.
        let (lo, hi) = shape.bounds().unwrap();
        let aim = 0.5 * (lo + hi);
        let hit = shape.intersect(DVec3::new(aim.x, aim.y, 0.0), DVec3::Z, 0.0, f64::INFINITY);
        assert!(hit.is_some(), "{kind}: no hit at {aim}");
    }
}

/// A convex polygon is flat: a phase hologram takes it, as it takes a parallelogram.
#[test]
fn a_phase_hologram_works_on_a_convex_polygon() {
    let text = "[[object]]\nshape = { type = \"convex-polygon\", vertices = [[0, 0, 5], [-1, 0, 5], [-1, 1, 5], [0, 1, 5]] }\nsurface = { type = \"phase-hologram\", phase = { type = \"linear\", gradient = [0.1, 0] } }\n";
    file::parse(text, "s.toml").unwrap_or_else(|e| panic!("{e}"));
}

/// Tiny and huge polyhedra: finite, outward frames and exact hits (no product of two tiny
/// edges underflows to a zero normal).
#[test]
fn tiny_and_huge_polyhedra_are_hit() {
    for s in [1e-200, 1e-5, 1e12] {
        let shapes = [
            Shape::Cuboid(Cuboid::new(DVec3::ZERO, DVec3::splat(2.0 * s)).unwrap()),
            Shape::PlatonicSolid(
                PlatonicSolid::new(PlatonicKind::Cube, DVec3::ZERO, 3f64.sqrt() * s).unwrap(),
            ),
        ];
        for shape in shapes {
            let hit = shape.intersect(
                DVec3::new(0.1 * s, 0.2 * s, -5.0 * s),
                DVec3::Z,
                0.0,
                f64::INFINITY,
            );
            let (t, part) = hit.unwrap_or_else(|| panic!("{s}: {shape:?}"));
            assert!((t - 4.0 * s).abs() <= 1e-15 * s, "{s}: {t}");
            let f = shape.frame(DVec3::new(0.1 * s, 0.2 * s, -s), part);
            check_frame(&f).unwrap();
            assert!((f.w - DVec3::NEG_Z).length() < 1e-15, "{s}: {f:?}");
        }
    }
}
