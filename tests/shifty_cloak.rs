//! Issue 41 item 2, Dr TIM's shifty cloaks (`EditableCubicShiftyCloak`,
//! `EditableSimpleTetrahedralShiftyCloak`), checked against what a transformation-optics cloak
//! must do, worked out from its parameters alone:
//!
//! * seen from outside, space outside the cloak is as it is: a ray that enters and leaves the
//!   cloak goes on along the line it came on;
//! * the inner cube (or tetrahedron) and everything in it is seen shifted by δ: a ray leaving a
//!   point P inside it leaves the cloak on a line through P + δ;
//! * both hold for the cloak placed by any invertible affine map T, with T P + L δ for the
//!   shifted image (L the linear part of T), since imaging is kept by affine maps;
//! * Dr TIM's defaults, part names and refusals.

mod common;

use glam::{DMat3, DVec3};
use timbre::surfaces::Surface;
use timbre::trajectories::{self, End, Trajectory};

use common::cli::{location, path_str, timbre, write};
use common::rng::Rng;

fn trace(text: &str) -> Vec<Trajectory> {
    let description = common::images::parse(text);
    trajectories::trace(common::rays::device(), &description).expect("trace")
}

/// Distance of `p` from the line through `a` along `d`.
fn line_distance(p: DVec3, a: DVec3, d: DVec3) -> f64 {
    (p - a).reject_from_normalized(d.normalize()).length()
}

/// A point in the box [−1, 1]³ times `size`.
fn random_point(rng: &mut Rng, size: f64) -> DVec3 {
    size * DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    )
}

/// A `[[ray_trajectory]]` table.
fn ray(start: DVec3, direction: DVec3) -> String {
    format!(
        "[[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 1000\n",
        start.x, start.y, start.z, direction.x, direction.y, direction.z
    )
}

/// The cloaks checked: type, the `lenses` keys beyond it, the device's transform (a TOML
/// table, or empty) and that transform as a linear map and translation.
struct Case {
    kind: &'static str,
    keys: &'static str,
    transform: &'static str,
    linear: DMat3,
    shift: DVec3,
    /// Whether |n̂·δ| is less than the distance h between the outer and inner faces for every
    /// face: otherwise a frustum is seen folded over, and rays from inside can circle for ever.
    unfolded: bool,
}

fn cases() -> Vec<Case> {
    let plain = |kind, keys, unfolded| Case {
        kind,
        keys,
        transform: "",
        linear: DMat3::IDENTITY,
        shift: DVec3::ZERO,
        unfolded,
    };
    vec![
        // Dr TIM's defaults (δ = (1, 0, 0) is four times the distance between the faces: the
        // frusta on ±u are folded over).
        plain("cubic-shifty-cloak", "centre = [0, 0, 0]", false),
        plain(
            "simple-tetrahedral-shifty-cloak",
            "centre = [0, 0, 0]",
            false,
        ),
        plain(
            "cubic-shifty-cloak",
            "centre = [0.1, -0.2, 0.05], u_direction = [1, 1, 0], v_direction = [0, 0.3, 1], \
             side_length_outside = 1.3, side_length_inside = 0.4, delta = [0.1, -0.05, 0.07]",
            true,
        ),
        plain(
            "simple-tetrahedral-shifty-cloak",
            "centre = [0, 0.1, 0], u_direction = [0, 1, 1], v_direction = [1, 0, 0], \
             side_length_outside = 1.5, side_length_inside = 0.3, delta = [-0.05, 0.08, 0.1]",
            true,
        ),
        plain(
            "tetrahedral-shifty-cloak",
            "centre = [0, 0, 0], delta = [0.05, 0.02, -0.03]",
            true,
        ),
        plain(
            "tetrahedral-shifty-cloak",
            "centre = [0.1, 0, 0], u = [1, 1, 0], v = [-1, 1, 0], w = [0, 0, 1], \
             asymmetric_configuration = false, side_length = 1.2, side_length_i = 0.3, \
             delta = [-0.02, 0.04, 0.03]",
            true,
        ),
        // Stretched and moved: [[2, 0.3, 0], [0, 1, 0], [0.2, 0, 0.7]] (rows), then (0, 0, 1).
        Case {
            kind: "cubic-shifty-cloak",
            keys: "centre = [0, 0, 0], delta = [0.1, 0.2, -0.1]",
            transform: "transform = { matrix = [[2, 0.3, 0], [0, 1, 0], [0.2, 0, 0.7]], translate = [0, 0, 1] }\n",
            linear: DMat3::from_cols_array(&[2.0, 0.0, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0, 0.7]),
            shift: DVec3::new(0.0, 0.0, 1.0),
            unfolded: true,
        },
        // Mirrored (x → −x) and sheared.
        Case {
            kind: "tetrahedral-shifty-cloak",
            keys: "centre = [0, 0, 0], delta = [0.04, -0.03, 0.02]",
            transform: "transform = { matrix = [[-1, 0, 0], [0, 1, 0.3], [0, 0, 2]] }\n",
            linear: DMat3::from_cols_array(&[-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.3, 2.0]),
            shift: DVec3::ZERO,
            unfolded: true,
        },
    ]
}

