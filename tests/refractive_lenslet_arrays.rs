//! Issue 40 item 2, real lenslet arrays: Dr TIM's `RefractiveLensletArray` (the
//! `refractive-lenslet-array` device), traced as one solid of glass, checked against facts
//! worked out here:
//!
//! * its surface against the same lenslets built another way, each on its own by constructive
//!   solid geometry from balls and its cell's prism, with Dr TIM's minimum-thickness rule
//!   (`RefractiveBoxLens`) evaluated here: first hits from outside agree in distance and
//!   normal, for centred lenslets, off-centre ones (a Gabor superlens's steps) and diverging
//!   ones, on a skew lattice;
//! * the sheet is one piece of glass: a ray inside it crosses from lenslet to lenslet without
//!   meeting a surface, and leaves by the array's edge;
//! * the sagitta: a lenslet is 2 (R − √(R² − a²)) + d thick on its axis;
//! * optics, with Snell's law written here: a lenslet focuses a paraxial ray at the thick
//!   lens's focal length for radii ±2 f (n − 1) and its traced thickness;
//! * the research scene `GaborSupererLensExplorer`: each pair of lenslets is a Galilean
//!   telescope that turns a line of sight from the camera by the angular magnification
//!   −f_ocular/f_objective = 5 (paraxial optics of two thin lenses);
//! * impossible parameters refused by `timbre check` where they are written.

mod common;

use glam::DVec3;
use tempfile::TempDir;
use timbre::geometry::{Csg, CsgOperation, Parallelepiped, Shape, Sphere};
use timbre::scene::file;

use common::cli::{path_str, timbre, write};
use common::glass::follow;
use common::rng::Rng;

/// A lattice and lenslets: clear-aperture periods u, v about the centre (0, 0, 5), principal
/// points offset from the apertures by i δu + j δv, 3 × 3 lenslets.
struct Case {
    u: DVec3,
    v: DVec3,
    du: DVec3,
    dv: DVec3,
    f: f64,
    n: f64,
    d: f64,
}

const CENTRE: DVec3 = DVec3::new(0.0, 0.0, 5.0);

impl Case {
    fn lenses(&self) -> String {
        let v = |x: DVec3| format!("[{}, {}, {}]", x.x, x.y, x.z);
        format!(
            "{{ type = \"refractive-lenslet-array\", centre = {}, width = {}, height = {}, \
             u_period_clear_aperture = {}, v_period_clear_aperture = {}, \
             u_period_principal_point = {}, v_period_principal_point = {}, focal_length = {}, \
             refractive_index = {}, thickness_at_thinnest_point = {} }}",
            v(CENTRE),
            3.0 * self.u.length(),
            3.0 * self.v.length(),
            v(self.u),
            v(self.v),
            v(self.u + self.du),
            v(self.v + self.dv),
            self.f,
            self.n,
            self.d
        )
    }

    fn array(&self) -> timbre::scene::SceneDescription {
        let text = format!(
            "studio = \"none\"\n[[device]]\nname = \"array\"\nlenses = {}\n",
            self.lenses()
        );
        file::parse(&text, "array.toml").unwrap()
    }

    /// Lenslet (i, j) by CSG: Dr TIM's `RefractiveBoxLens` with its aperture's corners and
    /// principal point worked out here.
    fn lenslet(&self, i: f64, j: f64) -> Shape {
        let a = CENTRE + i * self.u + j * self.v;
        let p = a + i * self.du + j * self.dv;
        let r = (2.0 * self.f * (self.n - 1.0)).abs();
        let corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .map(|(x, y)| a + x * self.u + y * self.v - p);
        let far = corners.iter().map(|c| c.length()).fold(0.0, f64::max);
        let ball = |z: f64| Shape::Sphere(Sphere::new(p + z * DVec3::Z, r).unwrap());
        let inverse = |s: Shape| Shape::Csg(Csg::new(CsgOperation::Inverse, vec![s]).unwrap());
        let prism = |depth: f64| {
            Shape::Parallelepiped(
                Parallelepiped::new(
                    DVec3::new(a.x, a.y, p.z),
                    [self.u, self.v, depth * DVec3::Z],
                )
                .unwrap(),
            )
        };
        let members = if self.f > 0.0 {
            // Thinnest (d) at the farthest corner: the balls' centres ±c with
            // √(R² − far²) − c = d/2.
            let c = (r * r - far * far).sqrt() - 0.5 * self.d;
            assert!(c > 0.0);
            vec![ball(c), ball(-c), prism(4.0 * r)]
        } else {
            // Thinnest (d) at the aperture's point nearest the axis, at distance b (0 where the
            // axis passes through the aperture): the balls' centres ±(√(R² − b²) + d/2), the
            // glass between the planes through them.
            let b = nearest(&corners, a - p);
            let c = (r * r - b * b).sqrt() + 0.5 * self.d;
            vec![inverse(ball(c)), inverse(ball(-c)), prism(2.0 * c)]
        };
        Shape::Csg(Csg::new(CsgOperation::Intersection, members).unwrap())
    }
}

