//! Random-dot autostereograms (single-image random-dot stereograms, SIRDS), following Thimbleby,
//! Inglis & Witten, "Displaying 3D images: algorithms for single-image random-dot stereograms"
//! (IEEE Computer, 1994).
//!
//! # Viewing geometry and depth
//! The viewer's eyes, `E` pixels apart, look at the screen from a distance `D`. The scene lies
//! behind the screen: the far plane is `D` behind it (`2D` from the eyes) and the near plane is
//! `μD` in front of the far plane, μ being [`Autostereogram::depth_of_field`]. A depth value
//! `z ∈ [0, 1]` puts a point `μzD` in front of the far plane (0 = far plane, 1 = near plane),
//! straight behind its pixel of the depth map. Its lines of sight to the two eyes cross the screen
//! `s(z) = (1 − μz)E / (2 − μz)` pixels apart, placed symmetrically about the pixel (the paper's
//! approximation): `E/2` for the far plane, `(1 − μ)E/(2 − μ)` for the near plane. Nearer points
//! have smaller separations.
//!
//! # Algorithm
//! Rows are independent. For each pixel `x` of a row, with depth `z` and `s = round(s(z))`, the
//! point's two image pixels are `left = x − ⌊s/2⌋` and `right = left + s`; if both are in the row
//! and the point is visible to both eyes (below), they must have the same colour: they are
//! *linked*. Links live in a `same` array, where `same[p]` is a pixel right of `p` that must share
//! its colour (or `p` itself if there is none). A new link from a pixel that is already linked is
//! threaded into its chain in order of position, so every constraint added stays in force and each
//! pixel keeps a single link to its right. Pixels are then coloured right to left: a linked pixel
//! copies the colour of `same[p]`, already coloured; an unlinked one gets a fresh random dot.
//!
//! # Hidden surfaces
//! In depth units (1 = near minus far plane) the eyes are `2/μ` in front of the far plane, so a
//! line of sight from a point at depth `z` rises by `2(2 − μz)/(μE)` per pixel it moves sideways.
//! Walking `t = 1, 2, …` pixels out from `x` on both sides until the lines pass the near plane,
//! the point is hidden from an eye if the depth map at `x ± t` reaches the line towards that eye.
//! Hidden points add no link, so pixels that only one eye sees keep free random dots instead of
//! false constraints. Pixels beyond the row's ends never occlude.
//!
//! # Options
//! `eye_separation` (E, pixels) scales the whole pattern: the image repeats every `E/2` pixels on
//! the far plane. `depth_of_field` (μ) sets how far the near plane comes out: larger μ means more
//! depth but harder fusion (1/3 is the paper's default). `seed` chooses the dots and `colour`
//! switches between random RGB dots (each channel uniform in [0, 1)) and black-and-white dots.

use rayon::prelude::*;

use crate::math::Colour;
use crate::math::random::uniform;

/// Options of a random-dot autostereogram.
#[derive(Debug, Clone, PartialEq)]
pub struct Autostereogram {
    /// Separation of the viewer's eyes, in pixels (E).
    pub eye_separation: u32,
    /// Depth of field μ ∈ (0, 1): the near plane's distance in front of the far plane as a
    /// fraction of the eyes' distance D from the screen, the far plane being D behind the screen
    /// (Thimbleby's μ; 1/3 is their default).
    pub depth_of_field: f64,
    /// Seed of the random dots.
    pub seed: u64,
    /// Random colours (each channel uniform) when true; black and white dots when false.
    pub colour: bool,
}

