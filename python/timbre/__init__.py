"""timbre: a fast, scientifically exact ray tracer for ray-optics research, from Python.

Scenes are timbre's TOML scene files (docs/SCENE_FORMAT.md); renders come back as numpy
arrays with exactly the values ``timbre render -o NAME.exr`` writes. The example scenes ship
with the package (:data:`SCENES`, :func:`example`):

>>> import timbre
>>> scene = timbre.example("fig2a-at-rest", set={"camera.beta": [0, 0, 0.9]})
>>> image = scene.render(width=64, spp=1)      # float32, linear RGB; the scene's aspect kept
>>> image.shape, image.dtype
((48, 64, 3), dtype('float32'))

``timbre.studio()`` is TIM's standard studio without a file; ``timbre.load(path)`` reads any
scene file. ``Scene.set`` changes a value as ``--set KEY=VALUE`` does on the command line, for
parameter sweeps. docs/PYTHON.md is the guide.
"""

from __future__ import annotations

import json
import math
import numbers
import operator
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np

from ._timbre import NativeScene as _NativeScene
from ._timbre import SceneError, embree_version
from ._timbre import png_bytes as _png_bytes
from ._timbre import render_settings as _render_settings
from ._timbre import rgb8 as _rgb8

__all__ = [
    "AOVS",
    "Image",
    "STUDIOS",
    "Scene",
    "SCENES",
    "SceneError",
    "embree_version",
    "example",
    "examples",
    "load",
    "studio",
]

try:
    __version__ = version("timbre-optics")
except PackageNotFoundError:  # imported from a source tree without being installed
    __version__ = "unknown"

#: The folder of the example scenes that ship with the package (package data ``timbre/scenes``:
#: the repository's ``scenes/``), with the meshes and pictures they use.
SCENES = Path(__file__).parent / "scenes"

#: The studios a scene can start from (the scene file's ``studio`` key).
STUDIOS = ("empty", "lattice", "metatoy-window", "none")

#: The arbitrary output variables ``Scene.render(aovs=...)`` can add: the distance to the surface
#: seen through each pixel centre, its outward normal, the object's index (-1 for none), and the
#: albedo (a denoiser's guide: docs/SCENE_FORMAT.md).
AOVS = ("depth", "normal", "object", "albedo")

# The render settings, defined once in timbre (its ``SETTINGS``): each key's kind ("whole" or
# "switch") and range. ``Scene.render`` takes each as a keyword (a test checks that it does).
_SETTINGS = {key: (kind, least, most) for key, kind, least, most in _render_settings()}

PathLike = Union[str, "os.PathLike[str]"]


def _toml_string(text: str) -> str:
    """A TOML basic string: quotes, backslashes and control characters escaped, the rest as it
    is (TOML is UTF-8)."""
    def escape(c: str) -> str:
        if c in '"\\':
            return "\\" + c
        if ord(c) < 0x20 or ord(c) == 0x7F:
            return f"\\u{ord(c):04x}"
        return c

    return '"' + "".join(map(escape, text)) + '"'


_I64 = range(-(2**63), 2**63)


def _toml(value: Any, top: bool) -> str:
    """A Python value as the TOML text of a ``--set`` value.

    At the top, a string is taken as the command line takes it: TOML (``"[0, 0, 1]"``) or a
    bare word (``"lattice"``); inside lists and tables strings are strings.
    """
    if isinstance(value, str):
        return value if top else _toml_string(value)
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        if int(value) not in _I64:
            raise ValueError(f"{value} is beyond TOML's 64-bit integers")
        return str(int(value))
    if isinstance(value, numbers.Real):
        v = float(value)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(value, np.ndarray):
        return _toml(value.tolist(), top)
    if isinstance(value, Mapping):
        items = (f"{_toml_string(str(k))} = {_toml(v, False)}" for k, v in value.items())
        return "{ " + ", ".join(items) + " }"
    # Ordered sequences only: a set's order is arbitrary, bytes are not numbers.
    if isinstance(value, Sequence) and not isinstance(value, (bytes, bytearray)):
        return "[" + ", ".join(_toml(v, False) for v in value) + "]"
    raise TypeError(
        f"{value!r} ({type(value).__name__}) has no TOML form: give a number, a bool, a "
        "string, a list, tuple or numpy array, or a dict of them"
    )


