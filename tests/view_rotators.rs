//! Issue 40 item 3, view rotators: Dr TIM's `RefractiveViewRotator` (the
//! `refractive-view-rotator` device), traced as one solid of glass, checked against facts
//! worked out here:
//!
//! * its surface against the same wedges built another way, each pixel on its own by
//!   constructive solid geometry from half-spaces (the wedge's two faces as Dr TIM's
//!   `SurfaceOfRefractiveViewRotator` places them, the four walls of the pixel's voxel through
//!   the eye, Dr TIM's two `FanOfPlanes`) and the bounding box: first hits from outside, and the
//!   next change between glass and air from anywhere in the box with the search cut short,
//!   agree in distance and normal, with the research program's parameters and with a skew one
//!   (magnification 2, a tilted rotation axis, skew periods, the eye off the axis, the wedges
//!   set back by a derivative-control thickness);
//! * optics, with Snell's law and Rodrigues' rotation written here: the ray from the eye
//!   through a pixel's centre leaves its wedge towards the point of the view plane that the eye
//!   sees, undeviated, in the rotated (and magnified) direction, so the view is rotated (also
//!   with ViewRotationExplorerWithUnits's wedges set 10 mm back);
//! * without rotation or magnification every wedge is a plane-parallel plate, which leaves the
//!   direction of every ray from the eye as it was;
//! * the diffraction blur: rays leaving the box are kicked along the periods by a pixel's
//!   single-slit diffraction, (2/π) Si(2π) ≈ 0.903 of them within the first minimum along each
//!   side (Abramowitz & Stegun's Si), also with the device turned and at another wavelength;
//!   rays leaving a skew box by any of its faces meet the blur once;
//! * impossible parameters refused by `timbre check` where they are written.

mod common;

use glam::DVec3;
use tempfile::TempDir;
use timbre::geometry::{Csg, CsgOperation, Parallelepiped, Plane, Shape};
use timbre::scene::{SceneDescription, file};
use timbre::trajectories;

use common::cli::{path_str, timbre, write};
use common::glass::{follow, snell};
use common::rng::Rng;

const MM: f64 = 1e-3;

/// A view rotator's parameters, as Dr TIM's `RefractiveViewRotator` takes them.
struct Rotator {
    box_centre: DVec3,
    spans: [DVec3; 3],
    eye: DVec3,
    origin: DVec3,
    p1: DVec3,
    p2: DVec3,
    angle_deg: f64,
    axis: DVec3,
    magnification: f64,
    view_point: DVec3,
    view_normal: DVec3,
    n: f64,
    thickness: f64,
    /// D, Dr TIM's derivative-control thickness.
    offset: f64,
}

/// ViewRotationExplorerWithUnitsSpacePlateTest's rotator, its box cut to `spans` about
/// `box_centre`.
fn research(box_centre: DVec3, spans: [DVec3; 3]) -> Rotator {
    Rotator {
        box_centre,
        spans,
        eye: DVec3::new(0.0, 0.0, -15.0 * MM),
        origin: DVec3::ZERO,
        p1: DVec3::new(0.5 * MM, 0.0, 0.0),
        p2: DVec3::new(0.0, 0.5 * MM, 0.0),
        angle_deg: 10.0,
        axis: DVec3::new(0.0, 0.0, -1.0),
        magnification: 1.0,
        view_point: DVec3::new(0.0, 0.0, 2.0),
        view_normal: DVec3::Z,
        n: 1.5,
        thickness: 1.0 * MM,
        offset: 0.0,
    }
}

