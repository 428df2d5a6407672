"""What the Python tests share: the repository, the command-line timbre to compare with, and
reading what it writes."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import OpenEXR
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
# The bound on every wait of the tests (seconds): reached only by a hang, far above any honest
# run on a 2-core machine kept busy by other work (speed is measured by benchmarks, not tests).
HANG = 300


@pytest.fixture(scope="session")
def timbre_cli() -> Path:
    """The command-line timbre (``$TIMBRE``, or target/release/timbre)."""
    path = Path(os.environ.get("TIMBRE", ROOT / "target" / "release" / "timbre"))
    if not path.is_file():
        pytest.fail(f"{path} not found: build it with `cargo build --release` or set TIMBRE")
    return path


def cli(timbre_cli: Path, *args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    """Runs the command-line timbre, which must succeed."""
    done = subprocess.run(
        [str(timbre_cli), *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=HANG
    )
    assert done.returncode == 0, f"timbre {' '.join(map(str, args))}: {done.stderr}"
    return done


def read_exr(path: Path) -> dict[str, np.ndarray]:
    """Every channel of an OpenEXR file by name (independently of timbre: the OpenEXR
    project's own Python bindings)."""
    with OpenEXR.File(str(path), separate_channels=True) as f:
        return {name: np.array(c.pixels) for name, c in f.channels().items()}


def exr_rgb(channels: dict[str, np.ndarray]) -> np.ndarray:
    return np.stack([channels["R"], channels["G"], channels["B"]], axis=-1)
