//! Devices made of ideal thin lenses (`[[device]]`), checked against independent derivations.
//!
//! Lens star. Take the lens plane through the star's axis, in coordinates (x along the lens
//! plane perpendicular to the axis, y along the optical axis, z along the star's axis) with the
//! principal point at the origin. An ideal thin lens is the projective map, in homogeneous
//! coordinates (x, y, z, 1), that fixes the lens plane y = 0 point by point and sends the focal
//! plane y = −f to infinity: M = [[I₃, 0], [(0, 1/f, 0), 1]]. Lens i is Rⁱ M R⁻ⁱ with R the
//! rotation by 2π/N about the axis, so a full loop through the N lenses is (R⁻¹M)ᴺ (up to R^N =
//! I). Writing R⁻¹M = [[A, 0], [B, I₂]] in the blocks (x, y) and (z, w), with A the rotation by
//! −2π/N, (R⁻¹M)ᴺ = [[Aᴺ, 0], [B(I + A + … + Aᴺ⁻¹), I₂]] = I, because Aᴺ = I and the powers
//! of a rotation by a whole fraction of a turn sum to zero: every point is imaged to itself, so
//! every ray that goes once round the star continues along the line it started on. With the
//! principal points a distance d off the axis, M is conjugated by a shift along x, A becomes
//! rotation·shear of trace 2cos(2π/N) + sin(2π/N) d/f, Aᴺ ≠ I, and the loop does not close.

mod common;

use std::f64::consts::PI;

use glam::DVec3;
use timbre::geometry::Shape;
use timbre::surfaces::Surface;
use timbre::surfaces::metatoys::Phase;
use timbre::trajectories::{self, Trajectory};

use common::cli::{location, path_str, timbre, write};

/// A TOML vector with every digit of the f64s.
fn v(p: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", p.x, p.y, p.z)
}

/// `d` rotated by `angle` (radians) about the unit `axis`, right-handed (Rodrigues).
fn rotate(d: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    d * angle.cos() + axis.cross(d) * angle.sin() + axis * axis.dot(d) * (1.0 - angle.cos())
}

/// The device's placement in the tests: rotated about (1, 1, 0) by 30°, then shifted.
const TRANSFORM: &str = "transform = { rotate = { axis = [1, 1, 0], angle_deg = 30 }, \
                         translate = [0.5, -1, 2] }";

fn place(p: DVec3) -> DVec3 {
    rotate(p, DVec3::new(1.0, 1.0, 0.0).normalize(), 30f64.to_radians())
        + DVec3::new(0.5, -1.0, 2.0)
}

/// A lens star of `n` lenses of focal length `f` about the z axis (lens 1 along +x), placed by
/// [`TRANSFORM`], and the trajectory of one ray that starts between lens N and lens 1 near the
/// regular-polygon loop (vertices 2f tan(π/N) from the axis on the lenses), perturbed off it and
/// off the plane of the loop, followed through N + 1 lenses.
fn star_trajectory(n: u32, f: f64, principal_point_distance: f64) -> Trajectory {
    let rho = 2.0 * f * (PI / n as f64).tan();
    let last = rho
        * DVec3::new(
            (-2.0 * PI / n as f64).cos(),
            (-2.0 * PI / n as f64).sin(),
            0.0,
        );
    let first = rho * DVec3::X;
    let start = 0.5 * (first + last) + DVec3::new(0.02, -0.03, -0.5);
    let direction = ((first - last).normalize() + DVec3::new(0.03, 0.02, 0.08)).normalize();
    let text = format!(
        r#"studio = "none"
[[device]]
name = "star"
{TRANSFORM}
lenses = {{ type = "lens-star", number_of_lenses = {n}, focal_length = {f:?}, principal_point_distance = {principal_point_distance:?}, centre = [0, 0, 0], intersection_direction = [0, 0, 1], point_on_lens1 = [1, 0, 0], star_radius = 4, star_length = 6 }}

[[ray_trajectory]]
start = {}
direction = {}
max_interactions = {}
"#,
        v(place(start)),
        v(place(direction) - place(DVec3::ZERO)),
        n + 1
    );
    let description = common::images::parse(&text);
    let mut traced = trajectories::trace(common::rays::device(), &description).expect("trace");
    assert_eq!(traced.len(), 1);
    let t = traced.remove(0);
    // The ray meets lens 1, 2, …, N and lens 1 again, in that order.
    let names: Vec<&str> = t.points[1..]
        .iter()
        .map(|p| {
            description.objects[p.object.expect("a surface point")]
                .name
                .as_str()
        })
        .collect();
    let expected: Vec<String> = (0..=n)
        .map(|k| format!("star/lens {}", k % n + 1))
        .collect();
    assert_eq!(names, expected, "n = {n}, f = {f}");
    t
}

#[test]
fn a_full_loop_round_a_lens_star_returns_every_ray_to_itself() {
    for (n, f) in [(5, 1.0), (3, 0.6), (4, 1.3), (8, 2.0)] {
        let t = star_trajectory(n, f, 0.0);
        let p = |k: usize| t.points[k].position;
        // After N lenses the ray is back on its first line: it meets lens 1 where it did first,
        // in the direction it had then.
        let back = (p(n as usize + 1) - p(1)).length();
        assert!(
            back < 1e-9,
            "n = {n}, f = {f}: missed the first hit by {back}"
        );
        let first = (p(1) - p(0)).normalize();
        let again = (p(n as usize + 1) - p(n as usize)).normalize();
        let turn = first.cross(again).length();
        assert!(
            turn < 1e-9 && first.dot(again) > 0.0,
            "n = {n}, f = {f}: turned by {turn}"
        );
    }
}

#[test]
fn with_principal_points_off_the_axis_the_loop_does_not_close() {
    let n = 5;
    let t = star_trajectory(n, 1.0, 0.2);
    let back = (t.points[n as usize + 1].position - t.points[1].position).length();
    assert!(back > 1e-3, "closed anyway, to {back}");
}

