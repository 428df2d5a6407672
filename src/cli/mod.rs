//! The `timbre` command's own parts: its arguments, how it shows progress, and `timbre render`
//! (main.rs runs the other commands, which are short).

pub mod args;
pub mod denoise;
pub mod image;
pub mod movie;
pub mod progress;
pub mod render;
