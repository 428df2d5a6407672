//! TIM's standard studio rendered at 160×120: pixel checks against the studio's geometry and
//! lighting rules, made both on a fresh render and on the committed reference image, and a
//! comparison of the two with a stated tolerance (see `common::images::REFERENCE_LEVELS`).
//!
//! Regenerate the reference (after an intended change, looked at by a person) with
//! `TIMBRE_UPDATE_REFERENCE=1 cargo test --release --test studio matches_the_committed_reference`.
//! That run writes the file and fails on purpose: it checked nothing. Run the tests again without
//! the variable; `the_committed_reference_shows_the_studio` then checks the new file against the
//! geometry before it is committed.

mod common;

use glam::DVec3;
use image::RgbImage;
use timbre::embree::Device;
use timbre::io::to_rgb8;
use timbre::render::Image;
use timbre::render::render;
use timbre::scene::RenderSettings;
use timbre::scene::Scene;
use timbre::scene::studio::Studio;

use common::images::{STUDIO_REFERENCE, compare_with_reference, studio_reference};

const W: u32 = 160;
const H: u32 = 120;
const SKY: DVec3 = DVec3::new(0.5, 0.5, 1.0);
const LIGHT: DVec3 = DVec3::new(100.0, 300.0, -500.0);

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

/// A picture to check against the studio's geometry: its colours, and how far they may be from
/// the colours worked out here.
struct Picture {
    colour: Box<dyn Fn(u32, u32) -> DVec3>,
    tolerance: f64,
    /// Whether colours were clamped to [0, 1] (8 bits per channel).
    clamped: bool,
}

impl Picture {
    /// A render here, in f64: 1e-9 for the sums of the lighting model.
    fn rendered(image: Image) -> Picture {
        Picture {
            colour: Box::new(move |x, y| image.pixel(x, y)),
            tolerance: 1e-9,
            clamped: false,
        }
    }

    /// An 8-bit picture: within one step of 255 (rounding, on whichever machine wrote it).
    fn eight_bit(image: RgbImage) -> Picture {
        assert_eq!(image.dimensions(), (W, H));
        Picture {
            colour: Box::new(move |x, y| {
                let [r, g, b] = image.get_pixel(x, y).0.map(|c| f64::from(c) / 255.0);
                DVec3::new(r, g, b)
            }),
            tolerance: 1.0 / 255.0,
            clamped: true,
        }
    }

    fn pixel(&self, x: u32, y: u32) -> DVec3 {
        (self.colour)(x, y)
    }

    fn is(&self, x: u32, y: u32, want: DVec3) -> bool {
        let want = if self.clamped {
            want.clamp(DVec3::ZERO, DVec3::ONE)
        } else {
            want
        };
        (self.pixel(x, y) - want).abs().max_element() <= self.tolerance
    }
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

/// The lattice's top ends 1.02 above the camera at z = 10, i.e. below the top 10 rows: they
/// see the sky's constant colour.
fn check_sky(picture: &Picture) {
    for y in 0..10 {
        for x in 0..W {
            assert!(
                picture.is(x, y, SKY),
                "pixel ({x}, {y}): {}",
                picture.pixel(x, y)
            );
        }
    }
}

/// The bottom row sees the floor at z ≈ 7.6, in front of the lattice: each pixel not too close
/// to a tile boundary has the colour of its tile (grey 0.8 or white 1, by the parity of the
/// tile) lit by ambient 0.2, Lambert and Phong (exponent 40) from the point light, both tile
/// colours appearing.
fn check_floor(picture: &Picture) {
    let y = H - 1;
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
        let l = (LIGHT - p).normalize();
        let r = 2.0 * l.y * DVec3::Y - l;
        let specular = r.dot(-d).max(0.0).powf(40.0);
        let expected = grey * (0.2 + l.y) + specular;
        assert!(
            picture.is(x, y, DVec3::splat(expected)),
            "pixel ({x}, {y}): {} vs {expected}",
            picture.pixel(x, y)
        );
        seen[even as usize] += 1;
    }
    assert!(
        seen[0] > 10 && seen[1] > 10,
        "both tile colours must appear: {seen:?}"
    );
}

/// Whether some pixel within one pixel of `p`'s projection is dominated by colour channel `k`.
fn dominated_near(picture: &Picture, p: DVec3, k: usize) -> bool {
    let (cx, cy) = project(p);
    (cx - 1..=cx + 1).any(|x| {
        (cy - 1..=cy + 1).any(|y| {
            let c = picture.pixel(x, y).to_array();
            (0..3).all(|j| j == k || c[k] > 2.0 * c[j] + 0.05)
        })
    })
}