#[test]
fn a_lens_star_has_its_lenses_and_edges_as_objects() {
    let d = common::images::parse(
        r#"studio = "none"
[[group]]
name = "g"
[[group.device]]
name = "star"
show_edges = true
edge_radius = 0.02
lenses = { type = "lens-star", number_of_lenses = 3, focal_length = 1, centre = [0, 0, 0], intersection_direction = [0, 1, 0], point_on_lens1 = [1, 0, 0], star_radius = 2, star_length = 1, lens_transmission_coefficient = 0.9, shown_lenses_start_index = 2, number_of_shown_lenses = 2 }
"#,
    );
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "g/star/lens 1",
            "g/star/top edge 1",
            "g/star/outer edge 1",
            "g/star/bottom edge 1",
            "g/star/lens 3",
            "g/star/top edge 3",
            "g/star/outer edge 3",
            "g/star/bottom edge 3",
            "g/star/axial edge",
        ]
    );
    for o in &d.objects {
        // Lenses throw no shadows unless asked; edges do.
        assert_eq!(o.shadow_throwing, !o.name.contains("/lens "), "{}", o.name);
    }
}

#[test]
fn a_star_with_its_lens_on_the_axis_is_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = "studio = \"none\"\n\n[[device]]\nname = \"s\"\nlenses = { type = \"lens-star\", number_of_lenses = 4, focal_length = 1, centre = [0, 0, 0], intersection_direction = [0, 0, 1], point_on_lens1 = [0, 0, 3], star_radius = 1, star_length = 1 }\n";
    let path = write(dir.path(), "bad.toml", text);
    let run = timbre(dir.path(), &["check", path_str(&path)]);
    run.assert_bad_input(&["'s'", "lens-star", "point_on_lens1", "on the star's axis"]);
    assert_eq!(location(&run.stderr, &path).0, 5);
}

// ---------------------------------------------------------------------------------------------
// Lens simplicial complexes. Every cell of a consistent complex appears, from outside, as the
// tetrahedron of its vertices' virtual positions, and the outside appears as itself. So (i) a
// ray that crosses the complex leaves it on the straight line it came in on, and (ii) the rays
// from one point of a cell leave the complex on lines through one point, its virtual position,
// which lies inside the cell's virtual tetrahedron (a projective map that takes the vertices
// of a tetrahedron to those of another, without sending a point of it to infinity, takes its
// inside to the other's inside).
// ---------------------------------------------------------------------------------------------

/// Dr TIM's default lens simplicial complex (`EditableLensSimplicialComplex`'s
/// `initialiseToOmnidirectionalLens`): a tetrahedron on a triangular base with two inner
/// vertices on its axis, which virtual space moves up by 0.2.
const VERTICES: [[f64; 3]; 6] = [
    [-1.5, 1.1, 10.0],
    [1.0, 1.0, 10.0],
    [0.0, -0.5, 10.0],
    [0.0, 0.0, 10.6],
    [0.0, 0.0, 11.2],
    [0.0, 0.0, 12.0],
];
const VERTICES_V: [[f64; 3]; 6] = [
    [-1.5, 1.1, 10.0],
    [1.0, 1.0, 10.0],
    [0.0, -0.5, 10.0],
    [0.0, 0.0, 10.8],
    [0.0, 0.0, 11.4],
    [0.0, 0.0, 12.0],
];
const EDGES: &str = "[[0, 1], [1, 2], [2, 0], [3, 0], [3, 1], [3, 2], [4, 0], [4, 1], [4, 2], \
                     [5, 0], [5, 1], [5, 2], [3, 4], [4, 5]]";

fn list(points: &[[f64; 3]]) -> String {
    let items: Vec<String> = points.iter().map(|p| v(DVec3::from(*p))).collect();
    format!("[{}]", items.join(", "))
}

/// A scene with the complex (virtual positions `vertices_v`) placed by [`TRANSFORM`], and
/// `rays` (start, direction, in the complex's coordinates) as ray trajectories.
fn complex_scene(vertices_v: &[[f64; 3]], rays: &[(DVec3, DVec3)]) -> String {
    let mut text = format!(
        "studio = \"none\"\n[[device]]\nname = \"lsc\"\nshow_edges = false\n{TRANSFORM}\nlenses = {{ type = \"lens-simplicial-complex\", vertices = {}, vertices_v = {}, edges = {EDGES}, show_structure_v = false }}\n",
        list(&VERTICES),
        list(vertices_v)
    );
    for (start, direction) in rays {
        text += &format!(
            "[[ray_trajectory]]\nstart = {}\ndirection = {}\nmax_interactions = 40\n",
            v(place(*start)),
            v(place(*direction) - place(DVec3::ZERO))
        );
    }
    text
}

/// Each ray's last lens crossing and the direction it leaves in, mapped back into the
/// complex's coordinates, with the number of lenses it crossed.
fn exits(text: &str) -> Vec<(DVec3, DVec3, usize)> {
    let description = common::images::parse(text);
    let traced = trajectories::trace(common::rays::device(), &description).expect("trace");
    let axis = DVec3::new(1.0, 1.0, 0.0).normalize();
    let unplace = |p: DVec3| rotate(p - DVec3::new(0.5, -1.0, 2.0), axis, -30f64.to_radians());
    traced
        .iter()
        .map(|t| {
            let hits: Vec<DVec3> = t
                .points
                .iter()
                .filter(|p| p.object.is_some())
                .map(|p| p.position)
                .collect();
            let last = *hits.last().expect("the ray meets the complex");
            (
                unplace(last),
                unplace(t.direction) - unplace(DVec3::ZERO),
                hits.len(),
            )
        })
        .collect()
}

/// Distance of `x` from the line through `a` along unit `d`.
fn off_line(x: DVec3, a: DVec3, d: DVec3) -> f64 {
    (x - a).reject_from_normalized(d).length()
}

/// Each ray (start, direction) crossed at least `lenses` lenses and left ([`exits`]) on the line
/// it came in on, in its own direction, to 1e-9; `label` names the case in messages.
#[track_caller]
fn assert_on_their_lines(
    label: &str,
    rays: &[(DVec3, DVec3)],
    out: Vec<(DVec3, DVec3, usize)>,
    lenses: usize,
) {
    for ((start, d), (last, leaving, crossed)) in rays.iter().zip(out) {
        let d = d.normalize();
        assert!(
            crossed >= lenses,
            "{label}ray from {start} crossed only {crossed} lenses"
        );
        let miss = off_line(last, *start, d);
        let turn = leaving.cross(d).length();
        assert!(
            miss < 1e-9 && turn < 1e-9 && leaving.dot(d) > 0.0,
            "{label}ray from {start}: left {miss} off its line, turned by {turn}"
        );
    }
}

