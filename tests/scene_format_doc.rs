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
    let fragment = "```toml\n[object.shape]\ntype = \"sphere\"\ncentre = [0, 0, 5]\n```\n";
    let e = check(&device, "test.md", &toml_blocks(fragment).unwrap()[0]).unwrap_err();
    assert!(e.contains("radius"), "{e}");
    assert!(toml_blocks("```toml\nstudio = \"none\"\n").is_err());
    // Mesh files are found in scenes/.
    let mesh = "```toml\n[object.shape]\ntype = \"mesh\"\nfile = \"meshes/prism.obj\"\n```\n";
    check(&device, "test.md", &toml_blocks(mesh).unwrap()[0]).unwrap();
}