/// The distance from the z axis through the origin to the parallelogram with `corners` (about
/// its centre `centre`, both relative to the axis): 0 if the axis passes through it, else the
/// least distance to its edges, found by ternary search along each (the distance along an edge
/// is convex).
fn nearest(corners: &[DVec3; 4], centre: DVec3) -> f64 {
    let flat = |x: DVec3| DVec3::new(x.x, x.y, 0.0);
    let crosses = (0..4).all(|k| {
        let (a, b) = (flat(corners[k]), flat(corners[(k + 1) % 4]));
        // The origin is on the centre's side of every edge.
        (b - a).cross(-a).z * (b - a).cross(flat(centre) - a).z >= 0.0
    });
    if crosses {
        return 0.0;
    }
    (0..4)
        .map(|k| {
            let (a, b) = (flat(corners[k]), flat(corners[(k + 1) % 4]));
            let at = |s: f64| (a + s * (b - a)).length();
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..200 {
                let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                if at(m1) <= at(m2) {
                    hi = m2;
                } else {
                    lo = m1;
                }
            }
            at(0.5 * (lo + hi))
        })
        .fold(f64::INFINITY, f64::min)
}

fn cases() -> Vec<Case> {
    let (u, v) = (DVec3::new(0.3, 0.0, 0.0), DVec3::new(0.05, 0.25, 0.0));
    let centred = |f: f64, d: f64| Case {
        u,
        v,
        du: DVec3::ZERO,
        dv: DVec3::ZERO,
        f,
        n: 1.5,
        d,
    };
    vec![
        centred(0.5, 0.01),
        centred(0.4, 0.0),
        centred(-0.4, 0.02),
        // Principal points drifting off the apertures' centres: steps between the lenslets.
        Case {
            du: DVec3::new(0.03, 0.01, 0.0),
            dv: DVec3::new(-0.01, 0.02, 0.0),
            ..centred(0.6, 0.01)
        },
        Case {
            du: DVec3::new(0.02, 0.0, 0.0),
            dv: DVec3::new(0.0, -0.03, 0.0),
            ..centred(-0.5, 0.01)
        },
        // Diverging lenslets whose axes miss their apertures (but the middle one's): thinnest
        // at the aperture's nearest point.
        Case {
            du: DVec3::new(0.2, 0.0, 0.0),
            dv: DVec3::new(0.0, -0.17, 0.0),
            ..centred(-0.6, 0.01)
        },
    ]
}