impl Case {
    fn scene(&self, rays: &str) -> String {
        format!(
            "studio = \"none\"\n[[device]]\nname = \"cloak\"\nshow_edges = false\n{}lenses = {{ type = \"{}\", {} }}\n{rays}",
            self.transform, self.kind, self.keys
        )
    }

    fn place(&self, p: DVec3) -> DVec3 {
        self.linear * p + self.shift
    }
}

#[test]
fn space_outside_the_cloak_is_seen_as_it_is() {
    let mut rng = Rng(41);
    for case in cases() {
        // Rays from a sphere of radius 4 about the cloak through points near its centre.
        let mut rays = Vec::new();
        for _ in 0..40 {
            let start = case.place(4.0 * random_point(&mut rng, 1.0).normalize());
            let target = case.place(random_point(&mut rng, 0.4));
            rays.push((start, target - start));
        }
        let text = case.scene(&rays.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        let traced = trace(&text);
        let mut crossed = 0;
        for (t, &(start, direction)) in traced.iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped, "{}: {:?}", case.keys, t.points);
            if t.points.len() < 3 {
                continue;
            }
            crossed += 1;
            let last = t.points.last().unwrap().position;
            let d = t.direction;
            assert!(
                (d - direction.normalize()).length() < 1e-9,
                "{} {}: leaves along {d}, came along {}",
                case.kind,
                case.keys,
                direction.normalize()
            );
            let off = line_distance(last, start, direction);
            assert!(
                off < 1e-9,
                "{} {}: {off} off its line",
                case.kind,
                case.keys
            );
        }
        assert!(crossed >= 30, "{}: only {crossed} rays crossed", case.keys);
    }
}

#[test]
fn the_inner_polyhedron_is_seen_shifted_by_delta() {
    let mut rng = Rng(7);
    for case in cases().into_iter().filter(|c| c.unfolded) {
        let delta = delta_of(&case);
        let size = inner_half_size(&case);
        let mut rays = Vec::new();
        for _ in 0..20 {
            // Inside the inner polyhedron: within a third of its half side of the centre.
            let p = centre_of(&case) + random_point(&mut rng, size / 3.0);
            rays.push((p, random_point(&mut rng, 1.0)));
        }
        let placed: Vec<_> = rays
            .iter()
            .map(|&(p, d)| (case.place(p), case.linear * d))
            .collect();
        let text = case.scene(&placed.iter().map(|&(s, d)| ray(s, d)).collect::<String>());
        for (t, &(p, _)) in trace(&text).iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped, "{}: {:?}", case.keys, t.points);
            let last = t.points.last().unwrap().position;
            let image = case.place(p) + case.linear * delta;
            let off = line_distance(image, last, t.direction);
            assert!(
                off < 1e-9,
                "{} {}: the ray from {p} leaves {off} off {image}",
                case.kind,
                case.keys
            );
        }
    }
}