impl Autostereogram {
    /// Checks the options against an image `width`: eye_separation ≥ 2, the widest repeat (the
    /// far plane's separation) smaller than the width, depth_of_field strictly between 0 and 1
    /// and finite.
    pub fn validate(&self, width: u32) -> Result<(), String> {
        if self.eye_separation < 2 {
            return Err(format!(
                "eye_separation must be at least 2 pixels, got {}",
                self.eye_separation
            ));
        }
        let mu = self.depth_of_field;
        if !(mu.is_finite() && mu > 0.0 && mu < 1.0) {
            return Err(format!(
                "depth_of_field must be finite and strictly between 0 and 1, got {mu}"
            ));
        }
        let far = self.separation(0.0).round();
        if far >= f64::from(width) {
            return Err(format!(
                "eye_separation {} is too wide for an image {width} pixels wide: the far plane's \
                 repeat ({far} pixels) must be smaller than the width",
                self.eye_separation
            ));
        }
        Ok(())
    }

    /// Separation in pixels (not rounded) of the two image points of a point at depth
    /// z ∈ [0, 1] (0 = far plane, 1 = near plane): (1 − μz)E/(2 − μz).
    pub fn separation(&self, z: f64) -> f64 {
        let mz = self.depth_of_field * z;
        (1.0 - mz) * f64::from(self.eye_separation) / (2.0 - mz)
    }

    /// The autostereogram of a depth map: `depth` is row-major, `width × height`, each value in
    /// [0, 1] (0 far, 1 near; values outside are clamped, NaN counts as far). Returns
    /// width × height colours, row-major from the top-left.
    ///
    /// # Panics
    /// If `depth.len()` is not `width × height`.
    pub fn render(&self, depth: &[f64], width: u32, height: u32) -> Vec<Colour> {
        let (w, h) = (width as usize, height as usize);
        assert_eq!(
            depth.len(),
            w * h,
            "autostereogram depth map has {} values, expected {width} × {height}",
            depth.len()
        );
        let mut image = vec![Colour::ZERO; w * h];
        if w == 0 {
            return image;
        }
        image
            .par_chunks_mut(w)
            .zip(depth.par_chunks(w))
            .enumerate()
            .for_each(|(y, (out, row))| self.render_row(row, y as u32, out));
        image
    }

    /// Colours one row `y` from its depths.
    fn render_row(&self, row: &[f64], y: u32, out: &mut [Colour]) {
        let depth: Vec<f64> = row
            .iter()
            .map(|&z| if z.is_nan() { 0.0 } else { z.clamp(0.0, 1.0) })
            .collect();
        let same = self.links(&depth);
        for x in (0..out.len()).rev() {
            out[x] = if same[x] == x {
                self.dot(x as u32, y)
            } else {
                out[same[x]]
            };
        }
    }

    /// The `same` array of a row of depths in [0, 1]: `same[p] > p` is the pixel `p` must match,
    /// or `same[p] == p` if `p` is free.
    fn links(&self, depth: &[f64]) -> Vec<usize> {
        let w = depth.len();
        let mut same: Vec<usize> = (0..w).collect();
        for (x, &z) in depth.iter().enumerate() {
            let s = self.separation(z).round();
            // Also skips NaN and separations that don't fit (only with invalid options).
            if !(s >= 1.0 && s < w as f64) {
                continue;
            }
            let s = s as usize;
            let Some(left) = x.checked_sub(s / 2) else {
                continue;
            };
            let right = left + s;
            if right < w && self.visible(depth, x, z) {
                link(&mut same, left, right);
            }
        }
        same
    }

    /// Whether the point at pixel `x` and depth `z` of a row is seen by both eyes, i.e. no nearer
    /// part of the row crosses its lines of sight (see the module doc).
    fn visible(&self, depth: &[f64], x: usize, z: f64) -> bool {
        let mu = self.depth_of_field;
        let rise = 2.0 * (2.0 - mu * z) / (mu * f64::from(self.eye_separation));
        let occludes =
            |i: Option<usize>, zt: f64| i.and_then(|i| depth.get(i)).is_some_and(|&d| d >= zt);
        for t in 1..=depth.len() {
            let zt = z + rise * t as f64;
            if occludes(x.checked_sub(t), zt) || occludes(x.checked_add(t), zt) {
                return false;
            }
            if zt >= 1.0 {
                break;
            }
        }
        true
    }

