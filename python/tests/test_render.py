"""timbre from Python against the command line: the same scenes give the same values, bit for
bit; `set` is `--set`; errors carry their place; renders run from threads, report progress and
stop on Ctrl-C."""

from __future__ import annotations

import inspect
import io
import json
import signal
import subprocess
import sys
import textwrap
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from conftest import HANG, ROOT, SCENES, cli, exr_rgb, read_exr
from PIL import Image as PILImage

import timbre

# Scenes of several kinds: the studio, a relativistic finite-aperture camera (random pupil
# points and pixel offsets), METATOYs, an ideal-lens cloak, a gradient-index lens.
CASES = [
    ("studio.toml", 96, 64, 1, 0),
    ("fig3-finite-aperture-0.99c.toml", 64, 48, 3, 7),
    ("metatoy-window.toml", 80, 60, 2, 1),
    ("ideal-lens-cloak.toml", 64, 48, 1, 0),
    ("fig9-ggrin-lens.toml", 48, 36, 1, 0),
]


@pytest.mark.parametrize("name,width,height,spp,seed", CASES)
def test_arrays_equal_the_cli_exr_bit_for_bit(timbre_cli, tmp_path, name, width, height, spp, seed):
    exr = tmp_path / "out.exr"
    cli(timbre_cli, "render", SCENES / name, "--width", width, "--height", height,
        "--spp", spp, "--seed", seed, "--aov", "depth,normal,object,albedo", "-q", "-o", exr)
    want = read_exr(exr)
    image = timbre.load(SCENES / name).render(
        width, height, spp=spp, seed=seed, aovs=["depth", "normal", "object", "albedo"]
    )
    assert image.dtype == np.float32 and image.shape == (height, width, 3)
    # Bit for bit: the same float32 values, NaN and infinities included.
    assert np.array_equal(image.view(np.ndarray), exr_rgb(want))
    assert np.array_equal(image.aovs["depth"], want["depth.Z"])
    normal = np.stack([want[f"normal.{a}"] for a in "XYZ"], axis=-1)
    assert np.array_equal(image.aovs["normal"], normal)
    assert np.array_equal(image.aovs["object"], want["object.id"])
    albedo = np.stack([want[f"albedo.{c}"] for c in "RGB"], axis=-1)
    assert np.array_equal(image.aovs["albedo"], albedo)
    # Something is seen: the comparison is not of two black pictures.
    assert image.max() > 0.1 and (image.aovs["object"] >= 0).any()


def test_a_stereo_scene_renders_its_combined_output_as_the_cli(timbre_cli, tmp_path):
    exr = tmp_path / "anaglyph.exr"
    scene = SCENES / "fig4-relativistic-anaglyph.toml"
    cli(timbre_cli, "render", scene, "--width", 64, "--height", 48, "-q", "-o", exr)
    image = timbre.load(scene).render(64, 48)
    assert np.array_equal(image.view(np.ndarray), exr_rgb(read_exr(exr)))
    with pytest.raises(ValueError, match="single views only"):
        timbre.load(scene).render(64, 48, aovs=["depth"])


def test_every_render_setting_is_a_keyword_of_render_and_means_the_cli_option(
        timbre_cli, tmp_path):
    # The render settings are defined once (timbre's SETTINGS): each is a keyword of
    # Scene.render and an entry of Scene.settings, and means what `timbre render --KEY` means.
    keys = [key for key, *_ in timbre._timbre.render_settings()]
    assert set(keys) <= set(inspect.signature(timbre.Scene.render).parameters)
    assert set(keys) <= set(timbre.studio().settings)
    # A value of each, none of them the studio's own (a new setting needs one here).
    values = {"width": 40, "height": 30, "spp": 2, "seed": 7, "max_trace_level": 3,
              "shadows": False, "exposure": 1.5, "png_transfer": "srgb"}
    assert set(values) == set(keys)
    assert all(timbre.studio().settings[k] != v for k, v in values.items())
    exr = tmp_path / "out.exr"
    options = [a for k, v in values.items()
               for a in (f"--{k.replace('_', '-')}", str(v).lower())]
    cli(timbre_cli, "render", *options, "-q", "-o", exr)
    image = timbre.studio().render(**values)
    assert np.array_equal(image.view(np.ndarray), exr_rgb(read_exr(exr)))
    # And differs from the studio's own settings at the same size.
    plain = timbre.studio().render(40, 30, spp=2, seed=7)
    assert not np.array_equal(image.view(np.ndarray), plain.view(np.ndarray))
    with pytest.raises(TypeError, match="shadows"):
        timbre.studio().render(8, 6, shadows=1)


