"""The examples work: both notebooks in examples/notebooks run headless (nbclient) without
errors and show their pictures, and examples/python/dask_sweep.py renders on a Dask
LocalCluster exactly what a single in-process render gives, bit for bit."""

from __future__ import annotations

import struct
import subprocess
import sys

import nbformat
import numpy as np
import pytest
from conftest import HANG, ROOT, SCENES
from dask.distributed import Client, LocalCluster
from nbclient import NotebookClient

import timbre

NOTEBOOKS = ROOT / "examples" / "notebooks"
EXAMPLES = ROOT / "examples" / "python"
FIG2A = SCENES / "fig2a-at-rest.toml"

# The Dask example is a script, not a package. On sys.path before the cluster starts, its
# functions are found by the worker processes too (they are spawned with this sys.path).
if str(EXAMPLES) not in sys.path:
    sys.path.insert(0, str(EXAMPLES))
import dask_sweep  # noqa: E402


def png_size(data: bytes) -> tuple[int, int]:
    """(width, height) from a PNG file's IHDR chunk."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG file"
    return struct.unpack(">II", data[16:24])


# ------------------------------------------------------------------------------- notebooks


def execute(name: str) -> nbformat.NotebookNode:
    """Runs a notebook as Jupyter does, in its own folder; a failing cell raises."""
    path = NOTEBOOKS / name
    nb = nbformat.read(path, as_version=4)
    before = sorted(p.name for p in NOTEBOOKS.iterdir())
    NotebookClient(
        nb, timeout=HANG, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOKS)}}
    ).execute()
    # Nothing written beside the notebooks.
    assert sorted(p.name for p in NOTEBOOKS.iterdir()) == before
    return nb


def pngs(cell: nbformat.NotebookNode) -> list[bytes]:
    import base64

    return [
        base64.b64decode(out["data"]["image/png"])
        for out in cell.get("outputs", [])
        if "image/png" in out.get("data", {})
    ]


@pytest.mark.parametrize("name", ["paper-figure.ipynb", "beta-sweep.ipynb"])
def test_notebooks_are_valid_and_committed_without_outputs(name):
    nb = nbformat.read(NOTEBOOKS / name, as_version=4)
    nbformat.validate(nb)
    assert nb.nbformat == 4
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code, "a notebook without code"
    for cell in code:
        assert cell.outputs == [] and cell.execution_count is None, cell.source[:60]


def test_paper_figure_notebook_shows_fig2_and_an_image():
    nb = execute("paper-figure.ipynb")
    code = [c for c in nb.cells if c.cell_type == "code"]
    shown = [p for c in code for p in pngs(c)]
    # The matplotlib figure of the three panels, and the last cell's Image by _repr_png_
    # at the notebook's default size.
    assert len(shown) == 2
    assert png_size(pngs(code[-1])[0]) == (320, 240)
    assert png_size(shown[0])[0] > png_size(shown[0])[1] * 2, "three panels side by side"


def test_beta_sweep_notebook_shows_a_figure():
    nb = execute("beta-sweep.ipynb")
    code = [c for c in nb.cells if c.cell_type == "code"]
    figures = [p for c in code for p in pngs(c)]
    assert len(figures) == 1
    width, height = png_size(figures[0])
    assert width > 400 and height > 200


# ------------------------------------------------------------------------------------ Dask


@pytest.fixture(scope="module")
def client():
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as cluster, Client(cluster) as client:
        yield client


def test_tile_bounds_cover_every_pixel_once():
    for width, height, tiles in [(7, 5, 3), (100, 75, (3, 4)), (10, 1, (10, 1))]:
        count = np.zeros((height, width), dtype=int)
        for x0, x1, y0, y1 in dask_sweep.tile_bounds(width, height, tiles):
            assert x0 < x1 and y0 < y1
            count[y0:y1, x0:x1] += 1
        assert (count == 1).all()
    with pytest.raises(ValueError):
        dask_sweep.tile_bounds(4, 4, 5)


# A scene of straight rays, and a relativistic finite-aperture camera whose samples take
# random pupil points and pixel offsets (so each pixel's samples must be the same whoever
# renders it); uneven tile sizes.
TILED = [
    ("fig2a-at-rest.toml", None, 100, 75, 2, (3, 4)),
    ("fig2a-at-rest.toml", {"camera.beta": [0.2, 0, 0.9]}, 64, 48, 1, 2),
    ("fig3-finite-aperture-0.99c.toml", None, 64, 48, 3, (4, 3)),
]


@pytest.mark.parametrize("name,overrides,width,height,spp,tiles", TILED)
def test_tiled_render_equals_a_single_render_bit_for_bit(
    client, name, overrides, width, height, spp, tiles
):
    path = SCENES / name
    image = dask_sweep.tiled(client, path, width, height, spp, tiles, overrides)
    want = timbre.load(path, set=overrides).render(width, height, spp=spp)
    assert image.dtype == np.float32 and image.shape == (height, width, 3)
    assert np.array_equal(image, want.view(np.ndarray))
    assert want.max() > 0.1, "not a black picture"


def test_sweep_renders_one_frame_per_beta(client):
    betas = [0.0, 0.5, 0.99]
    frames = dask_sweep.sweep(client, FIG2A, betas, 64, 48, spp=1)
    assert len(frames) == len(betas)
    for frame in frames:
        assert isinstance(frame, np.ndarray) and frame.dtype == np.float32
        assert frame.shape == (48, 64, 3)
    # beta = 0 is the scene file as it is; the others are its --set camera.beta.
    assert np.array_equal(frames[0], timbre.load(FIG2A).render(64, 48, spp=1).view(np.ndarray))
    fast = timbre.load(FIG2A, set={"camera.beta": [0, 0, 0.99]}).render(64, 48, spp=1)
    assert np.array_equal(frames[2], fast.view(np.ndarray))
    for i in range(len(frames)):
        for j in range(i + 1, len(frames)):
            assert not np.array_equal(frames[i], frames[j]), (betas[i], betas[j])


def test_the_script_runs_and_saves_its_frames(tmp_path):
    # As a user runs it (its own LocalCluster; the task functions sent from __main__).
    out = tmp_path / "frames.png"
    done = subprocess.run(
        [sys.executable, str(EXAMPLES / "dask_sweep.py"), "--width", "48", "--height", "36",
         "--frames", "3", "--tiles", "3", "-o", str(out)],
        capture_output=True, text=True, cwd=tmp_path, timeout=HANG,
    )
    assert done.returncode == 0, done.stderr
    assert "tiles of beta = 0.990c equal its frame: True" in done.stdout
    assert png_size(out.read_bytes()) == (3 * 48, 36)
