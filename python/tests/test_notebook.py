"""A notebook session's steps: a scene read back as a dict and
from a dict in another folder, one colour convention for PNG, images shown
inline, setup times that say what a render spent, devices() without a
driver, and the package imported from inside python/."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import glint
from conftest import ROOT, gpu, small

# Half a PNG level through the steepest part of the sRGB decoding (slope
# 2.4 / 1.055 at 1.0): the most a linear value moves through a PNG.
PNG_ROUNDING = 0.5 / 255 * 2.4 / 1.055


def test_to_dict_and_from_dict_give_the_same_bits():
    scene = small("seed-fig5.toml")
    again = glint.Scene.from_dict(scene.to_dict(), base=scene.base)
    assert again.width == 80 and again.height == 60
    a = glint.render(scene, backend="cpu")
    b = glint.render(again, backend="cpu")
    assert a.tobytes() == b.tobytes()
    # A check that can fail: a changed radius is another image.
    d = scene.to_dict()
    d["spheres"][0]["radius"] *= 1.1
    moved = glint.render(glint.Scene.from_dict(d, base=scene.base), backend="cpu")
    assert moved.tobytes() != a.tobytes()


def test_from_dict_reads_relative_files_from_its_base(tmp_path, monkeypatch):
    scene = small("textures.toml")
    d = scene.to_dict()
    assert d["textures"]["map"]["image"] == "meshes/globe.png"
    monkeypatch.chdir(tmp_path)
    # Of the working directory, the texture is not there: the error names it.
    with pytest.raises(glint.SceneError, match="globe.png"):
        glint.Scene.from_dict(d)
    again = glint.Scene.from_dict(d, base=ROOT / "scenes")
    assert glint.render(again, backend="cpu").tobytes() == glint.render(scene, backend="cpu").tobytes()


def test_an_nff_scene_comes_back_as_its_conversion():
    scene = glint.load(ROOT / "scenes/spd/tetra.nff", width=48, height=48)
    d = scene.to_dict()
    assert d["image"]["width"] == 48 and "triangles" in d
    again = glint.Scene.from_dict(d)
    assert glint.render(again, backend="cpu").tobytes() == glint.render(scene, backend="cpu").tobytes()


def test_a_half_goes_through_png_and_exr_as_a_half(tmp_path):
    half = np.full((4, 6, 3), 0.5, dtype=np.float32)
    glint.write(half, tmp_path / "h.exr")
    assert np.all(glint.read(tmp_path / "h.exr") == 0.5)
    glint.write(half, tmp_path / "h.png")
    back = glint.read(tmp_path / "h.png")
    assert np.abs(back - 0.5).max() <= PNG_ROUNDING
    assert np.abs(back - 0.5).max() > 0, "a PNG holds 8-bit levels"
    # The level is the sRGB one: 188, where a linear PNG would hold 128.
    levels = np.round(glint.read(tmp_path / "h.png", srgb=False) * 255)
    assert np.all(levels == 188)
    # A PNG read and written again keeps its levels.
    glint.write(back, tmp_path / "again.png")
    assert (tmp_path / "again.png").read_bytes() == (tmp_path / "h.png").read_bytes()


def test_linear_png_levels_are_there_when_asked_for(tmp_path):
    half = np.full((2, 2, 3), 0.5, dtype=np.float32)
    glint.write(half, tmp_path / "linear.png", srgb=False)
    assert np.all(np.round(glint.read(tmp_path / "linear.png", srgb=False) * 255) == 128)


def texture_scene(image: str) -> str:
    return f"""
