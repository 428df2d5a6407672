//! Issue 37 item 4, stigmatic refractive lenses: Dr TIM's `LensSurface` (the `lens-surface`
//! shape), `FresnelLensSurface` and `FresnelLens` (devices), checked against facts worked out
//! here, independently of timbre's code:
//!
//! * hits against a brute-force march along the ray on Dr TIM's explicit surface,
//!   w = W(ρ) (`calculateW`), bisected at each sign change;
//! * the defining property, with Snell's law written here from the shape's normal: rays
//!   travelling along the axis inside the glass leave through the focal point (or, diverging,
//!   from it), and a Fresnel lens sends every ray from its front conjugate point that crosses
//!   a lens section on each side exactly through its back conjugate point, ring by ring;
//! * the research scene `scenes/research/CollimatingFresnelLensSurfaceTest.toml`, traced
//!   by `timbre trace --json`: rays from the focal point leave each ring along the axis;
//! * Dr TIM's spherical thick lenses of the same family, `RefractiveLensSurfaces` and
//!   `TriangularThickLens`: their paraxial focal lengths, traced, against the thick-lens
//!   lensmaker's equation;
//! * impossible parameters refused by `timbre check` with the line and column of the table.

mod common;

use std::path::Path;

use glam::DVec3;
use tempfile::TempDir;
use timbre::geometry::{Shape, lens_surface};
use timbre::scene::file;

use common::cli::{path_str, timbre, write};
use common::glass::{across, follow, snell};
use common::rng::Rng;

/// How far the line through `p` along the unit vector `e` passes from `q`.
fn miss(p: DVec3, e: DVec3, q: DVec3) -> f64 {
    (q - p).cross(e).length()
}

/// Dr TIM's lens surface, described here by its explicit form: focal point F, outward axis ŵ,
/// focal length f, index n; w(ρ) = −f (n + √(1 + (n + 1) ρ²/((n − 1) f²)))/(n + 1).
struct Explicit {
    f_point: DVec3,
    w_hat: DVec3,
    f: f64,
    n: f64,
}

impl Explicit {
    fn w_of(&self, rho: f64) -> f64 {
        let (f, n) = (self.f, self.n);
        -f * (n + (1.0 + (n + 1.0) / (n - 1.0) * rho * rho / (f * f)).sqrt()) / (n + 1.0)
    }

    /// w − W(ρ): zero on the sheet, of one sign on each side (the sheet is a graph over ρ).
    fn field(&self, p: DVec3) -> f64 {
        let r = p - self.f_point;
        let w = r.dot(self.w_hat);
        w - self.w_of(r.reject_from_normalized(self.w_hat).length())
    }

    /// The sheet's point at distance ρ from the axis in the direction `dir` across it.
    fn point(&self, rho: f64, dir: DVec3) -> DVec3 {
        self.f_point + rho * dir + self.w_of(rho) * self.w_hat
    }

    fn shape(&self) -> Shape {
        lens_surface(self.f_point, self.w_hat, self.f, self.n).unwrap()
    }

