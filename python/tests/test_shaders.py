"""Shader experiments: folders and texts searched before the built-in files."""

import pytest

import glint
from conftest import ROOT, gpu, small

pytestmark = gpu


def test_an_experiment_folder_changes_the_image(renderer):
    scene = small("seed-fig5.toml")
    stock = renderer.render(scene)
    phong = glint.Renderer(include=ROOT / "shaders/experiments/phong").render(scene)
    assert glint.diff(phong, stock).max_abs > 1 / 255


def test_a_shader_text_edited_in_python_changes_the_image(renderer, root):
    scene = small("seed-fig5.toml")
    specular = (root / "shaders/specular.glsl").read_text()
    same = glint.Renderer(include={"specular.glsl": specular}).render(scene)
    assert same.tobytes() == renderer.render(scene).tobytes()
    # The specular term off: the highlights go.
    body = specular.replace("return ", "return 0.0 * ", 1)
    assert body != specular
    dull = glint.Renderer(include={"specular.glsl": body}).render(scene)
    assert (dull <= same).all() and glint.diff(dull, same).max_abs > 0.05


def test_a_file_name_with_a_folder_is_refused():
    with pytest.raises(ValueError, match="no folders"):
        glint.Renderer(include={"../specular.glsl": ""})


def test_devices_lists_the_default_first(renderer):
    devices = glint.devices()
    assert devices and devices[0]["name"] == renderer.device
