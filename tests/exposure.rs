//! Exposure compensation and the PNG transfer (`--exposure`, `[render] exposure`,
//! `--png-transfer`): against the definition 2^stops, the sRGB curve of IEC 61966-2-1 and the
//! PNG specification's chunks, on a scene whose every pixel is one known colour.

mod common;

use std::path::Path;

use common::cli::{path_str, timbre, write};

/// A scene of nothing but a sky of `grey` (TIM's constant-colour sky, as the `none` studio
/// leaves it): every pixel is `grey` in every channel.
fn grey_scene(dir: &Path, grey: f64, render: &str) -> String {
    let text = format!(
        "studio = \"none\"\n[render]\nwidth = 4\nheight = 3\n{render}\n\
         [[object]]\nshape = {{ type = \"sphere\", centre = [0, 0, 0], radius = 100 }}\n\
         surface = {{ type = \"constant-colour\", colour = [{grey}, {grey}, {grey}] }}\n"
    );
    path_str(&write(dir, "grey.toml", text)).to_string()
}

/// The red channel of every pixel of an OpenEXR file.
fn exr_reds(path: &Path) -> Vec<f32> {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| vec![0f32; size.0 * size.1],
        |pixels: &mut Vec<f32>, position, (r, _, _, _): (f32, f32, f32, f32)| {
            pixels[position.y() * 4 + position.x()] = r;
        },
    )
    .unwrap();
    image.layer_data.channel_data.pixels
}

/// The chunks of a PNG file: (type, data) in order.
fn png_chunks(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let mut chunks = Vec::new();
    let mut at = 8;
    while at < bytes.len() {
        let n = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let kind = String::from_utf8(bytes[at + 4..at + 8].to_vec()).unwrap();
        chunks.push((kind, bytes[at + 8..at + 8 + n].to_vec()));
        at += 12 + n;
    }
    chunks
}

/// The first pixel's red value of a PNG file.
fn png_red(path: &Path) -> u8 {
    common::cli::decode_png(path).get_pixel(0, 0).0[0]
}

/// `--exposure 1.5` and `[render] exposure = -2` multiply every OpenEXR value by 2^stops
/// (exactly: a power of two times a value changes only its exponent), and the file says so.
#[test]
fn exposure_scales_openexr_values_by_two_to_the_stops() {
    let dir = tempfile::tempdir().unwrap();
    let scene = grey_scene(dir.path(), 0.3, "");
    let out = |name: &str| dir.path().join(name);
    timbre(
        dir.path(),
        &["render", &scene, "-o", path_str(&out("a.exr"))],
    )
    .assert_success();
    timbre(
        dir.path(),
        &[
            "render",
            &scene,
            "--exposure",
            "2",
            "-o",
            path_str(&out("b.exr")),
        ],
    )
    .assert_success();
    let plain = exr_reds(&out("a.exr"));
    assert!(plain.iter().all(|&r| r == 0.3f64 as f32), "{plain:?}");
    assert!(
        exr_reds(&out("b.exr"))
            .iter()
            .all(|&r| r == (0.3 * 4.0) as f32)
    );
    // The scene file's own setting, a fractional one.
    let scene = grey_scene(dir.path(), 0.3, "exposure = -1.5");
    timbre(
        dir.path(),
        &["render", &scene, "-o", path_str(&out("c.exr"))],
    )
    .assert_success();
    let want = (0.3 * 2f64.powf(-1.5)) as f32;
    assert!(exr_reds(&out("c.exr")).iter().all(|&r| r == want));
    let header = std::fs::read(out("c.exr")).unwrap();
    assert!(header.windows(15).any(|w| w == b"timbre.exposure"));
    assert!(
        !std::fs::read(out("a.exr"))
            .unwrap()
            .windows(15)
            .any(|w| w == b"timbre.exposure")
    );
}