def test_exposure_scales_and_png_transfer_encodes_as_the_cli_does():
    # A scene of one grey: 2^exposure times it, and the sRGB curve of IEC 61966-2-1 for the PNG
    # (0.5 -> 0.735357 -> 188; linear: 128), with the chunk that says so.
    grey = timbre.load('studio = "none"\n[[object]]\n'
                       'shape = { type = "sphere", centre = [0, 0, 0], radius = 100 }\n'
                       'surface = { type = "constant-colour", colour = [0.25, 0.25, 0.25] }\n')
    image = grey.render(4, 3, exposure=1)
    assert np.all(image == np.float32(0.5))
    assert image.png_transfer == "linear" and image.to_rgb8()[0, 0, 0] == 128
    srgb = grey.render(4, 3, exposure=1, png_transfer="srgb")
    assert srgb.to_rgb8()[0, 0, 0] == 188
    assert b"sRGB" in srgb.png() and b"sRGB" not in image.png()
    with pytest.raises(ValueError, match="png_transfer"):
        grey.render(4, 3, png_transfer="gamma")
    with pytest.raises(ValueError, match="exposure"):
        grey.render(4, 3, exposure=31)


def test_pixel_bounds_are_those_pixels_of_the_whole_render_and_of_the_cli_part(timbre_cli, tmp_path):
    scene = timbre.load(SCENES / "fig3-finite-aperture-0.99c.toml")
    whole = scene.render(64, 48, spp=2, seed=3)
    part = scene.render(64, 48, spp=2, seed=3, pixel_bounds=(5, 37, 9, 30))
    assert part.shape == (21, 32, 3)
    assert np.array_equal(part.view(np.ndarray), whole[9:30, 5:37].view(np.ndarray))
    exr = tmp_path / "part.exr"
    cli(timbre_cli, "render", SCENES / "fig3-finite-aperture-0.99c.toml", "--width", 64,
        "--height", 48, "--spp", 2, "--seed", 3, "--pixel-bounds", "5,37,9,30", "-q", "-o", exr)
    assert np.array_equal(part.view(np.ndarray), exr_rgb(read_exr(exr)))


def test_shapes_dtypes_and_aovs():
    image = timbre.studio().render(40, 30, aovs=("depth", "normal", "object"))
    assert isinstance(image, np.ndarray) and isinstance(image, timbre.Image)
    assert image.shape == (30, 40, 3) and image.dtype == np.float32
    assert image.flags.c_contiguous
    assert set(image.aovs) == {"depth", "normal", "object"}
    assert image.aovs["depth"].shape == (30, 40) and image.aovs["depth"].dtype == np.float32
    assert image.aovs["normal"].shape == (30, 40, 3)
    assert image.aovs["object"].shape == (30, 40)
    # Every pixel of the studio sees the floor, the sky or a cylinder: unit normals, finite
    # depths and ids of the scene's objects.
    ids = image.aovs["object"]
    assert ((ids >= 0) & (ids < len(timbre.studio().object_names))).all()
    assert np.allclose(np.linalg.norm(image.aovs["normal"], axis=-1), 1, atol=1e-6)
    assert np.isfinite(image.aovs["depth"]).all()
    assert image.rays >= 40 * 30
    # Only the AOVs asked for.
    assert set(timbre.studio().render(8, 6, aovs="depth").aovs) == {"depth"}
    assert timbre.studio().render(8, 6).aovs == {}
    # The scene's own size when none is given.
    assert timbre.studio().render(spp=1).shape == (480, 640, 3)
    # A width or a height alone keeps the studio's 640:480: 100 wide is 75 high, 30 high 40 wide.
    assert timbre.studio().render(width=100).shape == (75, 100, 3)
    assert timbre.studio().render(height=30).shape == (30, 40, 3)


def test_the_studio_is_the_cli_default_scene(timbre_cli, tmp_path):
    exr = tmp_path / "studio.exr"
    cli(timbre_cli, "render", "--width", 64, "--height", 48, "-q", "-o", exr)
    image = timbre.studio("lattice").render(64, 48)
    assert np.array_equal(image.view(np.ndarray), exr_rgb(read_exr(exr)))


