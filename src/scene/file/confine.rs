//! Scene text confined to the scene file's directory (`timbre serve` reads text from its page
//! so): every file it reaches, through includes of includes and the meshes they name, must be
//! there, checked before the file is touched, except the files the user named.

use std::path::{Component, Path, PathBuf};

/// How a confined scene is read ([`super::parse_confined`]).
pub struct Confinement<'a> {
    /// Whether a file name in the scene text itself (not in a file it includes) is the user's
    /// own: that file, and every file it reaches, is read wherever it is.
    pub trusted: Box<dyn Fn(&str) -> bool + 'a>,
    /// Whether a name not trusted is refused even in the scene file's directory (a public
    /// server reads no file its pages name).
    pub only_trusted: bool,
}

/// A confinement at work: the scene file's directory, with symbolic links resolved.
pub(super) struct Within<'a> {
    root: Result<PathBuf, String>,
    rule: &'a Confinement<'a>,
}

impl<'a> Within<'a> {
    /// The confinement of the scene file at `scene`.
    pub(super) fn new(scene: &Path, rule: &'a Confinement<'a>) -> Within<'a> {
        let dir = match scene.parent() {
            Some(dir) if !dir.as_os_str().is_empty() => dir,
            _ => Path::new("."),
        };
        let root = dir
            .canonicalize()
            .map_err(|e| format!("the scene file's directory cannot be resolved: {e}"));
        Within { root, rule }
    }

    /// Whether `name`, given in the scene text itself, is the user's own.
    pub(super) fn trusts(&self, name: &str) -> bool {
        (self.rule.trusted)(name)
    }

    /// Refuses `path` (named `name`) unless it is in the scene file's directory, symbolic links
    /// followed; a file that does not exist is placed where it would be.
    pub(super) fn check(&self, name: &str, path: &Path) -> Result<(), String> {
        if self.rule.only_trusted {
            return Err(format!(
                "'{name}': a public server reads no file that its pages name"
            ));
        }
        let root = self.root.as_ref().map_err(String::clone)?;
        match resolve(path) {
            Some(p) if p.starts_with(root) => Ok(()),
            _ => Err(format!(
                "'{name}': only files in the scene file's directory may be named here"
            )),
        }
    }
}

/// `path` with its symbolic links resolved as far as it exists; the rest, which has no links,
/// taken as written (`..` drops the name before it).
fn resolve(path: &Path) -> Option<PathBuf> {
    let parts: Vec<Component> = path.components().collect();
    (0..=parts.len()).rev().find_map(|k| {
        let head: PathBuf = parts[..k].iter().collect();
        let head = if head.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            head
        };
        let mut at = head.canonicalize().ok()?;
        for part in &parts[k..] {
            match part {
                Component::ParentDir => {
                    at.pop();
                }
                Component::Normal(name) => at.push(name),
                _ => {}
            }
        }
        Some(at)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_resolved_through_links_and_past_their_end() {
        let dir = tempfile::TempDir::new().unwrap();
        let root = dir.path().canonicalize().unwrap();
        std::fs::create_dir(root.join("sub")).unwrap();
        std::os::unix::fs::symlink("/", root.join("sub/up")).unwrap();
        assert_eq!(resolve(&root.join("sub")), Some(root.join("sub")));
        // Not there: where it would be.
        assert_eq!(
            resolve(&root.join("sub/a/../b.toml")),
            Some(root.join("sub/b.toml"))
        );
        assert_eq!(
            resolve(&root.join("sub/../../x")),
            Some(root.parent().unwrap().join("x"))
        );
        // Through the link, there or not.
        assert_eq!(
            resolve(&root.join("sub/up/etc")),
            Some(PathBuf::from("/etc"))
        );
        assert_eq!(
            resolve(&root.join("sub/up/nowhere/x")),
            Some(PathBuf::from("/nowhere/x"))
        );
    }
}