[image]
width = 9
height = 9
[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]
vfov = 20
[textures.t]
image = "{image}"
[materials.m]
texture = "t"
[[spheres]]
center = [0, 0, 0]
radius = 1
material = "m"
[[lights]]
type = "directional"
direction = [0, 0, -1]
diffuse = [1, 1, 1]
"""


def test_a_half_written_to_png_renders_as_a_half_as_a_texture(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    half = np.full((4, 4, 3), 0.5, dtype=np.float32)
    glint.write(half, "half.png")
    glint.write(half, "half.pfm")
    png = glint.render(glint.loads(texture_scene("half.png")), backend="cpu")[4, 4]
    pfm = glint.render(glint.loads(texture_scene("half.pfm")), backend="cpu")[4, 4]
    assert pfm[0] > 0.4, "the centre is lit head-on"
    assert np.abs(png / pfm * 0.5 - 0.5).max() <= PNG_ROUNDING


def test_uint8_levels_are_srgb_and_are_written_as_they_are(tmp_path):
    levels = np.full((2, 3, 3), 128, dtype=np.uint8)
    glint.write(levels, tmp_path / "x.png")
    assert np.all(np.round(glint.read(tmp_path / "x.png", srgb=False) * 255) == 128)
    glint.write(levels, tmp_path / "x.pfm")
    assert np.allclose(glint.read(tmp_path / "x.pfm"), 0.2158605, atol=1e-6)


def decode_png(data: bytes, tmp_path) -> np.ndarray:
    path = tmp_path / "shown.png"
    path.write_bytes(data)
    return glint.read(path)


def test_show_gives_the_png_of_the_image(tmp_path):
    image = glint.render(small("seed-fig4.toml", 40, 30), backend="cpu")
    data = glint.show(image)._repr_png_()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    shown = decode_png(data, tmp_path)
    assert shown.shape == image.shape
    assert np.abs(shown - np.clip(image, 0, 1)).max() <= PNG_ROUNDING
    # Two side by side, with a white gap of 4 columns.
    both = decode_png(glint.show(image, image * 0.5)._repr_png_(), tmp_path)
    assert both.shape == (30, 84, 3)
    assert np.all(both[:, 40:44] == 1.0)
    with pytest.raises(ValueError, match="at least one"):
        glint.show()


def test_a_comparison_shows_image_reference_and_failing_pixels(tmp_path):
    scene = small("seed-fig4.toml", 40, 30)
    reference = glint.render(scene, backend="cpu", precision="f64")
    darker = reference * 0.5
    result = glint.compare(scene, darker, backend="cpu")
    assert not result.passed
    shown = decode_png(result._repr_png_(), tmp_path)
    assert shown.shape == (30, 3 * 40 + 8, 3)
    mask = shown[:, 88:]
    assert np.all((mask[..., 0] == 1.0) == result.failing)


@gpu
def test_a_prepared_scenes_second_render_spent_no_setup(renderer):
    r = glint.Renderer()
    prepared = r.prepare(small("seed-fig4.toml", 32, 24), stats=True)
    _, first = prepared.render(stats=True)
    _, second = prepared.render(stats=True)
    assert first["seconds"]["setup"] > 0
    # The device's opening was counted again at every render.
    assert second["seconds"]["setup"] == 0.0, second["seconds"]
    # Another scene on the same renderer: its compile, not the device again.
    _, other = r.render(small("seed-fig5.toml", 32, 24), stats=True)
    t = other["times"]
    spent = t["setup"]["compile_s"] + t["setup"]["pipeline_s"] + t["setup"]["driver_compile_s"] + t["bvh_s"]
    assert t["setup"]["device_s"] > 0
    assert other["seconds"]["setup"] == pytest.approx(spent, abs=1e-12)


def python(code: str, cwd, **env) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code],
        cwd=cwd,
        env=dict(os.environ, **env),
        capture_output=True,
        text=True,
        timeout=120,
    )


@gpu
def test_devices_without_a_vulkan_driver_is_an_empty_list(tmp_path):
    run = python(
        "import glint, json; print(json.dumps(glint.devices()))",
        tmp_path,
        VK_DRIVER_FILES=str(tmp_path / "no-such-icd.json"),
        VK_ICD_FILENAMES=str(tmp_path / "no-such-icd.json"),
    )
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout) == []


def test_the_package_imports_from_inside_the_python_folder():
    # python/glint/ once shadowed the installed package there, without its
    # compiled module: a circular-import ImportError.
    run = python("import glint; print(glint.GPU_BUILT)", ROOT / "python")
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == str(glint.GPU_BUILT)


@gpu
def test_a_sphere_swept_through_a_mesh_scene_compiles_once():
    # Every position compiled a new variant (the BVH's node
    # count and depth were in its key).
    d = {
        "image": {"width": 48, "height": 36},
        "camera": {"eye": [0, 0.5, 4], "look_at": [0, 0, 0], "vfov": 45},
        "materials": {"m": {"ambient": [0.1, 0.1, 0.1], "diffuse": [0.6, 0.6, 0.6]}},
        "meshes": [{"file": "meshes/icosphere-smooth.obj", "material": "m"}],
        "spheres": [{"center": [0, 0, 0], "radius": 0.3, "material": "m"}],
        "lights": [{"type": "point", "position": [2, 3, 4], "diffuse": [1, 1, 1]}],
    }
    r = glint.Renderer()
    compiled = []
    for i in range(6):
        d["spheres"][0]["center"] = [-1.5 + 0.6 * i, 0.2 * i, 0.5]
        scene = glint.Scene.from_dict(d, base=ROOT / "scenes")
        image, stats = r.render(scene, stats=True)
        compiled.append(stats["compiled"])
    assert sum(compiled) <= 1, compiled
    # The last frame is a fresh renderer's, compiled afresh, bit for bit.
    fresh = glint.Renderer(cache=False).render(scene)
    assert image.tobytes() == fresh.tobytes()


def test_the_build_refuses_in_one_line_without_cargo(tmp_path):
    # Where cargo is missing, maturin would download a Rust toolchain of
    # about 1 GB into ~/.cache and say nothing; glint's backend stops
    # first, naming ci/setup.
    run = subprocess.run(
        [sys.executable, "-c", "import glint_build"],
        cwd=tmp_path,
        env=dict(os.environ, PATH="/usr/bin:/bin", PYTHONPATH=str(ROOT / "python/backend")),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode != 0
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "cargo" in lines[0] and "ci/setup" in lines[0], run.stderr


def read_obj(path):
    vertices, normals, faces = [], [], []
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            vertices.append([float(x) for x in w[1:4]])
        elif w[0] == "vn":
            normals.append([float(x) for x in w[1:4]])
        elif w[0] == "f":
            faces.append([int(c.split("/")[0]) - 1 for c in w[1:4]])
    return np.array(vertices), np.array(normals), np.array(faces, dtype=np.int32)


def mesh_scene(mesh):
    return {
        "image": {"width": 40, "height": 30},
        "camera": {"eye": [0.4, 0.6, 3], "look_at": [0, 0, 0], "vfov": 45},
        "materials": {"m": {"ambient": [0.1, 0.1, 0.1], "diffuse": [0.7, 0.6, 0.5], "specular": [0.3, 0.3, 0.3], "shininess": 20}},
        "meshes": [dict(mesh, material="m")],
        "lights": [{"type": "point", "position": [2, 3, 4], "diffuse": [1, 1, 1], "specular": [1, 1, 1]}],
    }


def test_a_mesh_from_numpy_renders_as_its_obj_file():
    obj = ROOT / "scenes/meshes/icosphere-smooth.obj"
    vertices, normals, faces = read_obj(obj)
    from_file = glint.Scene.from_dict(mesh_scene({"file": str(obj)}))
    from_arrays = glint.Scene.from_dict(mesh_scene({"vertices": vertices, "faces": faces, "normals": normals}))
    assert from_arrays.counts["triangles"] == len(faces) == 320
    a = glint.render(from_file, backend="cpu")
    b = glint.render(from_arrays, backend="cpu")
    assert a.tobytes() == b.tobytes()
    # Flat, without the normals: another image.
    flat = glint.Scene.from_dict(mesh_scene({"vertices": vertices, "faces": faces}))
    assert glint.render(flat, backend="cpu").tobytes() != a.tobytes()


def test_a_numpy_mesh_taken_as_arrays_is_its_written_file_parsed():
    # from_dict takes a numpy mesh's triangles from its arrays, not from
    # parsing back the OBJ file it writes: the same triangles as parsing
    # that file, with normals, uvs (a texture reads them), scale and translate.
    obj = ROOT / "scenes/meshes/icosphere-smooth.obj"
    vertices, normals, faces = read_obj(obj)
    uvs = np.stack([np.arctan2(vertices[:, 0], vertices[:, 2]) / 6.3 + 0.5, vertices[:, 1] / 2 + 0.5], 1)
    mesh = {"vertices": vertices, "faces": faces, "normals": normals, "uvs": uvs, "scale": 0.8, "translate": [0.1, -0.1, 0]}
    d = mesh_scene(mesh)
    texels = np.random.default_rng(61).random((8, 8, 3), dtype=np.float32)
    d["textures"] = {"t": {"image": texels}}
    d["materials"]["m"]["texture"] = "t"
    from_arrays = glint.Scene.from_dict(d)
    written = from_arrays.to_dict()["meshes"][0]
    assert written["file"].endswith(".obj")
    parsed = glint.Scene.from_dict(dict(d, meshes=[written]))
    a = glint.render(from_arrays, backend="cpu")
    assert a.tobytes() == glint.render(parsed, backend="cpu").tobytes()
    # A check that can fail: the uvs shifted are another image.
    shifted = glint.Scene.from_dict(dict(d, meshes=[dict(mesh, uvs=uvs + 0.05, material="m")]))
    assert glint.render(shifted, backend="cpu").tobytes() != a.tobytes()


def test_a_mesh_from_numpy_with_a_bad_index_is_refused_by_its_key():
    vertices = np.zeros((3, 3))
    with pytest.raises(ValueError, match=r"meshes\[0\]\.faces: vertex index 3 is outside the 3 vertices"):
        glint.Scene.from_dict(mesh_scene({"vertices": vertices, "faces": [[0, 1, 3]]}))
    with pytest.raises(ValueError, match=r"meshes\[0\]\.vertices: has shape \(3, 2\)"):
        glint.Scene.from_dict(mesh_scene({"vertices": np.zeros((3, 2)), "faces": [[0, 1, 2]]}))
    # Not truncated to vertex 0, as numpy's cast to integers would.
    with pytest.raises(ValueError, match=r"meshes\[0\]\.faces: holds 0\.5: a vertex index is a whole number"):
        glint.Scene.from_dict(mesh_scene({"vertices": vertices, "faces": [[0.5, 1, 2]]}))
    with pytest.raises(ValueError, match=r"meshes\[0\]\.faces: is empty"):
        glint.Scene.from_dict(mesh_scene({"vertices": vertices, "faces": np.zeros((0, 3), dtype=int)}))
    with pytest.raises(ValueError, match=r"meshes\[0\]\.vertices: holds NaN"):
        glint.Scene.from_dict(mesh_scene({"vertices": np.full((3, 3), np.nan), "faces": [[0, 1, 2]]}))


def test_a_texture_from_numpy_renders_as_its_file(tmp_path):
    rng = np.random.default_rng(60)
    texels = rng.random((8, 16, 3), dtype=np.float32)
    glint.write(texels, tmp_path / "t.pfm")
    levels = (rng.random((8, 16, 3)) * 255).astype(np.uint8)
    glint.write(levels, tmp_path / "t.png")
    for array, name in [(texels, "t.pfm"), (levels, "t.png")]:
        d = glint.loads(texture_scene(str(tmp_path / name))).to_dict()
        from_file = glint.render(glint.Scene.from_dict(d), backend="cpu")
        d["textures"]["t"]["image"] = array
        from_array = glint.render(glint.Scene.from_dict(d), backend="cpu")
        assert from_array.tobytes() == from_file.tobytes(), name
    # A bad texel is named by its key, not by the file it would be written as.
    d = glint.loads(texture_scene(str(tmp_path / "t.pfm"))).to_dict()
    for bad, shown in [(np.nan, "NaN"), (-1.0, "-1")]:
        d["textures"]["t"]["image"] = np.full((2, 2, 3), bad, dtype=np.float32)
        with pytest.raises(ValueError, match=rf"textures\.t\.image: holds {shown}"):
            glint.Scene.from_dict(d)


@pytest.mark.parametrize("backend", ["cpu", pytest.param("gpu", marks=gpu)])
def test_progress_counts_up_to_every_pixel(backend):
    scene = small("seed-fig5.toml", 96, 72)
    calls = []
    image = glint.render(scene, backend=backend, progress=lambda done, total: calls.append((done, total)))
    assert calls, "called at least at the end"
    assert calls[-1] == (96 * 72, 96 * 72)
    assert all(a[0] < b[0] for a, b in zip(calls, calls[1:])), "each call a step further"
    assert image.tobytes() == glint.render(scene, backend=backend).tobytes()
    # A region counts its own pixels.
    region_calls = []
    glint.render(scene, backend=backend, region=(8, 4, 16, 10), progress=lambda d, t: region_calls.append((d, t)))
    assert region_calls[-1] == (160, 160)


def test_a_progress_callback_that_raises_stops_the_render():
    scene = small("seed-fig5.toml", 96, 72)

    def fail(done, total):
        raise RuntimeError(f"stop at {done}")

    with pytest.raises(RuntimeError, match="stop at"):
        glint.render(scene, backend="cpu", progress=fail)


QUAD = {"vertices": np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float), "faces": np.array([[0, 1, 2], [0, 2, 3]])}


@pytest.mark.parametrize(
    "change, words",
    [
        # A vertex past the coordinates' bound once scaled.
        (lambda d: d["meshes"][0].update(scale=1e17, vertices=QUAD["vertices"] * 100), "meshes[0]: face 0: vertex"),
        (lambda d: d["meshes"][0].pop("material"), "meshes[0]: the mesh has no material: add material"),
        (lambda d: d["meshes"][0].update(file="elsewhere.obj"), "gives both a file and arrays"),
        (lambda d: d.update(textures={"t": {"image": np.ones((1, 8193, 3), np.float32)}}), "textures.t.image"),
    ],
)
def test_an_array_error_names_the_arrays_not_glints_files(change, words):
    # They named /tmp/glint-arrays-XXXX/1.obj, an MTL file there is none
    # of, a .pfm's size, or TOML's "duplicate key `file`".
    d = mesh_scene(dict(QUAD))
    change(d)
    with pytest.raises((glint.SceneError, ValueError)) as e:
        glint.Scene.from_dict(d)
    said = str(e.value)
    assert words in said, said
    assert "glint-arrays" not in said and ".pfm" not in said and "duplicate key" not in said, said


def test_a_copy_of_an_array_scene_outlives_the_original():
    # The copy named the original's temporary files; once the original was
    # collected, every change to the copy failed.
    import gc

    original = glint.Scene.from_dict(mesh_scene(dict(QUAD)))
    want = glint.render(original, backend="cpu")
    copy = glint.Scene.from_dict(original.to_dict(), base=original.base)
    del original
    gc.collect()
    copy.params["camera.vfov"] = 45.0
    assert glint.render(copy, backend="cpu").tobytes() == want.tobytes()
