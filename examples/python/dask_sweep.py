"""Rendering timbre scenes with Dask: a sweep of camera speeds, and one image cut into tiles.

Run it from the repository root (the package installed, e.g. ``source target/python/bin/activate``)::

    python examples/python/dask_sweep.py                      # prints a summary
    python examples/python/dask_sweep.py -o sweep.png         # also saves the frames side by side
    python examples/python/dask_sweep.py -o sweep.npz         # ... or every array, for numpy

It starts a ``LocalCluster`` of two single-threaded worker processes and

- ``sweep``: renders one frame per speed beta of the camera along its view direction
  (``camera.beta = [0, 0, beta]``, the relativistic aberration of Dr TIM's Fig. 2), one task
  per frame;
- ``tiled``: renders one image as a grid of tiles (``render(pixel_bounds=...)``), one task per
  tile, and puts the tiles together with numpy. The result equals a single render bit for bit:
  each pixel's samples depend only on (seed, pixel, sample), not on who renders it.

Scenes are not picklable, so each task gets the scene file's path and its overrides and loads
the scene on the worker. The path must be readable there (on a cluster: a shared filesystem).

On a Slurm cluster, use dask-jobqueue (``pip install dask-jobqueue``) instead of the
``LocalCluster``, with one single-threaded worker process per core, in the environment that
has timbre installed::

    from dask_jobqueue import SLURMCluster
    cluster = SLURMCluster(cores=16, processes=16, memory="32GB", walltime="01:00:00",
                           python="/path/to/env/bin/python")   # plus queue=/account= as needed
    cluster.scale(jobs=4)                                      # 4 nodes' worth of workers
    client = Client(cluster)
    frames = sweep(client, "/shared/scenes/fig2a-at-rest.toml", betas, 1920, 1080, spp=16)

The workers must be able to import the task functions: running this file as a script sends
them by value; when importing it from elsewhere, put it on the workers' path or call
``client.upload_file("dask_sweep.py")``.
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np
from dask.distributed import Client, LocalCluster

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_SCENE = ROOT / "scenes" / "fig2a-at-rest.toml"


def render_task(
    scene_path: str,
    width: int,
    height: int,
    spp: int,
    overrides: Optional[Mapping[str, Any]] = None,
    pixel_bounds: Optional[tuple[int, int, int, int]] = None,
    threads: int = 1,
) -> np.ndarray:
    """One task, run on a worker: loads the scene, renders it (or a rectangle of it) and returns
    the colours as a plain float32 array of shape (height, width, 3)."""
    import timbre  # imported on the worker

    scene = timbre.load(scene_path, set=dict(overrides or {}))
    image = scene.render(width, height, spp=spp, threads=threads, pixel_bounds=pixel_bounds)
    return image.view(np.ndarray)


# Threads: every task renders with threads=1, and the cluster runs one single-threaded worker
# per core, so Dask's scheduler alone decides how the cores are shared (timbre's default,
# every core per render, would oversubscribe them). With fewer, multi-threaded workers pass
# threads=<threads per worker> instead.


def sweep(
    client: Client,
    scene_path: Union[str, Path],
    betas: Sequence[float],
    width: int,
    height: int,
    spp: int = 1,
    threads: int = 1,
) -> list[np.ndarray]:
    """Renders the scene once per speed in ``betas`` (units of c) along the camera's view
    direction, ``camera.beta = [0, 0, beta]``: one task per frame. Returns the frames in the
    order of ``betas``."""
    path = str(Path(scene_path).resolve())
    futures = [
        client.submit(
            render_task, path, width, height, spp, {"camera.beta": [0, 0, float(b)]},
            threads=threads,
        )
        for b in betas
    ]
    return client.gather(futures)


def tile_bounds(width: int, height: int, tiles: Union[int, tuple[int, int]]) -> list[tuple[int, int, int, int]]:
    """The pixel bounds (x0, x1, y0, y1), half-open, of a grid of ``tiles`` = (columns, rows)
    tiles (an int: that many of each) covering a width x height image, as even as can be."""
    columns, rows = (tiles, tiles) if isinstance(tiles, int) else tiles
    if not (1 <= columns <= width and 1 <= rows <= height):
        raise ValueError(f"cannot cut a {width}x{height} image into {columns}x{rows} tiles")
    xs = [width * i // columns for i in range(columns + 1)]
    ys = [height * j // rows for j in range(rows + 1)]
    return [(xs[i], xs[i + 1], ys[j], ys[j + 1]) for j in range(rows) for i in range(columns)]


def tiled(
    client: Client,
    scene_path: Union[str, Path],
    width: int,
    height: int,
    spp: int = 1,
    tiles: Union[int, tuple[int, int]] = (2, 2),
    overrides: Optional[Mapping[str, Any]] = None,
    threads: int = 1,
) -> np.ndarray:
    """Renders one width x height image as a grid of tiles, one task per tile, and returns the
    assembled float32 array (height, width, 3): the same values as a single render."""
    path = str(Path(scene_path).resolve())
    bounds = tile_bounds(width, height, tiles)
    futures = [
        client.submit(render_task, path, width, height, spp, overrides, b, threads=threads)
        for b in bounds
    ]
    image = np.zeros((height, width, 3), dtype=np.float32)
    for (x0, x1, y0, y1), tile in zip(bounds, client.gather(futures)):
        image[y0:y1, x0:x1] = tile
    return image


def main(argv: Optional[Sequence[str]] = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", nargs="?", default=str(DEFAULT_SCENE), help="scene file")
    parser.add_argument("-o", "--output", help="save the frames side by side (.png) or all arrays (.npz)")
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--spp", type=int, default=1)
    parser.add_argument("--frames", type=int, default=6, help="speeds from 0 to 0.99c")
    parser.add_argument("--tiles", type=int, default=4, help="tiles per side of the tiled render")
    args = parser.parse_args(argv)

    betas = np.linspace(0.0, 0.99, args.frames)
    with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
        print(client)
        frames = sweep(client, args.scene, betas, args.width, args.height, args.spp)
        # The fastest frame again, as a grid of tiles: it must equal the sweep's last frame.
        fastest = {"camera.beta": [0, 0, float(betas[-1])]}
        image = tiled(client, args.scene, args.width, args.height, args.spp, args.tiles, fastest)

    for b, frame in zip(betas, frames):
        print(f"beta = {b:.3f}c: mean colour {frame.mean(axis=(0, 1)).round(4)}")
    same = np.array_equal(image, frames[-1])
    print(f"{args.tiles}x{args.tiles} tiles of beta = {betas[-1]:.3f}c equal its frame: {same}")

    if args.output:
        out = Path(args.output)
        if out.suffix == ".npz":
            np.savez(out, betas=betas, frames=np.stack(frames), tiled=image)
        else:
            import timbre

            out.write_bytes(timbre.Image(np.concatenate(frames, axis=1)).png())
        print(f"saved {out}")


if __name__ == "__main__":
    main()
