//! Rendering scene-file text in the library and comparing the pictures, with each other and
//! with a committed reference picture.

use std::path::Path;

use image::RgbImage;
use timbre::embree::Device;
use timbre::io::to_rgb8;
use timbre::render::{Image, render};
use timbre::scene::{Scene, SceneDescription, file};
use timbre::trajectories;

/// The scene of `text` (named "test.toml"), panicking with the error if it is rejected.
pub fn parse(text: &str) -> SceneDescription {
    parse_as(text, "test.toml")
}

/// The scene of `text` as if read from the file `path`: files it names (meshes) are looked up
/// beside it. Panics with the error if the scene is rejected.
pub fn parse_as(text: &str, path: &str) -> SceneDescription {
    file::parse(text, path).unwrap_or_else(|e| panic!("{e}\nin {path}:\n{text}"))
}

/// The picture of a scene description (its ray trajectories drawn in), with its own render
/// settings.
pub fn render_description(d: &SceneDescription) -> Image {
    let device = Device::new("").unwrap();
    let drawn = trajectories::draw(&device, d).unwrap();
    let scene = Scene::build(&device, &drawn).unwrap();
    render(&scene, &d.camera, &d.render, &|_| {}).unwrap()
}

/// The picture of the scene of `text`.
pub fn render_text(text: &str) -> Image {
    render_description(&parse(text))
}

/// The picture of the scene of `text` as if it were the file `scene.toml` in `dir` (meshes it
/// names are read from `dir`).
pub fn render_text_in(text: &str, dir: &Path) -> Image {
    let path = dir.join("scene.toml");
    render_description(&parse_as(text, path.to_str().expect("a UTF-8 path")))
}

/// Pixels whose 8-bit colours differ.
pub fn differing(a: &Image, b: &Image) -> usize {
    assert_eq!((a.width, a.height), (b.width, b.height));
    to_rgb8(a)
        .pixels()
        .zip(to_rgb8(b).pixels())
        .filter(|(p, q)| p != q)
        .count()
}

/// Pixels whose 8-bit colours differ by more than `levels` in some channel (shading that moves
/// by a rounding step is not a different picture).
pub fn differing_by_more_than(a: &Image, b: &Image, levels: u8) -> usize {
    rgb8_differing_by_more_than(&to_rgb8(a), &to_rgb8(b), levels)
}

/// [`differing_by_more_than`] for 8-bit pictures.
pub fn rgb8_differing_by_more_than(a: &RgbImage, b: &RgbImage, levels: u8) -> usize {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > levels))
        .count()
}

/// The committed picture of TIM's standard studio at 160 × 120 (`tests/studio.rs` checks it
/// against the studio's geometry and lighting; `tests/relativity.rs` compares cameras at rest
/// with it).
pub const STUDIO_REFERENCE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/reference/studio-160x120.png"
);

/// Tolerance for comparing a picture rendered here with a reference picture rendered and
/// committed on another machine: a pixel differs if some channel differs by more than
/// `REFERENCE_LEVELS` (of 255), which absorbs shading that rounds to the next 8-bit step;
/// another CPU or Embree build (Embree traverses in f32) may flip pixels on cylinder
/// silhouettes between the cylinder and what is behind it, so up to `1 / REFERENCE_FRACTION` of
/// the pixels (0.5%, 96 pixels at 160 × 120) may differ. A render on the machine that wrote the
/// reference matches it exactly.
pub const REFERENCE_LEVELS: u8 = 2;
/// See [`REFERENCE_LEVELS`]: at most one pixel in `REFERENCE_FRACTION` may differ.
pub const REFERENCE_FRACTION: usize = 200;

/// The committed studio reference, 8 bits per channel.
pub fn studio_reference() -> RgbImage {
    image::open(STUDIO_REFERENCE)
        .unwrap_or_else(|e| panic!("{STUDIO_REFERENCE}: {e}"))
        .to_rgb8()
}

/// Whether `got` matches `reference` within the tolerance of [`REFERENCE_LEVELS`]; the error
/// says by how much it does not.
pub fn compare_with_reference(got: &RgbImage, reference: &RgbImage) -> Result<(), String> {
    if got.dimensions() != reference.dimensions() {
        return Err(format!(
            "{:?} pixels, the reference {:?}",
            got.dimensions(),
            reference.dimensions()
        ));
    }
    let differing = rgb8_differing_by_more_than(got, reference, REFERENCE_LEVELS);
    let allowed = reference.pixels().len() / REFERENCE_FRACTION;
    if differing <= allowed {
        Ok(())
    } else {
        Err(format!(
            "{differing} pixels differ from the reference by more than {REFERENCE_LEVELS}/255 \
             (at most {allowed} may)"
        ))
    }
}