def _override(key: str, value: Any) -> str:
    if not isinstance(key, str) or "=" in key or not key.strip():
        raise ValueError(f"{key!r} is not a scene-file key such as 'camera.position'")
    return f"{key.strip()}={_toml(value, True)}"


def _setting(key: str, value: Any) -> Union[int, bool, float, str]:
    """The render setting ``key`` given ``value``: a whole number or a number in its range, a
    bool, or one of its names."""
    kind, least, most = _SETTINGS[key]
    if kind == "switch":
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{key} must be True or False, got {value!r}")
        return bool(value)
    if kind == "number":
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
            raise TypeError(f"{key} must be a number, got {value!r}")
        if not least <= float(value) <= most:
            raise ValueError(f"{key} must be from {least} to {most}, got {value!r}")
        return float(value)
    if kind == "choice":
        if value not in least:
            raise ValueError(f"{key} must be one of {', '.join(least)}, got {value!r}")
        return str(value)
    return _whole(key, value, least, most)


def _whole(name: str, value: Any, least: int, most: int) -> int:
    """A whole-number argument from ``least`` to ``most``, or a TypeError/ValueError naming it."""
    try:
        if isinstance(value, (bool, np.bool_)):
            raise TypeError
        v = operator.index(value)
    except TypeError:
        raise TypeError(f"{name} must be a whole number, got {value!r}") from None
    if not least <= v <= most:
        raise ValueError(f"{name} must be from {least} to {most}, got {v}")
    return v


class Image(np.ndarray):
    """A rendered image: a float32 numpy array of shape (height, width, 3), linear RGB, row 0 at
    the top, with exactly the values ``timbre render`` writes to OpenEXR.

    ``aovs`` holds the AOVs asked for (``depth`` and ``object`` of shape (height, width),
    ``normal`` and ``albedo`` of shape (height, width, 3)); ``rays`` counts the rays traced. Arrays derived from
    an image (slices, arithmetic) are images without AOVs. In Jupyter an image shows itself as
    the PNG ``timbre render -o NAME.png`` would write.
    """

    aovs: dict[str, np.ndarray]
    rays: int
    #: How :meth:`png` and :meth:`to_rgb8` encode the values: the render's ``png_transfer``.
    png_transfer: str

    def __new__(cls, rgb: np.ndarray, aovs: Optional[dict[str, np.ndarray]] = None, rays: int = 0,
                png_transfer: str = "linear"):
        image = np.asarray(rgb, dtype=np.float32).view(cls)
        image.aovs = dict(aovs or {})
        image.rays = rays
        image.png_transfer = png_transfer
        return image

    def __array_finalize__(self, obj: Optional[np.ndarray]) -> None:
        self.aovs = {}
        self.rays = 0
        self.png_transfer = getattr(obj, "png_transfer", "linear")

    def __array_wrap__(self, array, context=None, return_scalar=False):
        # What a ufunc makes that is no longer an image (a reduction, one channel of a sum) is a
        # plain array, or a number (numpy 1 hands over 0-d arrays for those).
        if array.ndim != 3 or array.shape[-1] != 3:
            array = array.view(np.ndarray)
            return array[()] if return_scalar or array.ndim == 0 else array
        return np.ndarray.__array_wrap__(self, array, context)

    def __reduce__(self):
        # Pickled (to and from other processes, e.g. Dask's) with its AOVs and ray count.
        rebuild, args, state = super().__reduce__()
        return rebuild, args, (state, self.aovs, self.rays, self.png_transfer)

    def __setstate__(self, state) -> None:
        array_state, self.aovs, self.rays, self.png_transfer = state
        super().__setstate__(array_state)

    def _colours(self) -> np.ndarray:
        if self.ndim != 3 or self.shape[2] != 3:
            raise ValueError(f"an array of shape {self.shape} is not an image: (height, width, 3)")
        return np.ascontiguousarray(self.view(np.ndarray), dtype=np.float32)

    def to_rgb8(self) -> np.ndarray:
        """The 8-bit image (uint8, (height, width, 3)) of ``timbre render -o NAME.png``: each
        channel clamped to [0, 1], encoded by ``png_transfer`` (linear: no curve; srgb: the
        sRGB curve), times 255, rounded."""
        return _rgb8(self._colours(), self.png_transfer)

    def png(self) -> bytes:
        """The PNG file ``timbre render -o NAME.png`` writes of this image."""
        if self.size == 0:
            raise ValueError("an empty image has no PNG")
        return _png_bytes(self._colours(), self.png_transfer)

    def _repr_png_(self) -> Optional[bytes]:
        if self.ndim != 3 or self.shape[2] != 3 or self.size == 0:
            return None
        return self.png()

    def copy(self, order: str = "C") -> "Image":
        """A copy, with the AOVs (copied too) and the ray count."""
        image = super().copy(order)
        image.aovs = {k: v.copy() for k, v in self.aovs.items()}
        image.rays = self.rays
        return image

    __copy__ = copy

    def __deepcopy__(self, memo: dict) -> "Image":
        return self.copy()


