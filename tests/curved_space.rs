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
    // The star turned by 90° about x, and the ray with it: the same polygon, turned (the
    // rotation axis, given in the device's coordinates, turns with it).
    let turned = |v: DVec3| DVec3::new(v.x, -v.z, v.y);
    let (s, d) = (turned(start), turned(direction));
    let moved = text
        .replace(
            "[[device]]\n",
            "[[device]]\ntransform = { rotate = { axis = [1, 0, 0], angle_deg = 90 } }\n",
        )
        .replace(
            &format!("start = [{}, {}, {}]", start.x, start.y, start.z),
            &format!("start = [{}, {}, {}]", s.x, s.y, s.z),
        )
        .replace(
            &format!(
                "direction = [{}, {}, {}]",
                direction.x, direction.y, direction.z
            ),
            &format!("direction = [{}, {}, {}]", d.x, d.y, d.z),
        );
    let traced = trace(&moved);
    assert_eq!(traced[0].points.len(), 14);
    for (k, p) in traced[0].points.iter().enumerate().skip(1) {
        let expected = turned(vertex((k as u32 - 1) % n));
        assert!(
            (p.position - expected).length() < 1e-9,
            "turned, point {k}: {} != {expected}",
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
    // Dr TIM's ray-rotation sheets throw shadows, its negative-space wedges' sheets do not.
    for o in &d.objects {
        let sheet =
            o.name.starts_with("r/") || o.name.ends_with("sheet 1") || o.name.ends_with("sheet 2");
        if sheet && !o.name.contains("edge") {
            assert_eq!(o.shadow_throwing, o.name.starts_with("r/"), "{}", o.name);
        }
    }
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

// ---------------------------------------------------------------------------------------------
// The Chen–Belin black hole: n = (jR + r)³ / (r² (r − R)) inside the simulation sphere. For a
// spherically symmetric index the angular momentum L = n r sin θ of a ray is conserved (also
// across the sphere's surface, by Snell's law), and a ray turns where n r = L. With j = 3/5,
// n r is least at the photon sphere r = 3R, where it is (3.6R)³/(9R² · 2R) · 3R = 7.776 R: a ray
// from far away with impact parameter b below 7.776 R never turns and falls in (the black
// hole's shadow), one above turns at the larger root of n r = b and escapes.
// ---------------------------------------------------------------------------------------------

/// Traces rays along +z with impact parameters `b` (along x) past a black hole of horizon radius
/// `horizon` (j = 3/5) at the origin, in a simulation sphere of radius 1.
fn past_black_hole(horizon: f64, bs: &[f64]) -> Vec<Trajectory> {
    let mut text = format!(
        "studio = \"none\"\n[[device]]\nlenses = {{ type = \"chen-belin-black-hole\", \
         centre = [0, 0, 0], horizon_radius = {horizon}, j_parameter = 0.6, \
         simulation_sphere_radius = 1, simulation_sphere_surface_transmission_coefficient = 1 }}\n"
    );
    for b in bs {
        text += &format!("[[ray_trajectory]]\nstart = [{b}, 0, -3]\ndirection = [0, 0, 1]\n");
    }
    trace(&text)
}

#[test]
fn the_black_holes_shadow_is_its_photon_spheres_critical_impact_parameter() {
    let horizon = 0.05;
    let critical = 7.776 * horizon;
    let traced = past_black_hole(
        horizon,
        &[
            0.0,
            0.5 * critical,
            critical * (1.0 - 1e-4),
            critical * (1.0 + 1e-4),
            1.5 * critical,
        ],
    );
    let ends: Vec<bool> = traced
        .iter()
        .map(|t| matches!(t.end, trajectories::End::Escaped))
        .collect();
    assert_eq!(ends, [false, false, false, true, true], "{traced:#?}");
}

#[test]
fn an_escaping_ray_comes_closest_where_n_r_equals_its_impact_parameter() {
    let (horizon, j) = (0.05f64, 0.6);
    let n = |r: f64| (j * horizon + r).powi(3) / (r * r * (r - horizon));
    for b in [0.45, 0.6, 0.8] {
        // The turning point: the root of n(r) r = b beyond the photon sphere (bisection; n r
        // rises from 7.776 R there).
        let (mut lo, mut hi) = (3.0 * horizon, 1.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if n(mid) * mid < b { lo = mid } else { hi = mid }
        }
        let traced = past_black_hole(horizon, &[b]);
        let closest = traced[0]
            .points
            .iter()
            .map(|p| p.position.length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            (closest - lo).abs() < 2e-3 * lo,
            "b = {b}: closest {closest}, turning point {lo}"
        );
        assert!(matches!(traced[0].end, trajectories::End::Escaped));
    }
}

/// Dr TIM's shell simulation of the black hole (`SPHERICAL_SHELLS_CONSTANT_N`): between
/// spheres about the centre the index is constant, so a ray is straight there, |r × d̂| fixed,
/// and at each sphere Snell's law keeps n |r × d̂| (n sin θ at one r). So n |r × d̂| along the
/// whole path is the impact parameter b, with n the index of the shell a segment runs in: the
/// profile at the middle of the shell, worked out here from the shell's number. A ray well
/// inside the smooth profile's shadow (b = 7.776 R / 3) falls onto the horizon.
#[test]
fn in_the_shell_simulation_n_r_sin_theta_stays_the_impact_parameter() {
    let (horizon, j, layers) = (0.05f64, 0.6, 40u32);
    let step = (1.0 - horizon) / (layers - 1) as f64;
    let n = |r: f64| (j * horizon + r).powi(3) / (r * r * (r - horizon));
    let shell = |r: f64| match r < 1.0 {
        true => n(horizon + ((r - horizon) / step).ceil().max(1.0) * step - 0.5 * step),
        false => 1.0,
    };
    let bs = [0.13f64, 0.45, 0.8];
    let mut text = format!(
        "studio = \"none\"\n[[device]]\nlenses = {{ type = \"chen-belin-black-hole\", \
         centre = [0, 0, 0], horizon_radius = {horizon}, j_parameter = {j}, \
         simulation_type = \"spherical-shells-constant-n\", number_of_spherical_layers = {layers} }}\n"
    );
    for b in bs {
        text += &format!(
            "[[ray_trajectory]]\nstart = [{b}, 0, -3]\ndirection = [0, 0, 1]\nmax_interactions = 10000\n"
        );
    }
    let traced = trace(&text);
    for (t, b) in traced.iter().zip(bs) {
        let mut crossings = 0;
        for w in t.points.windows(2) {
            let (p, q) = (w[0].position, w[1].position);
            let d = (q - p).normalize();
            let middle = (0.5 * (p + q)).length();
            let l = shell(middle) * p.cross(d).length();
            assert!((l - b).abs() < 1e-9, "b = {b}: n r sin θ = {l} at {p}");
            crossings += 1;
        }
        assert!(crossings > 10, "b = {b}: {} points", t.points.len());
    }
    // The ray with b = 0.13 falls in; the others come out again.
    assert_eq!(traced[0].end, trajectories::End::Absorbed);
    let objects = common::images::parse(&text).objects;
    let on = traced[0]
        .points
        .last()
        .unwrap()
        .object
        .expect("on an object");
    assert!(
        objects[on].name.ends_with("/horizon"),
        "{}",
        objects[on].name
    );
    assert!(
        traced[1..]
            .iter()
            .all(|t| t.end == trajectories::End::Escaped)
    );
}

#[test]
fn bad_shell_simulations_are_refused_where_they_are_given() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, needles) in [
        (
            "number_of_spherical_layers = 10",
            &["belongs to simulation_type"][..],
        ),
        (
            "simulation_type = \"spherical-shells-constant-n\", number_of_spherical_layers = 1",
            &["from 2 to"][..],
        ),
        (
            "simulation_type = \"shells\"",
            &["smooth-n", "spherical-shells-constant-n"][..],
        ),
        (
            "simulation_type = \"spherical-shells-constant-n\", horizon_radius = 2",
            &["larger than the horizon"][..],
        ),
    ] {
        let text = format!(
            "studio = \"none\"\n\n[[device]]\nname = \"b\"\nlenses = {{ type = \"chen-belin-black-hole\", {keys} }}\n"
        );
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
}

// ---------------------------------------------------------------------------------------------
// Space-cancelling wedges and the net of a hypercube. A space-cancelling wedge of apex angle ν
// removes the wedge of space between its legs: a ray that crosses it leaves on the line it came
// on turned by ν about the apex edge (position and direction), whether the legs teleport to each
// other or N negative-space wedges of δ = ν/(2N) each turn it by 2δ; Dr TIM's three-lens wedges
// image every point Q (through all three lenses) onto Q turned by ν. The net of a hypercube is
// glued into the tesseract's surface, on which a straight line along an edge of the tesseract's
// grid closes on itself after four cubes.

/// The scene text of the wedge `lenses` (apex edge along z through the origin, bisector
/// (1, 1, 0), so the legs of a 90° wedge lie along +x and +y) with one trajectory from `start`
/// along `direction`.
fn wedge_scene(lenses: &str, start: DVec3, direction: DVec3) -> String {
    format!(
        "studio = \"none\"\n[[device]]\nname = \"w\"\nlenses = {{ type = \"space-cancelling-wedge\", \
         apex_edge_centre = [0, 0, 0], apex_edge_direction = [0, 0, 1], \
         bisector_direction = [1, 1, 0], {lenses} }}\n\
         [[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 50\n",
        start.x, start.y, start.z, direction.x, direction.y, direction.z
    )
}

#[test]
fn a_space_cancelling_wedge_turns_a_crossing_ray_by_its_apex_angle() {
    // From below the x leg (y < 0), upwards: crossing the wedge turns the line by +ν about +z.
    for apex in [90f64, 60.0, 150.0] {
        let nu = apex.to_radians();
        for gluing in [
            "\"perfect\"".to_string(),
            "\"negative-space-wedges\", number_of_negative_space_wedges = 1".into(),
            "\"negative-space-wedges\", number_of_negative_space_wedges = 3".into(),
            "\"negative-space-wedges-symmetric\", number_of_negative_space_wedges = 2".into(),
            "\"negative-space-wedges-with-containment-mirrors\", number_of_negative_space_wedges = 4"
                .into(),
        ] {
            // The x leg is at −ν/2 from the bisector's side: rotate the set-up so that the leg
            // the ray crosses first lies along (cos(45° − ν/2), sin(45° − ν/2)).
            let leg = 45f64.to_radians() - nu / 2.0;
            let start = rotate(DVec3::new(0.45, -0.5, 0.1), DVec3::Z, leg);
            let direction = rotate(DVec3::new(0.1, 1.0, 0.05).normalize(), DVec3::Z, leg);
            let lenses = format!(
                "apex_angle_deg = {apex}, leg_length = 30, apex_edge_length = 4, gluing_type = {gluing}"
            );
            let traced = trace(&wedge_scene(&lenses, start, direction));
            let t = &traced[0];
            let label = format!("ν = {apex}°, {gluing}");
            assert!(t.points.len() >= 3, "{label}: {:?}", t.points);
            let last = t.points.last().unwrap().position;
            let expected = rotate(direction, DVec3::Z, nu);
            assert!(
                (t.direction - expected).length() < 1e-9,
                "{label}: leaves along {} != {expected}",
                t.direction
            );
            let before = t.points[t.points.len() - 2].position;
            let back = rotate(before, DVec3::Z, -nu);
            assert!(
                line_distance(back, start, direction) < 1e-9,
                "{label}: {before} turned back is {} off the incoming line (last {last})",
                line_distance(back, start, direction)
            );
        }
    }
}

#[test]
fn three_lens_space_cancelling_wedges_image_points_turned_by_the_apex_angle() {
    for (gluing, q) in [
        ("lenses-completely-symmetric", DVec3::new(1.5, -1.0, 0.1)),
        ("lenses-quite-symmetric", DVec3::new(3.0, -0.05, 0.1)),
    ] {
        let image = rotate(q, DVec3::Z, 90f64.to_radians());
        for direction in [
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.01, 1.0, 0.02),
            DVec3::new(-0.01, 1.0, -0.01),
        ] {
            let lenses =
                format!("gluing_type = \"{gluing}\", leg_length = 100, apex_edge_length = 100");
            let traced = trace(&wedge_scene(&lenses, q, direction.normalize()));
            let t = &traced[0];
            // Through L3, L2 and L1, then on to beyond the scene.
            assert!(
                t.points.len() == 5 && t.points[1..4].iter().all(|p| p.object.is_some()),
                "{gluing}: {:?}",
                t.points
            );
            let exit = t.points[3].position;
            assert!(
                line_distance(image, exit, t.direction) < 1e-8 * (1.0 + image.length()),
                "{gluing}: from {q} along {direction}, the ray leaves {} off {image}",
                line_distance(image, exit, t.direction)
            );
        }
    }
}