def test_png_is_the_cli_png(timbre_cli, tmp_path):
    png = tmp_path / "out.png"
    cli(timbre_cli, "render", SCENES / "metatoy-window.toml", "--width", 64, "--height", 48,
        "-q", "-o", png)
    want = np.asarray(PILImage.open(png).convert("RGB"))
    image = timbre.load(SCENES / "metatoy-window.toml").render(64, 48)
    shown = np.asarray(PILImage.open(io.BytesIO(image._repr_png_())).convert("RGB"))
    assert np.array_equal(shown, want)
    assert np.array_equal(image.to_rgb8(), want)
    # A slice that is no longer an image has no picture.
    assert image[..., 0]._repr_png_() is None


SETS = [
    ("camera.beta", [0, 0, 0.9], "[0, 0, 0.9]"),
    ("camera.beta", np.array([0.2, 0.0, 0.7]), "[0.2, 0.0, 0.7]"),
    ("camera.horizontal_view_angle_deg", 45, "45"),
    ("render.shadows", False, "false"),
    # A string is taken as the command line takes it: TOML here.
    ("camera.beta", "[0, 0, 0.3]", "[0, 0, 0.3]"),
    ("camera.position", (0.5, 1, -9.5), "[0.5, 1, -9.5]"),
]


@pytest.mark.parametrize("key,value,text", SETS)
def test_set_equals_the_cli_set(timbre_cli, tmp_path, key, value, text):
    exr = tmp_path / "set.exr"
    cli(timbre_cli, "render", SCENES / "studio.toml", "--width", 48, "--height", 36,
        "--set", f"{key}={text}", "-q", "-o", exr)
    want = exr_rgb(read_exr(exr))
    scene = timbre.load(SCENES / "studio.toml")
    plain = scene.render(48, 36)
    changed = scene.set(key, value).render(48, 36)
    assert np.array_equal(changed.view(np.ndarray), want)
    # The same through load(set=...), and the change is real.
    again = timbre.load(SCENES / "studio.toml", set={key: value}).render(48, 36)
    assert np.array_equal(again.view(np.ndarray), want)
    assert not np.array_equal(plain.view(np.ndarray), want)
    # unset goes back to the file's own values.
    assert np.array_equal(scene.unset(key).render(48, 36).view(np.ndarray), plain.view(np.ndarray))


def test_set_overrides_apply_in_order_and_a_bad_one_changes_nothing():
    scene = timbre.studio()
    scene.set("camera.beta", [0, 0, 0.5]).set("render.width", 100)
    scene.set("camera.beta", [0, 0, 0.6])
    assert scene.overrides == {"render.width": "100", "camera.beta": "[0, 0, 0.6]"}
    assert scene.settings["width"] == 100
    before = scene.render(20, 15)
    with pytest.raises(timbre.SceneError, match="unknown field `nonsense`"):
        scene.set("camera.nonsense", 1)
    with pytest.raises(timbre.SceneError):
        scene.set("camera.beta", [0, 0, 1.5])  # faster than light
    assert scene.overrides == {"render.width": "100", "camera.beta": "[0, 0, 0.6]"}
    assert np.array_equal(scene.render(20, 15).view(np.ndarray), before.view(np.ndarray))
    # A copy changes on its own.
    other = scene.copy().set("camera.beta", [0, 0, 0])
    assert scene.overrides["camera.beta"] == "[0, 0, 0.6]"
    assert not np.array_equal(other.render(20, 15).view(np.ndarray), before.view(np.ndarray))
    with pytest.raises(TypeError):
        scene.set("camera.beta", None)