#[test]
fn first_hits_match_the_lenslets_built_one_by_one() {
    let mut rng = Rng(40);
    for (k, case) in cases().iter().enumerate() {
        let description = case.array();
        let array = &description.objects[0].shape;
        let lenslets: Vec<Shape> = (-1..=1)
            .flat_map(|i| (-1..=1).map(move |j| (i as f64, j as f64)))
            .map(|(i, j)| case.lenslet(i, j))
            .collect();
        let half = 1.5 * (case.u + case.v).abs() + DVec3::new(0.0, 0.0, 0.2);
        let (mut hits, mut walls) = (0, 0);
        for _ in 0..4000 {
            let o = CENTRE + 3.0 * rng.unit();
            let target = rng.point_in_box(CENTRE - half, CENTRE + half);
            let d = (target - o).normalize();
            let expected = lenslets
                .iter()
                .filter_map(|l| l.intersect(o, d, 1e-9, 1e3).map(|(t, part)| (t, part, l)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let got = array.intersect(o, d, 1e-9, 1e3);
            match (expected, got) {
                (None, None) => {}
                (Some((t, part, l)), Some((t2, part2))) => {
                    assert!((t - t2).abs() < 1e-9, "case {k}: t {t} vs {t2}");
                    let p = o + t * d;
                    let (n1, n2) = (l.normal(p, part), array.normal(p, part2));
                    assert!((n1 - n2).length() < 1e-9, "case {k} at {p}: {n1} vs {n2}");
                    hits += 1;
                    walls += usize::from(n1.z.abs() < 1e-12);
                }
                (e, g) => panic!("case {k}: {o} along {d}: expected {e:?}, got {g:?}"),
            }
        }
        assert!(hits > 1000, "case {k}: {hits} hits");
        assert!(walls > 0, "case {k}: no wall met");
    }
}

#[test]
fn inside_the_sheet_light_crosses_from_lenslet_to_lenslet() {
    // Converging lenslets at least d thick everywhere: the middle plane is glass throughout.
    let case = &cases()[0];
    let description = case.array();
    let array = &description.objects[0].shape;
    // From the centre along u: the first surface is the array's edge, 1.5 periods away.
    let (t, part) = array.intersect(CENTRE, DVec3::X, 1e-9, 10.0).unwrap();
    assert!((t - 1.5 * 0.3).abs() < 1e-12, "{t}");
    let normal = array.normal(CENTRE + t * DVec3::X, part);
    let expected = case.v.cross(DVec3::Z).normalize();
    assert!((normal - expected).length() < 1e-12, "{normal}");
    // Along v, likewise 1.5 periods along the skew lattice's v.
    let along = case.v.normalize();
    let (t, _) = array.intersect(CENTRE, along, 1e-9, 10.0).unwrap();
    assert!((t - 1.5 * case.v.length()).abs() < 1e-12, "{t}");
}

/// The distance through the array along z at (x, y).
fn thickness(array: &Shape, x: f64, y: f64) -> f64 {
    let o = DVec3::new(x, y, CENTRE.z - 2.0);
    let (t0, _) = array.intersect(o, DVec3::Z, 0.0, 10.0).unwrap();
    let (t1, _) = array.intersect(o, DVec3::Z, t0 + 1e-9, 10.0).unwrap();
    t1 - t0
}

#[test]
fn a_lenslet_is_as_thick_as_its_sagitta_says() {
    let (u, v) = (DVec3::new(0.3, 0.0, 0.0), DVec3::new(0.0, 0.2, 0.0));
    let a = 0.5 * (u + v).length();
    for (f, d) in [(0.5, 0.01), (0.3, 0.001), (-0.4, 0.02)] {
        let case = Case {
            u,
            v,
            du: DVec3::ZERO,
            dv: DVec3::ZERO,
            f,
            n: 1.6,
            d,
        };
        let description = case.array();
        let array = &description.objects[0].shape;
        let r = (2.0 * f * 0.6f64).abs();
        let sagitta = r - (r * r - a * a).sqrt();
        let (centre, corner) = (
            thickness(array, 0.3, 0.0),
            thickness(array, 0.45 - 1e-9, 0.1),
        );
        let (thick, thin) = if f > 0.0 {
            (centre, corner)
        } else {
            (corner, centre)
        };
        assert!((thin - d).abs() < 1e-6, "f {f}: thinnest {thin}");
        assert!(
            (thick - (2.0 * sagitta + d)).abs() < 1e-6,
            "f {f}: {thick} vs {}",
            2.0 * sagitta + d
        );
    }
}

#[test]
fn a_lenslet_focuses_as_a_thick_lens_of_radii_2_f_n_minus_1() {
    // The lenslet at the centre, a ray parallel to the axis 10⁻⁴ from it: it leaves at slope s
    // towards the axis, f' = 10⁻⁴/s, the thick lens's 1/f' = (n − 1)(2/R − (n − 1) d_c/(n R²))
    // with d_c its thickness on the axis, traced.
    for (f, n) in [(0.5, 1.5), (-0.4, 1.5), (0.8, 1.7)] {
        let case = Case {
            u: DVec3::new(0.3, 0.0, 0.0),
            v: DVec3::new(0.0, 0.25, 0.0),
            du: DVec3::ZERO,
            dv: DVec3::ZERO,
            f,
            n,
            d: 0.01,
        };
        let description = case.array();
        let d_c = thickness(&description.objects[0].shape, 0.0, 0.0);
        let h = 1e-4;
        let (met, _, e) = follow(&description, DVec3::new(h, 0.0, 0.0), DVec3::Z).unwrap();
        assert_eq!(met.len(), 2, "{met:?}");
        let traced = -h * e.z / e.x;
        let r = 2.0 * f * (n - 1.0);
        let expected = 1.0 / ((n - 1.0) * (2.0 / r - (n - 1.0) * d_c / (n * r * r)));
        assert!(
            (traced - expected).abs() < 1e-6 * f.abs(),
            "f {f}: {traced} vs {expected}"
        );
    }
}

#[test]
fn the_gabor_superer_lens_explorers_telescopes_magnify_angles_five_times() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/research/GaborSupererLensExplorer.toml"
    );
    let mut description = file::parse(&std::fs::read_to_string(path).unwrap(), path).unwrap();
    description
        .objects
        .retain(|o| o.name.ends_with("/lenslets"));
    let camera = DVec3::new(0.0, 0.0, -0.014);
    for theta in [0.002, -0.005, 0.01] {
        // Towards lenslet (0, 0) of both arrays; the objects met are the two arrays' glass.
        let d = DVec3::new(f64::sin(theta), 0.0, f64::cos(theta));
        let (met, _, e) = follow(&description, camera, d).unwrap();
        let expected = ["ocular/lenslets", "ocular/lenslets", "objective/lenslets"];
        assert_eq!(met[..3], expected, "{met:?}");
        assert_eq!(met.len(), 4, "{met:?}");
        let ratio = (e.x / e.z).atan() / theta;
        assert!(
            (ratio - 5.0).abs() < 0.1,
            "theta {theta}: magnified {ratio}"
        );
    }
}