/// A straight line in the tesseract's surface closes after four cubes (length 4s): round the
/// ring of four outer cubes about an inner-cube edge's direction, and through an outer cube,
/// the eighth cube and the opposite outer cube. The net is skew (right (1, 1, 0), up made
/// perpendicular to it from (−1, 1, 0.3)), of side 0.7, about (0.3, −0.2, 5).
#[test]
fn the_net_of_a_hypercube_closes_straight_lines_after_four_cubes() {
    let (centre, s) = (DVec3::new(0.3, -0.2, 5.0), 0.7);
    let right = DVec3::new(1.0, 1.0, 0.0).normalize();
    let up = DVec3::new(-1.0, 1.0, 0.3)
        .reject_from_normalized(right)
        .normalize();
    let front = up.cross(right);
    for (start, direction) in [
        // Through the right outer cube, the eighth cube and the left outer cube.
        (centre + 0.1 * up + 0.2 * front, right),
        // Round the ring of the right, top, left and bottom outer cubes.
        (centre + s * right + 0.2 * front, up),
    ] {
        let text = format!(
            "studio = \"none\"\n[[device]]\nname = \"net\"\nlenses = {{ type = \"net-of-hypercube\", \
                 centre = [{}, {}, {}], right_direction = [1, 1, 0], up_direction = [-1, 1, 0.3], \
                 side_length = {s}, gluing_type = \"perfect\" }}\n\
                 [[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 40\n",
            centre.x,
            centre.y,
            centre.z,
            start.x,
            start.y,
            start.z,
            direction.x,
            direction.y,
            direction.z
        );
        let traced = trace(&text);
        let t = &traced[0];
        // The ray comes back onto its start line, in its start direction, after passing
        // wedges, having gone exactly 4s.
        let mut travelled = 0.0;
        let mut closed = false;
        for (k, pair) in t.points.windows(2).enumerate() {
            if pair[1].arrival == trajectories::Arrival::Teleported {
                continue;
            }
            let step = pair[1].position - pair[0].position;
            let along = step.normalize();
            let back_on_line = k > 1
                && (along - direction).length() < 1e-9
                && line_distance(pair[0].position, start, direction) < 1e-9;
            if back_on_line && (start - pair[0].position).dot(direction) >= 0.0 {
                let total = travelled + (start - pair[0].position).length();
                assert!((total - 4.0 * s).abs() < 1e-9, "closed after {total}");
                closed = true;
                break;
            }
            travelled += step.length();
        }
        assert!(closed, "path {:?}", t.points);
    }
}

