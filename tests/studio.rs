//! TIM's standard studio rendered at 160×120: pixel checks against the studio's geometry and
//! lighting rules, and a comparison with a committed reference image.
//!
//! Regenerate the reference (after an intended change, looked at by a person) with
//! `TIMBRE_UPDATE_REFERENCE=1 cargo test --release --test studio`.

use glam::DVec3;
use timbre::embree::Device;
use timbre::io::to_rgb8;
use timbre::render::Image;
use timbre::render::render;
use timbre::scene::RenderSettings;
use timbre::scene::Scene;
use timbre::scene::studio::Studio;

const W: u32 = 160;
const H: u32 = 120;

fn render_studio_with(shadows: bool) -> Image {
    let d = Studio::Lattice.description();
    let device = Device::new("").unwrap();
    let scene = Scene::build(&device, &d).unwrap();
    let settings = RenderSettings {
        width: W,
        height: H,
        shadows,
        ..RenderSettings::default()
    };
    render(&scene, &d.camera, &settings, &|_| {}).unwrap()
}

fn render_studio() -> Image {
    render_studio_with(true)
}

/// Direction through the centre of pixel (x, y), derived here from TIM's convention: detector
/// at distance 1, the 20° horizontal view angle spans the centres of the outermost columns.
fn pixel_direction(x: u32, y: u32) -> DVec3 {
    let pitch = 2.0 * 10f64.to_radians().tan() / (W - 1) as f64;
    DVec3::new(
        (x as f64 - (W - 1) as f64 / 2.0) * pitch,
        ((H - 1) as f64 / 2.0 - y as f64) * pitch,
        1.0,
    )
    .normalize()
}

/// Pixel whose centre sees the world point p (camera at the origin looking along +z).
fn project(p: DVec3) -> (u32, u32) {
    let pitch = 2.0 * 10f64.to_radians().tan() / (W - 1) as f64;
    let x = p.x / p.z / pitch + (W - 1) as f64 / 2.0;
    let y = (H - 1) as f64 / 2.0 - p.y / p.z / pitch;
    (x.round() as u32, y.round() as u32)
}

#[test]
fn sky_fills_the_top_rows_with_its_constant_colour() {
    let image = render_studio();
    // The lattice's top ends 1.02 above the camera at z = 10, i.e. below the top 10 rows.
    for y in 0..10 {
        for x in 0..W {
            assert_eq!(
                image.pixel(x, y),
                DVec3::new(0.5, 0.5, 1.0),
                "pixel ({x}, {y})"
            );
        }
    }
}

#[test]
fn lit_floor_tiles_alternate_between_the_two_expected_values() {
    let image = render_studio();
    let light = DVec3::new(100.0, 300.0, -500.0);
    let y = H - 1; // the bottom row sees the floor at z ≈ 7.6, in front of the lattice
    let mut seen = [0, 0];
    for x in 0..W {
        let d = pixel_direction(x, y);
        let t = -1.0001 / d.y;
        let p = t * d;
        let (fx, fz) = (p.x - p.x.floor(), p.z - p.z.floor());
        if fx.min(1.0 - fx) < 0.02 || fz.min(1.0 - fz) < 0.02 {
            continue; // too close to a tile boundary to be sure which tile the pixel sees
        }
        let even = (p.x.floor() + p.z.floor()).rem_euclid(2.0) == 0.0;
        let grey = if even { 0.8 } else { 1.0 };
        // ambient + Lambert + Phong (normal +y, viewer −d) for the shiny tile
        let l = (light - p).normalize();
        let r = 2.0 * l.y * DVec3::Y - l;
        let specular = r.dot(-d).max(0.0).powf(40.0);
        let expected = grey * (0.2 + l.y) + specular;
        let got = image.pixel(x, y);
        assert!(
            (got - DVec3::splat(expected)).abs().max_element() < 1e-9,
            "pixel ({x}, {y}): {got} vs {expected}"
        );
        seen[even as usize] += 1;
    }
    assert!(
        seen[0] > 10 && seen[1] > 10,
        "both tile colours must appear: {seen:?}"
    );
}

/// Whether some pixel within one pixel of `p`'s projection is dominated by colour channel `k`.
fn dominated_near(image: &Image, p: DVec3, k: usize) -> bool {
    let (cx, cy) = project(p);
    (cx - 1..=cx + 1).any(|x| {
        (cy - 1..=cy + 1).any(|y| {
            let c = image.pixel(x, y).to_array();
            (0..3).all(|j| j == k || c[k] > 2.0 * c[j] + 0.05)
        })
    })
}

#[test]
fn cylinders_of_each_colour_appear_where_the_lattice_puts_them() {
    let image = render_studio();
    // red along z at (x, y) = (1/3, −0.98), seen from above
    assert!(
        dominated_near(&image, DVec3::new(1.0 / 3.0, -0.98, 20.0), 0),
        "red"
    );
    // green along y at (x, z) = (1, 10), between two rows of blue cylinders
    assert!(
        dominated_near(&image, DVec3::new(1.0, 0.02, 10.0), 1),
        "green"
    );
    // blue along x at (y, z) = (−0.98, 10)
    assert!(
        dominated_near(&image, DVec3::new(0.0, -0.98, 10.0), 2),
        "blue"
    );
    // and through the gap between cylinders (passing above the lattice's far layers) the sky
    let (x, y) = project(DVec3::new(0.0, 0.6, 10.0));
    assert_eq!(
        image.pixel(x, y),
        DVec3::new(0.5, 0.5, 1.0),
        "gap at ({x}, {y})"
    );
}

#[test]
fn lattice_casts_shadows_on_the_floor() {
    // The floor point in the shadow of the top blue cylinder at z = 10 (it falls near
    // x = −0.68, z = 13.5, where the camera sees the floor unobstructed): the shadow ray from it
    // towards the light hits the cylinder, so only ambient light remains.
    let light = DVec3::new(100.0, 300.0, -500.0);
    let on_cylinder = DVec3::new(0.0, 1.02, 10.0);
    let l = (on_cylinder - light).normalize();
    let floor = on_cylinder + ((-1.0001 - on_cylinder.y) / l.y) * l;
    let (x, y) = project(floor);
    let grey = render_studio().pixel(x, y);
    let ambient_only = [0.2 * 0.8, 0.2 * 1.0];
    assert!(
        ambient_only.iter().any(|a| (grey.x - a).abs() < 1e-12),
        "floor pixel ({x}, {y}) at {floor} should be in shadow, got {grey}"
    );
    // With shadows switched off scene-wide, the same point is lit by the point light.
    let lit = render_studio_with(false).pixel(x, y);
    assert!(
        lit.x > grey.x + 0.3,
        "without shadows ({x}, {y}) should be lit, got {lit}"
    );
}

#[test]
fn matches_the_committed_reference_image() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/reference/studio-160x120.png"
    );
    let got = to_rgb8(&render_studio());
    if std::env::var_os("TIMBRE_UPDATE_REFERENCE").is_some() {
        got.save(path).unwrap();
    }
    let reference = image::open(path).expect("reference image").to_rgb8();
    assert_eq!(reference.dimensions(), got.dimensions());
    // Tolerance: a different CPU or Embree build may flip pixels on cylinder silhouettes, so at
    // most 0.5% of the pixels may differ by more than 2/255 in any channel.
    let differing = reference
        .pixels()
        .zip(got.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0.iter()).any(|(p, q)| p.abs_diff(*q) > 2))
        .count();
    assert!(
        differing * 200 <= (W * H) as usize,
        "{differing} pixels differ from the reference"
    );
}
