//! Issue 41 item 1, Dr TIM's curved-space simulations, checked against facts worked out here:
//!
//! * a negative-space wedge (two sheets that rotate ray directions by 180° about their normals,
//!   ω apart) sends a ray that crosses both sheets on along the line it came on turned by 2ω
//!   about the star's axis: a rotation by π about n̂ is minus the mirror in the sheet, and two
//!   mirrors ω apart make a rotation by 2ω;
//! * a star of N ray-rotation sheets rotating by 2π/N about its axis closes the regular N-gon
//!   whose vertices lie on the sheets: the exterior angle of the polygon is the rotation;
//! * Dr TIM's defaults, names and refusals.

mod common;

use std::f64::consts::TAU;

use glam::DVec3;
use timbre::trajectories::{self, Trajectory};

use common::cli::{location, path_str, timbre, write};

/// `d` rotated by `angle` (radians) about the unit `axis`, right-handed (Rodrigues).
fn rotate(d: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    d * angle.cos() + axis.cross(d) * angle.sin() + axis * axis.dot(d) * (1.0 - angle.cos())
}

fn trace(text: &str) -> Vec<Trajectory> {
    let description = common::images::parse(text);
    trajectories::trace(common::rays::device(), &description).expect("trace")
}

/// Distance of `p` from the line through `a` along the unit `d`.
fn line_distance(p: DVec3, a: DVec3, d: DVec3) -> f64 {
    (p - a).reject_from_normalized(d).length()
}

/// The unit radial direction at azimuth φ of a star about +y whose azimuth 0 is +x: it turns
/// from +x towards ŵ × x̂ = −z.
fn radial(phi: f64) -> DVec3 {
    DVec3::new(phi.cos(), 0.0, -phi.sin())
}

#[test]
fn a_negative_space_wedge_turns_a_ray_by_twice_its_angle_about_the_axis() {
    // 4 wedges cutting out 120°: each wedge ω = 15° wide, turning rays by 30°.
    let (n, deficit) = (4, 120f64);
    let turn = (deficit / n as f64).to_radians();
    for (start_azimuth, height, dy) in [(-30f64, 0.0, 0.0), (-40.0, 0.1, 0.05)] {
        let start = 1.2 * radial(start_azimuth.to_radians()) + DVec3::new(0.0, height, 0.0);
        let direction = DVec3::new(0.0, dy, -1.0).normalize();
        let text = format!(
            "studio = \"none\"\n[[device]]\nlenses = {{ type = \"negative-space-wedge-star\", \
             deficit_angle_deg = {deficit}, number_of_negative_space_wedges = {n}, \
             centre = [0, 0, 0], axis_direction = [0, 1, 0], \
             direction_of_centre_of_wedge0 = [1, 0, 0], star_radius = 2, star_length = 1 }}\n\
             [[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\n",
            start.x, start.y, start.z, direction.x, direction.y, direction.z
        );
        let traced = trace(&text);
        let t = &traced[0];
        assert!(t.points.len() >= 3, "{:?}", t.points);
        // The first two points lie on wedge 0's sheets, at azimuths ∓7.5°.
        for (k, azimuth) in [(1, -7.5f64), (2, 7.5)] {
            let p = t.points[k].position;
            let normal = DVec3::Y.cross(radial(azimuth.to_radians()));
            assert!(p.dot(normal).abs() < 1e-9, "point {k}: {p}");
        }
        // After the second sheet: the incoming line turned by 2ω about the axis.
        let p = t.points[2].position;
        let after = match t.points.get(3) {
            Some(next) => (next.position - p).normalize(),
            None => t.direction,
        };
        let expected = rotate(direction, DVec3::Y, turn);
        assert!((after - expected).length() < 1e-9, "{after} != {expected}");
        let back = rotate(p, DVec3::Y, -turn);
        assert!(
            line_distance(back, start, direction) < 1e-9,
            "{p} turned back by {turn} is {} off the incoming line",
            line_distance(back, start, direction)
        );
    }
}