#[test]
fn the_wedge_and_the_net_have_dr_tims_defaults_and_refuse_bad_parameters() {
    let d = common::images::parse(
        "studio = \"none\"\n[[device]]\nname = \"w\"\nshow_edges = true\nlenses = { type = \"space-cancelling-wedge\" }\n\
         [[device]]\nname = \"n\"\nlenses = { type = \"net-of-hypercube\" }\n",
    );
    let names: Vec<&str> = d
        .objects
        .iter()
        .map(|o| o.name.as_str())
        .filter(|n| n.starts_with("w/"))
        .collect();
    // Dr TIM's default: one negative-space wedge of 45° (two 180° ray-rotation sheets and a
    // black base) cancelling a 90° wedge about (0, 0, 10) along y, bisector +x, legs 1 long.
    assert_eq!(
        names,
        [
            "w/surface 0",
            "w/top edge of surface 0",
            "w/outer edge of surface 0",
            "w/bottom edge of surface 0",
            "w/surface 1",
            "w/top edge of surface 1",
            "w/outer edge of surface 1",
            "w/bottom edge of surface 1",
            "w/base surface of negative-space wedge 0",
            "w/top edge of base surface of negative-space wedge 0",
            "w/bottom edge of base surface of negative-space wedge 0",
            "w/apex edge",
        ]
    );
    let sheet = |name: &str| match &d.objects.iter().find(|o| o.name == name).unwrap().shape {
        timbre::geometry::Shape::Parallelogram(p) => (p.corner(), p.span_u(), p.span_v()),
        other => panic!("{other:?}"),
    };
    // Surface 0 at −45° from +x about y (towards ĉ = x̂ × ŷ = +z, negated), surface 1 on the
    // bisector.
    let (corner, along, out) = sheet("w/surface 0");
    assert!(
        (corner - DVec3::new(0.0, -0.5, 10.0)).length() < 1e-12,
        "{corner}"
    );
    assert!((along - DVec3::Y).length() < 1e-12);
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!((out - DVec3::new(h, 0.0, -h)).length() < 1e-12, "{out}");
    assert!((sheet("w/surface 1").2 - DVec3::X).length() < 1e-12);
    // The default net: 24 perfect wedges of two teleporting legs each, no edges or faces.
    let net: Vec<&str> = d
        .objects
        .iter()
        .map(|o| o.name.as_str())
        .filter(|n| n.starts_with("n/"))
        .collect();
    assert_eq!(net.len(), 48, "{net:?}");
    assert!(net.iter().all(|n| n.contains("teleporting surface")));

    let dir = tempfile::tempdir().unwrap();
    for (lenses, needles) in [
        (
            "{ type = \"space-cancelling-wedge\", apex_angle_deg = 400 }",
            &["apex angle", "360"][..],
        ),
        (
            "{ type = \"space-cancelling-wedge\", bisector_direction = [0, 3, 0] }",
            &["bisector_direction", "along apex_edge_direction"],
        ),
        (
            "{ type = \"space-cancelling-wedge\", gluing_type = \"mirror-approximation\" }",
            &["mirror-approximation", "perfect"],
        ),
        (
            "{ type = \"net-of-hypercube\", gluing_type = \"negative-space-wedges-with-containment-mirrors\" }",
            &["number_of_negative_space_wedges = 2 or more"],
        ),
        (
            "{ type = \"space-cancelling-wedge\", apex_angle_deg = 180, gluing_type = \"negative-space-wedges-with-containment-mirrors\" }",
            &["containment mirrors", "never meet"],
        ),
        (
            "{ type = \"space-cancelling-wedge\", apex_angle_deg = 0.3, gluing_type = \"lenses-quite-symmetric\" }",
            &["above 0.4°"],
        ),
        (
            "{ type = \"space-cancelling-wedge\", apex_angle_deg = 360, gluing_type = \"lenses-completely-symmetric\" }",
            &["infinite", "below 360°"],
        ),
        (
            "{ type = \"net-of-hypercube\", up_direction = [2, 0, 0] }",
            &["up_direction", "along right_direction"],
        ),
        (
            "{ type = \"net-of-symmetric-four-simplex\", gluing_type = \"negative-space-wedges-with-containment-mirrors\" }",
            &["containment-mirrors", "not built"],
        ),
        (
            "{ type = \"net-of-symmetric-four-simplex\", gluing_type = \"lenses-quite-symmetric\" }",
            &["gluing_type = \"lenses-quite-symmetric\"", "perfect"],
        ),
        (
            "{ type = \"net-of-symmetric-four-simplex\", normal_to_enclosing_cube_3 = [1, 1, 0] }",
            &["perpendicular"],
        ),
    ] {
        let text = format!("studio = \"none\"\n\n[[device]]\nname = \"s\"\nlenses = {lenses}\n");
        let path = write(dir.path(), "bad.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
    }
    // A device whose surfaces teleport to each other cannot be arrayed.
    let text = "studio = \"none\"\n\n[[device]]\nname = \"s\"\narray = { vectors = [[5, 0, 0]], counts = [2] }\n\
                lenses = { type = \"space-cancelling-wedge\", gluing_type = \"perfect\" }\n";
    let path = write(dir.path(), "array.toml", text);
    let run = timbre(dir.path(), &["check", path_str(&path)]);
    run.assert_bad_input(&["teleports to another part of its device", "array"]);
    assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
}

/// The shape of the object `name` of `d`, which must be a convex polygon: its vertices.
fn polygon(d: &timbre::scene::SceneDescription, name: &str) -> Vec<DVec3> {
    match &d
        .objects
        .iter()
        .find(|o| o.name == name)
        .unwrap_or_else(|| panic!("no {name}"))
        .shape
    {
        timbre::geometry::Shape::ConvexPolygon(p) => p.vertices().to_vec(),
        other => panic!("{name}: {other:?}"),
    }
}

/// The net of a symmetric 4-simplex. With outer tetrahedra of the inner one's height it is the
/// net of the regular 4-simplex: every edge is as long as the inner tetrahedron's, and round
/// each inner edge three regular tetrahedra (dihedral angle arccos ⅓ each) leave
/// 360° − 3 arccos ⅓ = 148.4° for the wedge, whose legs are the two outer tetrahedra's facing
/// faces. With half that height the eight vertices are the corners of the cube the inner
/// tetrahedron is inscribed in, and the wedges are flat (180°). A ray through a perfect wedge's
/// leg leaves the other leg turned by the wedge's angle about the edge.
#[test]
fn the_net_of_a_symmetric_4_simplex_is_regular_or_fills_a_cube() {
    let net = |factor: f64, gluing: &str| {
        common::images::parse(&format!(
            "studio = \"none\"\n[[device]]\nname = \"n\"\nshow_edges = true\n\
             lenses = {{ type = \"net-of-symmetric-four-simplex\", centroid = [0, 0, 0], \
             edge_length = 1.3, outer_tetrahedron_height_factor = {factor}, gluing_type = \"{gluing}\" }}\n"
        ))
    };
    let e = 1.3;
    let h = 0.5 * e / std::f64::consts::SQRT_2;
    let vertex = |d: &timbre::scene::SceneDescription, k: usize| match &d
        .objects
        .iter()
        .find(|o| o.name == format!("n/vertex {k}"))
        .unwrap()
        .shape
    {
        timbre::geometry::Shape::Sphere(s) => s.centre(),
        other => panic!("{other:?}"),
    };
    let angle = |a: DVec3, b: DVec3| a.angle_between(b);
    // The regular 4-simplex.
    let d = net(1.0, "perfect");
    let v: Vec<DVec3> = (0..8).map(|k| vertex(&d, k)).collect();
    let edges: Vec<(usize, usize)> = (0..4)
        .flat_map(|i| (i + 1..4).map(move |j| (i, j)))
        .chain((0..4).flat_map(|k| (0..4).filter(move |&f| f != k).map(move |f| (f, 4 + k))))
        .collect();
    assert_eq!(edges.len(), 18);
    for &(a, b) in &edges {
        assert!(((v[a] - v[b]).length() - e).abs() < 1e-12, "edge {a}-{b}");
    }
    let nu = std::f64::consts::TAU - 3.0 * (1.0f64 / 3.0).acos();
    for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (2, 3), (3, 1)] {
        let leg = |k: u32| {
            polygon(
                &d,
                &format!("n/wedge at edge {i}-{j}/sub-wedge 0 leg surface {k}"),
            )
        };
        let (l1, l2) = (leg(1), leg(2));
        let mid = 0.5 * (v[i] + v[j]);
        assert!(
            (angle(l1[2] - mid, l2[2] - mid) - nu).abs() < 1e-12,
            "edge {i}-{j}"
        );
        // Each leg's far vertex is an outer tetrahedron's fourth vertex.
        for l in [l1[2], l2[2]] {
            assert!(
                (4..8).any(|k| (v[k] - l).length() < 1e-12),
                "edge {i}-{j}: {l}"
            );
        }
        // A ray from the outer tetrahedron onto leg 1 leaves leg 2 turned by ν.
        let axis = (l1[2] - mid).cross(l2[2] - mid).normalize();
        let inwards = (l1[2] - mid).cross(v[j] - v[i]).normalize();
        let outside = if inwards.dot(l2[2] - mid) > 0.0 {
            -inwards
        } else {
            inwards
        };
        let hit = mid + 0.4 * (l1[2] - mid) + 0.1 * (v[j] - v[i]);
        let start = hit + 0.05 * outside;
        let direction = (-outside + 0.2 * (v[j] - v[i])).normalize();
        // One sub-wedge, or two (which a perfect wedge makes as one).
        for n in [1, 2] {
            let text = format!(
                "studio = \"none\"\n[[device]]\nname = \"n\"\nlenses = {{ type = \"net-of-symmetric-four-simplex\", \
                 centroid = [0, 0, 0], edge_length = 1.3, number_of_negative_space_wedges = {n} }}\n\
                 [[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 3\n",
                start.x, start.y, start.z, direction.x, direction.y, direction.z
            );
            let traced = trace(&text);
            let t = &traced[0];
            assert_eq!(
                t.points[2].arrival,
                trajectories::Arrival::Teleported,
                "{:?}",
                t.points
            );
            let arrival = t.points[1].position;
            let after = (t.points[3].position - t.points[2].position).normalize();
            let expected = rotate(direction, axis, nu);
            assert!(
                (after - expected).length() < 1e-9,
                "edge {i}-{j}: {after} != {expected}"
            );
            let expected_exit = mid + rotate(arrival - mid, axis, nu);
            assert!(
                (t.points[2].position - expected_exit).length() < 1e-9,
                "edge {i}-{j}"
            );
        }
    }
    // Half-height outer tetrahedra fill the cube; the wedges are flat.
    let d = net(0.5, "negative-space-wedges");
    for k in 0..8 {
        let c = vertex(&d, k);
        assert!(
            [c.x, c.y, c.z].iter().all(|x| (x.abs() - h).abs() < 1e-12),
            "vertex {k} = {c} is no corner of the cube of half side {h}"
        );
    }
    for (i, j) in [(0, 1), (2, 3)] {
        let prefix = format!("n/wedge at edge {i}-{j}/sub-wedge 0 ");
        let (leg, bisector) = (
            polygon(&d, &format!("{prefix}leg surface 1")),
            polygon(&d, &format!("{prefix}bisector surface")),
        );
        let mid = 0.5 * (v[i] + v[j]);
        // The negative-space wedge is half the flat wedge: 90° from leg 1 to the bisector.
        assert!(
            (angle(leg[2] - mid, bisector[2] - mid) - std::f64::consts::FRAC_PI_2).abs() < 1e-12
        );
    }
}