/// Cylinders of each colour appear where the lattice puts them, and the sky through a gap.
fn check_cylinders(picture: &Picture) {
    // red along z at (x, y) = (1/3, −0.98), seen from above
    assert!(
        dominated_near(picture, DVec3::new(1.0 / 3.0, -0.98, 20.0), 0),
        "red"
    );
    // green along y at (x, z) = (1, 10), between two rows of blue cylinders
    assert!(
        dominated_near(picture, DVec3::new(1.0, 0.02, 10.0), 1),
        "green"
    );
    // blue along x at (y, z) = (−0.98, 10)
    assert!(
        dominated_near(picture, DVec3::new(0.0, -0.98, 10.0), 2),
        "blue"
    );
    // and through the gap between cylinders (passing above the lattice's far layers) the sky
    let (x, y) = project(DVec3::new(0.0, 0.6, 10.0));
    assert!(
        picture.is(x, y, SKY),
        "gap at ({x}, {y}): {}",
        picture.pixel(x, y)
    );
}

/// The floor point in the shadow of the top blue cylinder at z = 10 (it falls near x = −0.68,
/// z = 13.5, where the camera sees the floor unobstructed): the shadow ray from it towards the
/// light hits the cylinder, so only ambient light remains, 0.2 × (0.8 or 1). Returns the pixel.
fn check_shadow(picture: &Picture) -> (u32, u32) {
    let on_cylinder = DVec3::new(0.0, 1.02, 10.0);
    let l = (on_cylinder - LIGHT).normalize();
    let floor = on_cylinder + ((-1.0001 - on_cylinder.y) / l.y) * l;
    let (x, y) = project(floor);
    let ambient_only = [0.2 * 0.8, 0.2 * 1.0];
    assert!(
        ambient_only
            .iter()
            .any(|&a| picture.is(x, y, DVec3::splat(a))),
        "floor pixel ({x}, {y}) at {floor} should be in shadow, got {}",
        picture.pixel(x, y)
    );
    (x, y)
}

#[test]
fn sky_fills_the_top_rows_with_its_constant_colour() {
    check_sky(&Picture::rendered(render_studio()));
}

#[test]
fn lit_floor_tiles_alternate_between_the_two_expected_values() {
    check_floor(&Picture::rendered(render_studio()));
}

#[test]
fn cylinders_of_each_colour_appear_where_the_lattice_puts_them() {
    check_cylinders(&Picture::rendered(render_studio()));
}

#[test]
fn lattice_casts_shadows_on_the_floor() {
    let shadowed = Picture::rendered(render_studio());
    let (x, y) = check_shadow(&shadowed);
    // With shadows switched off scene-wide, the same point is lit by the point light.
    let lit = render_studio_with(false).pixel(x, y);
    assert!(
        lit.x > shadowed.pixel(x, y).x + 0.3,
        "without shadows ({x}, {y}) should be lit, got {lit}"
    );
}

#[test]
fn the_committed_reference_shows_the_studio() {
    // The reference is not trusted because the code wrote it: it must show the sky, the lit
    // floor tiles, the coloured cylinders and the shadow where the geometry puts them, to
    // within an 8-bit step.
    let reference = Picture::eight_bit(studio_reference());
    check_sky(&reference);
    check_floor(&reference);
    check_cylinders(&reference);
    check_shadow(&reference);
}

#[test]
fn matches_the_committed_reference_image() {
    let got = to_rgb8(&render_studio());
    if std::env::var_os("TIMBRE_UPDATE_REFERENCE").is_some() {
        // The previous file may be missing or unreadable: that is what updating is for.
        let previous = image::open(STUDIO_REFERENCE)
            .map(|old| compare_with_reference(&got, &old.to_rgb8()))
            .map_err(|e| e.to_string());
        got.save(STUDIO_REFERENCE).unwrap();
        panic!(
            "TIMBRE_UPDATE_REFERENCE: wrote {STUDIO_REFERENCE} from this render (against the \
             previous file: {previous:?}). Nothing was checked: look at the picture, run the \
             tests again without TIMBRE_UPDATE_REFERENCE, then commit it."
        );
    }
    compare_with_reference(&got, &studio_reference())
        .unwrap_or_else(|e| panic!("{STUDIO_REFERENCE}: {e}"));
}