/// δ, the centre and the inner half side of a case, read from its keys.
fn key(case: &Case, name: &str) -> Option<String> {
    let at = case.keys.find(&format!("{name} = "))? + name.len() + 3;
    let rest = &case.keys[at..];
    let end = if rest.starts_with('[') {
        rest.find(']').unwrap() + 1
    } else {
        rest.find(',').unwrap_or(rest.len())
    };
    Some(rest[..end].to_string())
}

fn vector(text: &str) -> DVec3 {
    let v: Vec<f64> = text
        .trim_matches(|c| c == '[' || c == ']')
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    DVec3::new(v[0], v[1], v[2])
}

fn delta_of(case: &Case) -> DVec3 {
    key(case, "delta").map_or(DVec3::X, |d| vector(&d))
}

fn centre_of(case: &Case) -> DVec3 {
    vector(&key(case, "centre").unwrap())
}

/// Half the inner cube's side, or the radius of the inner tetrahedron's inscribed sphere: the
/// points used lie within a third of it of the centre.
fn inner_half_size(case: &Case) -> f64 {
    let side = |name, default| key(case, name).map_or(default, |s| s.parse().unwrap());
    // The tetrahedron of alternate corners of a cube of side s has inradius s / (2√3).
    let inradius = |s: f64| s / (2.0 * 3f64.sqrt());
    match case.kind {
        "simple-tetrahedral-shifty-cloak" => inradius(side("side_length_inside", 0.5)),
        "tetrahedral-shifty-cloak" => inradius(side("side_length_i", 0.3)),
        _ => 0.5 * side("side_length_inside", 0.5),
    }
}

/// `EditableCubicShiftyCloak(parent, studio)` and `EditableSimpleTetrahedralShiftyCloak(parent,
/// studio)`: centre (0, 0, 10), u (1, 0, 0), v (0, 1, 0), sides 1 and 0.5, δ (1, 0, 0),
/// interfaces shown with transmission coefficient 0.96, frames shown, radius 0.01,
/// `GREY50_SHINY`. The cube has 6 outer, 6 inner and 12 diagonal faces, 16 vertices and
/// 12 + 12 + 8 edges; the tetrahedron 4, 4 and 6 faces, 8 vertices and 6 + 6 + 4 edges.
#[test]
fn shifty_cloaks_named_by_their_type_alone_are_dr_tims_default_cloaks() {
    for (kind, faces, frames, corner) in [
        (
            "cubic-shifty-cloak",
            24,
            16 + 32,
            DVec3::new(0.5, 0.5, 10.5),
        ),
        (
            "simple-tetrahedral-shifty-cloak",
            14,
            8 + 16,
            DVec3::new(0.5, 0.5, 10.5),
        ),
    ] {
        let d = common::images::parse(&format!(
            "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = {{ type = \"{kind}\" }}\n"
        ));
        let interfaces: Vec<_> = d
            .objects
            .iter()
            .filter(|o| matches!(o.surface, Surface::ConfocalLensletArrays(_)))
            .collect();
        assert_eq!(interfaces.len(), faces, "{kind}");
        assert_eq!(d.objects.len(), faces + frames, "{kind}");
        for o in &interfaces {
            let Surface::ConfocalLensletArrays(a) = &o.surface else {
                unreachable!()
            };
            assert_eq!(
                a.transmission,
                timbre::surfaces::metatoys::Transmission::Constant(0.96)
            );
            assert!(!o.shadow_throwing, "{}", o.name);
        }
        let vertex = d
            .objects
            .iter()
            .find(|o| o.name == "d/outer vertex +u+v+w")
            .unwrap_or_else(|| panic!("{kind}: no outer vertex"));
        let (lo, hi) = vertex.shape.bounds().unwrap();
        assert!(((lo + hi) / 2.0 - corner).length() < 1e-12, "{kind}");
        assert!(((hi - lo).x - 0.02).abs() < 1e-12, "{kind}: radius 0.01");
        let Surface::Coloured(c) = &vertex.surface else {
            panic!("{kind}: frames are coloured")
        };
        assert_eq!(c.diffuse, timbre::math::Colour::splat(0.5));
        assert!(
            d.objects.iter().any(|o| o.name == "d/inner vertex +u+v+w"),
            "{kind}"
        );
    }
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\nshow_edges = false\n\
         lenses = { type = \"cubic-shifty-cloak\" }\n",
    );
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    for name in [
        "d/outer face in +u direction",
        "d/inner face in -w direction",
        "d/diagonal face between the +u and +v faces",
    ] {
        assert!(names.contains(&name), "{name} in {names:?}");
    }
    let hidden = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"d\"\n\
         lenses = { type = \"simple-tetrahedral-shifty-cloak\", show_interfaces = false }\n",
    );
    assert_eq!(hidden.objects.len(), 24);
}