/// Dr TIM's `PositiveSpaceOnlyOrthographicCamera` (the orthographic camera's
/// `positive_space_only`): 4 wedges cutting out 240° leave gaps of 30° centred on 45°, 135°,
/// ...; the camera stretches the 90° sector of pixels about each gap's centre onto the gap. A
/// small sphere in the gap at azimuth 40° (2 from the axis) therefore appears, stretching the
/// angle, at azimuth 45° + (40° − 45°) × 90°/30° = 30°, 2 from the axis; stretching the width,
/// at the same distance along the gap's centre line and tan 45°/tan 15° times as far across it.
#[test]
fn the_positive_space_only_camera_stretches_the_gaps_between_wedges() {
    let (r, phi, centre) = (2.0f64, 40f64.to_radians(), 45f64.to_radians());
    // Camera right +z, up −x, looking down −y; azimuth from right towards up.
    let point = r * (phi.cos() * DVec3::Z - phi.sin() * DVec3::X);
    for (method, expected) in [
        ("stretch-angle", {
            let a = centre + (phi - centre) * 3.0;
            (r * a.cos(), r * a.sin())
        }),
        ("stretch-width", {
            let (along, across) = (r * (phi - centre).cos(), r * (phi - centre).sin());
            let across = across * 45f64.to_radians().tan() / 15f64.to_radians().tan();
            (
                along * centre.cos() - across * centre.sin(),
                along * centre.sin() + across * centre.cos(),
            )
        }),
    ] {
        let text = format!(
            "studio = \"none\"\n[render]\nwidth = 201\nheight = 201\n\
             [camera]\ntype = \"orthographic\"\nposition = [0, 100, 0]\nview_direction = [0, -1, 0]\n\
             up = [-1, 0, 0]\nview_width = 8\n\
             positive_space_only = {{ deficit_angle_deg = 240, number_of_negative_space_wedges = 4, \
             leftover_space_stretching_method = \"{method}\" }}\n\
             [[object]]\nshape = {{ type = \"sphere\", centre = [{}, {}, {}], radius = 0.05 }}\n\
             surface = {{ type = \"constant-colour\", colour = [1, 1, 1] }}\n",
            point.x, point.y, point.z
        );
        let image = common::images::render_text(&text);
        let (mut sum, mut n) = ((0.0, 0.0), 0.0);
        for y in 0..image.height {
            for x in 0..image.width {
                if image.pixels[(y * image.width + x) as usize].x > 0.5 {
                    sum = (sum.0 + x as f64, sum.1 + y as f64);
                    n += 1.0;
                }
            }
        }
        assert!(n > 0.0, "{method}: the sphere is not seen");
        let pitch = 8.0 / 200.0;
        let (x, y) = ((sum.0 / n - 100.0) * pitch, (100.0 - sum.1 / n) * pitch);
        assert!(
            (x - expected.0).abs() < 1.0 * pitch && (y - expected.1).abs() < 1.0 * pitch,
            "{method}: seen at ({x}, {y}), expected {expected:?}"
        );
    }
}

