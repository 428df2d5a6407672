//! Rendering scene-file text in the library and comparing the pictures.

use timbre::embree::Device;
use timbre::io::to_rgb8;
use timbre::render::{Image, render};
use timbre::scene::{Scene, SceneDescription, file};
use timbre::trajectories;

/// The scene of `text` (named "test.toml"), panicking with the error if it is rejected.
pub fn parse(text: &str) -> SceneDescription {
    file::parse(text, "test.toml").unwrap_or_else(|e| panic!("{e}\nin:\n{text}"))
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
    assert_eq!((a.width, a.height), (b.width, b.height));
    to_rgb8(a)
        .pixels()
        .zip(to_rgb8(b).pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > levels))
        .count()
}
