//! Builds timbre's C shim against the installed Embree and generates Rust bindings for the
//! shim's own header (never for Embree's headers).
//!
//! Embree is found by its header: `$EMBREE_DIR/include` when set, else the system include paths.
//! `embree4/rtcore.h` is preferred when present, `embree3/rtcore.h` otherwise.

use std::env;
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=vendor-headers/shim.h");
    println!("cargo:rerun-if-changed=vendor-headers/shim.c");
    println!("cargo:rerun-if-env-changed=EMBREE_DIR");

    let embree_dir = env::var_os("EMBREE_DIR").map(PathBuf::from);
    let mut include_dirs: Vec<PathBuf> = Vec::new();
    if let Some(dir) = &embree_dir {
        include_dirs.push(dir.join("include"));
        println!(
            "cargo:rustc-link-search=native={}",
            dir.join("lib").display()
        );
    }
    include_dirs.push(PathBuf::from("/usr/include"));
    include_dirs.push(PathBuf::from("/usr/local/include"));

    let has = |major: &str| {
        include_dirs
            .iter()
            .any(|d| d.join(format!("embree{major}/rtcore.h")).exists())
    };
    let (major, lib) = if has("4") {
        (4, "embree4")
    } else if has("3") {
        (3, "embree3")
    } else {
        panic!(
            "Embree headers not found (looked for embree4/rtcore.h and embree3/rtcore.h in {:?}). \
             Install Debian's libembree-dev (scripts/setup.sh does) or set EMBREE_DIR.",
            include_dirs
        );
    };

    let mut build = cc::Build::new();
    build
        .file("vendor-headers/shim.c")
        .include("vendor-headers")
        .opt_level(3);
    for d in &include_dirs {
        if d.exists() {
            build.include(d);
        }
    }
    if major == 4 {
        build.define("TIMBRE_EMBREE4", None);
    }
    build.compile("timbre_embree_shim");
    println!("cargo:rustc-link-lib={lib}");

    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    bindgen::Builder::default()
        .header(Path::new("vendor-headers/shim.h").to_string_lossy())
        .allowlist_function("timbre_.*")
        .allowlist_type("Timbre.*")
        .allowlist_var("TIMBRE_.*")
        .generate()
        .expect("bindgen could not read vendor-headers/shim.h")
        .write_to_file(out.join("shim.rs"))
        .expect("could not write the generated bindings");
}