/// A device's teleporting surfaces move with its transform: a perfect wedge scaled by 2.5 (and
/// by −2.5, a mirror), turned by 37° about (1, 2, 3) and moved sends the transformed ray where
/// the transform takes the untransformed ray's exit, along the turned (or mirrored) direction.
/// A stretching transform is refused.
#[test]
fn a_transformed_perfect_wedge_teleports_as_the_transform_says() {
    let lenses = "{ type = \"space-cancelling-wedge\", gluing_type = \"perfect\", \
                  apex_edge_centre = [0, 0, 0], apex_edge_direction = [0, 0, 1], \
                  bisector_direction = [1, 1, 0] }";
    let scene = |transform: &str, start: DVec3, d: DVec3| {
        format!(
            "studio = \"none\"\n[[device]]\nname = \"w\"\n{transform}lenses = {lenses}\n\
             [[ray_trajectory]]\nstart = [{}, {}, {}]\ndirection = [{}, {}, {}]\nmax_interactions = 3\n",
            start.x, start.y, start.z, d.x, d.y, d.z
        )
    };
    let (start, direction) = (
        DVec3::new(0.45, -0.5, 0.1),
        DVec3::new(0.1, 1.0, 0.05).normalize(),
    );
    let plain = trace(&scene("", start, direction));
    let (exit, out) = (plain[0].points[2].position, plain[0].direction);
    assert_eq!(
        plain[0].points[2].arrival,
        trajectories::Arrival::Teleported
    );
    let axis = DVec3::new(1.0, 2.0, 3.0).normalize();
    let angle = 37f64.to_radians();
    let shift = DVec3::new(0.3, -1.0, 2.0);
    for k in [2.5, -2.5] {
        let map = |p: DVec3| rotate(k * p, axis, angle) + shift;
        let turn = |d: DVec3| rotate(k.signum() * d, axis, angle);
        let transform = format!(
            "transform = {{ scale = {k}, rotate = {{ axis = [1, 2, 3], angle_deg = 37 }}, translate = [0.3, -1, 2] }}\n"
        );
        let moved = trace(&scene(&transform, map(start), turn(direction)));
        let t = &moved[0];
        assert_eq!(
            t.points[2].arrival,
            trajectories::Arrival::Teleported,
            "{k}: {:?}",
            t.points
        );
        assert!(
            (t.points[2].position - map(exit)).length() < 1e-9,
            "scale {k}: exit {}",
            t.points[2].position
        );
        assert!(
            (t.direction - turn(out)).length() < 1e-9,
            "scale {k}: direction {}",
            t.direction
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "studio = \"none\"\n\n[[device]]\nname = \"w\"\ntransform = {{ scale = [1, 3, 1] }}\nlenses = {lenses}\n"
    );
    let path = write(dir.path(), "stretched.toml", text);
    let run = timbre(dir.path(), &["check", path_str(&path)]);
    run.assert_bad_input(&["teleporting surfaces", "not stretched"]);
    assert_eq!(location(&run.stderr, &path).0, 5, "{}", run.stderr);
}

/// `positive_space_only` belongs to the orthographic camera at rest with one eye, as Dr TIM's
/// camera is: elsewhere it is refused at the key that conflicts.
#[test]
fn positive_space_only_is_refused_where_it_cannot_work() {
    let dir = tempfile::tempdir().unwrap();
    let view =
        "positive_space_only = { deficit_angle_deg = 300, number_of_negative_space_wedges = 10 }";
    for (camera, needles, line) in [
        (
            format!("type = \"pinhole\"\n{view}"),
            &["positive_space_only", "orthographic"][..],
            5,
        ),
        (
            format!("type = \"equirectangular\"\n{view}"),
            &["equirectangular", "positive_space_only"],
            5,
        ),
        (
            format!("type = \"orthographic\"\nview_width = 4\n{view}\nbeta = [0, 0, 0.5]"),
            &["at rest", "beta"],
            7,
        ),
        (
            format!("type = \"orthographic\"\nview_width = 4\n{view}\nstereo = \"anaglyph\""),
            &["one eye", "stereo"],
            7,
        ),
    ] {
        let text = format!("studio = \"none\"\n\n[camera]\n{camera}\n");
        let path = write(dir.path(), "camera.toml", text);
        let run = timbre(dir.path(), &["check", path_str(&path)]);
        run.assert_bad_input(needles);
        assert_eq!(location(&run.stderr, &path).0, line, "{}", run.stderr);
    }
}

/// The nets' wedge edges are Dr TIM's 10⁻⁴ thinner than the net's edges, whatever radius those
/// are given.
#[test]
fn the_nets_wedge_edges_follow_the_nets_edge_radius() {
    for lenses in ["net-of-hypercube", "net-of-symmetric-four-simplex"] {
        let d = common::images::parse(&format!(
            "studio = \"none\"\n[[device]]\nname = \"n\"\nshow_edges = true\nedge_radius = 0.05\n\
             lenses = {{ type = \"{lenses}\", show_space_cancelling_wedge_edges = true }}\n"
        ));
        let radius = |wanted: &dyn Fn(&str) -> bool| {
            d.objects
                .iter()
                .filter(|o| wanted(&o.name))
                .find_map(|o| match &o.shape {
                    timbre::geometry::Shape::Cylinder(c) => Some(c.radius()),
                    _ => None,
                })
                .unwrap_or_else(|| panic!("{lenses}: no such edge"))
        };
        let wedge = radius(&|n| n.contains("wedge at"));
        let net = radius(&|n| !n.contains("wedge at"));
        assert!((net - 0.05).abs() < 1e-12, "{lenses}: {net}");
        assert!((wedge - (0.05 - 1e-4)).abs() < 1e-12, "{lenses}: {wedge}");
    }
}
