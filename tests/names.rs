//! One naming scheme: kebab-case values in scene files, with the older snake_case spellings
//! still accepted as aliases that mean exactly the same.

use timbre::scene::file;

/// A scene using every value renamed to kebab-case, written with `old` spellings or not.
fn scene(old: bool) -> String {
    let name = |kebab: &str| {
        if old {
            kebab.replace('-', "_")
        } else {
            kebab.to_string()
        }
    };
    format!(
        r#"studio = "{studio}"
[camera]
type = "{camera}"
aperture_radius = 0.1
shutter = "{shutter}"
stereo = "{stereo}"
[[object]]
shape = {{ type = "{mesh}", vertices = [[0, 0, 5], [1, 0, 5], [0, 1, 5]], triangles = [[0, 1, 2]] }}
surface = {{ type = "{constant}", colour = [1, 0, 0] }}
[[object]]
shape = {{ type = "sphere", centre = [3, 0, 9], radius = 1 }}
surface = {{ type = "{lens}" }}
[[object]]
shape = {{ type = "disc", centre = [-3, 0, 9], normal = [0, 0, 1], radius = 1 }}
surface = {{ type = "{metric}", outside = [[1, 0, 0], [0, 1, 0], [0, 0, 4]] }}
[[object]]
shape = {{ type = "disc", centre = [-3, 3, 9], normal = [0, 0, 1], radius = 1 }}
surface = {{ type = "{rotating}", angle_deg = 30 }}
"#,
        studio = name("metatoy-window"),
        camera = name("finite-aperture"),
        shutter = name("entrance-pupil"),
        stereo = name("side-by-side"),
        mesh = name("triangle-mesh"),
        constant = name("constant-colour"),
        lens = name("luneburg-lens"),
        metric = name("metric-interface"),
        rotating = name("ray-rotating"),
    )
}

#[test]
fn old_snake_case_names_are_aliases_of_the_kebab_case_names() {
    let new = scene(false);
    let old = scene(true);
    assert_ne!(new, old, "the two spellings differ");
    assert!(new.contains("\"constant-colour\"") && old.contains("\"constant_colour\""));
    let new = file::parse(&new, "new.toml").unwrap_or_else(|e| panic!("{e}"));
    let old = file::parse(&old, "old.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(new, old);
}

#[test]
fn an_unknown_type_lists_the_kebab_case_names() {
    let text = "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"constant colour\", colour = [1, 0, 0] }\n";
    let e = file::parse(text, "s.toml").unwrap_err().to_string();
    assert!(e.contains("constant-colour"), "{e}");
    assert!(e.contains("s.toml:3:"), "located: {e}");
}
