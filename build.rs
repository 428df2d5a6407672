//! Builds timbre's C shim against the installed Embree and generates Rust bindings for the
//! shim's own header (never for Embree's headers).
//!
//! The Embree major version follows the `embree4` cargo feature, never what happens to be
//! installed: without it, Embree 3 (`embree3/rtcore.h`, `-lembree3`: Debian 12's
//! libembree-dev); with it, Embree 4 (`embree4/rtcore.h`, `-lembree4`, and the shim compiled
//! with `TIMBRE_EMBREE4`). The header is looked for in `$EMBREE_DIR/include` when set, then in
//! the system include paths; the library in `$EMBREE_DIR/lib` (added to the binaries' rpath, so
//! that they run without `LD_LIBRARY_PATH`), then in the system's.

use std::env;
use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=vendor-headers/shim.h");
    println!("cargo:rerun-if-changed=vendor-headers/shim.c");
    println!("cargo:rerun-if-env-changed=EMBREE_DIR");
    println!("cargo:rerun-if-env-changed=OIDN_DIR");
    // The `denoise` feature links Open Image Denoise from $OIDN_DIR/lib (the oidn crate's build
    // finds it there): the binaries find it at run time through their rpath.
    if env::var_os("CARGO_FEATURE_DENOISE").is_some() {
        match env::var_os("OIDN_DIR").filter(|d| !d.is_empty()) {
            Some(dir) => println!(
                "cargo:rustc-link-arg=-Wl,-rpath,{}",
                Path::new(&dir).join("lib").display()
            ),
            None => println!(
                "cargo:warning=the denoise feature needs Open Image Denoise: run scripts/setup-oidn.sh and build with OIDN_DIR=target/oidn"
            ),
        }
    }

    let embree4 = env::var_os("CARGO_FEATURE_EMBREE4").is_some();
    let (major, lib) = if embree4 {
        (4, "embree4")
    } else {
        (3, "embree3")
    };

    let embree_dir = env::var_os("EMBREE_DIR")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from);
    let mut include_dirs: Vec<PathBuf> = Vec::new();
    if let Some(dir) = &embree_dir {
        include_dirs.push(dir.join("include"));
    }
    include_dirs.push(PathBuf::from("/usr/include"));
    include_dirs.push(PathBuf::from("/usr/local/include"));

    let header = format!("embree{major}/rtcore.h");
    let Some(found) = include_dirs.iter().find(|d| d.join(&header).exists()) else {
        let looked = include_dirs
            .iter()
            .map(|d| d.display().to_string())
            .collect::<Vec<_>>()
            .join(", ");
        let other = format!("embree{}/rtcore.h", if embree4 { 3 } else { 4 });
        let other_found = include_dirs.iter().find(|d| d.join(&other).exists());
        let how = if let (false, Some(d)) = (embree4, other_found) {
            format!(
                "Embree 4 is installed ({} exists; Debian 13's libembree-dev is Embree 4): \
                 build with `--features embree4`, or install Embree 3 (Debian 12's libembree-dev).",
                d.join(&other).display()
            )
        } else if embree4 {
            "The `embree4` feature builds against Embree 4. On Debian 12, install it with \
             scripts/setup-embree4.sh (from PyPI's embreex wheel and the embree4-sys crate) and \
             set EMBREE_DIR to the directory it prints (target/embree4 by default); on Debian 13, \
             `apt-get install libembree-dev` provides it in the system paths. Or build without \
             `--features embree4` for Debian 12's Embree 3."
                .to_string()
        } else {
            "Install Debian's libembree-dev (scripts/setup.sh does), or set EMBREE_DIR to a \
             directory with include/embree3/ and lib/libembree3.so. (For Embree 4, build with \
             `--features embree4`.)"
                .to_string()
        };
        panic!("Embree {major} headers not found: no {header} in {looked}. {how}");
    };
    // A different Embree installed over this one rebuilds the shim.
    let config = found.join(format!("embree{major}/rtcore_config.h"));
    if config.exists() {
        println!("cargo:rerun-if-changed={}", config.display());
    }

    if let Some(dir) = &embree_dir {
        let lib_dir = dir.join("lib");
        let so = lib_dir.join(format!("lib{lib}.so"));
        if *found == dir.join("include") && !so.exists() {
            panic!(
                "EMBREE_DIR={} has Embree {major}'s headers but no {}: the linker needs it \
                 (scripts/setup-embree4.sh lays out both for Embree 4).",
                dir.display(),
                so.display()
            );
        }
        if lib_dir.exists() {
            println!("cargo:rustc-link-search=native={}", lib_dir.display());
            // Embree 4 from EMBREE_DIR is not in the loader's paths: the binaries, tests and
            // benchmarks find it through their rpath.
            if embree4 {
                println!("cargo:rustc-link-arg=-Wl,-rpath,{}", lib_dir.display());
            }
        }
    }

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
    if embree4 {
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
