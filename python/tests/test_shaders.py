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


def test_the_same_shader_texts_compile_once_across_renderers(tmp_path, root):
    # Each Renderer wrote its texts into a folder of its own, and the cache
    # key took that folder's path: a byte-identical entry each time, never
    # found again.
    import os
    import subprocess
    import sys

    code = """
import json, glint
specular = open(%r).read() + "\\n// edited\\n"
scene = glint.load(%r, width=32, height=24)
cached = []
for _ in range(3):
    _, stats = glint.Renderer(include={"specular.glsl": specular}).render(scene, stats=True)
    cached.append(stats["times"]["setup"]["spirv_cached"])
print(json.dumps(cached))
""" % (str(root / "shaders/specular.glsl"), str(root / "scenes/seed-fig5.toml"))
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[false, true, true]", done.stdout
    entries = list((tmp_path / "glint" / "spirv").iterdir())
    assert len(entries) == 1, entries


def test_a_damaged_cache_entry_is_compiled_again_and_logged(tmp_path, root):
    # One flipped bit in a cached entry rendered a wrong image, silently.
    import os
    import subprocess
    import sys

    code = """
import logging, sys, glint
logging.basicConfig(level=logging.INFO, stream=sys.stderr)
scene = glint.load(%r, width=32, height=24)
sys.stdout.buffer.write(glint.Renderer().render(scene).tobytes())
""" % str(root / "scenes/seed-fig3.toml")
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path))
    run = lambda: subprocess.run([sys.executable, "-c", code], capture_output=True, env=env, timeout=300)
    first = run()
    assert first.returncode == 0, first.stderr
    (entry,) = (tmp_path / "glint" / "spirv").iterdir()
    data = bytearray(entry.read_bytes())
    data[len(data) // 2] ^= 0x08
    entry.write_bytes(bytes(data))
    again = run()
    assert again.returncode == 0, again.stderr
    assert again.stdout == first.stdout
    assert b"the cached SPIR-V" in again.stderr and b"damaged" in again.stderr, again.stderr
