"""Every error is a glint.Error with the binary's one line."""

import os

import numpy as np
import pytest

import glint
from conftest import ROOT, cpu_only, gpu, small


def test_a_scene_error_names_its_file_line_and_column(tmp_path):
    path = tmp_path / "bad.toml"
    text = (ROOT / "scenes/seed-fig4.toml").read_text()
    text = text.replace("radius = 6.0", "radius = -6.0")
    path.write_text(text)
    line = next(i for i, l in enumerate(text.splitlines(), 1) if "radius = -6.0" in l)
    with pytest.raises(glint.SceneError) as e:
        glint.load(path)
    err = e.value
    assert isinstance(err, glint.Error)
    assert err.file == str(path)
    assert (err.line, err.column) == (line, len("radius = ") + 1)
    assert "\n" not in str(err)
    assert str(err).startswith(f"{path}:{line}:{len('radius = ') + 1}: spheres[0].radius:")


def test_a_syntax_error_in_a_string_says_where():
    with pytest.raises(glint.SceneError) as e:
        glint.loads("[image]\nwidth = 64\nheight = = 3\n")
    assert (e.value.file, e.value.line) == ("<string>", 3)


def test_a_dict_error_names_the_key():
    d = {"image": {"width": 8, "height": 8}, "camera": {"eye": [0, 0, 1], "look_at": [0, 0, 0], "vfov": 40},
         "spheres": [{"center": [0, 0, 0], "radius": 0.0, "material": "m"}],
         "materials": {"m": {"diffuse": [1, 1, 1]}}}
    with pytest.raises(glint.SceneError) as e:
        glint.Scene.from_dict(d)
    assert str(e.value).startswith("<dict>: spheres[0].radius:")
    assert e.value.line is None
    with pytest.raises(TypeError, match=r"spheres\[0\]\.center\[1\]: None"):
        d["spheres"][0]["center"][1] = None
        glint.Scene.from_dict(d)


def test_a_missing_file_is_a_scene_error():
    with pytest.raises(glint.SceneError, match="cannot read scene"):
        glint.load("no/such/scene.toml")


@gpu
def test_a_shader_error_is_one_line_naming_the_file_and_line(root):
    specular = (root / "shaders/specular.glsl").read_text().splitlines()
    specular.insert(3, "this is not GLSL;")
    renderer = glint.Renderer(include={"specular.glsl": "\n".join(specular)})
    with pytest.raises(glint.ShaderError) as e:
        renderer.render(small("seed-fig4.toml"))
    message = str(e.value)
    assert "\n" not in message
    assert message.startswith("the shader does not compile: ")
    assert "specular.glsl:4: error:" in message
    assert e.value.log.splitlines()[0] in message


def test_an_image_error_leaves_no_file(tmp_path):
    image = np.zeros((4, 4, 3), np.float32)
    with pytest.raises(glint.ImageError):
        glint.write(image, tmp_path / "picture.bmp")
    with pytest.raises(glint.ImageError):
        glint.write(image, tmp_path / "no-such-folder" / "picture.png")
    assert os.listdir(tmp_path) == []
    with pytest.raises(glint.ImageError):
        glint.read(tmp_path / "missing.pfm")


def test_images_round_trip(tmp_path):
    rng = np.random.default_rng(7)
    image = rng.random((5, 7, 3), dtype=np.float32) * 4
    for ext in ["pfm", "exr"]:
        glint.write(image, tmp_path / f"a.{ext}")
        assert glint.read(tmp_path / f"a.{ext}").tobytes() == image.tobytes()
    # A PNG is sRGB-encoded: half a level, through the decoding.
    glint.write(image / 4, tmp_path / "a.png")
    back = glint.read(tmp_path / "a.png")
    assert np.abs(back - image / 4).max() <= 0.5 / 255 * 2.4 / 1.055


