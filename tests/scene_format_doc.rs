//! Every TOML example in `docs/SCENE_FORMAT.md` is a valid scene: each ```` ```toml ```` block
//! (also one indented in a list item) is read by the scene-file loader, as `timbre check` reads
//! a file, and built into an Embree scene, as `timbre render` builds it.
//!
//! Most blocks are whole scene files. A block whose first table header is a sub-table of an
//! object, `[object.shape]` or `[object.surface]`, shows one table of an object; it is read as
//! the only `[[object]]` of a scene, given a parallelogram shape or a matt surface when it
//! lacks that table (see [`completed`]). Relative file names (meshes, includes) resolve in
//! `scenes/`, beside the complete example scenes and their meshes.

use std::path::{Path, PathBuf};

use timbre::embree::Device;
use timbre::scene::Scene;
use timbre::scene::file;
use timbre::{stereo, trajectories};

/// One ```` ```toml ```` block: its text, without the fence's indentation, and the line of
/// the Markdown file it starts on (1-based, the line after the opening fence).
#[derive(Debug)]
struct Block {
    line: usize,
    text: String,
}

/// The ```` ```toml ```` blocks of `markdown`. An opening fence without its closing one is an
/// error.
fn toml_blocks(markdown: &str) -> Result<Vec<Block>, String> {
    let mut blocks = Vec::new();
    let mut lines = markdown.lines().enumerate();
    while let Some((i, line)) = lines.next() {
        if line.trim_start() != "```toml" {
            continue;
        }
        let indent = line.len() - line.trim_start().len();
        let mut text = String::new();
        loop {
            let Some((_, l)) = lines.next() else {
                return Err(format!("the ```toml block on line {} is not closed", i + 1));
            };
            if l.trim() == "```" {
                break;
            }
            // Strip the fence's indentation (never more than the line's own).
            let strip = indent.min(l.len() - l.trim_start().len());
            text.push_str(&l[strip..]);
            text.push('\n');
        }
        blocks.push(Block { line: i + 2, text });
    }
    Ok(blocks)
}