/// PNG: linear is the value ×255 (0.5 → 127.5 → 128) with a gAMA chunk of gamma 1 (100000),
/// sRGB is the IEC 61966-2-1 curve (0.5 → 0.735357 → 187.5 → 188; 0.002 → 12.92 × 0.002 →
/// 6.59 → 7) with an sRGB chunk; exposure applies before the transfer; the scene hash, seed and
/// version are tEXt chunks.
#[test]
fn png_transfer_and_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name);
    let scene = grey_scene(dir.path(), 0.5, "seed = 42");
    timbre(
        dir.path(),
        &["render", &scene, "-o", path_str(&out("l.png"))],
    )
    .assert_success();
    assert_eq!(png_red(&out("l.png")), 128);
    let bytes = std::fs::read(out("l.png")).unwrap();
    let chunks = png_chunks(&bytes);
    let gama = chunks
        .iter()
        .find(|(k, _)| k == "gAMA")
        .expect("a gAMA chunk");
    assert_eq!(u32::from_be_bytes(gama.1[..4].try_into().unwrap()), 100_000);
    assert!(!chunks.iter().any(|(k, _)| k == "sRGB"));
    let texts: Vec<String> = chunks
        .iter()
        .filter(|(k, _)| k == "tEXt")
        .map(|(_, d)| String::from_utf8(d.clone()).unwrap())
        .collect();
    assert!(
        texts.contains(&"timbre.seed\u{0}42".to_string()),
        "{texts:?}"
    );
    let version = format!("timbre.version\u{0}{}", env!("CARGO_PKG_VERSION"));
    assert!(texts.contains(&version), "{texts:?}");
    let hash = texts
        .iter()
        .find_map(|t| t.strip_prefix("timbre.scene\u{0}"))
        .expect("the scene hash");
    assert_eq!(hash.len(), 16);

    timbre(
        dir.path(),
        &[
            "render",
            &scene,
            "--png-transfer",
            "srgb",
            "-o",
            path_str(&out("s.png")),
        ],
    )
    .assert_success();
    assert_eq!(png_red(&out("s.png")), 188);
    let chunks = png_chunks(&std::fs::read(out("s.png")).unwrap());
    assert!(chunks.iter().any(|(k, d)| k == "sRGB" && d.len() == 1));
    // The linear part of the curve, through the scene file's keys, after the exposure:
    // 0.004 × 2^−1 = 0.002.
    let scene = grey_scene(dir.path(), 0.004, "png_transfer = \"srgb\"\nexposure = -1");
    timbre(
        dir.path(),
        &["render", &scene, "-o", path_str(&out("d.png"))],
    )
    .assert_success();
    assert_eq!(png_red(&out("d.png")), 7);
}

/// Values out of range or of the wrong kind are refused, located, exit 2.
#[test]
fn bad_exposure_and_transfer_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = grey_scene(dir.path(), 0.5, "");
    let png = path_str(&dir.path().join("x.png")).to_string();
    for (option, value) in [
        ("--exposure", "31"),
        ("--exposure", "nan"),
        ("--png-transfer", "gamma"),
    ] {
        // Refused by the option parser (clap's own message), exit 2.
        let run = timbre(dir.path(), &["render", &scene, option, value, "-o", &png]);
        assert_eq!(run.code, Some(2), "{}", run.stderr);
        assert!(
            run.stderr.contains(&format!("got '{value}'")),
            "{}",
            run.stderr
        );
    }
    for (line, needle) in [
        ("exposure = 40", "a number from -30 to 30"),
        ("exposure = \"1\"", "a number from -30 to 30"),
        ("png_transfer = \"log\"", "one of linear, srgb"),
        ("png_transfer = 1", "one of linear, srgb"),
    ] {
        let scene = grey_scene(dir.path(), 0.5, line);
        timbre(dir.path(), &["render", &scene, "-o", &png])
            .assert_bad_input(&[needle, "grey.toml:5"]);
    }
    assert!(!dir.path().join("x.png").exists());
}