@cpu_only
def test_without_the_gpu_a_gpu_call_is_a_device_error_and_the_cpu_renders():
    with pytest.raises(glint.DeviceError, match="built without it"):
        glint.Renderer()
    with pytest.raises(glint.DeviceError, match="built without it"):
        glint.render(small("seed-fig4.toml"))
    with pytest.raises(glint.DeviceError):
        glint.devices()
    assert glint.render(small("seed-fig4.toml"), backend="cpu").shape == (60, 80, 3)
    assert glint.compare(small("seed-fig4.toml"), backend="cpu").passed


def test_bad_arguments_are_value_errors():
    scene = small("seed-fig4.toml")
    with pytest.raises(ValueError, match="precision"):
        glint.render(scene, backend="cpu", precision="f16")
    with pytest.raises(ValueError, match="backend"):
        glint.render(scene, backend="tpu")
    with pytest.raises(ValueError, match="not inside"):
        glint.render(scene, backend="cpu", region=(70, 0, 20, 10))


@pytest.mark.parametrize("on_render_thread", [False, True])
def test_a_panic_is_a_glint_error_and_the_interpreter_goes_on(on_render_thread):
    with pytest.raises(glint.Error, match="internal error .*a test's panic"):
        glint._glint._test_panic(on_render_thread)
    assert glint.render(small("seed-fig4.toml", 8, 6), backend="cpu").shape == (6, 8, 3)


@gpu
def test_an_open_given_up_does_not_hang_the_interpreters_exit(tmp_path):
    """A driver library that is a FIFO holds the dynamic loader's lock for
    ever inside dlopen. The Renderer gives the open up at its limit (20 s),
    and the interpreter's exit, whose C library takes that lock, hung for
    ever after it; it now ends with the script's own status."""
    import subprocess
    import sys

    fifo = tmp_path / "libfifo.so"
    os.mkfifo(fifo)
    manifest = tmp_path / "fifo.json"
    manifest.write_text(
        '{"file_format_version": "1.0.0", '
        f'"ICD": {{"library_path": "{fifo}", "api_version": "1.3.0"}}}}'
    )
    child = """
import sys, glint
try:
    glint.Renderer()
    print("opened")
except glint.DeviceError as e:
    print("refused:", "did not finish within" in str(e), flush=True)
sys.exit(3)
"""
    env = dict(os.environ, VK_DRIVER_FILES=str(manifest))
    out = subprocess.run(
        [sys.executable, "-c", child], capture_output=True, text=True, env=env, timeout=90
    )
    assert out.stdout.strip() == "refused: True", (out.stdout, out.stderr)
    assert out.returncode == 3, (out.returncode, out.stderr)


@pytest.mark.parametrize(
    "keyword, value",
    [("width", -1), ("height", -3), ("samples", 2**40), ("max_depth", 0), ("width", 10**40)],
)
def test_a_whole_number_keyword_out_of_range_is_a_value_error_naming_it(keyword, value):
    # They raised OverflowError "out of range integral type conversion
    # attempted", naming nothing.
    path = ROOT / "scenes" / "seed-fig3.toml"
    with pytest.raises(ValueError, match=f"{keyword}={value}: must be a whole number in 1..="):
        glint.load(path, **{keyword: value})
    with pytest.raises(ValueError, match=f"{keyword}="):
        glint.Scene.from_dict(glint.load(path).to_dict(), **{keyword: value})
    with pytest.raises(TypeError, match=f"{keyword}="):
        glint.load(path, **{keyword: "3"})


@gpu
def test_a_sample_keyword_below_zero_is_a_value_error_naming_it(renderer):
    with pytest.raises(ValueError, match="sample=-1"):
        glint.explain(small("seed-fig3.toml", 16, 12), (1, 1), sample=-1, renderer=renderer)


@gpu
def test_a_reserved_define_is_refused_in_pythons_words():
    # It raised "-D MAX_DEPTH: ...", the command line's words.
    with pytest.raises(ValueError, match='defines: "MAX_DEPTH": glint defines MAX_DEPTH itself') as e:
        glint.Renderer(defines={"MAX_DEPTH": "3"})
    assert "-D" not in str(e.value)