def test_a_scene_error_carries_its_file_line_and_column_as_the_cli_says(timbre_cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[camera]\nposition = [0, 0, -5]\nhorizontal_view_angle_deg = "wide"\n')
    with pytest.raises(timbre.SceneError) as caught:
        timbre.load(bad)
    e = caught.value
    assert (e.path, e.line, e.column) == (str(bad), 3, 29)
    assert isinstance(e, ValueError)
    done = subprocess.run([str(timbre_cli), "check", str(bad)], capture_output=True, text=True)
    assert done.returncode == 2
    assert done.stderr.strip() == f"timbre: error: {e}"
    # Text: the same error at the same place, named <text>.
    with pytest.raises(timbre.SceneError) as caught:
        timbre.load(bad.read_text())
    assert (caught.value.path, caught.value.line, caught.value.column) == ("<text>", 3, 29)


def test_vectors_have_exactly_three_components_and_errors_are_escaped_as_the_cli_does(
    timbre_cli, tmp_path
):
    """Issue 36: set() takes a vector of exactly its length, and no error text carries raw
    control characters (an uncaught traceback could otherwise drive the terminal): the message
    is the CLI's, escaped the same way."""
    scene = timbre.studio()
    for key, value in [("camera.position", [0, 0, -5, 9]), ("camera.view_direction", (0, 1)),
                       ("camera.position", np.zeros(4))]:
        with pytest.raises(timbre.SceneError, match="expected an array of 3 values, got"):
            scene.set(key, value)
    assert scene.overrides == {}
    with pytest.raises(timbre.SceneError) as caught:
        scene.set("cam\x1bera.position", [0, 0, 1])
    assert "\x1b" not in str(caught.value) and "cam\\x1bera" in str(caught.value)
    evil = tmp_path / "evil.toml"
    evil.write_text(
        'studio = "empty"\n[[object]]\nname = "evil\\u001b]0;pwned\\u0007"\n'
        'shape = { type = "parallelogram", corner = [0, 0, 0], span_u = [0, 0, 0], '
        'span_v = [0, 0, 0] }\nsurface = { type = "matt", colour = [1, 1, 1] }\n'
    )
    with pytest.raises(timbre.SceneError) as caught:
        timbre.load(evil)
    message = str(caught.value)
    assert "\x1b" not in message and "\x07" not in message
    assert "evil\\x1b]0;pwned\\x07" in message
    done = subprocess.run([str(timbre_cli), "check", str(evil)], capture_output=True, text=True)
    assert done.stderr.strip() == f"timbre: error: {message}"


def test_other_errors_are_python_exceptions():
    with pytest.raises(FileNotFoundError):
        timbre.load(ROOT / "no-such-scene.toml")
    with pytest.raises(timbre.SceneError) as caught:
        timbre.load(SCENES / "studio.toml", set={"object.99.shape.radius": 1})
    assert caught.value.path == str(SCENES / "studio.toml") and caught.value.line is None
    scene = timbre.studio()
    for bad in [dict(width=0), dict(spp=0), dict(threads=0), dict(threads=5000),
                dict(pixel_bounds=(0, 700, 0, 10)), dict(pixel_bounds=(5, 5, 0, 10)),
                dict(aovs=["colour"])]:
        with pytest.raises(ValueError):
            scene.render(**{"width": 64, "height": 48, **bad})
    with pytest.raises(ValueError):
        scene.set("camera.beta=1", 0)
    with pytest.raises(ValueError):
        timbre.studio("cathedral")


def test_renders_from_two_python_threads_at_once():
    studio = timbre.load(SCENES / "studio.toml")
    cloak = timbre.load(SCENES / "ideal-lens-cloak.toml")
    jobs = [(studio, 1), (cloak, 2), (studio, 3), (cloak, 4)]
    alone = [s.render(64, 48, spp=2, seed=k, threads=1) for s, k in jobs]
    # Two at a time, the same Scene objects shared by both threads.
    barrier = threading.Barrier(2)

    def render(job):
        scene, seed = job
        barrier.wait(timeout=HANG)
        return scene.render(64, 48, spp=2, seed=seed, threads=1)

    with ThreadPoolExecutor(2) as pool:
        together = list(pool.map(render, jobs))
    for a, b in zip(alone, together):
        assert np.array_equal(a.view(np.ndarray), b.view(np.ndarray))


def test_progress_counts_every_pixel_of_every_view():
    counts = []
    timbre.studio().render(50, 37, progress=counts.append)
    assert sum(counts) == 50 * 37 and all(n > 0 for n in counts)
    counts = []
    timbre.load(SCENES / "fig4-relativistic-anaglyph.toml").render(30, 20, progress=counts.append)
    assert sum(counts) == 2 * 30 * 20
    counts = []
    timbre.studio().render(64, 48, pixel_bounds=(0, 10, 0, 16), progress=counts.append)
    assert sum(counts) == 160


def test_an_exception_in_the_progress_callback_stops_the_render():
    # A render of many minutes, in a child process: the callback's exception must end it.
    script = textwrap.dedent(
        """
        import timbre
        class Enough(Exception):
            pass
        def stop(n):
            raise Enough
        try:
            timbre.studio().render(6000, 6000, spp=64, progress=stop)
        except Enough:
            print("stopped")
        """
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=HANG)
    assert done.stdout.strip() == "stopped", done.stderr


def test_a_render_too_large_for_the_memory_is_refused_not_aborted():
    # 10^10 pixels need some 360 GB.
    with pytest.raises(MemoryError, match="needs about"):
        timbre.studio().render(100_000, 100_000)
    # Under an address-space limit (as `ulimit -v`), in a child process: a clear MemoryError,
    # never an abort.
    script = textwrap.dedent(
        """
        import resource, timbre
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
        try:
            timbre.studio("none").render(16000, 8000)
        except MemoryError as e:
            print("refused:", e)
        """
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=HANG)
    assert done.returncode == 0 and done.stdout.startswith("refused: a 16000x8000 render"), (
        done.returncode, done.stdout, done.stderr)


def test_ctrl_c_interrupts_a_render(tmp_path):
    # A render of many minutes; SIGINT once it has started must end it with KeyboardInterrupt.
    script = textwrap.dedent(
        """
        import sys, timbre
        started = []
        def progress(n):
            if not started:
                started.append(n)
                print("started", flush=True)
        try:
            timbre.studio().render(6000, 6000, spp=64, progress=progress)
            print("finished", flush=True)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
        """
    )
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "started"
        child.send_signal(signal.SIGINT)
        out, _ = child.communicate(timeout=HANG)
    finally:
        child.kill()
    assert out.strip() == "interrupted"
    assert child.returncode == 0


def test_trajectories_are_those_of_timbre_trace(timbre_cli):
    path = SCENES / "trajectories-glass-ball.toml"
    traced = json.loads(cli(timbre_cli, "trace", "--json", path).stdout)["rays"]
    got = timbre.load(path).trajectories()
    # The same format and values (JSON carries each f64 exactly, in its shortest round-trip
    # form), ray for ray.
    assert got == traced and len(got) > 0
    assert set(got[0]) == {"trajectory", "ray", "points", "end", "direction"}
    assert set(got[0]["points"][0]) == {"arrival", "object", "position"}
    # A glass ball refracts: some ray changes direction.
    assert any(len(g["points"]) > 2 for g in got)


def test_scene_information():
    scene = timbre.load(SCENES / "studio.toml", set={"render.spp": 4})
    assert scene.settings["spp"] == 4 and scene.settings["views"] == 1
    assert "sky" in scene.object_names
    assert len(scene.hash) == 16
    assert "spp = 4" in scene.toml().replace("spp=4", "spp = 4")
    assert repr(scene).startswith("<timbre.Scene ")
    assert scene.name == str(SCENES / "studio.toml")


def test_get_reads_the_scene_text_with_the_overrides():
    scene = timbre.load(SCENES / "studio.toml", set={"camera.beta": [0, 0, 0.5]})
    assert scene.get("camera.beta") == [0, 0, 0.5]
    assert scene.get("render.width") == 640
    assert scene.get("camera.type") == "pinhole"
    assert scene.get("render.shadows") is True
    assert isinstance(scene.get("camera"), dict)
    assert scene.set("render.width", 99).get("render.width") == 99
    with pytest.raises(KeyError):
        scene.get("camera.no_such_key")
    with pytest.raises(KeyError):
        scene.get("light.99")


def test_images_pickle_with_their_aovs_and_derived_arrays_are_plain():
    import pickle

    image = timbre.studio().render(16, 12, aovs=["depth"])
    again = pickle.loads(pickle.dumps(image))
    assert isinstance(again, timbre.Image) and again.rays == image.rays > 0
    assert np.array_equal(again.view(np.ndarray), image.view(np.ndarray))
    assert np.array_equal(again.aovs["depth"], image.aovs["depth"])
    # A reduction is a number, one channel a plain array; arithmetic keeps an image.
    assert type(image.mean()) is np.float32
    assert type(image.sum(axis=2)) is np.ndarray
    assert isinstance(image * 2, timbre.Image)


def test_python_values_become_the_toml_the_cli_takes():
    scene = timbre.studio()
    scene.set("camera.position", np.array([1e-7, 1e14, -0.0]))
    position = scene.get("camera.position")
    assert position == [1e-7, 1e14, 0.0] and np.signbit(position[2])
    scene.set("render.spp", np.array(3))  # a 0-d array is its number
    assert scene.get("render.spp") == 3
    # Strings inside tables are TOML strings, any character included: a table read with get
    # and set again comes back the same.
    file = timbre.load(SCENES / "studio.toml")
    sky = file.get("object.0")
    for odd in ["😀", 'a "quoted" \\ one', "tab\tand\u007f"]:
        named = file.copy().set("object.0", {**sky, "name": odd})
        assert named.get("object.0") == {**sky, "name": odd}
        assert named.object_names[0] == odd
    with pytest.raises(ValueError, match="64-bit"):
        scene.set("render.seed", 2**64)
    for bad in [{1, 2}, b"ab", object()]:
        with pytest.raises(TypeError):
            scene.set("camera.position", bad)


def test_bad_render_arguments_name_themselves():
    scene = timbre.studio()
    with pytest.raises(TypeError, match="pixel_bounds"):
        scene.render(64, 48, pixel_bounds=(0.5, 4, 0, 4))
    with pytest.raises(ValueError, match="width"):
        scene.render(-64, 48)
    with pytest.raises(TypeError, match="spp"):
        scene.render(64, 48, spp=True)
    # numpy's integers are whole numbers.
    assert scene.render(np.int64(8), np.uint16(6)).shape == (6, 8, 3)
    with pytest.raises(ValueError, match="threads"):
        scene.render(64, 48, threads=-1)
    with pytest.raises(ValueError, match="seed"):
        scene.render(64, 48, seed=-1)
    with pytest.raises(ValueError, match="pixel_bounds"):
        scene.render(64, 48, pixel_bounds=(0, 4, 0))


def test_copies_are_independent():
    import copy

    scene = timbre.studio()
    for other in (copy.copy(scene), copy.deepcopy(scene), scene.copy()):
        other.set("camera.beta", [0, 0, 0.5])
        assert scene.overrides == {} and "beta" not in scene.toml()
        assert other.overrides == {"camera.beta": "[0, 0, 0.5]"}
    image = scene.render(8, 6, aovs=["depth"])
    for other in (copy.copy(image), copy.deepcopy(image), image.copy()):
        assert np.array_equal(other.aovs["depth"], image.aovs["depth"]) and other.rays == image.rays


def test_renders_go_on_under_an_address_space_limit():
    # The memory check counts what earlier renders of the process mapped once, not again (a
    # render maps some 270 MiB of thread arenas and Embree; it reserves 416 MiB for them).
    script = textwrap.dedent(
        """
        import resource, timbre
        resource.setrlimit(resource.RLIMIT_AS, (850 << 20, 850 << 20))
        scene = timbre.studio()
        for k in range(4):
            scene.render(64, 48, threads=2)
        print("rendered")
        """
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=HANG)
    assert done.stdout.strip() == "rendered", done.stderr


def test_a_scene_loaded_from_a_relative_path_survives_a_change_of_directory(monkeypatch):
    monkeypatch.chdir(SCENES)
    scene = timbre.load("mesh.toml")
    assert scene.name == str((SCENES / "mesh.toml").resolve())
    monkeypatch.chdir("/")
    # Its meshes are found again when an override makes it read them.
    assert scene.set("render.spp", 2).render(16, 12).shape == (12, 16, 3)


def test_an_empty_image_has_no_png():
    image = timbre.Image(np.zeros((0, 4, 3), np.float32))
    assert image._repr_png_() is None
    with pytest.raises(ValueError):
        image.png()


def test_an_image_sky_renders_as_the_cli_with_the_texel_ahead(timbre_cli, tmp_path, monkeypatch):
    # A 9 x 3 equirectangular sky, a different colour in each texel (column c, row r).
    texels = np.array(
        [[[10 + 25 * c, 20 + 100 * r, 128] for c in range(9)] for r in range(3)], dtype=np.uint8
    )
    PILImage.fromarray(texels, "RGB").save(tmp_path / "sky.png")
    text = 'studio = "none"\n[sky]\nimage = "sky.png"\n'
    path = tmp_path / "scene.toml"
    path.write_text(text)
    exr = tmp_path / "out.exr"
    cli(timbre_cli, "render", path, "--width", 3, "--height", 3, "-q", "-o", exr)
    scene = timbre.load(path)
    image = scene.render(3, 3)
    assert np.array_equal(image.view(np.ndarray), exr_rgb(read_exr(exr)))
    # The standard camera looks along +z, the picture's centre: column 4 of 9, the middle row.
    assert np.allclose(image[1, 1], texels[1, 4] / np.float32(255), atol=1e-6)
    # Turned by 90 degrees about +y, the centre moves to +x; +z is then at u = 1/4, column 2.
    turned = scene.copy().set("sky.rotation", 90).render(3, 3)
    assert np.allclose(turned[1, 1], texels[1, 2] / np.float32(255), atol=1e-6)
    # Scene text names the picture relative to the working directory.
    monkeypatch.chdir(tmp_path)
    assert np.array_equal(timbre.load(text).render(3, 3), image)
