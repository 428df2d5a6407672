//! Cameras: where primary rays start and in which directions.

mod pinhole;

pub use pinhole::PinholeCamera;
