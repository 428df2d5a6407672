//! The layers of docs/ARCHITECTURE.md are kept: no module of the library refers to a module of a
//! layer above its own, nor to another module of its own layer. The layers are read from the
//! document itself, so the document and the code cannot drift apart.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The layers from the first ```text block after "## Layers", bottom layer first: each line
/// names a layer, then its top-level modules.
fn layers() -> Vec<(String, Vec<String>)> {
    let doc = std::fs::read_to_string(Path::new(ROOT).join("docs/ARCHITECTURE.md")).unwrap();
    let section = doc
        .split("\n## Layers")
        .nth(1)
        .expect("docs/ARCHITECTURE.md has a \"## Layers\" section");
    let block = section
        .split("```text\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("the Layers section has a ```text block");
    let mut layers: Vec<(String, Vec<String>)> = block
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let mut words = l.split_whitespace().map(|w| w.trim_end_matches(".rs"));
            let name = words.next().unwrap().to_string();
            (name, words.map(String::from).collect())
        })
        .collect();
    layers.reverse();
    layers
}

/// Every .rs file under `dir`.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(sources(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// The module path of a source file relative to src/ (`surfaces/lenses/mod.rs` → surfaces,
/// lenses).
fn module_path(relative: &Path) -> Vec<String> {
    let mut parts: Vec<String> = relative
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// The code of a source file without comments (doc links may point anywhere).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules a file refers to: through `crate::name`, or through `super::`
/// chains that climb to the crate root.
fn referenced(module: &[String], code: &str) -> Vec<String> {
    let mut found = Vec::new();
    let word = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    for (i, _) in code.match_indices("crate::") {
        let before = code[..i].chars().next_back();
        if before.is_none_or(|c| !(c.is_alphanumeric() || c == '_')) {
            found.push(word(&code[i + "crate::".len()..]));
        }
    }
    for (i, _) in code.match_indices("super::") {
        if code[..i].ends_with("super::") {
            continue;
        }
        let mut rest = &code[i..];
        let mut depth = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            depth += 1;
            rest = r;
        }
        // A file's own module counts as one level (`super` of surfaces/lenses/mod.rs is
        // surfaces); each inline module opened before (`mod tests {`) adds one more.
        let inline = code[..i]
            .lines()
            .filter(|l| {
                let l = l.trim_start();
                (l.starts_with("mod ") || l.starts_with("pub mod ")) && l.ends_with('{')
            })
            .count();
        if depth >= module.len() + inline {
            found.push(word(rest));
        }
    }
    found
}

#[test]
fn no_module_refers_to_a_layer_above_or_beside_its_own() {
    let layers = layers();
    assert!(layers.len() >= 5, "layers: {layers:?}");
    let rank: BTreeMap<&str, usize> = layers
        .iter()
        .enumerate()
        .flat_map(|(k, (_, modules))| modules.iter().map(move |m| (m.as_str(), k)))
        .collect();

    // Every module of the library is in exactly one layer.
    let lib = std::fs::read_to_string(Path::new(ROOT).join("src/lib.rs")).unwrap();
    let declared: Vec<String> = code(&lib)
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|m| m.trim_end_matches(';').to_string())
        .collect();
    assert!(declared.len() >= 10, "modules of src/lib.rs: {declared:?}");
    for m in &declared {
        assert!(rank.contains_key(m.as_str()), "module {m} is in no layer");
    }
    let listed: usize = layers.iter().map(|(_, m)| m.len()).sum();
    assert_eq!(listed, rank.len(), "a module is listed twice: {layers:?}");

    let src = Path::new(ROOT).join("src");
    let mut violations = Vec::new();
    let mut checked = 0;
    for file in sources(&src) {
        let relative = file.strip_prefix(&src).unwrap();
        let module = module_path(relative);
        let own = module[0].as_str();
        if own == "lib" {
            continue;
        }
        let own_rank = rank[own];
        let text = code(&std::fs::read_to_string(&file).unwrap());
        for target in referenced(&module, &text) {
            checked += 1;
            if target == own {
                continue;
            }
            match rank.get(target.as_str()) {
                Some(&r) if r < own_rank => {}
                Some(&r) => violations.push(format!(
                    "{} ({}, layer {}) refers to {target} (layer {})",
                    relative.display(),
                    own,
                    layers[own_rank].0,
                    layers[r].0
                )),
                None => violations.push(format!(
                    "{} refers to crate::{target}, which is in no layer",
                    relative.display()
                )),
            }
        }
    }
    assert!(
        checked > 100,
        "only {checked} references found: is the parser broken?"
    );
    assert!(violations.is_empty(), "{}", violations.join("\n"));
}

#[test]
fn the_reference_finder_sees_crate_and_super_paths() {
    let module = vec!["surfaces".to_string(), "lenses".to_string()];
    let text = code(
        "use crate::geometry::Shape;\nuse super::super::render::Tracer; // crate::scene\n\
         fn f() { crate::math::Ray::new(); super::Redirection::Lost }\n\
         mod tests {\n    use super::super::*;\n    use super::super::super::io::X;\n}",
    );
    assert_eq!(
        referenced(&module, &text),
        ["geometry", "math", "render", "io"],
        "crate:: paths, and super:: only where it climbs out of the crate's top module"
    );
}