    /// Fresh random dot of pixel (x, y).
    fn dot(&self, x: u32, y: u32) -> Colour {
        let u = |channel| uniform(self.seed, x, y, 0, channel);
        if self.colour {
            Colour::new(u(0), u(1), u(2))
        } else if u(0) < 0.5 {
            Colour::ONE
        } else {
            Colour::ZERO
        }
    }
}

/// Adds the constraint "`left` and `right` share a colour" (`left < right`) to `same`, keeping
/// every pixel's chain of links sorted by position so that earlier constraints still hold.
fn link(same: &mut [usize], mut left: usize, mut right: usize) {
    loop {
        let next = same[left];
        if next == left || next == right {
            break;
        }
        if next < right {
            // `left` already links to a pixel before `right`: link that pixel to `right` instead.
            left = next;
        } else {
            // `left` links beyond `right`: put `right` in between and carry on linking onwards.
            same[left] = right;
            left = right;
            right = next;
        }
    }
    same[left] = right;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sirds(eye_separation: u32, seed: u64, colour: bool) -> Autostereogram {
        Autostereogram {
            eye_separation,
            depth_of_field: 1.0 / 3.0,
            seed,
            colour,
        }
    }

    /// Depth map with `background`, a rectangle at `rect` and a square at `square` on part of it.
    fn layered(width: u32, height: u32, background: f64, rect: f64, square: f64) -> Vec<f64> {
        let mut depth = vec![background; (width * height) as usize];
        for y in 0..height {
            for x in 0..width {
                let z = &mut depth[(y * width + x) as usize];
                if (100..300).contains(&x) && (10..50).contains(&y) {
                    *z = rect;
                }
                if (170..240).contains(&x) && (20..40).contains(&y) {
                    *z = square;
                }
            }
        }
        depth
    }

    /// Depth recovered at pixel `x` of `row` by finding the unique separation whose pixel pair
    /// around `x` matches over a window of ±`window` pixels; `None` if no or several match.
    fn recover(a: &Autostereogram, row: &[Colour], x: usize, window: usize) -> Option<f64> {
        let lo = a.separation(1.0).round() as usize - 1;
        let hi = a.separation(0.0).round() as usize + 1;
        let matching: Vec<usize> = (lo..=hi)
            .filter(|&s| {
                (0..=2 * window).all(|k| {
                    let left = (x + k).checked_sub(window + s / 2);
                    left.is_some_and(|l| l + s < row.len() && row[l] == row[l + s])
                })
            })
            .collect();
        let [s] = matching[..] else { return None };
        let (e, s) = (f64::from(a.eye_separation), s as f64);
        Some((e - 2.0 * s) / (a.depth_of_field * (e - s)))
    }

    /// Fraction of the pixels away from borders and depth edges of `truth` whose depth is
    /// recovered from `image` within one separation step, and the number of such pixels.
    fn recovered_fraction(
        a: &Autostereogram,
        image: &[Colour],
        truth: &[f64],
        width: usize,
    ) -> (f64, usize) {
        let window = 2;
        // Lines of sight reach the near plane within μE/4 pixels (from the far plane).
        let reach = (a.depth_of_field * f64::from(a.eye_separation) / 4.0).ceil() as usize;
        let margin = window + reach + 1;
        let border = a.separation(0.0).round() as usize / 2 + window + 2;
        let (mut good, mut total) = (0, 0);
        for (row, depth) in image.chunks(width).zip(truth.chunks(width)) {
            for x in border..width - border {
                let z = depth[x];
                if depth[x - margin..=x + margin].iter().any(|&d| d != z) {
                    continue;
                }
                total += 1;
                // One pixel of separation is |dz/ds| = (2 − μz)²/(μE) of depth.
                let step = (2.0 - a.depth_of_field * z).powi(2)
                    / (a.depth_of_field * f64::from(a.eye_separation));
                if recover(a, row, x, window).is_some_and(|r| (r - z).abs() <= step) {
                    good += 1;
                }
            }
        }
        (good as f64 / total as f64, total)
    }

    #[test]
    fn depth_map_is_recovered_from_matching_repeats() {
        let (width, height) = (400, 60);
        let a = sirds(90, 7, true);
        a.validate(width).unwrap();
        let depth = layered(width, height, 0.0, 0.6, 1.0);
        let image = a.render(&depth, width, height);
        let (fraction, total) = recovered_fraction(&a, &image, &depth, width as usize);
        // Every counted pixel and its window neighbours are visible and linked at their own
        // separation, so recovery should be exact; 0.99 leaves room only for a chance ambiguity.
        assert!(total > 10_000, "only {total} pixels counted");
        assert!(fraction >= 0.99, "recovered {fraction} of {total} pixels");

        // A different depth map gives a different image: its repeats no longer match `depth`.
        let other = layered(width, height, 0.3, 1.0, 0.0);
        let image = a.render(&other, width, height);
        let (fraction, _) = recovered_fraction(&a, &image, &depth, width as usize);
        assert!(fraction < 0.05, "wrong map recovered for {fraction}");
        let (fraction, _) = recovered_fraction(&a, &image, &other, width as usize);
        assert!(fraction >= 0.99, "other map recovered for {fraction}");
    }

    #[test]
    fn constant_depth_repeats_with_its_separation() {
        let (width, height) = (300, 4);
        let a = sirds(80, 3, true);
        for z in [0.0, 0.25, 0.6, 1.0] {
            let s = a.separation(z).round() as usize;
            let image = a.render(&vec![z; width * height], width as u32, height as u32);
            for row in image.chunks(width) {
                for x in s..width {
                    assert_eq!(row[x], row[x - s], "z = {z}, x = {x}");
                }
                // Within one period the dots are all different, so the repeat is not trivial.
                assert!((1..s).all(|x| row[x] != row[x - 1]), "z = {z}");
            }
        }
    }

    #[test]
    fn separation_follows_the_formula() {
        let a = sirds(90, 0, true);
        assert_eq!(a.separation(0.0), 45.0);
        let mu = 1.0 / 3.0;
        assert!((a.separation(1.0) - (1.0 - mu) * 90.0 / (2.0 - mu)).abs() < 1e-12);
        assert!((a.separation(1.0) - 36.0).abs() < 1e-12);
        let mut previous = f64::INFINITY;
        for i in 0..=100 {
            let s = a.separation(i as f64 / 100.0);
            assert!(s < previous, "not decreasing at z = {}", i as f64 / 100.0);
            previous = s;
        }
    }

    #[test]
    fn dots_are_deterministic_and_black_and_white_on_request() {
        let (width, height) = (200, 20);
        let depth = layered(width, height, 0.0, 0.5, 1.0);
        let a = sirds(60, 11, true);
        let first = a.render(&depth, width, height);
        assert_eq!(first, a.render(&depth, width, height));
        let b = sirds(60, 12, true);
        let second = b.render(&depth, width, height);
        let same = first.iter().zip(&second).filter(|(p, q)| p == q).count();
        assert!(same < first.len() / 100, "{same} equal pixels");

        let bw = sirds(60, 11, false).render(&depth, width, height);
        assert!(bw.iter().all(|c| *c == Colour::ZERO || *c == Colour::ONE));
        let white = bw.iter().filter(|c| **c == Colour::ONE).count();
        assert!(
            white > bw.len() / 3 && white < 2 * bw.len() / 3,
            "{white} white"
        );
    }

    #[test]
    fn validate_rejects_bad_options() {
        let good = sirds(90, 0, true);
        assert_eq!(good.validate(400), Ok(()));
        assert_eq!(sirds(790, 0, true).validate(400), Ok(()));
        for mu in [0.0, 1.0, f64::NAN, f64::INFINITY, -0.5] {
            let a = Autostereogram {
                depth_of_field: mu,
                ..good.clone()
            };
            let error = a.validate(400).unwrap_err();
            assert!(error.contains("depth_of_field"), "{error}");
        }
        for e in [0, 1, 800, 10_000] {
            let error = sirds(e, 0, true).validate(400).unwrap_err();
            assert!(error.contains("eye_separation"), "{error}");
        }
    }

    #[test]
    fn hidden_surfaces_leave_pixels_free() {
        let width = 400;
        let a = sirds(90, 5, true);
        // Far background with a narrow occluder on the near plane at x ∈ [200, 210).
        let mut row = vec![0.0; width];
        row[200..210].fill(1.0);
        let image = a.render(&row, width as u32, 1);
        let s = a.separation(0.0).round() as usize;
        // A line of sight from the far plane rises 4/(μE) = 2/15 per pixel, so the occluder (at
        // depth 1) hides background points up to 7.5 pixels from it from one eye: the right eye
        // left of it, the left eye right of it. Those pairs must not be linked; all others must.
        let mut hidden = 0;
        for x in s / 2..width - s + s / 2 {
            let distance = if x < 200 {
                200 - x
            } else {
                x.saturating_sub(209)
            };
            if distance == 0 {
                continue;
            }
            let seen_by_both = distance as f64 * 4.0 / (a.depth_of_field * 90.0) > 1.0;
            let (left, right) = (x - s / 2, x - s / 2 + s);
            assert_eq!(image[left] == image[right], seen_by_both, "x = {x}");
            hidden += usize::from(!seen_by_both);
        }
        assert_eq!(hidden, 14);

        // Free pixels short of the last repeat: none on a flat map, some beside the occluder.
        let free = |same: &[usize]| (0..width - s).filter(|&p| same[p] == p).count();
        assert_eq!(free(&a.links(&vec![0.0; width])), 0);
        let same = a.links(&row);
        let near: Vec<usize> = (0..width - s).filter(|&p| same[p] == p).collect();
        assert!(!near.is_empty());
        assert!(
            near.iter().all(|p| (200 - s..210 + s).contains(p)),
            "{near:?}"
        );
    }

    #[test]
    fn odd_depths_are_clamped_and_never_panic() {
        let a = sirds(40, 1, true);
        let clamped = a.render(&[0.0, 1.0, 0.5, 0.0].repeat(30), 120, 1);
        assert_eq!(
            a.render(&[f64::NAN, 7.0, 0.5, -3.0].repeat(30), 120, 1),
            clamped
        );
        assert!(a.render(&[], 0, 5).is_empty());
        assert!(a.render(&[], 5, 0).is_empty());
        // Invalid options still render (validate reports them).
        for mu in [0.0, 1.0, 1.5, 3.0, f64::NAN, -1.0] {
            let b = Autostereogram {
                depth_of_field: mu,
                ..a.clone()
            };
            assert_eq!(b.render(&[0.5; 120], 40, 3).len(), 120);
        }
        assert_eq!(sirds(10_000, 1, true).render(&[0.5; 120], 40, 3).len(), 120);
    }

    #[test]
    fn links_keep_every_constraint() {
        // Hand-made overlapping links: all pixels constrained together end in one chain.
        let mut same: Vec<usize> = (0..10).collect();
        link(&mut same, 0, 6);
        link(&mut same, 0, 4);
        link(&mut same, 2, 6);
        link(&mut same, 1, 9);
        link(&mut same, 5, 9);
        let root = |mut p: usize| {
            while same[p] != p {
                assert!(same[p] > p);
                p = same[p];
            }
            p
        };
        for (l, r) in [(0, 6), (0, 4), (2, 6), (1, 9), (5, 9)] {
            assert_eq!(root(l), root(r), "{l} {r}");
        }
        assert_ne!(root(0), root(1));
        assert_eq!(root(3), 3);
    }
}