    /// Nearest crossing of the sheet in (0, t_max) by marching `steps` steps and bisecting.
    fn march(&self, o: DVec3, d: DVec3, t_max: f64, steps: usize) -> Option<f64> {
        let at = |t: f64| self.field(o + t * d);
        let h = t_max / steps as f64;
        let mut previous = at(0.0);
        for i in 1..=steps {
            let t = i as f64 * h;
            let value = at(t);
            if previous.signum() != value.signum() {
                let (mut lo, mut hi) = (t - h, t);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if at(mid).signum() == at(lo).signum() {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(0.5 * (lo + hi));
            }
            previous = value;
        }
        None
    }
}

fn surfaces() -> Vec<Explicit> {
    let mut rng = Rng(37);
    let mut out = Vec::new();
    for f in [0.7, 2.0, -0.7, -2.0] {
        for n in [1.3, 1.5, 2.4] {
            out.push(Explicit {
                f_point: rng.point(3.0),
                w_hat: rng.unit(),
                f,
                n,
            });
        }
    }
    out
}

#[test]
fn lens_surface_hits_match_a_march_along_the_ray() {
    let mut rng = Rng(4);
    let mut hits = 0;
    for s in surfaces() {
        let shape = s.shape();
        let scale = s.f.abs();
        for k in 0..150 {
            let o = s.f_point + rng.point(4.0 * scale);
            // Half the rays aimed at a point of the sheet, half anywhere.
            let d = if k % 2 == 0 {
                let (u, v) = across(s.w_hat);
                let phi = rng.range(0.0, std::f64::consts::TAU);
                let target = s.point(rng.range(0.0, 3.0 * scale), phi.cos() * u + phi.sin() * v);
                (target - o).normalize()
            } else {
                rng.unit()
            };
            let t_max = 20.0 * scale;
            let reference = s.march(o, d, t_max, 40_000);
            let got = shape.intersect(o, d, 1e-9, t_max).map(|h| h.0);
            match (reference, got) {
                (Some(r), Some(g)) => {
                    assert!(
                        (r - g).abs() < 1e-9 * (1.0 + r),
                        "f {} n {}: march {r}, shape {g} (o {o}, d {d})",
                        s.f,
                        s.n
                    );
                    hits += 1;
                }
                (None, None) => {}
                (r, g) => {
                    // Only a ray grazing the sheet may be found by one and not the other: the
                    // crossings are then within a step of each other.
                    let t = r.or(g).unwrap();
                    let p = o + t * d;
                    let normal = shape.normal(p, 0);
                    assert!(
                        normal.dot(d).abs() < 1e-2,
                        "f {} n {}: march {r:?}, shape {g:?} (o {o}, d {d})",
                        s.f,
                        s.n
                    );
                }
            }
        }
    }
    assert!(hits > 900, "only {hits} hits");
}

#[test]
fn lens_surface_sends_axial_rays_in_the_glass_through_its_focal_point() {
    for s in surfaces() {
        let shape = s.shape();
        let (u, v) = across(s.w_hat);
        for i in 0..40 {
            let rho = 3.0 * s.f.abs() * i as f64 / 40.0;
            let phi = 0.7 * i as f64;
            let p = s.point(rho, phi.cos() * u + phi.sin() * v);
            // Inside the glass, travelling outwards along the axis, onto the sheet at p.
            let start = p - s.w_hat;
            assert!(
                shape.contains(start),
                "f {}: the glass is behind the sheet",
                s.f
            );
            let (t, part) = shape.intersect(start, s.w_hat, 1e-9, 10.0).unwrap();
            let hit = start + t * s.w_hat;
            assert!((hit - p).length() < 1e-9 * (1.0 + rho));
            let normal = shape.normal(hit, part);
            assert!(
                normal.dot(s.w_hat) > 0.0,
                "the normal points out of the glass"
            );
            let Some(e) = snell(s.w_hat, normal, s.n) else {
                // Totally reflected: beyond the sheet's useful aperture (f > 0, steep).
                assert!(s.f > 0.0, "a diverging surface never reflects axial rays");
                continue;
            };
            let to_focus = s.f_point - hit;
            assert!(
                miss(hit, e, s.f_point) < 1e-9 * to_focus.length(),
                "f {} n {} ρ {rho}: the ray misses F by {}",
                s.f,
                s.n,
                miss(hit, e, s.f_point)
            );
            // Towards a real focus (f > 0), away from a virtual one (f < 0).
            assert_eq!(e.dot(to_focus) > 0.0, s.f > 0.0);
            if s.f > 0.0 {
                // Reversed: from F onto the sheet, into the glass along the axis, inwards.
                let e = snell(-to_focus.normalize(), normal, s.n).unwrap();
                assert!((e + s.w_hat).length() < 1e-9, "{e}");
            }
        }
    }
}

/// Rays from `from` in every direction within `cone` radians of `towards`, on rings of 24.
fn fan(towards: DVec3, cone: f64, rings: usize) -> Vec<DVec3> {
    let (u, v) = across(towards);
    let mut out = Vec::new();
    for i in 1..=rings {
        let theta = cone * i as f64 / rings as f64;
        for j in 0..24 {
            let phi = std::f64::consts::TAU * (j as f64 + 0.5 * i as f64) / 24.0;
            out.push(theta.cos() * towards + theta.sin() * (phi.cos() * u + phi.sin() * v));
        }
    }
    out
}

/// Every ray from the front conjugate point that crosses a lens section of the front surface
/// and then one of the back surface (and nothing else) passes through the back conjugate
/// point; every section of both sides is crossed by some such ray (`every_section`), or at
/// least five of each side.
fn assert_images(lenses: &str, front: DVec3, back: DVec3, cone: f64, every_section: bool) {
    let text = format!("studio = \"none\"\n[[device]]\nname = \"lens\"\nlenses = {lenses}\n");
    let description = file::parse(&text, "fresnel.toml").unwrap();
    let sections: Vec<&str> = description
        .objects
        .iter()
        .map(|o| o.name.as_str())
        .filter(|n| n.contains("lens section"))
        .collect();
    let mut crossed = std::collections::HashSet::new();
    let mut imaged = 0;
    let rays = fan((back - front).normalize(), cone, 300);
    for d in &rays {
        let Some((met, p, e)) = follow(&description, front, *d) else {
            continue; // ends on a black step
        };
        let through = |i: usize, side: &str| {
            met.get(i)
                .is_some_and(|m| m.contains(&format!("{side} surface/lens section")))
        };
        if !(met.len() == 2 && through(0, "front") && through(1, "back")) {
            continue; // past a rim (the two sides' rings differ), or through a step
        }
        let off = miss(p, e, back);
        assert!(
            off < 1e-9,
            "{lenses}: {met:?} misses the back point by {off}"
        );
        assert!(e.dot(back - p) > 0.0, "it goes towards the back point");
        crossed.extend(met);
        imaged += 1;
    }
    match every_section {
        true => {
            for section in &sections {
                assert!(
                    crossed.contains(*section),
                    "{lenses}: no ray crosses {section}"
                );
            }
        }
        false => {
            for side in ["front", "back"] {
                let rings = crossed.iter().filter(|m| m.contains(side)).count();
                assert!(
                    rings >= 5,
                    "{lenses}: rays image through {rings} {side} sections"
                );
            }
        }
    }
    assert!(
        imaged > rays.len() / 4,
        "only {imaged} of {} rays imaged",
        rays.len()
    );
}

#[test]
fn dr_tims_default_fresnel_lens_images_its_front_point_onto_its_back_point() {
    assert_images(
        "{ type = \"fresnel-lens\" }",
        DVec3::NEG_Z,
        DVec3::Z,
        0.7,
        true,
    );
}

#[test]
fn a_skew_fresnel_lens_images_its_conjugate_points_ring_by_ring() {
    // The central plane turned by 20° about y (its forwards normal towards the front point,
    // as in Dr TIM's default), the conjugate points off its normal, at different distances and
    // in line with the centre (Dr TIM's numberOfLensSections counts from the surfaces through
    // the centre), glass of index 1.7, refractive steps. The tilted plane also cuts surfaces
    // whose vertices lie behind it (f > f_P), off the axis: Dr TIM's first sections are then
    // crescents far out to one side, which rays from the front point cross without meeting a
    // back section, so only most sections are checked here.
    let (s, c) = 20f64.to_radians().sin_cos();
    let front = DVec3::new(0.3, 0.15, -1.5);
    let back = DVec3::new(-0.4, -0.2, 2.0);
    let lenses = format!(
        "{{ type = \"fresnel-lens\", forwards_central_plane_normal = [-{s}, 0, -{c}], \
         front_conjugate_point = [0.3, 0.15, -1.5], back_conjugate_point = [-0.4, -0.2, 2], \
         refractive_index = 1.7, thickness = 0.08, number_of_lens_sections = 6, \
         make_step_surfaces_black = false }}"
    );
    assert_images(&lenses, front, back, 0.5, false);
}

// ------------------------------------------------------------------------------------------
// Spherical thick lenses
// ------------------------------------------------------------------------------------------

/// The effective focal length of the lens device `lenses` with optical axis `axis` through
/// `point`: a ray parallel to the axis, 10⁻⁴ from it, traced through (Snell here), leaves at
/// slope s towards the axis: f = 10⁻⁴/s (paraxially, to about 10⁻⁸ relatively).
fn traced_focal_length(lenses: &str, point: DVec3, axis: DVec3) -> f64 {
    let text = format!("studio = \"none\"\n[[device]]\nname = \"lens\"\nlenses = {lenses}\n");
    let description = file::parse(&text, "thick.toml").unwrap();
    let (u, _) = across(axis);
    let h = 1e-4;
    let (met, _, e) = follow(&description, point + h * u - 10.0 * axis, axis).unwrap();
    assert_eq!(met.len(), 2, "{lenses}: {met:?}");
    -h * e.dot(axis) / e.dot(u)
}

/// The distance the lens device `lenses` spans along `axis` through `point`.
fn traced_thickness(lenses: &str, point: DVec3, axis: DVec3) -> f64 {
    let text = format!("studio = \"none\"\n[[device]]\nname = \"lens\"\nlenses = {lenses}\n");
    let description = file::parse(&text, "thick.toml").unwrap();
    let shape = &description.objects[0].shape;
    let o = point - 10.0 * axis;
    let (t0, _) = shape.intersect(o, axis, 0.0, 100.0).unwrap();
    let (t1, _) = shape.intersect(o, axis, t0 + 1e-9, 100.0).unwrap();
    t1 - t0
}

#[test]
fn refractive_lens_surfaces_have_the_focal_length_they_are_given() {
    // Dr TIM solves the thick-lens lensmaker's equation for the radius: the traced lens must
    // focus at f, thick as it is.
    let axis = DVec3::new(0.2, -0.1, 1.0).normalize();
    let centre = DVec3::new(0.5, 0.2, 6.0);
    for (f, n, d) in [
        (2.0, 1.5, 0.3),
        (0.8, 1.7, 0.2),
        (-1.5, 1.5, 0.1),
        (-0.6, 2.0, 0.05),
    ] {
        let lenses = format!(
            "{{ type = \"refractive-lens-surfaces\", centre = [{}, {}, {}], \
             normalised_optical_axis_direction = [{}, {}, {}], focal_length = {f}, \
             refractive_index = {n}, centre_thickness = {d} }}",
            centre.x, centre.y, centre.z, axis.x, axis.y, axis.z
        );
        let traced = traced_focal_length(&lenses, centre, axis);
        assert!(
            (traced - f).abs() < 1e-6 * f.abs(),
            "f {f}: traced {traced}"
        );
        let thickness = traced_thickness(&lenses, centre, axis);
        assert!((thickness - d).abs() < 1e-9, "f {f}: {thickness}");
    }
}

#[test]
fn triangular_thick_lenses_focus_as_thick_lenses_of_radius_2_f_n_minus_1() {
    // Dr TIM's radius R = 2 f (n − 1) is the thin lens's; the lens, of centre thickness d_c
    // (traced), focuses at the thick lens's 1/f' = (n − 1)(2/R − (n − 1) d_c/(n R²)).
    let corners = "corner1 = [1, 0, 4], corner2 = [-0.5, 0.8, 4], corner3 = [-0.5, -0.9, 4]";
    let p = DVec3::new(0.1, 0.05, 4.0);
    for (f, n) in [(2.0, 1.5), (3.0, 1.49), (-2.0, 1.5)] {
        let lenses = format!(
            "{{ type = \"triangular-thick-lens\", focal_length = {f}, \
             principal_point = [0.1, 0.05, 4], {corners}, refractive_index = {n}, \
             thickness_at_thinnest_point = 0.02 }}"
        );
        let d_c = traced_thickness(&lenses, p, DVec3::Z);
        let r = 2.0 * f * (n - 1.0);
        let expected = 1.0 / ((n - 1.0) * (2.0 / r - (n - 1.0) * d_c / (n * r * r)));
        let traced = traced_focal_length(&lenses, p, DVec3::Z);
        assert!(
            (traced - expected).abs() < 1e-6 * f.abs(),
            "f {f}: {traced} vs {expected}"
        );
        if f < 0.0 {
            assert!((d_c - 0.02).abs() < 1e-12, "thinnest on the axis: {d_c}");
        } else {
            // Thinnest at the corner farthest from the principal point, (−0.5, −0.9).
            let corner = DVec3::new(-0.5, -0.9, 4.0);
            let inside = corner + 1e-9 * (p - corner).normalize();
            let d = traced_thickness(&lenses, inside, DVec3::Z);
            assert!((d - 0.02).abs() < 1e-6, "at the corner: {d}");
        }
    }
}

// ------------------------------------------------------------------------------------------
// The research scene
// ------------------------------------------------------------------------------------------

const RESEARCH: &str = "scenes/research/CollimatingFresnelLensSurfaceTest.toml";

fn research() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(RESEARCH)
}

