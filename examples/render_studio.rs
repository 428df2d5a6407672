//! Using timbre as a library: render TIM's standard studio and write it as a PNG.
//! Run with `cargo run --release --example render_studio`.

use timbre::embree::Device;
use timbre::io::{Provenance, write_image};
use timbre::render::render;
use timbre::scene::{Scene, studio::Studio};
use timbre::trajectories;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let description = Studio::Lattice.description();
    let device = Device::new("")?;
    // Ray trajectories (none in the studio) are drawn into the scene as objects first.
    let drawn = trajectories::draw(&device, &description)?;
    let scene = Scene::build(&device, &drawn)?;
    let image = render(&scene, &description.camera, &description.render, &|_| {})?;
    let provenance = Provenance::whole(&description.render, description.hash());
    write_image("studio.png".as_ref(), &image, &provenance)?;
    println!("{} rays -> studio.png", image.rays);
    Ok(())
}