class Scene:
    """A timbre scene: a scene file (or its text) with ``--set`` overrides.

    Make one with :func:`load` or :func:`studio`. Renders of one scene may run from several
    threads at once; the BVH is built on the first render and kept until ``set`` changes what
    it holds.
    """

    def __init__(self, native: _NativeScene):
        self._native = native

    def __repr__(self) -> str:
        s = self._native.settings()
        sets = "".join(f", {k}={v}" for k, v in self._native.overrides())
        return f"<timbre.Scene {self.name} {s['width']}x{s['height']}{sets}>"

    @property
    def name(self) -> str:
        """The scene file's absolute path, or the name that stands for its text in messages."""
        return self._native.name()

    @property
    def overrides(self) -> dict[str, str]:
        """The ``--set`` overrides in force, in the order they apply: key to TOML value."""
        return dict(self._native.overrides())

    @property
    def settings(self) -> dict[str, Any]:
        """The scene's ``[render]`` values (width, height, spp, seed, max_trace_level, shadows),
        its stereo output (``camera.stereo``) and how many views a render takes."""
        return self._native.settings()

    @property
    def object_names(self) -> list[str]:
        """The objects' names in the scene's order: the ids of the ``object`` AOV."""
        return self._native.object_names()

    @property
    def warnings(self) -> list[str]:
        """What is questionable about the scene (what ``timbre render`` warns of)."""
        return self._native.warnings()

    @property
    def hash(self) -> str:
        """The scene's hash (``timbre.scene`` in an EXR file's header)."""
        return self._native.hash()

    def get(self, key: str) -> Any:
        """The value the scene file (with the overrides) gives ``key`` (a dotted path as for
        :meth:`set`), as Python numbers, bools, strings, lists and dicts; ``KeyError`` where the
        file leaves it out (timbre then uses its default)."""
        return self._native.get(key)

    def toml(self) -> str:
        """The scene text with the overrides applied."""
        return self._native.text()

    def set(self, key: str, value: Any) -> "Scene":
        """Sets a scene-file value as ``--set KEY=VALUE`` does, and returns the scene (changed:
        use :meth:`copy` first to keep the original).

        ``key`` is a dotted path into the file (``camera.position``, ``object.0.shape.radius``);
        ``value`` a number, bool, list, tuple, dict or numpy array, or a string taken as the
        command line takes it (TOML, or a bare word). Setting a key again replaces its value and
        moves it last. A scene the value makes invalid raises :class:`SceneError` (a value that
        is not TOML: ``ValueError``) and stays as it was.

        >>> scene = timbre.studio().set("camera.beta", [0, 0, 0.5])
        >>> scene.get("camera.beta")
        [0, 0, 0.5]
        """
        self._native.update([_override(key, value)], [])
        return self

    def update(self, values: Mapping[str, Any]) -> "Scene":
        """``set`` for each key and value, in order, as one change."""
        self._native.update([_override(k, v) for k, v in values.items()], [])
        return self

    def unset(self, key: str) -> "Scene":
        """Removes the override of ``key`` (a ``KeyError`` if there is none)."""
        self._native.update([], [key])
        return self

    def copy(self) -> "Scene":
        """An independent copy (sharing the built BVH until either's objects change)."""
        return Scene(self._native.copy())

    __copy__ = copy

    def __deepcopy__(self, memo: dict) -> "Scene":
        return self.copy()

    def render(
        self,
        width: Optional[int] = None,
        height: Optional[int] = None,
        *,
        spp: Optional[int] = None,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        max_trace_level: Optional[int] = None,
        shadows: Optional[bool] = None,
        exposure: Optional[float] = None,
        png_transfer: Optional[str] = None,
        aovs: Iterable[str] = (),
        pixel_bounds: Optional[tuple[int, int, int, int]] = None,
        progress: Union[None, bool, Callable[[int], Any]] = None,
    ) -> Image:
        """Renders the scene; each argument left out is the scene's ``[render]`` value.

        Returns an :class:`Image` (float32, (height, width, 3)) whose values equal those
        ``timbre render --width W --height H --spp N --seed S -o NAME.exr`` writes, whatever
        ``threads`` is (default: every core).

        - ``width`` or ``height`` alone keeps the scene's aspect ratio, the other side scaled
          and rounded (as ``--width`` alone does).
        - ``exposure``: stops; the values are multiplied by 2^exposure (as in every file
          ``timbre render --exposure`` writes). ``png_transfer``: ``"linear"`` or ``"srgb"``,
          how :meth:`Image.png` encodes them.
        - ``aovs``: any of ``"depth"``, ``"normal"``, ``"object"``, ``"albedo"``
          (``Image.aovs``).
        - ``pixel_bounds``: ``(x0, x1, y0, y1)``, half-open, renders only those pixels of the
          ``width`` x ``height`` image (``--pixel-bounds``): shape (y1 - y0, x1 - x0, 3), the
          same values as those pixels of the whole render.
        - ``progress``: a callable given the number of pixels finished since its last call
          (``tqdm``'s ``update``), or ``True`` for a tqdm progress bar.

        The GIL is released while timbre renders, and Ctrl-C (KeyboardInterrupt) stops the render.
        A stereo scene (``camera.stereo``) renders its combined output, without AOVs or bounds.

        >>> image = timbre.studio().render(32, 24, aovs=["depth", "object"])
        >>> image.shape, image.aovs["depth"].shape
        ((24, 32, 3), (24, 32))
        """
        wanted = [aovs] if isinstance(aovs, str) else list(aovs)
        unknown = [a for a in wanted if a not in AOVS]
        if unknown:
            raise ValueError(f"unknown AOV {unknown[0]!r}: the AOVs are {', '.join(AOVS)}")
        wanted = [a for a in AOVS if a in wanted]
        u32 = 2**32 - 1
        given = dict(width=width, height=height, spp=spp, seed=seed,
                     max_trace_level=max_trace_level, shadows=shadows, exposure=exposure,
                     png_transfer=png_transfer)
        settings = {k: _setting(k, v) for k, v in given.items() if v is not None}
        threads = None if threads is None else _whole("threads", threads, 1, 1024)
        if pixel_bounds is not None:
            if not isinstance(pixel_bounds, Sequence) or isinstance(pixel_bounds, (str, bytes)) \
                    or len(pixel_bounds) != 4:
                raise ValueError(f"pixel_bounds must be (x0, x1, y0, y1), got {pixel_bounds!r}")
            pixel_bounds = tuple(_whole("pixel_bounds", v, 0, u32) for v in pixel_bounds)
        bar = None
        if progress is True:
            try:
                from tqdm.std import tqdm
            except ImportError as e:
                raise ImportError('progress=True needs tqdm (pip install "timbre-optics[progress]")') from e
            try:  # a widget in Jupyter, where there are widgets; text otherwise
                import ipywidgets  # noqa: F401
                from tqdm.auto import tqdm
            except ImportError:
                pass
            s = {**self._native.settings(), **settings}
            w, h = s["width"], s["height"]
            if pixel_bounds is not None:
                x0, x1, y0, y1 = pixel_bounds
                w, h = x1 - x0, y1 - y0
            bar = tqdm(total=w * h * s["views"], unit="px", unit_scale=True, leave=False)
            progress = bar.update
        elif progress is False:
            progress = None
        try:
            out = self._native.render(
                settings=list(settings.items()), threads=threads, aovs=wanted,
                pixel_bounds=pixel_bounds, progress=progress
            )
        finally:
            if bar is not None:
                bar.close()
        return Image(out["rgb"], {a: out[a] for a in wanted}, out["rays"], out["png_transfer"])

    def trajectories(self) -> list[dict[str, Any]]:
        """The scene's ``[[ray_trajectory]]`` rays, traced, exactly as ``timbre trace --json``
        gives them (its ``rays``): for each ray a dict with ``trajectory`` (its name), ``ray``
        (its index), ``points`` (the start and each point where it met a surface, each a dict
        with ``arrival``, how the ray got there, ``object``, the object there or None, and
        ``position``, [x, y, z]), ``end`` and ``direction`` ([x, y, z])."""
        return json.loads(self._native.trajectories())