/// The scene-file text for a block: the block itself, or for an object fragment (first table
/// header `[object.…]`) the block inside an `[[object]]` with the shape or surface it lacks.
/// Lines keep their numbers, shifted by the lines put in front.
fn completed(block: &str) -> String {
    let first_header = block.lines().map(str::trim).find(|l| l.starts_with('['));
    if !first_header.is_some_and(|h| h.starts_with("[object.")) {
        return block.to_string();
    }
    let has = |table: &str| {
        block
            .lines()
            .map(str::trim)
            .any(|l| l == format!("[object.{table}]") || l.starts_with(&format!("{table} =")))
    };
    let mut scene = String::from("[[object]]\nname = \"fragment\"\n");
    if !has("shape") {
        scene.push_str(
            "shape = { type = \"parallelogram\", corner = [-1, -1, 5], span_u = [2, 0, 0], \
             span_v = [0, 2, 0] }\n",
        );
    }
    if !has("surface") {
        scene.push_str("surface = { type = \"matt\", colour = [1, 1, 1] }\n");
    }
    scene + block
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Reads and builds one block; the error names the block's line in `doc`.
fn check(device: &Device, doc: &str, block: &Block) -> Result<(), String> {
    let text = completed(&block.text);
    // The name locates relative file names in scenes/ and appears in the loader's messages.
    let name: PathBuf = root()
        .join("scenes")
        .join(format!("SCENE_FORMAT.md-line-{}.toml", block.line));
    let fail = |e: String| {
        format!(
            "the ```toml block on line {} of {doc}: {e}\n{text}",
            block.line
        )
    };
    let description =
        file::parse(&text, &name.to_string_lossy()).map_err(|e| fail(e.to_string()))?;
    let r = &description.render;
    stereo::validate(&description.stereo, r.width, r.height).map_err(fail)?;
    let drawn = trajectories::draw(device, &description).map_err(|e| fail(e.to_string()))?;
    Scene::build(device, &drawn).map_err(|e| fail(e.to_string()))?;
    Ok(())
}

#[test]
fn every_toml_block_of_the_scene_format_is_a_valid_scene() {
    let doc = "docs/SCENE_FORMAT.md";
    let markdown = std::fs::read_to_string(root().join(doc)).expect("docs/SCENE_FORMAT.md");
    let blocks = toml_blocks(&markdown).unwrap();
    // Every opening fence was found, indented ones too.
    assert_eq!(blocks.len(), markdown.matches("```toml\n").count());
    assert!(!blocks.is_empty(), "no ```toml block in {doc}");
    let device = Device::new("").expect("Embree device");
    let failures: Vec<String> = blocks
        .iter()
        .filter_map(|b| check(&device, doc, b).err())
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn the_first_example_is_the_glass_ball_in_the_lattice() {
    // The page's opening example, as its text describes it and `timbre check` summarises it.
    let markdown = std::fs::read_to_string(root().join("docs/SCENE_FORMAT.md")).unwrap();
    let first = &toml_blocks(&markdown).unwrap()[0];
    let d = file::parse(&first.text, "example.toml").unwrap();
    assert_eq!(d.summary().objects, 51);
    assert_eq!(d.lights.points.len(), 1);
    let r = &d.render;
    assert_eq!((r.width, r.height, r.spp), (640, 480, 4));
    assert!(d.objects.iter().any(|o| o.name == "glass ball"));
}

#[test]
fn a_bad_block_fails_the_check() {
    let markdown = "Text.\n\n```toml\nstudio = \"lattice\"\n```\n\n  ```toml\n  [render]\n  hieght = 4\n  ```\n";
    let blocks = toml_blocks(markdown).unwrap();
    assert_eq!(blocks.len(), 2);
    assert_eq!(
        (blocks[1].line, blocks[1].text.as_str()),
        (8, "[render]\nhieght = 4\n")
    );
    let device = Device::new("").unwrap();
    check(&device, "test.md", &blocks[0]).unwrap();
    let e = check(&device, "test.md", &blocks[1]).unwrap_err();
    assert!(
        e.contains("line 8 of test.md") && e.contains("unknown field `hieght`"),
        "{e}"
    );
    // A fragment is completed, and a bad fragment still fails.
    let fragment = &toml_blocks("```toml\n[object.surface]\ntype = \"mirror\"\n```\n").unwrap()[0];
    check(&device, "test.md", fragment).unwrap();
    let fragment = "```toml\n[object.shape]\ntype = \"ellipsoid\"\ncentre = [0, 0, 5]\n```\n";
    let e = check(&device, "test.md", &toml_blocks(fragment).unwrap()[0]).unwrap_err();
    assert!(e.contains("semi_axes"), "{e}");
    assert!(toml_blocks("```toml\nstudio = \"none\"\n").is_err());
    // Mesh files are found in scenes/.
    let mesh = "```toml\n[object.shape]\ntype = \"mesh\"\nfile = \"meshes/prism.obj\"\n```\n";
    check(&device, "test.md", &toml_blocks(mesh).unwrap()[0]).unwrap();
}

/// `text` with the key `zzz = 1` added to the table whose `type = "…"` starts at byte `at`: on
/// the next line of a table given by its header, after the type in an inline table.
fn with_unknown_key(text: &str, at: usize) -> String {
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let value_end = at + text[at..].find('"').unwrap() + 1;
    let value_end = value_end + text[value_end..].find('"').unwrap() + 1;
    let inline = !text[line_start..at].trim().is_empty();
    let added = if inline { ", zzz = 1" } else { "\nzzz = 1" };
    format!("{}{added}{}", &text[..value_end], &text[value_end..])
}

/// Every example there is: (where it is, its text, the path it is read as) for each TOML block
/// of the documentation (completed) and each example scene.
fn examples() -> Vec<(String, String, PathBuf)> {
    let doc = "docs/SCENE_FORMAT.md";
    let markdown = std::fs::read_to_string(root().join(doc)).unwrap();
    let in_scenes = root().join("scenes").join("SCENE_FORMAT.md-example.toml");
    let mut examples: Vec<(String, String, PathBuf)> = toml_blocks(&markdown)
        .unwrap()
        .into_iter()
        .map(|b| {
            let at = format!("line {} of {doc}", b.line);
            (at, completed(&b.text), in_scenes.clone())
        })
        .collect();
    // The example scenes, the research programs' figures among them.
    let mut scenes: Vec<PathBuf> = ["scenes", "scenes/research"]
        .iter()
        .flat_map(|dir| std::fs::read_dir(root().join(dir)).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    scenes.sort();
    for path in scenes {
        let text = std::fs::read_to_string(&path).unwrap();
        examples.push((path.display().to_string(), text, path));
    }
    examples
}

#[test]
fn every_table_with_a_type_refuses_a_key_it_does_not_know() {
    // Each kind (law, shape, device, phase, camera, light, ...) reads its own keys in its own
    // file; none may take a key it does not know without a word. Every `type = "…"` of every
    // example gets an extra key, which must be refused.
    let mut tables = 0;
    let mut failures = Vec::new();
    for (at, text, path) in examples() {
        let path = path.to_string_lossy();
        if file::parse(&text, &path).is_err() {
            continue; // reported by every_toml_block_of_the_scene_format_is_a_valid_scene
        }
        for (start, _) in text.match_indices("type = \"") {
            let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
            if text[line_start..].trim_start().starts_with('#') {
                continue; // a comment
            }
            if text[..start].ends_with(|c: char| c == '_' || c.is_ascii_alphanumeric()) {
                continue; // a key ending in `type` (`lens_type`), not a table's type
            }
            tables += 1;
            let changed = with_unknown_key(&text, start);
            match file::parse(&changed, &path) {
                Err(e) if e.to_string().contains("unknown field `zzz`") => {}
                other => failures.push(format!("{at}: {:?}\n{changed}", other.map(|_| "accepted"))),
            }
        }
    }
    assert!(tables > 150, "only {tables} tables with a type");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn every_kind_has_an_example() {
    // The kinds of each table with a `type`, as the loader lists them for an unknown one, each
    // shown in a TOML example of the documentation or an example scene (and so each also
    // checked by the test above).
    let examples: String = examples().into_iter().map(|(_, text, _)| text).collect();
    let sphere = "shape = { type = \"sphere\", centre = [0, 0, 5], radius = 1 }";
    let matt = "surface = { type = \"matt\", colour = [1, 1, 1] }";
    let mut missing = Vec::new();
    for table in [
        format!("[[object]]\nshape = {{ type = \"zzz\" }}\n{matt}\n"),
        format!("[[object]]\n{sphere}\nsurface = {{ type = \"zzz\" }}\n"),
        "[[device]]\nlenses = { type = \"zzz\" }\n".to_string(),
        "[[device]]\naid = { type = \"zzz\" }\n".to_string(),
        "[[object]]\nshape = { type = \"disc\", centre = [0, 0, 5], normal = [0, 0, 1], \
         radius = 1 }\nsurface = { type = \"phase-hologram\", phase = { type = \"zzz\" } }\n"
            .to_string(),
    ] {
        let e = file::parse(&table, "kinds.toml").unwrap_err().to_string();
        let listed = e.split("expected ").nth(1).expect("the kinds listed");
        let names: Vec<&str> = listed.split('`').skip(1).step_by(2).collect();
        assert!(names.len() >= 2, "{e}");
        // Older spellings with underscores are aliases (tests/names.rs).
        for name in names.into_iter().filter(|n| !n.contains('_')) {
            if !examples.contains(&format!("type = \"{name}\"")) {
                missing.push(name.to_string());
            }
        }
    }
    assert!(missing.is_empty(), "no example of {missing:?}");
}