#[test]
fn impossible_lenslet_arrays_are_refused_where_they_are_written() {
    let device = |keys: &str| {
        format!(
            "[[device]]\nname = \"array\"\nlenses = {{ type = \"refractive-lenslet-array\", \
             centre = [0, 0, 5], width = 1, height = 1, u_period_clear_aperture = [0.1, 0, 0], \
             refractive_index = 1.5, {keys} }}\n"
        )
    };
    let cases = [
        (
            device("v_period_clear_aperture = [0, 0.1, 0], focal_length = 0"),
            vec![":3:10:", "non-zero number, got 0"],
        ),
        (
            device("v_period_clear_aperture = [0.2, 0, 0], focal_length = 1"),
            vec![":3:10:", "device 'array'", "parallel"],
        ),
        (
            // R = 2 f (n − 1) = 0.05 is shorter than the half-diagonal of a 0.1 × 0.1 lenslet.
            device("v_period_clear_aperture = [0, 0.1, 0], focal_length = 0.05"),
            vec![":3:10:", "beyond the radius of curvature"],
        ),
        (
            device("v_period_clear_aperture = [0, 0.1, 0], focal_length = 1, thickness = 1"),
            vec![":3:10:", "thickness"],
        ),
        (
            device(
                "v_period_clear_aperture = [0, 0.1, 0], focal_length = 1, \
                 clear_aperture_centre = [0, 0, 5.1], principal_point_centre = [0, 0, 5]",
            ),
            vec![":3:10:", "clear_aperture_centre must lie in the plane"],
        ),
        (
            device(
                "v_period_clear_aperture = [0, 0.1, 0], focal_length = 1, \
                 thickness_at_thinnest_point = -1",
            ),
            vec![":3:10:", "got -1"],
        ),
    ];
    let dir = TempDir::new().unwrap();
    for (text, needles) in cases {
        let path = write(&dir, "bad.toml", &text);
        timbre(dir.path(), &["check", path_str(&path)]).assert_bad_input(&needles);
    }
}

#[test]
fn an_edge_on_a_cell_boundary_adds_no_lenslet_beyond_it() {
    // Three lenslets 0.25 wide (s from −1.5 to 1.5) whose principal points drift 0.08 a
    // lenslet: the outer ones' apertures reach √(0.205² + 0.125²) ≈ 0.240 from their axes,
    // within R = 2 f (n − 1) = 0.25; a fourth, beyond the edge, would reach 0.311.
    let text = "[[device]]\nname = \"array\"\nlenses = { type = \"refractive-lenslet-array\", \
                centre = [0, 0, 5], width = 0.75, height = 0.25, \
                u_period_clear_aperture = [0.25, 0, 0], v_period_clear_aperture = [0, 0.25, 0], \
                u_period_principal_point = [0.33, 0, 0], focal_length = 0.25, \
                refractive_index = 1.5 }\n";
    let dir = TempDir::new().unwrap();
    let path = write(&dir, "edge.toml", text);
    timbre(dir.path(), &["check", path_str(&path)]).assert_success();
    let wider = text.replace("width = 0.75", "width = 0.8");
    let path = write(&dir, "wider.toml", &wider);
    timbre(dir.path(), &["check", path_str(&path)]).assert_bad_input(&[
        ":3:10:",
        "lenslet (-2, 0)",
        "beyond the radius of curvature",
    ]);
}
