"""`render(..., aovs=[...])`: the eye ray's first hit as arrays
beside the colour, on both renderers: ids and counts the same bits,
distances, normals and albedos within f32's rounding; left out of the
shader when not asked for."""

import numpy as np
import pytest

import glint
from conftest import gpu, small

ALL = ["depth", "normal", "albedo", "prim_id", "rays"]

ONE_SPHERE = """
[image]
width = 33
height = 25
[camera]
eye = [0, 0, 10]
look_at = [0, 0, 0]
vfov = 30
[materials.red]
ambient = [0.1, 0, 0]
diffuse = [0.7, 0.2, 0.1]
[[planes]]
point = [0, 0, -50]
normal = [0, 0, 1]
material = "red"
[[spheres]]
center = [0, 0, 0]
radius = 2
material = "red"
[[lights]]
type = "point"
position = [5, 5, 10]
diffuse = [1, 1, 1]
"""


@pytest.mark.parametrize("backend", ["cpu", pytest.param("gpu", marks=gpu)])
def test_aovs_say_what_the_eye_ray_met(backend):
    scene = glint.loads(ONE_SPHERE)
    out = glint.render(scene, backend=backend, aovs=ALL)
    assert set(out) == {"color", *ALL}
    h, w = 25, 33
    assert out["depth"].shape == (h, w) and out["depth"].dtype == np.float32
    assert out["normal"].shape == (h, w, 3) and out["albedo"].shape == (h, w, 3)
    assert out["prim_id"].shape == (h, w, 2) and out["prim_id"].dtype == np.int32
    assert out["rays"].shape == (h, w) and out["rays"].dtype == np.uint32
    # The centre pixel looks straight at the sphere (kind 0, index 0): 8
    # from the eye, its normal towards the eye, its diffuse colour.
    c = (12, 16)
    assert out["prim_id"][c].tolist() == [0, 0]
    assert out["depth"][c] == pytest.approx(8.0, rel=1e-5)
    assert out["normal"][c] == pytest.approx([0, 0, 1], abs=1e-5)
    assert out["albedo"][c] == pytest.approx([0.7, 0.2, 0.1], abs=1e-6)
    # An eye ray and a shadow ray; no mirror, no glass.
    assert out["rays"][c] == 2
    # A corner sees the plane behind, 60 away along the axis: kinds count
    # in the order of Scene.counts.
    assert list(scene.counts)[3] == "planes"
    assert out["prim_id"][0, 0].tolist() == [3, 0] and out["depth"][0, 0] > 60


def test_a_miss_is_infinite_and_has_no_primitive():
    scene = glint.loads(ONE_SPHERE.replace('[[planes]]\npoint = [0, 0, -50]\nnormal = [0, 0, 1]\nmaterial = "red"\n', ""))
    out = glint.render(scene, backend="cpu", aovs=["depth", "prim_id", "normal", "rays"])
    assert np.isinf(out["depth"][0, 0]) and out["prim_id"][0, 0].tolist() == [-1, -1]
    assert out["normal"][0, 0].tolist() == [0, 0, 0] and out["rays"][0, 0] == 1