#[test]
fn collimating_fresnel_lens_surface_test_checks_with_three_sections() {
    let dir = TempDir::new().unwrap();
    let run = timbre(dir.path(), &["check", path_str(&research())]);
    run.assert_success();
    // Sky, floor, three lens sections and the two steps between them.
    assert_eq!(run.count("objects"), 7, "{}", run.stdout);
    assert!(run.field("shapes").contains("5 masked"), "{}", run.stdout);
}

/// The program's Fresnel-lens surface (focal point at the origin, axis outwards −z, principal
/// plane z = 1) collimates: `timbre trace --json` follows rays from the focal point, and
/// every one that meets a lens section and nothing else of the lens leaves along +z, each
/// of the three sections taking some.
#[test]
fn collimating_fresnel_lens_surface_test_sends_rays_from_the_focus_along_the_axis() {
    let dir = TempDir::new().unwrap();
    let mut text = std::fs::read_to_string(research()).unwrap();
    let rays = fan(DVec3::Z, 0.55, 40);
    for (k, d) in rays.iter().enumerate() {
        text.push_str(&format!(
            "\n[[ray_trajectory]]\nname = \"test ray {k}\"\nstart = [0, 0, 0]\n\
             direction = [{}, {}, {}]\nmax_interactions = 20\n",
            d.x, d.y, d.z
        ));
    }
    let path = write(&dir, "scene.toml", text);
    let run = timbre(dir.path(), &["trace", "--json", path_str(&path)]);
    run.assert_success();
    let json: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let mut per_section = std::collections::HashMap::new();
    for ray in json["rays"].as_array().unwrap() {
        let objects: Vec<&str> = ray["points"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|p| p["object"].as_str())
            .filter(|o| o.starts_with("Fresnel lens/"))
            .collect();
        if objects.len() != 1 || !objects[0].contains("lens section") {
            continue; // past the lens, or (also) through a step
        }
        let d: Vec<f64> = ray["direction"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let d = DVec3::from_slice(&d);
        assert!(
            (d - DVec3::Z).length() < 1e-9,
            "{}: leaves {objects:?} along {d}",
            ray["trajectory"]
        );
        *per_section.entry(objects[0].to_string()).or_insert(0) += 1;
    }
    let mut names: Vec<&String> = per_section.keys().collect();
    names.sort();
    assert_eq!(
        names,
        [
            "Fresnel lens/lens section 1",
            "Fresnel lens/lens section 2",
            "Fresnel lens/lens section 3"
        ],
        "{per_section:?}"
    );
}

// ------------------------------------------------------------------------------------------
// Impossible parameters
// ------------------------------------------------------------------------------------------

#[test]
fn impossible_lenses_are_refused_where_they_are_written() {
    let surface = |keys: &str| {
        format!(
            "[[object]]\nsurface = {{ type = \"refractive\", index_ratio = 1.5 }}\n\
             shape = {{ type = \"lens-surface\", {keys} }}\n"
        )
    };
    let device = |keys: &str| format!("[[device]]\nname = \"lens\"\nlenses = {{ {keys} }}\n");
    let fresnel_surface = |keys: &str| {
        device(&format!(
            "type = \"fresnel-lens-surface\", point_in_principalish_plane = [0, 0, 1], \
             outwards_principalish_plane_normal = [0, 0, -1], refractive_index = 1.5, \
             optical_axis_direction = [0, 0, -1], approximate_thickness = 0.1, {keys}"
        ))
    };
    let cases = [
        (
            surface(
                "focal_point = [0, 0, 5], focal_length = 1, refractive_index = 1, \
                 optical_axis_outwards = [0, 0, -1]",
            ),
            vec![":3:9:", "a refractive index greater than 1, got 1"],
        ),
        (
            surface(
                "focal_point = [0, 0, 5], focal_length = 0, refractive_index = 1.5, \
                 optical_axis_outwards = [0, 0, -1]",
            ),
            vec![":3:9:", "non-zero number, got 0"],
        ),
        (
            surface(
                "focal_point = [0, 0, 5], focal_length = 1, refractive_index = 1.5, \
                 optical_axis_outwards = [0, 0, 0]",
            ),
            vec![":3:9:", "optical_axis_outwards must be a non-zero vector"],
        ),
        (
            device("type = \"fresnel-lens\", thickness = 0.01"),
            vec![
                ":3:10:",
                "device 'lens'",
                "must exceed the minimum_surface_separation",
            ],
        ),
        (
            device("type = \"fresnel-lens\", back_conjugate_point = [0, 0, -1]"),
            vec![":3:10:", "must cross the central plane"],
        ),
        (
            device("type = \"fresnel-lens\", forwards_central_plane_normal = [1, 0, -0.5]"),
            vec![":3:10:", "tilted too far from the optical axis"],
        ),
        (
            device(
                "type = \"fresnel-lens\", number_of_lens_sections = 3, focal_length_max_back = 1",
            ),
            vec![":3:10:", "not both"],
        ),
        (
            device("type = \"fresnel-lens\", refractive_index = 0.9"),
            vec![":3:10:", "a refractive index greater than 1, got 0.9"],
        ),
        (
            fresnel_surface("focal_point = [0, 0, 2], number_of_lens_sections = 3"),
            vec![":3:10:", "virtual focal point"],
        ),
        (
            fresnel_surface(
                "focal_point = [0, 0, 0], lens_surface_f_min = 1.5, lens_surface_f_max = 2",
            ),
            vec![":3:10:", "no lens section"],
        ),
        (
            fresnel_surface("focal_point = [0, 0, 0], lens_surface_f_max = 0.9"),
            vec![":3:10:", "give lens_surface_f_min and lens_surface_f_max"],
        ),
        (
            fresnel_surface("focal_point = [0, 0, 0], number_of_lens_sections = 100000"),
            vec![":3:10:", "at most 10000"],
        ),
        (
            format!(
                "{}show_edges = true\n",
                fresnel_surface("focal_point = [0, 0, 0], number_of_lens_sections = 3")
            ),
            vec![":3:10:", "no edges"],
        ),
        (
            device(
                "type = \"triangular-thick-lens\", focal_length = 0.9, principal_point = [0, 0, 4], \
                 corner1 = [1, 0, 4], corner2 = [-0.5, 0.8, 4], corner3 = [-0.5, -0.8, 4], \
                 refractive_index = 1.5, thickness_at_thinnest_point = 0.01",
            ),
            vec![":3:10:", "less than the aperture radius 1"],
        ),
        (
            device(
                "type = \"triangular-thick-lens\", focal_length = 2, principal_point = [0, 0, 4], \
                 corner1 = [1, 0, 4], corner2 = [2, 0, 4], corner3 = [3, 0, 4], \
                 refractive_index = 1.5, thickness_at_thinnest_point = 0.01",
            ),
            vec![":3:10:", "collinear"],
        ),
        (
            device(
                "type = \"refractive-lens-surfaces\", centre = [0, 0, 5], \
                 normalised_optical_axis_direction = [0, 0, 1], focal_length = 0.1, \
                 refractive_index = 1.5, centre_thickness = 0.2",
            ),
            vec![":3:10:", "no symmetric lens"],
        ),
    ];
    let dir = TempDir::new().unwrap();
    for (text, needles) in cases {
        let path = write(&dir, "bad.toml", &text);
        timbre(dir.path(), &["check", path_str(&path)]).assert_bad_input(&needles);
    }
}
