"""The examples in the package's docstrings run as written (doctest), against the installed
package and its shipped example scenes."""

from __future__ import annotations

import doctest

import pytest

import timbre


def test_the_docstring_examples_run():
    # Each docstring's example may say `timbre.` as a user would after `import timbre`.
    result = doctest.testmod(timbre, extraglobs={"timbre": timbre}, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
    # The module's, Scene.set's, Scene.render's, examples()'s and example()'s.
    assert result.attempted >= 10


def test_the_example_scenes_ship_with_the_package():
    names = timbre.examples()
    assert "fig2a-at-rest" in names and "research/WedgeExplorer" in names
    # The installed package's own copy, not the source tree's.
    assert "site-packages" in timbre.SCENES.parts, timbre.SCENES
    scene = timbre.example("mesh")
    assert scene.name == str(timbre.SCENES / "mesh.toml")
    # Meshes and pictures come with the scenes that use them.
    assert (timbre.SCENES / "meshes" / "textured-cube.obj").is_file()
    timbre.example("textured-mesh").render(16, 12, spp=1)
    with pytest.raises(ValueError, match="no example scene 'fig99'"):
        timbre.example("fig99")