#[test]
fn a_ray_crossing_a_lens_simplicial_complex_leaves_on_the_line_it_came_in_on() {
    let rays = [
        (DVec3::new(0.1, 0.2, 7.0), DVec3::new(0.02, -0.03, 1.0)),
        (DVec3::new(-3.0, 0.3, 10.9), DVec3::new(1.0, 0.05, 0.1)),
        (DVec3::new(2.0, 2.0, 13.0), DVec3::new(-0.6, -0.7, -0.8)),
        (DVec3::new(0.2, -3.0, 10.5), DVec3::new(-0.05, 1.0, 0.3)),
    ];
    assert_on_their_lines("", &rays, exits(&complex_scene(&VERTICES_V, &rays)), 3);
}

#[test]
fn rays_from_a_point_in_a_cell_leave_as_if_from_one_point_of_its_virtual_cell() {
    let [p0, p1, _, p3, p4, _] = VERTICES.map(DVec3::from);
    let [v0, v1, _, v3, v4, _] = VERTICES_V.map(DVec3::from);
    // A point of the cell 0-1-3-4.
    let x = 0.2 * p0 + 0.3 * p1 + 0.25 * p3 + 0.25 * p4;
    let rays: Vec<(DVec3, DVec3)> = [
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(0.3, 0.2, 1.0),
        DVec3::new(-1.0, -0.2, 0.1),
        DVec3::new(0.1, 1.0, -0.2),
        DVec3::new(0.5, -1.0, 0.4),
    ]
    .map(|d| (x, d))
    .to_vec();
    let out = exits(&complex_scene(&VERTICES_V, &rays));
    // The point nearest to all the leaving lines (least squares).
    let (mut a, mut b) = (glam::DMat3::ZERO, DVec3::ZERO);
    for (last, d, _) in &out {
        let d = d.normalize();
        let m = glam::DMat3::IDENTITY - glam::DMat3::from_cols(d * d.x, d * d.y, d * d.z);
        a += m;
        b += m * *last;
    }
    let image = a.inverse() * b;
    for (last, d, _) in &out {
        let miss = off_line(image, *last, d.normalize());
        assert!(
            miss < 1e-9,
            "a leaving line misses the image {image} by {miss}"
        );
    }
    assert!((image - x).length() > 1e-2, "the complex did not move {x}");
    // Inside the virtual tetrahedron 0-1-3-4: positive barycentric coordinates.
    let m = glam::DMat3::from_cols(v1 - v0, v3 - v0, v4 - v0);
    let w = m.inverse() * (image - v0);
    assert!(
        w.min_element() > 0.0 && w.element_sum() < 1.0,
        "image {image} is outside the virtual cell ({w})"
    );
}