@pytest.mark.parametrize("dtype", ["int16", "int32", "int64", "uint32", "bool"])
def test_a_texture_array_of_other_integers_is_refused_naming_its_dtype(dtype):
    # Levels of 200 in an int16 array became texels of 200.0.
    d = glint.load(ROOT / "scenes" / "seed-fig3.toml").to_dict()
    d["textures"] = {"t": {"image": np.full((2, 2, 3), 1, dtype=dtype)}}
    with pytest.raises(ValueError, match=f"textures.t.image: is an array of {dtype}"):
        glint.Scene.from_dict(d)


@gpu
@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"include": "no-such-folder"}, "no such folder"),
        ({"defines": {"A B": "1"}}, "a define is NAME"),
        ({"defines": {"A": 'say "hi"'}}, "may not hold"),
    ],
)
def test_a_renderer_refuses_what_the_binary_refuses(kwargs, words):
    with pytest.raises(ValueError, match=words):
        glint.Renderer(**kwargs)


@gpu
def test_a_renderer_refuses_a_file_as_an_include_folder(tmp_path):
    f = tmp_path / "shade.glsl"
    f.write_text("// a file, not a folder\n")
    with pytest.raises(ValueError, match="not a folder"):
        glint.Renderer(include=str(f))


@pytest.mark.parametrize("region", [(0, 0, 999, 4), (-1, 0, 4, 4), (0, 0, 4), (0.5, 0, 4, 4), (True, 0, 4, 4)])
@pytest.mark.parametrize("backend", ["cpu", pytest.param("gpu", marks=gpu)])
def test_a_bad_region_is_a_value_error_on_either_backend(region, backend):
    with pytest.raises(ValueError):
        glint.render(small("seed-fig4.toml"), backend=backend, region=region)


@gpu
@pytest.mark.parametrize("pixel", [(9.9, 5.9), (-0.5, 0), (1, 2, 3), (-1, 0)])
def test_explain_takes_a_pixel_of_two_whole_numbers(renderer, pixel):
    with pytest.raises(ValueError):
        renderer.explain(small("seed-fig4.toml"), pixel)


def test_errors_give_pythons_words_not_the_command_lines(tmp_path):
    # A keyword out of range is a ValueError naming it (it was a
    # glint.Error; a keyword out of range is a ValueError, as width=-1 is).
    with pytest.raises(ValueError) as e:
        glint.load(ROOT / "scenes" / "seed-fig4.toml", width=0)
    assert "--width" not in str(e.value) and "width=0" in str(e.value)
    locked = tmp_path / "locked.png"
    glint.write(np.zeros((2, 2, 3), np.float32), locked)
    locked.chmod(0o444)
    with pytest.raises(glint.Error) as e:
        glint.write(np.ones((2, 2, 3), np.float32), locked)
    assert "--force" not in str(e.value), str(e.value)


@gpu
def test_a_sample_past_the_pixels_is_named_as_python_names_it(renderer):
    with pytest.raises(ValueError) as e:
        renderer.explain(small("seed-fig4.toml"), (1, 1), sample=9)
    assert "--sample" not in str(e.value) and "sample=" in str(e.value)


def test_an_obj_files_error_is_said_of_the_obj(tmp_path):
    """A bad OBJ loaded as a scene was reported at line
    20 of the scene glint wrote around it, which the caller never sees."""
    obj = tmp_path / "bad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(glint.SceneError) as e:
        glint.load(obj)
    assert e.value.file == str(obj) and e.value.line is None, str(e.value)
    assert str(e.value).startswith(f"{obj}: ") and str(e.value).count(str(obj)) == 1, str(e.value)


@pytest.mark.parametrize("value, error", [(None, TypeError), (1, glint.SceneError)])
def test_a_bad_keys_control_characters_are_escaped(value, error):
    bad = "a\nb\x1b[31m"
    with pytest.raises(error) as e:
        glint.Scene.from_dict({"image": {"width": 8, "height": 8, bad: value}})
    text = str(e.value)
    assert "\n" not in text and "\x1b" not in text and "31m" in text, repr(text)
