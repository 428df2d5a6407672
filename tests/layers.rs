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

/// The names a path continues with after `rest`'s start: one name, or the first name of each
/// item of a `{...}` group (`crate::{geometry::Shape, math::Ray}`).
fn first_names(rest: &str) -> Vec<String> {
    let word = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let Some(group) = rest.strip_prefix('{') else {
        return vec![word(rest)];
    };
    let (mut depth, mut items, mut start) = (0, Vec::new(), 0);
    for (k, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                items.push(&group[start..k]);
                break;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&group[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    items
        .into_iter()
        .map(word)
        .filter(|w| !w.is_empty())
        .collect()
}

/// For each byte of `code`, how many inline modules (`mod tests { ... }`) enclose it.
fn inline_depths(code: &str) -> Vec<usize> {
    let mut depths = Vec::with_capacity(code.len());
    let (mut braces, mut open): (usize, Vec<usize>) = (0, Vec::new());
    let mut pending = false;
    for (k, c) in code.char_indices() {
        if c == 'm' && code[k..].starts_with("mod ") {
            let before = code[..k].chars().next_back();
            pending = before.is_none_or(|b| !(b.is_alphanumeric() || b == '_'));
        }
        match c {
            ';' => pending = false,
            '{' => {
                braces += 1;
                if pending {
                    open.push(braces);
                    pending = false;
                }
            }
            '}' => {
                if open.last() == Some(&braces) {
                    open.pop();
                }
                braces = braces.saturating_sub(1);
            }
            _ => {}
        }
        depths.extend(std::iter::repeat_n(open.len(), c.len_utf8()));
    }
    depths
}

/// The top-level modules a file refers to: through `crate::name` (or a `crate::{...}`
/// group), or through `super::` chains that climb to the crate root.
fn referenced(module: &[String], code: &str) -> Vec<String> {
    let mut found = Vec::new();
    let starts_word = |i: usize| {
        code[..i]
            .chars()
            .next_back()
            .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
    };
    for (i, _) in code.match_indices("crate::") {
        if starts_word(i) {
            found.extend(first_names(&code[i + "crate::".len()..]));
        }
    }
    let inline = inline_depths(code);
    for (i, _) in code.match_indices("super::") {
        if !starts_word(i) || code[..i].ends_with("super::") {
            continue;
        }
        let mut rest = &code[i..];
        let mut depth = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            depth += 1;
            rest = r;
        }
        // A file's own module counts as one level (`super` of surfaces/lenses/mod.rs is
        // surfaces); each inline module around the path (`mod tests { ... }`) adds one more.
        if depth >= module.len() + inline[i] {
            found.extend(first_names(rest));
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
        .filter_map(|l| {
            let l = l.trim();
            l.strip_prefix("pub mod ")
                .or_else(|| l.strip_prefix("mod "))
        })
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
        let Some(&own_rank) = rank.get(own) else {
            violations.push(format!(
                "{} is in module {own}, which is in no layer",
                relative.display()
            ));
            continue;
        };
        // The top layer is the binary (main.rs and its modules): its `crate::` is the binary's
        // own root, and the library (`timbre::`) is all below it.
        if own_rank == layers.len() - 1 {
            continue;
        }
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
    // After an inline module closes, super:: counts from the file's module again.
    let embree = vec!["embree".to_string()];
    let text = code("mod ffi {\n    fn g() {}\n}\nuse super::math::Ray;\n");
    assert_eq!(referenced(&embree, &text), ["math"]);
    // Groups name each of their modules.
    let text = code("use crate::{geometry::{Hit, Shape}, math::Ray};\n");
    assert_eq!(referenced(&embree, &text), ["geometry", "math"]);
}

/// `code` with the contents of string literals (plain and raw) blanked out.
fn without_strings(code: &str) -> String {
    let mut out = String::with_capacity(code.len());
    let mut chars = code.chars().peekable();
    while let Some(c) = chars.next() {
        out.push(c);
        match c {
            '\'' if chars.peek() == Some(&'"') => out.extend(chars.next()),
            'r' if matches!(chars.peek(), Some('#' | '"')) => {
                let mut hashes = 0;
                while chars.peek() == Some(&'#') {
                    chars.next();
                    hashes += 1;
                }
                if chars.peek() != Some(&'"') {
                    continue;
                }
                chars.next();
                let close = format!("\"{}", "#".repeat(hashes));
                let mut body = String::new();
                for c in chars.by_ref() {
                    body.push(c);
                    if body.ends_with(&close) {
                        break;
                    }
                }
                out.push('"');
            }
            '"' => {
                let mut escaped = false;
                for c in chars.by_ref() {
                    if c == '"' && !escaped {
                        out.push('"');
                        break;
                    }
                    escaped = c == '\\' && !escaped;
                }
            }
            _ => {}
        }
    }
    out
}

/// `unsafe` appears in code only under src/embree, and `unsafe_code` is allowed nowhere but on
/// the embree module (Cargo.toml denies it for every target).
#[test]
fn unsafe_code_lives_only_in_the_embree_module() {
    let manifest = std::fs::read_to_string(Path::new(ROOT).join("Cargo.toml")).unwrap();
    assert!(
        manifest.contains("[lints.rust]\nunsafe_code = \"deny\""),
        "Cargo.toml denies unsafe code"
    );
    let mut unsafe_files = Vec::new();
    for dir in ["src", "tests", "benches", "examples"] {
        for file in sources(&Path::new(ROOT).join(dir)) {
            let relative = file.strip_prefix(ROOT).unwrap().to_path_buf();
            let text = without_strings(&code(&std::fs::read_to_string(&file).unwrap()));
            let allows = text.matches("allow(unsafe_code)").count();
            if relative == Path::new("src/lib.rs") {
                assert_eq!(allows, 1, "one allow, on the embree module");
                assert!(text.contains("#[allow(unsafe_code)]\npub mod embree;"));
            } else {
                assert_eq!(allows, 0, "{} allows unsafe code", relative.display());
            }
            let ident = |c: char| c.is_alphanumeric() || c == '_';
            let uses_unsafe = text.match_indices("unsafe").any(|(i, w)| {
                !text[..i].ends_with(ident) && !text[i + w.len()..].starts_with(ident)
            });
            if uses_unsafe {
                unsafe_files.push(relative);
            }
        }
    }
    assert!(
        unsafe_files.iter().all(|f| f.starts_with("src/embree")),
        "unsafe outside src/embree: {unsafe_files:?}"
    );
    assert!(!unsafe_files.is_empty(), "the embree module is found");
    assert_eq!(
        without_strings("a \"x \\\" unsafe\" b r#\"unsafe \"# c '\"' unsafe"),
        "a \"\" b r\" c '\"' unsafe"
    );
}

/// The sibling modules a file of `dir` names through `super::NAME` (one level up: the files
/// and folders beside it).
fn siblings_used(dir: &Path, text: &str) -> Vec<String> {
    let mut used = Vec::new();
    for (i, _) in text.match_indices("super::") {
        let before = text[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        for name in first_names(&text[i + "super::".len()..]) {
            let file = dir.join(format!("{name}.rs"));
            if (file.is_file() || dir.join(&name).join("mod.rs").is_file()) && !used.contains(&name)
            {
                used.push(name);
            }
        }
    }
    used
}

#[test]
fn no_two_files_of_a_module_use_each_other() {
    // Within a module, the files beside each other use one another in one direction only (no
    // circle such as devices -> placement -> shapes -> devices): each folder's graph of
    // `super::sibling` uses has no cycle.
    fn folders(dir: &Path, found: &mut Vec<PathBuf>) {
        found.push(dir.to_path_buf());
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders(&path, found);
            }
        }
    }
    let mut dirs = Vec::new();
    folders(&Path::new(ROOT).join("src"), &mut dirs);
    let mut edges = 0;
    for dir in dirs {
        // Each sibling (file or folder, not mod.rs) and the siblings it uses.
        let mut graph: BTreeMap<String, Vec<String>> = BTreeMap::new();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_stem().unwrap().to_string_lossy().to_string();
            let files = if path.is_dir() {
                sources(&path)
            } else if path.extension().is_some_and(|e| e == "rs") && name != "mod" {
                vec![path.clone()]
            } else {
                continue;
            };
            let mut used = Vec::new();
            for file in files {
                // Only this folder's own files look one level up to the siblings.
                if file.parent() != Some(&dir) {
                    continue;
                }
                let text = code(&std::fs::read_to_string(&file).unwrap());
                used.extend(
                    siblings_used(&dir, &text)
                        .into_iter()
                        .filter(|u| *u != name),
                );
            }
            edges += used.len();
            graph.insert(name, used);
        }
        // Depth-first search for a cycle.
        fn cycle(
            graph: &BTreeMap<String, Vec<String>>,
            node: &str,
            path: &mut Vec<String>,
        ) -> Option<Vec<String>> {
            if let Some(at) = path.iter().position(|n| n == node) {
                return Some(path[at..].to_vec());
            }
            path.push(node.to_string());
            for next in graph.get(node).into_iter().flatten() {
                if let Some(c) = cycle(graph, next, path) {
                    return Some(c);
                }
            }
            path.pop();
            None
        }
        for node in graph.keys() {
            if let Some(c) = cycle(&graph, node, &mut Vec::new()) {
                panic!("{}: {} use each other", dir.display(), c.join(" -> "));
            }
        }
    }
    assert!(
        edges > 20,
        "only {edges} uses of siblings found: is the finder broken?"
    );
}