#[test]
fn virtual_positions_no_ideal_lenses_can_realise_are_refused() {
    let parse = |vertices_v: &[[f64; 3]]| {
        timbre::scene::file::parse(&complex_scene(vertices_v, &[]), "lsc.toml")
            .unwrap_err()
            .to_string()
    };
    // An inner vertex moved off the axis: the cells round face 0-1-4 disagree on its plane.
    let mut sideways = VERTICES_V;
    sideways[3][0] = 0.1;
    let e = parse(&sideways);
    assert!(e.starts_with("lsc.toml:6:"), "{e}");
    assert!(
        e.contains("face 0-1-4") && e.contains("cannot realise"),
        "{e}"
    );
    // An outer vertex moved: the outside is seen as itself, so it cannot move.
    let mut outer = VERTICES_V;
    outer[0][0] = -1.6;
    let e = parse(&outer);
    assert!(
        e.contains("vertex 0") && e.contains("must keep their physical positions"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// The ideal-lens cloak: it images outside space to itself, so rays cross it on their own line
// and the scene behind it looks as without it, while the lower inner pyramid, squashed into the
// height h₁′ → 0 in EM space, hides what is inside it.
// ---------------------------------------------------------------------------------------------

/// Dr TIM's cloak (a regular tetrahedron of height 2 on the floor, `EditableIdealLensCloak`'s
/// default, moved to z = 7.5, in front of the lattice) with EM-space lower-inner-vertex height
/// `h1e`, placed by `transform`.
fn cloak(h1e: f64, transform: &str) -> String {
    format!(
        "[[device]]\nname = \"cloak\"\n{transform}\nlenses = {{ type = \"ideal-lens-cloak\", base_centre = [0, -0.98, 7.5], front_direction = [0, 0, -1], right_direction = [1, 0, 0], top_direction = [0, 1, 0], base_radius = 1.3333333333333333, height = 2, height_lower_inner_vertex_p = 0.6666666666666666, height_upper_inner_vertex_p = 1.3333333333333333, height_lower_inner_vertex_e = {h1e:?}, interface_transmission_coefficient = 1 }}\n"
    )
}

#[test]
fn a_ray_crossing_the_ideal_lens_cloak_leaves_on_the_line_it_came_in_on() {
    let rays = [
        (DVec3::new(0.1, -0.5, 3.5), DVec3::new(0.01, 0.02, 1.0)),
        (DVec3::new(-3.0, -0.6, 7.6), DVec3::new(1.0, -0.02, 0.05)),
        (DVec3::new(0.5, 2.0, 6.5), DVec3::new(-0.2, -1.0, 0.3)),
        (DVec3::new(2.0, -0.9, 9.5), DVec3::new(-0.7, 0.1, -0.8)),
    ];
    // (As h₁′ → 0 the focal lengths shrink with it and rounding errors grow: at h₁′ = 0.001
    // the ray leaves 2e-5 off its direction, so the 1e-9 check uses moderate squashing.)
    for h1e in [-1.0, 0.0666, 0.2] {
        let mut text = format!("studio = \"none\"\n{}", cloak(h1e, TRANSFORM));
        for (start, direction) in &rays {
            text += &format!(
                "[[ray_trajectory]]\nstart = {}\ndirection = {}\nmax_interactions = 40\n",
                v(place(*start)),
                v(place(*direction) - place(DVec3::ZERO))
            );
        }
        assert_on_their_lines(&format!("h1e = {h1e}: "), &rays, exits(&text), 2);
    }
}

#[test]
fn a_ray_crossing_a_hexagonal_ideal_lens_cloak_leaves_on_the_line_it_came_in_on() {
    let rays = [
        (DVec3::new(0.1, -0.5, 3.5), DVec3::new(0.01, 0.02, 1.0)),
        (DVec3::new(-3.0, -0.6, 7.6), DVec3::new(1.0, -0.02, 0.05)),
        (DVec3::new(0.5, 2.0, 6.5), DVec3::new(-0.2, -1.0, 0.3)),
        (DVec3::new(0.3, -3.0, 7.4), DVec3::new(0.02, 1.0, 0.01)),
    ];
    let mut text = format!(
        "studio = \"none\"\n[[device]]\n{TRANSFORM}\nlenses = {{ type = \"polygonal-ideal-lens-cloak\", base_centre = [0, -0.98, 7.5], front_direction = [0, 0, -1], right_direction = [1, 0, 0], top_direction = [0, 1, 0], base_radius = 1.5, no_of_base_vertices = 6, height = 2, height_lower_inner_vertex_p = 0.5, height_upper_inner_vertex_p = 1.2, height_lower_inner_vertex_e = 0.1 }}\n"
    );
    for (start, direction) in &rays {
        text += &format!(
            "[[ray_trajectory]]\nstart = {}\ndirection = {}\nmax_interactions = 40\n",
            v(place(*start)),
            v(place(*direction) - place(DVec3::ZERO))
        );
    }
    assert_on_their_lines("", &rays, exits(&text), 2);
}

/// The 4π lens: inside space (the cell between L1 and the closer inner vertex) is seen from
/// outside, whichever lenses the light leaves through, where L1 alone images it. L1 is an ideal
/// thin lens of focal length f = −`focal_length_outwards` (Dr TIM's `Editable4PiLens`) at the
/// principal point C; in the projective form above, light crossing it along the unit normal n
/// sees X at C + (X − C)/(1 + y/f), y = (X − C)·n.
#[test]
fn a_four_pi_lens_images_inside_space_as_its_principal_plane_lens_does_in_every_direction() {
    let f_out = 0.8;
    let x = DVec3::new(0.1, -0.05, 0.2);
    let rays: Vec<(DVec3, DVec3)> = [
        DVec3::new(0.05, 0.02, -1.0),
        DVec3::new(0.3, 0.1, 1.0),
        DVec3::new(1.0, 0.2, 0.1),
        DVec3::new(-0.5, 1.0, 0.3),
        DVec3::new(0.2, -1.0, -0.05),
    ]
    .map(|d| (x, d))
    .to_vec();
    let mut text = format!(
        "studio = \"none\"\n[[device]]\nname = \"4pi\"\n{TRANSFORM}\nlenses = {{ type = \"four-pi-lens\", principal_point = [0, 0, 0], optical_axis_direction = [0, 0, 1], focal_length_outwards = {f_out:?}, transverse_direction1 = [1, 0, 0], transverse_direction2 = [0, 1, 0], radius = 1.5, length = 2, closer_inner_vertex_distance = 0.6, farther_inner_vertex_distance = 1.2, show_l1 = true }}\n"
    );
    for (start, direction) in &rays {
        text += &format!(
            "[[ray_trajectory]]\nstart = {}\ndirection = {}\nmax_interactions = 40\n",
            v(place(*start)),
            v(place(*direction) - place(DVec3::ZERO))
        );
    }
    // Inside space lies on the +z side of L1 (z = 0): light leaves it along n = −z.
    let y = -x.z;
    let image = x / (1.0 + y / -f_out);
    let out = exits(&text);
    for ((_, d), (last, leaving, crossed)) in rays.iter().zip(&out) {
        let miss = off_line(image, *last, leaving.normalize());
        assert!(
            miss < 1e-9,
            "the ray leaving along {d} after {crossed} lenses misses L1's image {image} by {miss}"
        );
    }
    // Some rays leave through L1, others through the lenses R1 round it.
    assert!(out.iter().any(|(_, _, crossed)| *crossed == 1));
    assert!(out.iter().any(|(_, _, crossed)| *crossed > 1));
}

/// TIM's lattice studio at 160 × 120 with `objects`.
fn lattice(objects: &str) -> String {
    format!("studio = \"lattice\"\n[render]\nwidth = 160\nheight = 120\n{objects}")
}

/// A white ball inside the lower inner pyramid (which reaches 2/3 up), throwing no shadow.
const BALL: &str = "[[object]]\nname = \"ball\"\nshadow_throwing = false\nshape = { type = \"sphere\", centre = [0, -0.73, 7.5], radius = 0.15 }\nsurface = { type = \"shiny\", colour = [1, 1, 1] }\n";

#[test]
fn the_lattice_seen_through_the_ideal_lens_cloak_looks_as_without_it() {
    let without = common::images::render_text(&lattice(""));
    let with = common::images::render_text(&lattice(&cloak(0.0666, "")));
    // Tolerance: a pixel in a thousand may differ by more than two levels (rays that graze the
    // lenses' edges, where the f32 intersection and the f64 law part ways).
    let differing = common::images::differing_by_more_than(&with, &without, 2);
    assert!(
        differing * 1000 <= 160 * 120,
        "{differing} pixels differ by more than 2 levels"
    );
    // The cloak is in view: dimmed lenses change the picture.
    let dimmed = lattice(&cloak(0.0666, "").replace(
        "interface_transmission_coefficient = 1",
        "interface_transmission_coefficient = 0.5",
    ));
    let dim = common::images::render_text(&dimmed);
    assert!(common::images::differing_by_more_than(&dim, &without, 2) > 1000);
}

#[test]
fn an_object_in_the_cloaked_region_is_hidden() {
    let render =
        |objects: &str| timbre::io::to_rgb8(&common::images::render_text(&lattice(objects)));
    let plain = render("");
    let ball = render(BALL);
    // Where the ball is seen without the cloak.
    let footprint: Vec<(u32, u32)> = plain
        .enumerate_pixels()
        .filter(|(x, y, p)| {
            ball.get_pixel(*x, *y)
                .0
                .iter()
                .zip(p.0)
                .any(|(a, b)| a.abs_diff(b) > 2)
        })
        .map(|(x, y, _)| (x, y))
        .collect();
    assert!(
        footprint.len() > 30,
        "the ball covers only {} pixels",
        footprint.len()
    );
    // With the cloak (h₁′ = 0.001 h₁), those pixels show what they show without the ball.
    let cloaked = render(&cloak(0.000666, ""));
    let cloaked_ball = render(&(cloak(0.000666, "") + BALL));
    let seen = footprint
        .iter()
        .filter(|(x, y)| {
            let (a, b) = (cloaked.get_pixel(*x, *y), cloaked_ball.get_pixel(*x, *y));
            a.0.iter().zip(b.0).any(|(p, q)| p.abs_diff(q) > 2)
        })
        .count();
    assert_eq!(
        seen,
        0,
        "of the ball's {} pixels, {seen} still show it",
        footprint.len()
    );
}

/// A Platonic lens: the three lenses of a tetrahedral one that meet along the line from the
/// centre to a vertex make a lens star about that line (120° apart, principal points on it, at
/// the centre), so a ray sent round it through each of them once, in the plane through the
/// centre perpendicular to the line (which the other three lenses touch only at the centre),
/// meets the first lens again where it first did, in the same direction. The ray starts near
/// the side of the star's regular triangular orbit (inscribed radius 2f sin(π/3)) between two
/// lenses, found from the vertex's neighbours as Dr TIM's `PlatonicSolidType` lists them (six
/// digits); as a lens star, also a ray off that orbit closes.
#[test]
fn a_ray_round_a_vertex_of_a_tetrahedral_platonic_lens_closes_on_itself() {
    let vertex = DVec3::Z;
    let neighbours = [
        DVec3::new(-0.471405, -0.816497, -0.333333),
        DVec3::new(-0.471405, 0.816497, -0.333333),
        DVec3::new(0.942809, 0.0, -0.333333),
    ];
    let (centre, radius, f) = (DVec3::new(0.2, -0.1, 6.0), 2.0, 0.1);
    let a = vertex;
    let e1 = neighbours[0].reject_from_normalized(a).normalize();
    let e2 = a.cross(e1);
    let next = neighbours[1..]
        .iter()
        .map(|&p| {
            let r = p.reject_from_normalized(a);
            r.dot(e2).atan2(r.dot(e1)).rem_euclid(2.0 * PI)
        })
        .fold(f64::INFINITY, f64::min);
    assert!((next - 2.0 * PI / 3.0).abs() < 1e-5, "{next}");
    let (sin, cos) = (0.5 * next).sin_cos();
    let rho = 2.0 * f * (PI / 3.0).sin();
    for (off_orbit, turn) in [(1.0, 0.0), (1.15, 0.1), (0.9, -0.15)] {
        let start = centre + off_orbit * rho * (cos * e1 + sin * e2);
        let direction = rotate(-sin * e1 + cos * e2, a, turn);
        let text = format!(
            "studio = \"none\"
[[device]]
name = \"platonic lens\"
lenses = {{ type = \"platonic-lens\", platonic_solid = \"tetrahedron\", centre = {}, radius = {radius:?}, focal_length = {f:?} }}
[[ray_trajectory]]
start = {}
direction = {}
max_interactions = 4
",
            v(centre),
            v(start),
            v(direction),
        );
        let description = common::images::parse(&text);
        let t = trajectories::trace(common::rays::device(), &description).expect("trace");
        let t = &t[0];
        assert_eq!(t.points.len(), 5, "{:?}", t.points);
        let p = |k: usize| t.points[k].position;
        // The three lenses about the vertex's line, in turn (lens 0-1, 0-2 and 0-3 are the
        // device's first three objects).
        let lenses: Vec<_> = (1..=4).map(|k| t.points[k].object.unwrap()).collect();
        let mut round = lenses[..3].to_vec();
        round.sort();
        assert_eq!((round, lenses[3]), (vec![0, 1, 2], lenses[0]), "{lenses:?}");
        let back = (p(4) - p(1)).length();
        assert!(back < 1e-9, "missed the first hit by {back}");
        let first = (p(2) - p(1)).normalize();
        assert!(
            first.cross(t.direction).length() < 1e-9 && first.dot(t.direction) > 0.0,
            "leaves along {}, first along {first}",
            t.direction
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Dr TIM's defaults. A device named by its type alone is Dr TIM's default object: the numbers
// below are those of each editable class's constructor `(SceneObject parent, Studio studio)`,
// copied from it, not from timbre.
// ---------------------------------------------------------------------------------------------

/// The parts of a device with only the entry `device` (its `lenses` or `aid` table and any
/// other keys), by name.
fn default_parts(device: &str) -> Vec<timbre::scene::SceneObject> {
    let d = common::images::parse(&format!(
        "studio = \"none\"\n[[device]]\nname = \"d\"\n{device}\n"
    ));
    d.objects
}

/// The ideal thin lens of `o`; panics if it is none.
#[track_caller]
fn ideal_lens(o: &timbre::scene::SceneObject) -> &timbre::surfaces::ThinLens {
    match &o.surface {
        Surface::IdealThinLens(l) => l,
        s => panic!("{}: {s:?} is no ideal thin lens", o.name),
    }
}

#[track_caller]
fn close(a: DVec3, b: DVec3, what: &str) {
    assert!((a - b).length() < 1e-12, "{what}: {a}, Dr TIM's {b}");
}

/// `EditableLensStar(parent, studio)`: 5 lenses of focal length 1 and transmission coefficient
/// 0.96, principal points on the axis (principalPointDistance 0) through centre (0, 0, 10)
/// along intersectionDirection (0, 1, 0), lens 1 towards pointOnLens1 (1, 0, 10), starRadius 2,
/// starLength 1, ideal thin lenses, lenses throwing no shadows, edges hidden.
#[test]
fn a_lens_star_named_by_its_type_alone_is_dr_tims_default_lens_star() {
    let parts = default_parts("lenses = { type = \"lens-star\" }");
    let names: Vec<&str> = parts.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        ["d/lens 1", "d/lens 2", "d/lens 3", "d/lens 4", "d/lens 5"]
    );
    let (centre, w, u) = (DVec3::new(0.0, 0.0, 10.0), DVec3::Y, DVec3::X);
    for (i, o) in parts.iter().enumerate() {
        let phi = 2.0 * PI * i as f64 / 5.0;
        let radial = phi.cos() * u + phi.sin() * w.cross(u);
        let lens = ideal_lens(o);
        assert_eq!(
            (lens.focal_length, lens.transmission_coefficient),
            (1.0, 0.96)
        );
        close(lens.principal_point, centre, &o.name);
        assert!(lens.optical_axis.dot(radial).abs() < 1e-12 && lens.optical_axis.dot(w) == 0.0);
        // The rectangle from the axis (length 1, centred on the centre) out to radius 2.
        let (lo, hi) = o.shape.bounds().unwrap();
        let corners = [centre - 0.5 * w, centre + 0.5 * w + 2.0 * radial];
        close(lo, corners[0].min(corners[1]), &o.name);
        close(hi, corners[0].max(corners[1]), &o.name);
        assert!(!o.shadow_throwing);
    }
}

/// `EditableIdealLensCloak(parent, studio)` and `EditablePolygonalIdealLensCloak(parent,
/// studio)` (the latter with noOfBaseVertices 3): base centre (0, −1, 10), front (0, 0, −1),
/// right (1, 0, 0), top (0, 1, 0), base radius 2·2/3, height 2, heightLowerInnerVertexP 2/3,
/// heightUpperInnerVertexP 4/3, heightLowerInnerVertexE −1, interface transmission coefficient
/// 0.96, frames hidden. The base lens images the lower inner vertex from h₁ = 2/3 to h₁′ = −1
/// through the base centre, so its focal length is f₀₀ = h₁ h₁′/(h₁′ − h₁) = 0.4 in magnitude
/// (the lens equation with both distances measured from the lens).
#[test]
fn cloaks_named_by_their_type_alone_are_dr_tims_default_cloaks() {
    for (kind, lenses, base) in [
        ("ideal-lens-cloak", 16, "d/base outer lens"),
        ("polygonal-ideal-lens-cloak", 18, "d/base outer lens #0"),
    ] {
        let parts = default_parts(&format!("lenses = {{ type = \"{kind}\" }}"));
        assert_eq!(parts.len(), lenses, "{kind}");
        for o in &parts {
            assert_eq!(ideal_lens(o).transmission_coefficient, 0.96, "{}", o.name);
        }
        let base = parts.iter().find(|o| o.name == base).unwrap();
        let (h1, h1e) = (2.0 / 3.0, -1.0);
        let f00 = h1 * h1e / (h1e - h1);
        assert!(
            (ideal_lens(base).focal_length.abs() - f00).abs() < 1e-12,
            "{kind}"
        );
        close(
            ideal_lens(base).principal_point,
            DVec3::new(0.0, -1.0, 10.0),
            kind,
        );
        // The tetrahedron: base on y = −1, tip 2 above; the back vertex 4/3 behind the centre.
        let (lo, hi) = parts
            .iter()
            .map(|o| o.shape.bounds().unwrap())
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), (l, h)| {
                (a.min(l), b.max(h))
            });
        let r = 4.0 / 3.0;
        let s = r * (PI / 3.0).sin();
        close(lo, DVec3::new(-s, -1.0, 10.0 - 0.5 * r), kind);
        close(hi, DVec3::new(s, 1.0, 10.0 + r), kind);
    }
}

/// `Editable4PiLens(parent, studio)`: principal point (0, 0, 5), optical axis (0, 0, 1),
/// focalLengthOutwards 1, transverse directions (1, 0, 0) and (0, 1, 0), radius 1, length 1,
/// showL1 false, showR1 true, inner vertices 1/3 and 2/3 from the principal point, ideal thin
/// lenses with transmission coefficient DEFAULT_TRANSMISSION_COEFFICIENT (0.96), frames hidden.
#[test]
fn a_four_pi_lens_named_by_its_type_alone_is_dr_tims_default_four_pi_lens() {
    let parts = default_parts("lenses = { type = \"four-pi-lens\" }");
    // The 15 lenses R1, without L1.
    assert_eq!(parts.len(), 15);
    assert!(parts.iter().all(|o| o.name != "d/base outer lens"));
    // The tip lenses' principal point is the tip, 1 from the principal point along the axis.
    let tip = parts
        .iter()
        .find(|o| o.name == "d/front outer lens")
        .unwrap();
    close(
        ideal_lens(tip).principal_point,
        DVec3::new(0.0, 0.0, 6.0),
        "tip",
    );
    for o in &parts {
        assert_eq!(ideal_lens(o).transmission_coefficient, 0.96);
        let (lo, hi) = o.shape.bounds().unwrap();
        assert!(lo.z >= 5.0 - 1e-12 && hi.z <= 6.0 + 1e-12, "{}", o.name);
    }
    // With L1 shown, the base lens images the closer inner vertex (1/3 above it) with focal
    // length −focalLengthOutwards = −1.
    let with_l1 = default_parts("lenses = { type = \"four-pi-lens\", show_l1 = true }");
    let l1 = with_l1
        .iter()
        .find(|o| o.name == "d/base outer lens")
        .unwrap();
    assert!((ideal_lens(l1).focal_length.abs() - 1.0).abs() < 1e-12);
    close(
        ideal_lens(l1).principal_point,
        DVec3::new(0.0, 0.0, 5.0),
        "L1",
    );
}

/// `EditablePlatonicLens(parent, studio)` with `EditablePlatonicSolid(parent, studio)`: a
/// tetrahedron of radius 1 about (0, 0, 10), lenses of focal length 1 and transmission
/// coefficient 0.96 throwing no shadows; the solid shown (vertices and edges of radius 0.01,
/// SurfaceColour.RED_SHINY, faces Transparent(0.75, true)), and the lens edges (from the centre
/// to the vertices) shown.
#[test]
fn a_platonic_lens_named_by_its_type_alone_is_dr_tims_default_platonic_lens() {
    let parts = default_parts("lenses = { type = \"platonic-lens\" }");
    let centre = DVec3::new(0.0, 0.0, 10.0);
    let red_shiny = Surface::Coloured(timbre::surfaces::Coloured::shiny(DVec3::X));
    let count = |prefix: &str| {
        parts
            .iter()
            .filter(|o| o.name.starts_with(&format!("d/{prefix}")))
            .count()
    };
    assert_eq!(
        [
            count("lens "),
            count("inner edge "),
            count("edge "),
            count("vertex ")
        ],
        [6, 4, 6, 4]
    );
    for o in &parts {
        match o.name.strip_prefix("d/").unwrap() {
            name if name.starts_with("lens ") => {
                let l = ideal_lens(o);
                assert_eq!((l.focal_length, l.transmission_coefficient), (1.0, 0.96));
                close(l.principal_point, centre, name);
                assert!(!o.shadow_throwing);
            }
            "faces" => {
                assert_eq!(
                    o.surface,
                    Surface::Transparent(timbre::surfaces::Transparent {
                        transmission_coefficient: 0.75
                    })
                );
                assert!(o.shadow_throwing);
                let (lo, hi) = o.shape.bounds().unwrap();
                assert!((hi.z - 11.0).abs() < 1e-9 && lo.z > 9.0, "{lo} {hi}");
            }
            name => {
                assert_eq!(o.surface, red_shiny, "{name}");
                match &o.shape {
                    Shape::Sphere(s) => {
                        assert_eq!(s.radius(), 0.01);
                        assert!((s.centre().distance(centre) - 1.0).abs() < 1e-12);
                    }
                    Shape::Cylinder(c) => assert_eq!(c.radius(), 0.01),
                    s => panic!("{name}: {s:?}"),
                }
            }
        }
    }
}

/// `EditableLensSimplicialComplex(description, parent, studio)`: its
/// `initialiseToOmnidirectionalLens()` ([`VERTICES`], [`VERTICES_V`], the 14 edges), lenses of
/// transmission coefficient DEFAULT_TRANSMISSION_COEFFICIENT (0.96), the physical-space
/// structure shown in SurfaceColour.BLUE_SHINY with radius 0.021 and the virtual-space one in
/// SurfaceColour.RED_SHINY with radius 0.02.
#[test]
fn a_lens_simplicial_complex_named_by_its_type_alone_is_dr_tims_omnidirectional_lens() {
    let parts = default_parts("lenses = { type = \"lens-simplicial-complex\" }");
    let given = default_parts(&format!(
        "show_edges = false\nlenses = {{ type = \"lens-simplicial-complex\", vertices = {}, vertices_v = {}, edges = {EDGES}, show_structure_v = false }}",
        list(&VERTICES),
        list(&VERTICES_V)
    ));
    let lenses: Vec<_> = parts
        .iter()
        .filter(|o| o.name.starts_with("d/face"))
        .collect();
    assert_eq!(lenses.len(), given.len());
    for (a, b) in lenses.iter().zip(&given) {
        assert_eq!((&a.name, &a.shape), (&b.name, &b.shape));
        assert_eq!(ideal_lens(a).transmission_coefficient, 0.96);
        let (la, lb) = (ideal_lens(a), ideal_lens(b));
        assert_eq!(la.focal_length, lb.focal_length);
    }
    for (space, positions, colour, radius) in [
        ("", VERTICES, DVec3::Z, 0.021),
        ("virtual ", VERTICES_V, DVec3::X, 0.02),
    ] {
        let surface = Surface::Coloured(timbre::surfaces::Coloured::shiny(colour));
        for (i, p) in positions.iter().enumerate() {
            let o = parts
                .iter()
                .find(|o| o.name == format!("d/{space}vertex {i}"))
                .unwrap();
            let Shape::Sphere(s) = &o.shape else { panic!() };
            assert_eq!((s.centre(), s.radius()), (DVec3::from(*p), radius));
            assert_eq!(o.surface, surface);
        }
        let edges = parts
            .iter()
            .filter(|o| o.name.starts_with(&format!("d/{space}edge ")))
            .count();
        assert_eq!(edges, 14, "{space}");
    }
}

/// `EditableTimHead(parent, studio)`: centre (0, 0, 10), radius 1.
#[test]
fn a_tim_head_named_by_its_type_alone_is_dr_tims_default_head() {
    let parts = default_parts("aid = { type = \"tim-head\" }");
    let Shape::Sphere(head) = &parts.iter().find(|o| o.name == "d/head").unwrap().shape else {
        panic!()
    };
    assert_eq!(
        (head.centre(), head.radius()),
        (DVec3::new(0.0, 0.0, 10.0), 1.0)
    );
}

/// Edges as given override the device's defaults: a cloak's frames (Dr TIM's are hidden, of
/// radius 0.02, red) shown with radius 0.05, and a 4π lens's (Dr TIM's grey, 0.01) shown.
#[test]
fn edges_take_the_devices_defaults_where_not_given() {
    let cloak = default_parts(
        "show_edges = true\nedge_radius = 0.05\nlenses = { type = \"ideal-lens-cloak\" }",
    );
    let four_pi = default_parts("show_edges = true\nlenses = { type = \"four-pi-lens\" }");
    for (parts, radius, colour) in [(cloak, 0.05, DVec3::X), (four_pi, 0.01, DVec3::splat(0.5))] {
        let frames: Vec<_> = parts.iter().filter(|o| !o.name.contains("lens")).collect();
        // 14 edges and 6 vertices.
        assert_eq!(frames.len(), 20);
        for o in frames {
            let Shape::Cylinder(c) = &o.shape else {
                let Shape::Sphere(s) = &o.shape else {
                    panic!("{}", o.name)
                };
                assert_eq!(s.radius(), radius);
                continue;
            };
            assert_eq!(c.radius(), radius, "{}", o.name);
            assert_eq!(
                o.surface,
                Surface::Coloured(timbre::surfaces::Coloured::shiny(colour))
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Lens types. A lens hologram (Dr TIM's `PhaseHologramOfLens`) changes the tangential part of
// the unit direction by −(S − P)/f where the ideal lens changes that of d/|d·â| by the same: a
// ray parallel to the optical axis at distance ρ from the principal point P leaves the ideal
// lens towards the focal point P + f â, and the hologram with tangential part −ρ/f, i.e. at
// sin θ = ρ/f to the axis, so that it crosses the axis f cos θ = √(f² − ρ²) from the lens: the
// hologram's spherical aberration, f − √(f² − ρ²) ≈ ρ²/(2f).
// ---------------------------------------------------------------------------------------------

/// Rays parallel to the optical axis of a one-lens star (lens in the plane z = 0, principal
/// point at the origin, focal length `f`), placed by [`TRANSFORM`], at distances `rhos` from
/// the principal point: where each crosses the axis after the lens, as the distance along the
/// axis and the distance by which it misses it.
fn axis_crossings(lens_type: &str, f: f64, rhos: &[f64]) -> Vec<(f64, f64)> {
    let mut text = format!(
        "studio = \"none\"\n[[device]]\nname = \"star\"\n{TRANSFORM}\nlenses = {{ type = \"lens-star\", number_of_lenses = 1, focal_length = {f:?}, centre = [0, 0, 0], intersection_direction = [0, 1, 0], point_on_lens1 = [1, 0, 0], star_radius = 3, star_length = 2, thin_lens_type = \"{lens_type}\" }}\n"
    );
    for rho in rhos {
        text += &format!(
            "[[ray_trajectory]]\nstart = {}\ndirection = {}\nmax_interactions = 1\n",
            v(place(DVec3::new(*rho, 0.0, -2.0))),
            v(place(DVec3::Z) - place(DVec3::ZERO))
        );
    }
    exits(&text)
        .into_iter()
        .map(|(at, d, crossed)| {
            assert_eq!(crossed, 1);
            // Where the leaving line meets the plane x = 0 of the axis (the z axis).
            let p = at - (at.x / d.x) * d;
            (p.z, (p - DVec3::new(0.0, 0.0, p.z)).length())
        })
        .collect()
}

#[test]
fn a_lens_hologram_focuses_a_bundle_where_the_ideal_lens_does_but_for_its_aberration() {
    let f = 2.0;
    let rhos = [0.05, 0.3, 0.8, 1.5];
    let ideal = axis_crossings("ideal-thin-lens", f, &rhos);
    let hologram = axis_crossings("lens-hologram", f, &rhos);
    for ((rho, (z_ideal, miss_ideal)), (z_hologram, miss_hologram)) in
        rhos.iter().zip(ideal).zip(hologram)
    {
        assert!(miss_ideal < 1e-9 && miss_hologram < 1e-9, "ρ = {rho}");
        assert!(
            (z_ideal - f).abs() < 1e-9,
            "ρ = {rho}: ideal focus at {z_ideal}"
        );
        let expected = (f * f - rho * rho).sqrt();
        assert!(
            (z_hologram - expected).abs() < 1e-9,
            "ρ = {rho}: hologram's focus at {z_hologram}, expected {expected}"
        );
        // Paraxially the same focus: the aberration is ρ²/(2f) to within ρ⁴/f³.
        assert!((z_ideal - z_hologram - rho * rho / (2.0 * f)).abs() < rho.powi(4) / f.powi(3));
    }
}

/// Every lens of a cloak made of lens holograms (Dr TIM's `PHASE_HOLOGRAM_OF_LENS`, by its Dr
/// TIM name) is the phase hologram of its ideal lens: same face, focal length and transmission
/// coefficient, the phase centred on the principal point; glass panes pass the light on
/// undeviated; `none` leaves only the edges.
#[test]
fn the_lens_types_of_a_cloak_are_made_from_its_ideal_lenses() {
    let cloak = |lens_type: &str| {
        default_parts(&format!(
            "show_edges = true\nlenses = {{ type = \"ideal-lens-cloak\", lens_element_type = \"{lens_type}\" }}"
        ))
    };
    let ideal = cloak("ideal-thin-lens");
    let holograms = cloak("phase-hologram-of-lens");
    let panes = cloak("glass-pane");
    let none = cloak("none");
    // 16 lenses, 14 edges and 6 vertices.
    assert_eq!(
        [ideal.len(), holograms.len(), panes.len(), none.len()],
        [36, 36, 36, 20]
    );
    for ((i, h), p) in ideal.iter().zip(&holograms).zip(&panes) {
        assert_eq!((&i.name, &i.name), (&h.name, &p.name));
        let Surface::IdealThinLens(lens) = &i.surface else {
            assert_eq!((&i.surface, &i.surface), (&h.surface, &p.surface));
            continue;
        };
        let Surface::PhaseHologram(hologram) = &h.surface else {
            panic!("{}", h.name)
        };
        let Phase::Quadratic(phase) = hologram.phase else {
            panic!()
        };
        assert_eq!(phase.focal_length, lens.focal_length);
        assert_eq!(hologram.transmission_coefficient, 0.96);
        let centre = h.shape.plane_coordinates(lens.principal_point, 0).unwrap();
        assert!((phase.centre - centre).length() < 1e-12);
        // The same triangle.
        let (hb, ib) = (h.shape.bounds().unwrap(), i.shape.bounds().unwrap());
        assert!((hb.0 - ib.0).length() < 1e-12 && (hb.1 - ib.1).length() < 1e-12);
        assert_eq!(
            p.surface,
            Surface::Transparent(timbre::surfaces::Transparent {
                transmission_coefficient: 0.96
            })
        );
    }
}

#[test]
fn a_device_of_lens_holograms_cannot_be_scaled() {
    let dir = tempfile::tempdir().unwrap();
    let text = "studio = \"none\"\n\n[[device]]\nname = \"s\"\ntransform = { scale = 2 }\nlenses = { type = \"lens-star\", thin_lens_type = \"lens-hologram\" }\n";
    let path = write(dir.path(), "bad.toml", text);
    let run = timbre(dir.path(), &["check", path_str(&path)]);
    run.assert_bad_input(&["'s'", "lens holograms cannot be scaled"]);
    assert_eq!(location(&run.stderr, &path).0, 5);
    // Turned and moved they are fine (the focusing test above places them so).
    let fine = text.replace("scale = 2", "translate = [1, 0, 0]");
    let path = write(dir.path(), "fine.toml", &fine);
    timbre(dir.path(), &["check", path_str(&path)]).assert_success();
}