#[test]
fn bad_shifty_cloaks_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            "side_length_inside = 1",
            &["side_length_inside", "less than side_length_outside"][..],
        ),
        (
            "v_direction = [2, 0, 0]",
            &["v_direction must not be along u_direction"][..],
        ),
        // h = (1 − 0.5) × 0.5 = 0.25 for the +u face.
        (
            "delta = [0.25, 0, 0]",
            &[
                "+u face",
                "inner face would appear in the outer face's plane",
            ][..],
        ),
        ("side_length_outside = -1", &["positive number"][..]),
        ("colour = 1", &["colour"][..]),
    ] {
        let text = format!(
            "studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ type = \"cubic-shifty-cloak\", {keys} }}\n"
        );
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}

/// A homogeneous planar imaging surface simplicial complex (Dr TIM's
/// `EditableHomogeneousPlanarImagingSurfaceSimplicialComplex`) shows each cell through the
/// affine map that takes its vertices to their virtual positions: a point with barycentric
/// coordinates w in a cell is seen at Σ wᵢ Vᵢ. Dr TIM's default, with its inner vertex seen far
/// outside the tetrahedron, folds the cells over; space outside is still seen as it is.
#[test]
fn a_complex_of_imaging_surfaces_shows_each_cell_through_the_map_of_its_vertices() {
    let p = [
        DVec3::new(-1.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(0.0, 0.4, 0.1),
    ];
    let list = |v: &[DVec3]| {
        v.iter()
            .map(|x| format!("[{}, {}, {}]", x.x, x.y, x.z))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut rng = Rng(3);
    for (v4, unfolded) in [
        (DVec3::new(0.1, 0.5, 0.2), true),
        (DVec3::new(2.0, 0.75, 3.0), false),
    ] {
        let mut v = p;
        v[4] = v4;
        let scene = |rays: &str| {
            format!(
                "studio = \"none\"\n[[device]]\nname = \"c\"\nshow_edges = false\n\
                 lenses = {{ type = \"homogeneous-planar-imaging-surface-simplicial-complex\", \
                 vertices = [{}], vertices_v = [{}], show_structure_v = false }}\n{rays}",
                list(&p),
                list(&v)
            )
        };
        // Outside: rays through the tetrahedron go on along their lines.
        let rays: Vec<(DVec3, DVec3)> = (0..30)
            .map(|_| {
                let start = 4.0 * random_point(&mut rng, 1.0).normalize();
                let target = DVec3::new(0.0, 0.3, 0.2) + random_point(&mut rng, 0.3);
                (start, target - start)
            })
            .collect();
        let traced = trace(&scene(
            &rays.iter().map(|&(s, d)| ray(s, d)).collect::<String>(),
        ));
        for (t, &(start, direction)) in traced.iter().zip(&rays) {
            assert_eq!(t.end, End::Escaped);
            assert!((t.direction - direction.normalize()).length() < 1e-9);
            let last = t.points.last().unwrap().position;
            assert!(line_distance(last, start, direction) < 1e-9);
        }
        if !unfolded {
            continue;
        }
        // Inside each of the four cells round vertex 4.
        for cell in [[0, 1, 2, 4], [0, 1, 3, 4], [0, 2, 3, 4], [1, 2, 3, 4]] {
            let w = [0.2, 0.25, 0.15, 0.4];
            let at = |x: &[DVec3; 5]| (0..4).map(|i| w[i] * x[cell[i]]).sum::<DVec3>();
            let (point, image) = (at(&p), at(&v));
            let rays: Vec<DVec3> = (0..8).map(|_| random_point(&mut rng, 1.0)).collect();
            let traced = trace(&scene(
                &rays.iter().map(|&d| ray(point, d)).collect::<String>(),
            ));
            for t in &traced {
                assert_eq!(t.end, End::Escaped, "{cell:?}: {:?}", t.points);
                let last = t.points.last().unwrap().position;
                let off = line_distance(image, last, t.direction);
                assert!(off < 1e-9, "{cell:?}: {off} off {image}");
            }
        }
    }
}

/// `EditableTetrahedralShiftyCloak(parent, studio)`: centre (0, 0, 10), u, v, w along x, y, z,
/// asymmetric, side lengths 1 and 0.3, δ = 0, interfaces shown with transmission coefficient
/// 0.96, frames shown, radius 0.01, `GREY50_SHINY`. With δ = 0 every face images space to
/// itself: its 32 faces (Dr TIM's 15 cells) are gCLAs with η = 1 and δ = 0. `EditableHomogeneousPlanarImagingSurfaceSimplicialComplex(
/// description, parent, studio)`: a tetrahedron on y = 0 about (0, 0, 10) with its top at
/// (0, 1, 10) and an inner vertex at (0, 0.5, 10) seen at (2, 0.75, 13): 6 faces meet that
/// vertex and all need imaging; its structure (blue, radius 0.021) and virtual structure (red,
/// 0.02) are shown, 10 edges and 5 vertices each.
#[test]
fn the_complex_and_the_tetrahedral_cloak_named_by_their_type_alone_are_dr_tims() {
    let parse = |lenses: &str| {
        common::images::parse(&format!(
            "studio = \"none\"\n[[device]]\nname = \"d\"\nlenses = {{ {lenses} }}\n"
        ))
        .objects
    };
    let cloak = parse("type = \"tetrahedral-shifty-cloak\"");
    let faces: Vec<_> = cloak
        .iter()
        .filter_map(|o| match &o.surface {
            Surface::ConfocalLensletArrays(a) => Some(a),
            _ => None,
        })
        .collect();
    assert_eq!(faces.len(), 32);
    for a in faces {
        assert!((a.eta - glam::DVec2::ONE).length() < 1e-12 && a.delta.length() < 1e-12);
        assert_eq!(
            a.transmission,
            timbre::surfaces::metatoys::Transmission::Constant(0.96)
        );
    }
    let vertex = |objects: &[timbre::scene::SceneObject], name: &str| {
        let o = objects
            .iter()
            .find(|o| o.name == name)
            .unwrap_or_else(|| panic!("no {name}"));
        let (lo, hi) = o.shape.bounds().unwrap();
        ((lo + hi) / 2.0, (hi - lo).x / 2.0)
    };
    let (at, radius) = vertex(&cloak, "d/vertex 0");
    assert!((at - DVec3::new(0.5, 0.5, 10.5)).length() < 1e-12 && (radius - 0.01).abs() < 1e-12);
    // Inner vertex 0 (vertex 4): the inner corner (0.15, 0.15, 0.15) moved 1 % further from
    // outer vertex 1, (0.5, −0.5, −0.5).
    let from = DVec3::new(0.5, -0.5, 9.5);
    let expected = from + 1.01 * (DVec3::new(0.15, 0.15, 10.15) - from);
    assert!((vertex(&cloak, "d/vertex 4").0 - expected).length() < 1e-12);
    // 6 + 6 + 12 edges.
    assert_eq!(cloak.iter().filter(|o| o.name.contains("edge")).count(), 24);

    let complex = parse("type = \"homogeneous-planar-imaging-surface-simplicial-complex\"");
    let faces: Vec<_> = complex
        .iter()
        .filter(|o| matches!(o.surface, Surface::ConfocalLensletArrays(_)))
        .collect();
    assert_eq!(faces.len(), 10, "4 outer and 6 inner faces");
    assert_eq!(complex.len(), 10 + 2 * (10 + 5));
    assert!(faces.iter().all(|o| !o.shadow_throwing));
    let (at, radius) = vertex(&complex, "d/virtual vertex 4");
    assert!((at - DVec3::new(2.0, 0.75, 13.0)).length() < 1e-12 && (radius - 0.02).abs() < 1e-12);
    let (_, radius) = vertex(&complex, "d/vertex 4");
    assert!((radius - 0.021).abs() < 1e-12);
}

#[test]
fn bad_complexes_and_tetrahedral_cloaks_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (lenses, needles) in [
        (
            "type = \"tetrahedral-shifty-cloak\", side_length_i = 0.97",
            &["side_length_i", "at most 0.96"][..],
        ),
        (
            "type = \"tetrahedral-shifty-cloak\", asymmetric_configuration = false, side_length_i = 0.33",
            &["symmetric configuration"][..],
        ),
        (
            "type = \"tetrahedral-shifty-cloak\", w = [1, 1, 0]",
            &["u, v and w must not lie in one plane"][..],
        ),
        (
            "type = \"homogeneous-planar-imaging-surface-simplicial-complex\", \
             vertices_v = [[-1, 0, 11], [1, 0, 11], [0, 0, 9], [0, 1.2, 10], [0, 0.5, 10]]",
            &[
                "vertex 3 is on the outside",
                "virtual position must be its physical one",
            ][..],
        ),
        (
            "type = \"homogeneous-planar-imaging-surface-simplicial-complex\", \
             vertices_v = [[-1, 0, 11], [1, 0, 11], [0, 0, 9], [0, 1, 10], [0, 0, 10.5]]",
            &["lie in a plane", "seen flat"][..],
        ),
        (
            "type = \"homogeneous-planar-imaging-surface-simplicial-complex\", edges = [[0, 1]]",
            &["vertex 4 is in no cell"][..],
        ),
    ] {
        let text =
            format!("studio = \"none\"\n\n[[device]]\nname = \"c\"\nlenses = {{ {lenses} }}\n");
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}

/// Dr TIM's gCLA mapping goggles (`EditableFramedGCLAMappingGoggles`): each triangle of the base
/// images the eye's image in the pyramid face above it back to the eye, so a ray from the eye
/// through a triangle and then the face leaves on a line from the eye (seen from the eye, the
/// goggles only move things across its view), to 10⁻⁹; for the default goggles and for ones
/// turned, moved and with another compression.
#[test]
fn the_mapping_goggles_send_rays_from_the_eye_on_lines_from_the_eye() {
    let mut rng = Rng(5);
    for (keys, eye, base, right, up, half_side) in [
        (
            "",
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::X,
            DVec3::Y,
            0.5,
        ),
        (
            "eye_position = [0.2, -0.1, 1], base_centre = [1, 0.5, 4], right = [1, 1, 0], \
             up = [0, 0.2, 1], base_centre_to_apex_distance = 0.6, base_side_length = 1.4, \
             view_compression_factor = 0.3",
            DVec3::new(0.2, -0.1, 1.0),
            DVec3::new(1.0, 0.5, 4.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 0.2, 1.0),
            0.7,
        ),
    ] {
        // The base's directions as Dr TIM makes them: up perpendicular to right.
        let right = right.normalize();
        let up = up.reject_from_normalized(right).normalize();
        let lenses = if keys.is_empty() {
            "type = \"framed-gcla-mapping-goggles\"".to_string()
        } else {
            format!("type = \"framed-gcla-mapping-goggles\", {keys}")
        };
        let mut rays = Vec::new();
        for _ in 0..40 {
            // Towards points of the base square (some through the open centre).
            let (a, b) = (rng.range(-0.95, 0.95), rng.range(-0.95, 0.95));
            let target = base + half_side * (a * right + b * up);
            rays.push(target - eye);
        }
        let text = format!(
            "studio = \"none\"\n[[device]]\nname = \"g\"\nshow_edges = false\nlenses = {{ {lenses} }}\n{}",
            rays.iter().map(|&d| ray(eye, d)).collect::<String>()
        );
        let description = common::images::parse(&text);
        let mut through_triangles = 0;
        for t in trace(&text) {
            let names: Vec<&str> = t
                .points
                .iter()
                .filter_map(|p| p.object.map(|i| description.objects[i].name.as_str()))
                .collect();
            if names.len() == 2 && names[0].contains("triangle") && names[1].contains("face") {
                through_triangles += 1;
                let last = t.points.last().unwrap().position;
                let off = line_distance(eye, last, t.direction);
                assert!(off < 1e-9, "{keys}: {names:?} leave {off} off the eye");
            }
        }
        assert!(through_triangles >= 10, "{keys}: {through_triangles} rays");
    }
}

/// `EditableFramedGCLAMappingGoggles(parent, studio)`: eye (0, 0, 0), base centre (0, 0, 5),
/// right (1, 0, 0), up (0, 1, 0), apex 1 beyond the base, side 1, compression 0.5; eight
/// windows of gCLAs (Dr TIM's `toGCLAs()`: the best-case geometric transmission, throwing
/// shadows), frames shown: 9 spheres and 16 cylinders of radius 0.01.
#[test]
fn mapping_goggles_named_by_their_type_alone_are_dr_tims() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"g\"\nlenses = { type = \"framed-gcla-mapping-goggles\" }\n",
    );
    let windows: Vec<_> = d
        .objects
        .iter()
        .filter(|o| matches!(o.surface, Surface::ConfocalLensletArrays(_)))
        .collect();
    assert_eq!(windows.len(), 8);
    for o in &windows {
        let Surface::ConfocalLensletArrays(a) = &o.surface else {
            unreachable!()
        };
        assert_eq!(
            a.transmission,
            timbre::surfaces::metatoys::Transmission::GeometricBest
        );
        assert!(o.shadow_throwing);
    }
    assert_eq!(d.objects.len(), 8 + 9 + 16);
    let at = |name: &str| {
        let o = d
            .objects
            .iter()
            .find(|o| o.name == name)
            .unwrap_or_else(|| panic!("no {name}"));
        let (lo, hi) = o.shape.bounds().unwrap();
        (lo + hi) / 2.0
    };
    assert!((at("g/apex of square pyramid") - DVec3::new(0.0, 0.0, 6.0)).length() < 1e-12);
    assert!(
        (at("g/inner corner of top distorted triangle") - DVec3::new(0.0, 0.25, 5.0)).length()
            < 1e-12
    );
    assert!(
        (at("g/top left corner of base of square pyramid") - DVec3::new(-0.5, 0.5, 5.0)).length()
            < 1e-12
    );
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            ", view_compression_factor = 0",
            &["view_compression_factor", "above 0"][..],
        ),
        (", up = [2, 0, 0]", &["up must not be along right"][..]),
        (
            ", eye_position = [0, 0, 5]",
            &["eye must not be at the base centre"][..],
        ),
    ] {
        let text = format!(
            "studio = \"none\"\n\n[[device]]\nname = \"g\"\nlenses = {{ type = \"framed-gcla-mapping-goggles\"{keys} }}\n"
        );
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}
