//! timbre: a fast, scientifically exact ray tracer for ray-optics research.
//!
//! Embree builds and traverses the BVH; everything optical is Rust in f64. The physics follows
//! "Dr TIM: Ray-tracer TIM, with additional specialist scientific capabilities" (Oxburgh, Tyc,
//! Courtial); equation numbers in doc comments refer to it.

pub mod cameras;
#[cfg(feature = "denoise")]
pub mod denoise;
pub mod devices;
pub mod display;
// The one exception to `unsafe_code = "deny"` (Cargo.toml's lints): the Embree binding calls C,
// and its safe API is the boundary that keeps every other module free of `unsafe`.
#[allow(unsafe_code)]
pub mod embree;
pub mod files;
pub mod geometry;
pub mod io;
pub mod keys;
pub mod math;
pub mod memory;
pub mod mesh;
pub mod picture;
pub mod prepare;
pub mod production;
pub mod render;
pub mod scene;
pub mod serve;
pub mod stereo;
pub mod surfaces;
pub mod text;
pub mod trajectories;