def _is_text(source: str) -> bool:
    """Whether a string is scene-file text rather than a path: it has a line break, or an ``=``
    and no file of that name exists."""
    return "\n" in source or ("=" in source and not os.path.exists(source))


def load(source: PathLike, set: Optional[Mapping[str, Any]] = None) -> Scene:
    """A scene from a scene file's path, or from scene-file text, with ``set`` applied as
    ``--set`` (key to value, in order; see :meth:`Scene.set`).

    A string with a line break, or with ``=`` that names no file, is taken as text (relative
    paths in it are relative to the working directory). Errors raise :class:`SceneError` with
    ``path``, ``line`` and ``column``; a missing file raises ``FileNotFoundError``.
    """
    sets = [_override(k, v) for k, v in (set or {}).items()]
    if isinstance(source, str) and _is_text(source):
        return Scene(_NativeScene.from_text(source, "<text>", sets))
    return Scene(_NativeScene.from_file(os.fspath(source), sets))


def studio(name: str = "lattice", set: Optional[Mapping[str, Any]] = None) -> Scene:
    """One of TIM's studios as a scene (``studio = NAME`` in a scene file): ``"lattice"`` (the
    scene ``timbre render`` draws without a scene file), ``"empty"``, ``"metatoy-window"``
    or ``"none"``."""
    if name not in STUDIOS:
        raise ValueError(f"unknown studio {name!r}: the studios are {', '.join(STUDIOS)}")
    sets = [_override(k, v) for k, v in (set or {}).items()]
    return Scene(_NativeScene.from_text(f'studio = "{name}"\n', f"<studio {name}>", sets))


def examples() -> list[str]:
    """The names of the example scenes in :data:`SCENES`, sorted (``research/NAME`` for the
    reproductions of Dr TIM's research programs): what :func:`example` takes.

    >>> "fig2a-at-rest" in timbre.examples()
    True
    """
    return sorted(p.relative_to(SCENES).with_suffix("").as_posix() for p in SCENES.rglob("*.toml"))


def example(name: str, set: Optional[Mapping[str, Any]] = None) -> Scene:
    """The example scene ``name`` (one of :func:`examples`, e.g. ``"fig2a-at-rest"``), with
    ``set`` applied as in :func:`load`.

    >>> timbre.example("studio").settings["width"]
    640
    """
    path = SCENES / f"{name}.toml"
    if name not in examples():
        raise ValueError(f"no example scene {name!r}; timbre.examples() lists them")
    return load(path, set=set)
