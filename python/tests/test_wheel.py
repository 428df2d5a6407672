"""The wheel: built by maturin with its native libraries bundled (auditwheel repair), it installs
into a fresh virtual environment and renders there what the command line renders, with Embree
and TBB loaded from the wheel, not from the system."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
from conftest import ROOT, cli, exr_rgb, read_exr


def run(*args, **kwargs) -> subprocess.CompletedProcess:
    done = subprocess.run(list(map(str, args)), capture_output=True, text=True, timeout=900, **kwargs)
    assert done.returncode == 0, f"{' '.join(map(str, args))}:\n{done.stdout}\n{done.stderr}"
    return done


def test_the_wheel_bundles_its_libraries_installs_fresh_and_renders(timbre_cli, tmp_path):
    wheels = tmp_path / "wheels"
    # As the docs say to build it (maturin build --auditwheel repair).
    run(ROOT / "scripts" / "build-wheel.sh", wheels, cwd=ROOT)
    [wheel] = wheels.glob("timbre_optics-*.whl")
    # A manylinux wheel for every CPython from 3.9 (the stable ABI), with Embree and TBB inside
    # it, and the example scenes as package data.
    assert "manylinux" in wheel.name and "-cp39-abi3-" in wheel.name, wheel.name
    names = zipfile.ZipFile(wheel).namelist()
    assert any(n.startswith("timbre_optics.libs/libembree3") for n in names), names
    assert any(n.startswith("timbre_optics.libs/libtbb") for n in names), names
    assert not any(n.startswith("tests/") or n.endswith("Cargo.toml") for n in names), names
    assert "timbre/scenes/fig2a-at-rest.toml" in names and "timbre/scenes/meshes/prism.obj" in names

    fresh = tmp_path / "fresh"
    run(sys.executable, "-m", "venv", fresh)
    python = fresh / "bin" / "python"
    # Installed without a Rust toolchain on PATH (nothing is compiled: a binary wheel).
    bare = {**os.environ, "PATH": "/usr/bin:/bin"}
    run(python, "-m", "pip", "install", "--quiet", "--disable-pip-version-check", wheel, env=bare)

    exr = tmp_path / "studio.exr"
    cli(timbre_cli, "render", "--width", 48, "--height", 36, "--spp", 2, "-q", "-o", exr)
    want = tmp_path / "want.npy"
    np.save(want, exr_rgb(read_exr(exr)))
    script = textwrap.dedent(
        f"""
        import sys, numpy as np, timbre
        assert timbre.__file__.startswith({str(fresh)!r}), timbre.__file__
        image = timbre.studio().render(48, 36, spp=2)
        assert np.array_equal(image.view(np.ndarray), np.load({str(want)!r}))
        assert timbre.example("mesh").render(16, 12).shape == (12, 16, 3)
        print(timbre._timbre.__file__)
        """
    )
    # Run away from the source tree, with no library path of its own and no Rust toolchain.
    clean = {k: v for k, v in os.environ.items() if k not in ("LD_LIBRARY_PATH", "PYTHONPATH")}
    clean["PATH"] = "/usr/bin:/bin"
    assert shutil.which("cargo", path=clean["PATH"]) is None
    module = run(python, "-c", script, cwd=tmp_path, env=clean).stdout.strip()
    # The dynamic linker finds Embree and TBB in the wheel's timbre_optics.libs/, next to the module.
    libs = Path(module).parent.parent / "timbre_optics.libs"
    linked = run("ldd", module, env=clean).stdout
    for name in ("libembree3", "libtbb"):
        [line] = [l for l in linked.splitlines() if name in l]
        found = Path(line.split("=>")[1].split("(")[0].strip())
        assert found.resolve().parent == libs.resolve(), linked