/// A skew rotator: magnification 2, a tilted axis, skew periods, the eye off the axis, a
/// tilted view plane.
fn skew() -> Rotator {
    Rotator {
        box_centre: DVec3::new(4.0 * MM, 2.0 * MM, 1.2 * MM),
        spans: [
            DVec3::new(2.0 * MM, 0.2 * MM, 0.0),
            DVec3::new(0.0, 2.5 * MM, 0.3 * MM),
            DVec3::new(0.0, 0.0, 3.0 * MM),
        ],
        eye: DVec3::new(1.0 * MM, -2.0 * MM, -12.0 * MM),
        origin: DVec3::new(0.1 * MM, 0.2 * MM, 0.0),
        p1: DVec3::new(0.5 * MM, 0.1 * MM, 0.0),
        p2: DVec3::new(-0.1 * MM, 0.4 * MM, 0.0),
        angle_deg: -25.0,
        axis: DVec3::new(0.2, 0.1, -1.0),
        magnification: 2.0,
        view_point: DVec3::new(0.0, 0.0, 1.5),
        view_normal: DVec3::new(0.1, 0.0, 1.0),
        n: 1.7,
        thickness: 0.8 * MM,
        offset: 0.3 * MM,
    }
}

/// ViewRotationExplorerWithUnits's rotator (its defaults): the wedges start D = 10 mm behind
/// the ocular plane, designed for the plane z = 1 m, in a box 44 mm deep about z = 20 mm.
fn with_units() -> Rotator {
    Rotator {
        view_point: DVec3::new(0.0, 0.0, 1.0),
        offset: 10.0 * MM,
        ..research(
            DVec3::new(0.0, 0.0, 20.0 * MM),
            [
                DVec3::new(50.0 * MM, 0.0, 0.0),
                DVec3::new(0.0, 50.0 * MM, 0.0),
                DVec3::new(0.0, 0.0, 44.0 * MM),
            ],
        )
    }
}

/// The research rotator without rotation, in a 2 cm × 2 cm box whose front face lies well
/// before the ocular faces, so that every ray from the eye enters its wedge through the
/// ocular face: every wedge a plane-parallel plate.
fn plate() -> Rotator {
    Rotator {
        angle_deg: 0.0,
        ..research(
            DVec3::ZERO,
            [
                DVec3::new(20.0 * MM, 0.0, 0.0),
                DVec3::new(0.0, 20.0 * MM, 0.0),
                DVec3::new(0.0, 0.0, 6.0 * MM),
            ],
        )
    }
}

impl Rotator {
    /// The coordinates of `x` along the box's spans from its centre (each within ±½ inside).
    fn box_coordinates(&self, x: DVec3) -> [f64; 3] {
        let s = self.spans;
        let volume = s[0].dot(s[1].cross(s[2]));
        [s[1].cross(s[2]), s[2].cross(s[0]), s[0].cross(s[1])]
            .map(|star| (x - self.box_centre).dot(star) / volume)
    }

    fn lenses(&self) -> String {
        let v = |x: DVec3| format!("[{:e}, {:e}, {:e}]", x.x, x.y, x.z);
        format!(
            "{{ type = \"refractive-view-rotator\", bounding_box_centre = {}, \
             bounding_box_span_vector_1 = {}, bounding_box_span_vector_2 = {}, \
             bounding_box_span_vector_3 = {}, eye_position = {}, ocular_plane_centre = {}, \
             period_vector_1 = {}, period_vector_2 = {}, rotation_angle_deg = {}, \
             rotation_axis_direction = {}, magnification_factor = {}, view_plane_point = {}, \
             view_plane_normal = {}, refractive_index = {}, wedge_thickness = {:e}, \
             derivative_control_thickness = {:e} }}",
            v(self.box_centre),
            v(self.spans[0]),
            v(self.spans[1]),
            v(self.spans[2]),
            v(self.eye),
            v(self.origin),
            v(self.p1),
            v(self.p2),
            self.angle_deg,
            v(self.axis),
            self.magnification,
            v(self.view_point),
            v(self.view_normal),
            self.n,
            self.thickness,
            self.offset
        )
    }

    fn scene(&self) -> SceneDescription {
        let text = format!(
            "studio = \"none\"\n[[device]]\nname = \"rotator\"\nlenses = {}\n",
            self.lenses()
        );
        file::parse(&text, "rotator.toml").unwrap()
    }