@gpu
@pytest.mark.parametrize("name", ["seed-fig5.toml", "glass.toml", "textures.toml", "triangles.toml"])
def test_the_gpu_and_the_cpu_give_the_same_aovs(name):
    # A renderer of its own: the session's is other tests' to compile on.
    renderer = glint.Renderer()
    scene = small(name, 48, 36)
    gpu_out, stats = glint.render(scene, aovs=ALL, stats=True, renderer=renderer)
    cpu_out = glint.render(scene, backend="cpu", aovs=ALL)
    assert np.array_equal(gpu_out["prim_id"], cpu_out["prim_id"])
    assert np.array_equal(gpu_out["rays"], cpu_out["rays"])
    hit = gpu_out["prim_id"][..., 0] >= 0
    assert hit.any()
    assert np.array_equal(np.isinf(gpu_out["depth"]), ~hit)
    # Within f32's rounding (tests/aovs.rs says why these bounds): an
    # interpolated normal to 1e-4; an image texture's albedo to 2e-3, its
    # sphere's uv coming through llvmpipe's acos and atan2.
    np.testing.assert_allclose(gpu_out["depth"][hit], cpu_out["depth"][hit], rtol=1e-5)
    np.testing.assert_allclose(gpu_out["normal"][hit], cpu_out["normal"][hit], atol=1e-4)
    textured = name == "textures.toml"
    np.testing.assert_allclose(
        gpu_out["albedo"][hit], cpu_out["albedo"][hit], rtol=1e-5, atol=2e-3 if textured else 1e-6
    )
    # The rays are those the render counts, pixel by pixel.
    r = stats["rays"]
    assert int(gpu_out["rays"].sum()) == r["eye"] + r["reflect"] + r["refract"] + r["shadow"]
    # The colour is the plain render's, bit for bit.
    assert gpu_out["color"].tobytes() == glint.render(scene, renderer=renderer).tobytes()
    assert cpu_out["color"].tobytes() == glint.render(scene, backend="cpu").tobytes()
    # A check that can fail: the ids a pixel over are others.
    assert not np.array_equal(gpu_out["prim_id"], np.roll(cpu_out["prim_id"], 1, axis=1))


@gpu
def test_aovs_are_left_out_of_the_shader_when_not_asked_for():
    renderer = glint.Renderer()
    scene = small("seed-fig5.toml", 32, 24)
    _, plain = glint.render(scene, stats=True, renderer=renderer)
    out, stats = glint.render(scene, stats=True, renderer=renderer, aovs=["depth"])
    assert "aovs" not in plain["variant"] and "aovs" in stats["variant"]
    assert set(out) == {"color", "depth"}


def test_bad_aovs_are_refused_in_one_line():
    scene = small("seed-fig5.toml", 16, 12)
    with pytest.raises(ValueError, match='"colour" is not an AOV glint gives'):
        glint.render(scene, backend="cpu", aovs=["colour"])
    with pytest.raises(ValueError, match='"depth" is asked for twice'):
        glint.render(scene, backend="cpu", aovs=["depth", "depth"])
    with pytest.raises(TypeError, match="a list of names"):
        glint.render(scene, backend="cpu", aovs="depth")
    corners = glint.loads(ONE_SPHERE.replace("height = 25", 'height = 25\nsampling = "corners"'))
    with pytest.raises(ValueError, match="pixel's own samples"):
        glint.render(corners, backend="cpu", aovs=["depth"])
    contrast = glint.loads(ONE_SPHERE.replace("height = 25", 'height = 25\nsampling = "contrast"'))
    with pytest.raises(ValueError, match="samples by contrast"):
        glint.render(contrast, backend="cpu", aovs=["depth"])
    # The plain render of the same scene is fine: one image, no AOVs.
    assert glint.render(contrast, backend="cpu").shape == (25, 33, 3)


@pytest.mark.parametrize("backend", ["cpu", pytest.param("gpu", marks=gpu)])
def test_a_one_channel_aov_is_shown_grey_and_written_and_read_as_itself(tmp_path, backend):
    # glint.show and glint.write refused glint's own (h, w) AOVs.
    scene = small("seed-fig3.toml", 16, 12)
    out = glint.render(scene, backend=backend, aovs=["depth", "rays"])
    for name in ("depth", "rays"):
        for ext in ("exr", "pfm"):
            path = tmp_path / f"{name}.{ext}"
            glint.write(out[name], path)
            back = glint.read(path)
            assert back.shape == out[name].shape, (name, ext)
            assert np.array_equal(back, out[name].astype(np.float32)), (name, ext)
    png = glint.show(out["depth"], out["color"])._repr_png_()
    assert png.startswith(b"\x89PNG")
    grey = glint._grey(out["depth"])
    assert grey.shape == (12, 16, 3) and grey.min() >= 0 and grey.max() <= 1
    assert np.all(grey[..., 0] == grey[..., 1])
    with pytest.raises(glint.ImageError, match="one channel"):
        glint.write(out["depth"], tmp_path / "depth.png")
    assert not (tmp_path / "depth.png").exists()
