//! The page `timbre serve` shows: one HTML file with its script and style, built into the
//! binary (no build step, nothing fetched from elsewhere).

pub const PAGE: &str = include_str!("page.html");