    /// Where pixel (i, j)'s wedge starts, C (D behind its centre along d_O), the direction d_O
    /// from the eye through the pixel's centre, and the point X of
    /// the view plane the eye is to see in that direction: on the ray from the eye along d_O
    /// rotated by Rodrigues' formula, its part across the axis divided by the magnification.
    fn design(&self, i: i64, j: i64) -> (DVec3, DVec3, DVec3) {
        let centre = self.origin + i as f64 * self.p1 + j as f64 * self.p2;
        let d_o = (centre - self.eye).normalize();
        let c = centre + self.offset * d_o;
        let (a, theta) = (self.axis.normalize(), self.angle_deg.to_radians());
        let rotated =
            d_o * theta.cos() + a.cross(d_o) * theta.sin() + a * a.dot(d_o) * (1.0 - theta.cos());
        let along = a * a.dot(rotated);
        let d_r = along + (rotated - along) / self.magnification;
        let mu = (self.view_point - self.eye).dot(self.view_normal) / d_r.dot(self.view_normal);
        (c, d_o, self.eye + mu * d_r)
    }

    /// Pixel (i, j)'s glass by CSG: the wedge between its ocular face (through C, normal to
    /// d_O) and its objective face (through Q = C + T d_O, normal to n d_O − d_obj, which
    /// refracts d_O into d_obj towards X), inside the pixel's voxel and the box.
    fn pixel(&self, i: i64, j: i64) -> Shape {
        let (c, d_o, x) = self.design(i, j);
        let centre = self.origin + i as f64 * self.p1 + j as f64 * self.p2;
        let q = c + self.thickness * d_o;
        let d_obj = (x - q).normalize();
        let mut n_obj = self.n * d_o - d_obj;
        if n_obj.dot(d_obj) < 0.0 {
            n_obj = -n_obj;
        }
        let half_space = |point: DVec3, outward: DVec3| {
            Shape::Plane(Plane::new(point, outward, outward.any_orthonormal_vector()).unwrap())
        };
        let mut members = vec![
            half_space(c, -d_o),
            half_space(q, n_obj),
            Shape::Parallelepiped(Parallelepiped::new(self.box_centre, self.spans).unwrap()),
        ];
        // The voxel: the planes through the eye and the lines through C ± p₁/2 along p₂ and
        // through C ± p₂/2 along p₁, each with C on its inner side.
        for (edge, along) in [
            (0.5 * self.p1, self.p2),
            (-0.5 * self.p1, self.p2),
            (0.5 * self.p2, self.p1),
            (-0.5 * self.p2, self.p1),
        ] {
            let mut normal = (centre + edge - self.eye).cross(along);
            if normal.dot(centre - self.eye) > 0.0 {
                normal = -normal;
            }
            members.push(half_space(self.eye, normal));
        }
        Shape::Csg(Csg::new(CsgOperation::Intersection, members).unwrap())
    }
}