#[test]
fn a_ray_rotation_sheet_star_closes_the_regular_polygon_of_its_angle() {
    let (n, radius) = (6u32, 1.5);
    let vertex = |i: u32| radius * radial(TAU * i as f64 / n as f64);
    // From the middle of the edge from the last vertex to the first, towards the first.
    let start = 0.5 * (vertex(n - 1) + vertex(0));
    let direction = (vertex(0) - vertex(n - 1)).normalize();
    let text = format!(
        "studio = \"none\"\n[[device]]\nlenses = {{ type = \"ray-rotation-sheet-star\", \
         number_of_ray_rotation_sheets = {n}, rotation_angle_deg = {}, \
         centre = [0, 0, 0], intersection_direction = [0, 1, 0], \
         point_on_ray_rotation_sheet1 = [1, 0, 0], star_radius = 2, star_length = 1 }}\n\
         [[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 13\n",
        360.0 / n as f64,
        start.x,
        start.y,
        start.z,
        direction.x,
        direction.y,
        direction.z
    );
    let traced = trace(&text);
    let points = &traced[0].points;
    assert_eq!(points.len(), 14, "the start and 13 sheets");
    for (k, p) in points.iter().enumerate().skip(1) {
        let expected = vertex((k as u32 - 1) % n);
        assert!(
            (p.position - expected).length() < 1e-9,
            "point {k}: {} != {expected}",
            p.position
        );
    }
    // Turned the other way (−60°), the ray leaves the polygon at the first sheet.
    let traced = trace(&text.replace(
        &format!("rotation_angle_deg = {}", 360.0 / n as f64),
        &format!("rotation_angle_deg = {}", -360.0 / n as f64),
    ));
    assert!(traced[0].points.len() < 4, "{:?}", traced[0].points);
}

#[test]
fn the_stars_have_dr_tims_defaults_and_named_parts() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"r\"\nlenses = { type = \"ray-rotation-sheet-star\" }\n\
         [[device]]\nname = \"w\"\nshow_edges = true\n\
         lenses = { type = \"negative-space-wedge-star\", number_of_shown_negative_space_wedges = 1, shown_negative_space_wedges_start_index = 99 }\n",
    );
    let names: Vec<&str> = d.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "r/ray-rotation sheet 1",
            "r/ray-rotation sheet 2",
            "r/ray-rotation sheet 3",
            "r/ray-rotation sheet 4",
            "r/ray-rotation sheet 5",
            "w/wedge 100 sheet 1",
            "w/top edge wedge 100 sheet 1",
            "w/outer edge wedge 100 sheet 1",
            "w/bottom edge wedge 100 sheet 1",
            "w/wedge 100 sheet 2",
            "w/top edge wedge 100 sheet 2",
            "w/outer edge wedge 100 sheet 2",
            "w/bottom edge wedge 100 sheet 2",
            "w/axial edge",
        ]
    );
    // Dr TIM's default ray-rotation-sheet star: 5 sheets about (0, 0, 10) along y, the first
    // towards +x, 2 long radially and 1 along the axis. Its 100 wedges cut out 340°: wedge 100
    // is centred 3.6° before wedge 1 (at +x), and its sheets are 1.7° apart.
    let corners = |o: &timbre::scene::SceneObject| match &o.shape {
        timbre::geometry::Shape::Parallelogram(p) => (p.corner(), p.span_u(), p.span_v()),
        other => panic!("{other:?}"),
    };
    let (corner, axial, outer) = corners(&d.objects[0]);
    assert!((corner - DVec3::new(0.0, -0.5, 10.0)).length() < 1e-12);
    assert!((axial - DVec3::Y).length() < 1e-12);
    assert!((outer - DVec3::new(2.0, 0.0, 0.0)).length() < 1e-12);
    for (k, azimuth) in [(5, -3.6 - 0.85f64), (9, -3.6 + 0.85)] {
        let (_, _, outer) = corners(&d.objects[k]);
        let expected = 2.0 * radial(azimuth.to_radians());
        assert!((outer - expected).length() < 1e-12, "{outer} != {expected}");
    }
}

#[test]
fn bad_star_parameters_are_refused_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    for (lenses, needles) in [
        (
            "{ type = \"negative-space-wedge-star\", deficit_angle_deg = 400 }",
            &["deficit_angle_deg", "between 0 and 360"][..],
        ),
        (
            "{ type = \"negative-space-wedge-star\", direction_of_centre_of_wedge0 = [0, 2, 0] }",
            &["direction_of_centre_of_wedge0", "axis"],
        ),
        (
            "{ type = \"ray-rotation-sheet-star\", number_of_ray_rotation_sheets = 0 }",
            &["number_of_ray_rotation_sheets = 0"],
        ),
        (
            "{ type = \"ray-rotation-sheet-star\", point_on_ray_rotation_sheet1 = [0, 5, 10] }",
            &["point_on_ray_rotation_sheet1", "on the star's axis"],
        ),
    ] {
        let text = format!("studio = \"none\"\n\n[[device]]\nname = \"s\"\nlenses = {lenses}\n");
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}
