//! One naming scheme: kebab-case values in scene files, with every older spelling still
//! accepted as an alias that means exactly the same (docs/SCENE_FORMAT.md, "Names").

use timbre::scene::file;

/// A sphere to carry a surface under test.
const SPHERE: &str = "shape = { type = \"sphere\", centre = [0, 0, 9], radius = 1 }";

/// (scene text with `@` where the name goes, the name, its older spellings).
fn aliases() -> Vec<(String, &'static str, Vec<String>)> {
    let surface =
        |extra: &str| format!("[[object]]\n{SPHERE}\nsurface = {{ type = \"@\"{extra} }}\n");
    let snake = |kebab: &str| vec![kebab.replace('-', "_")];
    let mut table = vec![
        ("studio = \"@\"\n".to_string(), "metatoy-window", snake("metatoy-window")),
        (
            "[camera]\ntype = \"@\"\naperture_radius = 0.1\n".to_string(),
            "finite-aperture",
            snake("finite-aperture"),
        ),
        (
            "[[object]]\nshape = { type = \"@\", vertices = [[0, 0, 5], [1, 0, 5], [0, 1, 5]], triangles = [[0, 1, 2]] }\nsurface = { type = \"matt\", colour = [1, 1, 1] }\n".to_string(),
            "triangle-mesh",
            snake("triangle-mesh"),
        ),
        (surface(", colour = [1, 0, 0]"), "constant-colour", snake("constant-colour")),
        (surface(""), "luneburg-lens", snake("luneburg-lens")),
        (surface(""), "eaton-lens", snake("eaton-lens")),
        (surface(""), "maxwell-fisheye-lens", snake("maxwell-fisheye-lens")),
        (surface(", r = 2, r_prime = 3, phi_deg = 30"), "ggrin-lens", snake("ggrin-lens")),
        (
            surface(", rho = [0, 1], n = [1.5, 1]"),
            "gradient-index-lens",
            snake("gradient-index-lens"),
        ),
        (surface(""), "metric-interface", snake("metric-interface")),
        (
            surface(", a = [0, 0, 1], u = [1, 0, 0], eta_u = -1, eta_v = -1"),
            "confocal-lenslet-arrays",
            vec!["confocal_lenslet_arrays".into(), "gcla".into()],
        ),
        (surface(""), "ray-rotating", snake("ray-rotating")),
        (
            surface(""),
            "ray-rotating-in-plane-of-incidence",
            snake("ray-rotating-in-plane-of-incidence"),
        ),
        (surface(""), "ray-flipping", snake("ray-flipping")),
        (
            "[[object]]\nshape = { type = \"disc\", centre = [0, 0, 9], normal = [0, 0, 1], radius = 1 }\nsurface = { type = \"@\", phase = { type = \"linear\", gradient = [0.1, 0] } }\n".to_string(),
            "phase-hologram",
            snake("phase-hologram"),
        ),
        (surface(""), "phase-conjugating", snake("phase-conjugating")),
        (surface(", beta = [0, 0, 0.5]"), "lorentz-window", snake("lorentz-window")),
        (surface(", beta = [0, 0, 0.5]"), "galileo-window", snake("galileo-window")),
        // A device's lens type, by Dr TIM's names of it in its several enums.
        (
            "[[device]]\nlenses = { type = \"ideal-lens-cloak\", lens_element_type = \"@\" }\n"
                .to_string(),
            "lens-hologram",
            vec![
                "phase-hologram-of-lens".into(),
                "quadratic-lens-phase-hologram".into(),
            ],
        ),
        (
            "[[device]]\nlenses = { type = \"clas\", lenslet_array_type = \"@\" }\n".to_string(),
            "semitransparent-plane",
            vec!["semi-transparent-plane".into()],
        ),
    ];
    for shutter in [
        "detector-plane",
        "entrance-pupil",
        "focus-surface",
        "arbitrary-plane",
        "fixed-point-surface",
    ] {
        let text = "[camera]\nbeta = [0, 0, 0.5]\nshutter = \"@\"\n".to_string();
        table.push((text, shutter, snake(shutter)));
    }
    for lens_type in ["ideal-lens", "lens-hologram"] {
        let text = "[camera]\nshutter = \"detector-plane\"\nlens_type = \"@\"\n".to_string();
        table.push((text, lens_type, snake(lens_type)));
    }
    for stereo in [
        "side-by-side",
        "side-by-side-half",
        "top-bottom",
        "top-bottom-half",
    ] {
        table.push((
            "[camera]\nstereo = \"@\"\n".to_string(),
            stereo,
            snake(stereo),
        ));
    }
    table.push((
        "[camera]\nstereo = \"@\"\n".to_string(),
        "colour-anaglyph",
        vec!["colour_anaglyph".into(), "color-anaglyph".into()],
    ));
    table
}

fn parse(text: &str) -> timbre::scene::SceneDescription {
    file::parse(text, "names.toml").unwrap_or_else(|e| panic!("{e}\nin:\n{text}"))
}

#[test]
fn every_older_spelling_is_an_alias_of_the_kebab_case_name() {
    let table = aliases();
    // Every alias the library declares (each kind's keys are read in its own file) is in the
    // table (or is a coefficient key, tested below).
    let mut declared = Vec::new();
    let mut dirs = vec![std::path::PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/src"
    ))];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
                continue;
            }
            let source = std::fs::read_to_string(path).unwrap();
            for piece in source.split("alias = \"").skip(1) {
                declared.push(piece.split('"').next().unwrap().to_string());
            }
        }
    }
    assert!(declared.len() >= 25, "{declared:?}");
    for alias in &declared {
        let tested = table.iter().any(|(_, _, older)| older.contains(alias));
        assert!(
            tested || ["reflection", "transmission"].contains(&alias.as_str()),
            "alias {alias} is not tested"
        );
    }
    for (text, name, older) in table {
        let new = parse(&text.replace('@', name));
        for old in older {
            assert_ne!(name, old);
            assert_eq!(parse(&text.replace('@', &old)), new, "{old} means {name}");
        }
    }
}

#[test]
fn the_older_coefficient_keys_are_aliases() {
    for (surface, key) in [
        ("\"mirror\"", "reflection"),
        ("\"phase-conjugating\"", "reflection"),
        ("\"refractive\", index_ratio = 1.5", "transmission"),
        ("\"transparent\"", "transmission"),
        ("\"luneburg-lens\"", "transmission"),
        ("\"ray-flipping\"", "transmission"),
    ] {
        let text = |extra: &str| {
            format!("[[object]]\n{SPHERE}\nsurface = {{ type = {surface}{extra} }}\n")
        };
        let new = parse(&text(&format!(", {key}_coefficient = 0.25")));
        assert_eq!(
            parse(&text(&format!(", {key} = 0.25"))),
            new,
            "{key} in {surface}"
        );
        assert_ne!(parse(&text("")), new, "the coefficient is read");
    }
}

#[test]
fn an_unknown_type_lists_the_kebab_case_names() {
    let text = "[[object]]\nshape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }\nsurface = { type = \"constant colour\", colour = [1, 0, 0] }\n";
    let e = file::parse(text, "s.toml").unwrap_err().to_string();
    assert!(e.contains("constant-colour"), "{e}");
    assert!(e.contains("s.toml:3:"), "located: {e}");
}