#[test]
fn first_hits_match_the_wedges_built_one_by_one() {
    let mut rng = Rng(41);
    let cases = [
        // The research program's rotator, off the axis where the wedges lean, its box's front
        // face 0.1 µm in front of the ocular plane as in the program (it cuts the ocular faces
        // that lean forwards).
        research(
            DVec3::new(6.0 * MM, 3.5 * MM, 1.4999 * MM),
            [
                DVec3::new(2.0 * MM, 0.0, 0.0),
                DVec3::new(0.0, 2.0 * MM, 0.0),
                DVec3::new(0.0, 0.0, 3.0 * MM),
            ],
        ),
        skew(),
    ];
    for (k, case) in cases.iter().enumerate() {
        let description = case.scene();
        let glass = &description.objects[0].shape;
        let pixels: Vec<Shape> = (-6..=22)
            .flat_map(|i| (-6..=22).map(move |j| (i, j)))
            .map(|(i, j)| case.pixel(i, j))
            .collect();
        let (mut hits, mut walls) = (0, 0);
        let half = 0.5 * (case.spans[0].abs() + case.spans[1].abs() + case.spans[2].abs());
        for _ in 0..3000 {
            let o = case.box_centre + 6.0 * MM * rng.unit();
            let target = rng.point_in_box(case.box_centre - half, case.box_centre + half);
            let d = (target - o).normalize();
            let expected = pixels
                .iter()
                .filter_map(|p| p.intersect(o, d, 1e-12, 1.0).map(|(t, part)| (t, part, p)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let got = glass.intersect(o, d, 1e-12, 1.0);
            match (expected, got) {
                (None, None) => {}
                (Some((t, part, p)), Some((t2, part2))) => {
                    assert!(
                        (t - t2).abs() < 1e-12,
                        "case {k}: {o} along {d}: t {t} vs {t2}"
                    );
                    let x = o + t * d;
                    let (n1, n2) = (p.normal(x, part), glass.normal(x, part2));
                    assert!((n1 - n2).length() < 1e-9, "case {k} at {x}: {n1} vs {n2}");
                    hits += 1;
                    // A wall is a plane through the eye.
                    walls +=
                        usize::from(n1.dot(x - case.eye).abs() < 1e-9 * (x - case.eye).length());
                }
                (e, g) => panic!("case {k}: {o} along {d}: expected {e:?}, got {g:?}"),
            }
        }
        assert!(hits > 1000, "case {k}: {hits} hits");
        assert!(walls > 10, "case {k}: {walls} walls met");
        // From anywhere in the box, in the glass or not, with the search cut short: the next
        // surface of the union of the pixels' glass (no surface where two pixels' glass meets).
        let union = Shape::Csg(Csg::new(CsgOperation::Union, pixels).unwrap());
        let (mut inside, mut hits) = (0, 0);
        for _ in 0..1500 {
            let o = rng.point_in_box(case.box_centre - half, case.box_centre + half);
            let d = rng.unit();
            let t_max = rng.range(0.1, 4.0) * MM;
            let expected = change_of_side(&union, o, d, t_max);
            let got = glass.intersect(o, d, 1e-12, t_max);
            inside += usize::from(union.contains(o));
            match (expected, got) {
                (None, None) => {}
                (Some((t, part)), Some((t2, part2))) => {
                    assert!(
                        (t - t2).abs() < 1e-12,
                        "case {k}: {o} along {d}: t {t} vs {t2}"
                    );
                    let x = o + t * d;
                    let (n1, n2) = (union.normal(x, part), glass.normal(x, part2));
                    assert!((n1 - n2).length() < 1e-9, "case {k} at {x}: {n1} vs {n2}");
                    hits += 1;
                }
                (e, g) => panic!("case {k}: {o} along {d} to {t_max}: expected {e:?}, got {g:?}"),
            }
        }
        assert!(
            inside > 100 && hits > 300,
            "case {k}: {inside} inside, {hits} hits"
        );
    }
}

/// The first hit of `shape` along the ray from `o` along `d` before `t_max` where the ray
/// crosses from glass to air or back: the union of pieces built independently may report the
/// boundary between two of them, where rounding leaves them a hair apart or overlapping.
fn change_of_side(shape: &Shape, o: DVec3, d: DVec3, t_max: f64) -> Option<(f64, u32)> {
    let mut from = 1e-12;
    while let Some((t, part)) = shape.intersect(o, d, from, t_max) {
        let side = |t: f64| shape.contains(o + t * d);
        if side(t - 1e-10) != side(t + 1e-10) {
            return Some((t, part));
        }
        from = t + 1e-10;
    }
    None
}

/// Where the ray from `o` along `d` meets the plane through `point` normal to `normal`.
fn on_plane(o: DVec3, d: DVec3, point: DVec3, normal: DVec3) -> DVec3 {
    o + (point - o).dot(normal) / d.dot(normal) * d
}

#[test]
fn the_eye_sees_through_each_pixel_the_rotated_point_of_the_view_plane() {
    // The whole research rotator, 5 cm square; and the skew one.
    let whole = research(
        DVec3::new(0.0, 0.0, 1.4999 * MM),
        [
            DVec3::new(50.0 * MM, 0.0, 0.0),
            DVec3::new(0.0, 50.0 * MM, 0.0),
            DVec3::new(0.0, 0.0, 3.0 * MM),
        ],
    );
    for case in [whole, skew(), with_units()] {
        // Pixels whose wedge's centre line, C to Q, lies inside the box.
        let in_box = |x: DVec3| case.box_coordinates(x).iter().all(|a| a.abs() < 0.5);
        let pixels: Vec<(i64, i64)> = (-60..=60)
            .flat_map(|i| (-60..=60).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                let (c, d_o, _) = case.design(i, j);
                in_box(c) && in_box(c + case.thickness * d_o)
            })
            .collect();
        assert!(pixels.len() > 5, "{} pixels", pixels.len());
        let pixels: Vec<_> = pixels.iter().step_by(pixels.len() / 30 + 1).collect();
        let description = case.scene();
        let glass = &description.objects[0].shape;
        let mut clear = 0;
        for &&(i, j) in &pixels {
            let (c, d_o, x) = case.design(i, j);
            // Into the ocular face at C at normal incidence (undeviated) ...
            let (t, part) = glass.intersect(case.eye, d_o, 1e-12, 1.0).unwrap();
            let at = case.eye + t * d_o;
            assert!(
                (at - c).length() < 1e-12,
                "pixel ({i}, {j}): entered at {at}, C = {c}"
            );
            let inside = snell(d_o, glass.normal(at, part), case.n).unwrap();
            assert!(
                (inside - d_o).length() < 1e-12,
                "pixel ({i}, {j}): bent to {inside}"
            );
            // ... and out of the objective face at Q, towards X.
            let (t, part) = glass.intersect(at, inside, 1e-12, 1.0).unwrap();
            let out = at + t * inside;
            let q = c + case.thickness * d_o;
            assert!(
                (out - q).length() < 1e-12,
                "pixel ({i}, {j}): left at {out}, Q = {q}"
            );
            let d = snell(inside, glass.normal(out, part), case.n).unwrap();
            let seen = on_plane(out, d, case.view_point, case.view_normal);
            assert!(
                (seen - x).length() < 1e-9 * (x - case.eye).length(),
                "pixel ({i}, {j}): sees {seen}, should see {x}"
            );
            // Unless the ray goes on through a neighbouring pixel's wedge (which the design
            // does not prevent, far off the axis), that is what the eye sees.
            let (met, last, d) = follow(&description, case.eye, d_o).unwrap();
            if met.len() == 2 {
                let seen = on_plane(last, d, case.view_point, case.view_normal);
                assert!((seen - x).length() < 1e-9 * (x - case.eye).length());
                clear += 1;
            }
        }
        assert!(
            2 * clear > pixels.len(),
            "{clear} of {} pixels clear",
            pixels.len()
        );
    }
    // The rotation is what the eye sees: by the program's 10° about −z, the point straight
    // ahead of pixel (40, 0) (d_O in the x-z plane) appears at azimuth −10°.
    let (_, d_o, x) = research(DVec3::ZERO, [DVec3::X; 3]).design(40, 0);
    let (azimuth_in, azimuth_seen) = (d_o.y.atan2(d_o.x), x.y.atan2(x.x));
    assert!(((azimuth_seen - azimuth_in).to_degrees() + 10.0).abs() < 1e-9);
}

#[test]
fn without_rotation_every_wedge_is_a_plate_that_keeps_directions() {
    let plate = plate();
    let description = plate.scene();
    let mut rng = Rng(7);
    for _ in 0..500 {
        let target = DVec3::new(rng.range(-9.0, 9.0) * MM, rng.range(-9.0, 9.0) * MM, 0.0);
        let d = (target - plate.eye).normalize();
        let (met, _, out) = follow(&description, plate.eye, d).unwrap();
        assert_eq!(met.len(), 2, "{d}: {met:?}");
        assert!((out - d).length() < 1e-12, "{d} left as {out}");
    }
}

#[test]
fn impossible_view_rotators_are_refused_where_they_are_written() {
    let device = |keys: &str| {
        format!(
            "[[device]]\nname = \"rotator\"\nlenses = {{ type = \"refractive-view-rotator\", \
             bounding_box_centre = [0, 0, 0.0015], bounding_box_span_vector_1 = [0.05, 0, 0], \
             bounding_box_span_vector_2 = [0, 0.05, 0], ocular_plane_centre = [0, 0, 0], \
             rotation_angle_deg = 10, rotation_axis_direction = [0, 0, -1], \
             view_plane_point = [0, 0, 2], view_plane_normal = [0, 0, 1], \
             refractive_index = 1.5, {keys} }}\n"
        )
    };
    let good = "period_vector_1 = [0.0005, 0, 0], period_vector_2 = [0, 0.0005, 0], \
                wedge_thickness = 0.001";
    let cases = [
        (
            device(&format!(
                "{good}, bounding_box_span_vector_3 = [0, 0, 0.003], eye_position = [0, 0, 0.001]"
            )),
            vec![
                ":3:10:",
                "device 'rotator'",
                "behind the plane through the eye",
            ],
        ),
        (
            device(&format!(
                "{good}, bounding_box_span_vector_3 = [0, 0, 0.003], eye_position = [0.1, 0, 0]"
            )),
            vec![":3:10:", "the eye lies in the ocular plane"],
        ),
        (
            device(
                "period_vector_1 = [0.0005, 0, 0], period_vector_2 = [0.001, 0, 0], \
                 wedge_thickness = 0.001, bounding_box_span_vector_3 = [0, 0, 0.003], eye_position = [0, 0, -0.015]",
            ),
            vec![":3:10:", "period vectors are (nearly) parallel"],
        ),
        (
            device(&format!(
                "{good}, bounding_box_span_vector_3 = [0.05, 0.05, 0], \
                 eye_position = [0, 0, -0.015]"
            )),
            vec![":3:10:", "span vectors are (nearly) coplanar"],
        ),
        (
            device(&format!(
                "{good}, bounding_box_span_vector_3 = [0, 0, 0.003], \
                 eye_position = [0, 0, -0.015], magnification_factor = 0"
            )),
            vec![":3:10:", "non-zero number, got 0"],
        ),
        (
            device(
                &format!(
                    "{good}, bounding_box_span_vector_3 = [0, 0, 0.003], \
                 eye_position = [0, 0, -0.015]"
                )
                .replace("wedge_thickness = 0.001", "wedge_thickness = -1"),
            ),
            vec![":3:10:", "got -1"],
        ),
        (
            // 1 nm pixels across a 5 cm box: far more than 2^28.
            device(
                "period_vector_1 = [1e-9, 0, 0], period_vector_2 = [0, 1e-9, 0], \
                 wedge_thickness = 0.001, bounding_box_span_vector_3 = [0, 0, 0.003], eye_position = [0, 0, -0.015]",
            ),
            vec![":3:10:", "pixels", "more than"],
        ),
    ];
    let cases = cases.into_iter().chain([
        (
            device(&format!(
                "{good}, bounding_box_span_vector_3 = [0, 0, 0.003], \
                 eye_position = [0, 0, -0.015], lambda = 5e-7"
            )),
            vec![":3:10:", "needs simulate_diffraction_blur = true"],
        ),
        (
            // The blur's pixel sizes and wavelength would not scale with the device.
            device(&format!(
                "{good}, bounding_box_span_vector_3 = [0, 0, 0.003], \
                 eye_position = [0, 0, -0.015], simulate_diffraction_blur = true"
            )) + "transform = { scale = 2 }\n",
            vec![":4:13:", "diffraction blur", "not scaled"],
        ),
    ]);
    let dir = TempDir::new().unwrap();
    for (text, needles) in cases {
        let path = write(&dir, "bad.toml", &text);
        timbre(dir.path(), &["check", path_str(&path)]).assert_bad_input(&needles);
    }
}

/// The single-slit distribution's P(|x| < π) = (2/π) Si(2π), Si(2π) = 1.418151576132628
/// (Abramowitz & Stegun, table 5.1): the fraction of rays inside the first diffraction minimum.
const INSIDE_FIRST_MINIMUM: f64 = 2.0 / std::f64::consts::PI * 1.418_151_576_132_628;

/// Follows rays (start, direction) through `rotator` with the keys `keys` added to its
/// `lenses` table and the device entry's lines `entry`: for each, the names of the objects met,
/// where it met the last and its final direction.
fn follow_rays(
    rotator: &Rotator,
    keys: &str,
    entry: &str,
    rays: &[(DVec3, DVec3)],
) -> Vec<(Vec<String>, DVec3, DVec3)> {
    let v = |x: DVec3| format!("[{:?}, {:?}, {:?}]", x.x, x.y, x.z);
    let mut text = format!(
        "studio = \"none\"\n[[device]]\nname = \"rotator\"\nlenses = {}\n{entry}\n",
        rotator.lenses().replace(" }", &format!(", {keys} }}"))
    );
    for (o, d) in rays {
        text += &format!(
            "[[ray_trajectory]]\nstart = {}\ndirection = {}\nmax_interactions = 20\n",
            v(*o),
            v(*d)
        );
    }
    let description = file::parse(&text, "blur.toml").unwrap();
    let traced = trajectories::trace(common::rays::device(), &description).unwrap();
    traced
        .iter()
        .map(|t| {
            let hits: Vec<_> = t.points.iter().filter(|p| p.object.is_some()).collect();
            let met = hits
                .iter()
                .map(|p| description.objects[p.object.unwrap()].name.clone())
                .collect();
            let last = hits.last().map_or(t.points[0].position, |p| p.position);
            (met, last, t.direction)
        })
        .collect()
}

#[test]
fn the_diffraction_blur_spreads_rays_leaving_the_box_as_a_pixel_diffracts() {
    // A plate (no rotation), pixels 0.5 mm × 0.25 mm: without the blur the rays from the eye
    // leave as they came; with it, each leaving the box is kicked by sin θ = x λ / (π w) along
    // each side w, x of density sin² x / (π x²). Also with the device turned by 30° about the
    // eye's axis and moved along it (the kicks turn with it), and at a wavelength of 1 µm.
    let mut plate = plate();
    plate.p2 = DVec3::new(0.0, 0.25 * MM, 0.0);
    let n = 2000;
    let mut rng = Rng(11);
    let targets: Vec<DVec3> = (0..n)
        .map(|_| DVec3::new(rng.range(-5.0, 5.0) * MM, rng.range(-5.0, 5.0) * MM, 0.0))
        .collect();
    let turn = glam::DMat3::from_rotation_z(30f64.to_radians());
    let shift = DVec3::new(0.0, 0.0, 2.0 * MM);
    let placed = "transform = { rotate = { axis = [0, 0, 1], angle_deg = 30 }, \
                  translate = [0, 0, 0.002] }";
    for (turned, lambda) in [(false, 550e-9), (true, 1e-6)] {
        let (turn, shift, entry) = if turned {
            (turn, shift, placed)
        } else {
            (glam::DMat3::IDENTITY, DVec3::ZERO, "")
        };
        let eye = turn * plate.eye + shift;
        let rays: Vec<(DVec3, DVec3)> = targets
            .iter()
            .map(|t| (eye, turn * (*t - plate.eye).normalize()))
            .collect();
        let lambda_key = if turned { ", lambda = 1e-6" } else { "" };
        let plain = follow_rays(&plate, "simulate_diffraction_blur = false", entry, &rays);
        let blurred = follow_rays(
            &plate,
            &format!("simulate_diffraction_blur = true{lambda_key}"),
            entry,
            &rays,
        );
        let (mut inside_u, mut inside_v, mut reflected) = (0, 0, 0);
        for (((met, _, out), (blur_met, _, blur_out)), (_, d)) in
            plain.iter().zip(&blurred).zip(&rays)
        {
            assert_eq!(met, &["rotator/wedges"; 2]);
            assert!((*out - *d).length() < 1e-12, "{d}: left as {out}");
            // In through the blur's transparent side, through the wedge, out through the blur;
            // a kick of the distribution's far tail (|x| ≳ π w / λ, about 1500 at 1 µm) is
            // evanescent, and the blur reflects the ray (as Dr TIM's pixellation does).
            assert_eq!(
                blur_met[..4],
                [
                    "rotator/diffraction blur",
                    "rotator/wedges",
                    "rotator/wedges",
                    "rotator/diffraction blur"
                ],
                "{d}"
            );
            if blur_met.len() > 4 {
                reflected += 1;
                continue;
            }
            // The kick changes the components along the box's back face, along the periods
            // p₁ and p₂ (turned with the device): x = Δ(sin θ) π w / λ.
            let change = *blur_out - *d;
            let pi = std::f64::consts::PI;
            let (xu, xv) = (
                change.dot(turn * DVec3::X) * pi * 0.5 * MM / lambda,
                change.dot(turn * DVec3::Y) * pi * 0.25 * MM / lambda,
            );
            inside_u += usize::from(xu.abs() < pi);
            inside_v += usize::from(xv.abs() < pi);
        }
        // P(|x| > X) ≈ 1/(π X) along each side: under 10⁻³ a ray.
        assert!(reflected <= 6, "{reflected} rays reflected");
        let n = n - reflected;
        let sigma = (INSIDE_FIRST_MINIMUM * (1.0 - INSIDE_FIRST_MINIMUM) / n as f64).sqrt();
        for (side, inside) in [("u", inside_u), ("v", inside_v)] {
            let fraction = inside as f64 / n as f64;
            assert!(
                (fraction - INSIDE_FIRST_MINIMUM).abs() < 4.0 * sigma,
                "turned {turned}, {side}: {fraction} inside the first minimum, expected \
                 {INSIDE_FIRST_MINIMUM}"
            );
        }
    }
}

#[test]
fn every_ray_leaving_a_skew_box_is_blurred_once() {
    // The skew rotator's box (its spans not along the periods, its faces tilted), rays from
    // points inside it in every direction: each leaves through some face and meets the blur
    // there, once, as its last surface.
    let rotator = skew();
    let mut rng = Rng(5);
    let rays: Vec<(DVec3, DVec3)> = (0..400)
        .map(|_| {
            // Inside the box: a random combination of the spans.
            let a = [0, 1, 2].map(|_| rng.range(-0.45, 0.45));
            let o = rotator.box_centre
                + a[0] * rotator.spans[0]
                + a[1] * rotator.spans[1]
                + a[2] * rotator.spans[2];
            (o, rng.unit())
        })
        .collect();
    let traced = follow_rays(&rotator, "simulate_diffraction_blur = true", "", &rays);
    let mut faces = std::collections::BTreeSet::new();
    for ((met, last, _), (o, d)) in traced.iter().zip(&rays) {
        let blurs = met
            .iter()
            .filter(|m| *m == "rotator/diffraction blur")
            .count();
        // A ray the blur reflects back into the box (about one in a thousand) meets it again.
        if blurs != 1 {
            assert!(blurs == 3, "{o} along {d}: {met:?}");
            continue;
        }
        assert_eq!(
            met.last().unwrap(),
            "rotator/diffraction blur",
            "{o} along {d}: {met:?}"
        );
        // The face it left by: the box coordinate that is ±½ there (just beyond, by the gap).
        let a = rotator.box_coordinates(*last);
        let k = (0..3).find(|&k| (a[k].abs() - 0.5).abs() < 1e-3).unwrap();
        faces.insert((k, a[k] > 0.0));
    }
    assert_eq!(faces.len(), 6, "left by the faces {faces:?} only");
}
