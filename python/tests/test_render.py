"""Renders against the reference, scenes built in code, prepared scenes."""

import tomllib

import numpy as np
import pytest

import glint
from conftest import ROOT, gpu, small


@gpu
@pytest.mark.parametrize("name", ["seed-fig4.toml", "seed-fig5.toml", "glass.toml"])
def test_the_gpu_image_is_the_cpu_f64_image_within_tolerance(renderer, name):
    scene = small(name)
    image = glint.render(scene, renderer=renderer)
    reference = glint.render(scene, backend="cpu", precision="f64")
    assert image.shape == reference.shape == (60, 80, 3)
    assert image.dtype == reference.dtype == np.float32
    figures = glint.diff(image, reference)
    assert figures.nonfinite == 0
    assert figures.frac_over_1_255 <= 1e-3
    assert figures.rmse <= 4e-3
    # A check that cannot fail says nothing: a darker image fails it.
    assert glint.diff(image * 0.9, reference).rmse > 4e-3


@gpu
def test_compare_passes_the_scene_and_fails_one_sphere_moved_a_tenth_of_its_radius(renderer):
    with open(ROOT / "scenes/seed-fig4.toml", "rb") as f:
        d = tomllib.load(f)
    scene = glint.Scene.from_dict(d, width=96, height=72)
    passed = glint.compare(scene, renderer=renderer)
    assert passed.passed, passed.violations
    assert not passed.failing.any()

    sphere = d["spheres"][0]
    sphere["center"][0] += 0.1 * sphere["radius"]
    moved = glint.Scene.from_dict(d, width=96, height=72)
    image = glint.render(moved, renderer=renderer)
    failed = glint.compare(scene, image)
    assert not failed.passed
    assert failed.violations
    assert failed.over.shape == (72, 96) and failed.over.dtype == np.bool_
    # The pixels over tolerance lie where the sphere was and is.
    assert failed.failing.sum() > 0.002 * failed.over.size
    assert np.array_equal(failed.image, image)


@pytest.mark.parametrize("backend", ["gpu", "cpu"])
def test_a_scene_from_a_dict_renders_the_bits_of_its_toml_file(backend):
    if backend == "gpu" and not glint.GPU_BUILT:
        pytest.skip("this glint was built without the GPU renderer")
    path = ROOT / "scenes/seed-fig5.toml"
    with open(path, "rb") as f:
        d = tomllib.load(f)
    from_file = glint.load(path, width=64, height=48)
    from_dict = glint.Scene.from_dict(d, width=64, height=48)
    a = glint.render(from_file, backend=backend)
    b = glint.render(from_dict, backend=backend)
    assert a.tobytes() == b.tobytes()
    # One changed colour is another image.
    d.setdefault("render", {})["background"] = [0.5, 0.5, 0.5]
    c = glint.render(glint.Scene.from_dict(d, width=64, height=48), backend=backend)
    assert a.tobytes() != c.tobytes()


@gpu
def test_a_prepared_scene_renders_twice_the_same_bits_without_a_second_compile(renderer):
    prepared = renderer.prepare(small("seed-fig5.toml"), stats=True)
    first, s1 = prepared.render(stats=True)
    second, s2 = prepared.render(stats=True)
    assert first.tobytes() == second.tobytes()
    # The first render reports the prepare's compile (or its SPIR-V from
    # the cache) and pipeline; the second did neither.
    assert s1["compiled"] and s1["times"]["setup"]["pipeline_s"] > 0
    assert not s2["compiled"]
    assert s2["times"]["setup"]["compile_s"] == 0 and s2["times"]["setup"]["pipeline_s"] == 0
    assert s1["rays"] == s2["rays"] and s2["rays"]["eye"] == 80 * 60


@gpu
def test_a_region_is_the_whole_images_pixels(renderer):
    scene = small("seed-fig4.toml")
    whole = renderer.render(scene)
    part = renderer.render(scene, region=(8, 16, 40, 24))
    assert part.shape == (24, 40, 3)
    assert part.tobytes() == whole[16:40, 8:48].tobytes()


def test_cpu_stats_count_the_rays():
    image, stats = glint.render(small("seed-fig4.toml"), backend="cpu", precision="f64", stats=True)
    assert stats["backend"] == "cpu"
    assert stats["rays"]["eye"] == 80 * 60
    assert stats["rays"]["shadow"] > 0
    assert stats["seconds"]["trace"] > 0


def test_an_image_comes_to_numpy_without_a_copy():
    image = glint.render(small("seed-fig4.toml"), backend="cpu")
    assert image.flags["C_CONTIGUOUS"] and not image.flags["OWNDATA"]
    # A view of the 1-D array numpy made over glint's own vector.
    assert image.base is not None and image.base.base is not None
    assert type(image.base.base).__name__ == "PySliceContainer"


def test_an_obj_file_loads_with_a_camera_that_frames_it():
    scene = glint.load(ROOT / "scenes/meshes/octahedron.obj", width=48, height=36)
    assert scene.counts["triangles"] == 8
    image = glint.render(scene, backend="cpu")
    lit = (image.max(axis=2) > 0.2)
    # The mesh is in the picture and does not spill out of it.
    assert lit.any()
    assert not lit[0].any() and not lit[-1].any()
    assert not lit[:, 0].any() and not lit[:, -1].any()


@gpu
def test_explain_agrees_on_a_scene_that_compares_well_and_names_a_near_tie(renderer):
    [why] = glint.explain(small("seed-fig5.toml"), (40, 30), renderer=renderer)
    assert why.agree and why.divergence is None, str(why)
    assert [t["renderer"] for t in why.trees] == ["gpu f32", "cpu f32", "cpu f64"]
    assert "every tree agrees" in str(why)
    # Two spheres 1e-7 apart: f32 cannot tell which is nearer.
    d = {
        "image": {"width": 32, "height": 24},
        "camera": {"eye": [0.0, 0.0, 0.0], "look_at": [0.0, 0.0, -1.0], "vfov": 30.0},
        "materials": {"red": {"diffuse": [0.9, 0.0, 0.0]}, "green": {"diffuse": [0.0, 0.9, 0.0]}},
        "spheres": [
            {"center": [0.0, 0.0, -5.0000001], "radius": 1.0, "material": "red"},
            {"center": [0.0, 0.0, -5.0], "radius": 1.0, "material": "green"},
        ],
        "lights": [{"type": "point", "position": [0.0, 5.0, 0.0], "diffuse": [1.0, 1.0, 1.0]}],
    }
    [tie] = renderer.explain(glint.Scene.from_dict(d), (16, 12))
    assert not tie.agree
    assert tie.divergence["quantity"] == "ray 1: hit"
    assert "sphere 1 on the CPU and sphere 0 on the GPU" in tie.divergence["cause"]
    assert "(a near-tie)" in tie.divergence["cause"]
    with pytest.raises(ValueError, match="pixel 32,0 is outside the 32x24 image"):
        renderer.explain(glint.Scene.from_dict(d), (32, 0))


@pytest.mark.parametrize("backend", ["cpu", pytest.param("gpu", marks=gpu)])
def test_an_empty_aov_list_gives_the_dict_with_the_colour_alone(backend):
    # It gave the bare image array.
    scene = small("seed-fig3.toml", 16, 12)
    out = glint.render(scene, backend=backend, aovs=[])
    assert isinstance(out, dict) and list(out) == ["color"]
    assert out["color"].tobytes() == glint.render(scene, backend=backend).tobytes()


@pytest.mark.parametrize("backend", ["cpu", pytest.param("gpu", marks=gpu)])
def test_a_tqdm_bar_or_its_update_follows_a_render(backend):
    # progress=bar.update, as the docs showed it, raised TypeError: tqdm's
    # update takes an increment, and glint passed (done, total).
    tqdm = pytest.importorskip("tqdm")
    import io

    scene = small("seed-fig3.toml", 40, 30)
    for given in ("update", "bar"):
        bar = tqdm.tqdm(file=io.StringIO(), disable=False)
        glint.render(scene, backend=backend, progress=bar.update if given == "update" else bar)
        assert bar.total == 40 * 30 and bar.n == 40 * 30, (given, bar.n, bar.total)
        bar.close()
    calls = []
    glint.render(scene, backend=backend, progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1] == (40 * 30, 40 * 30)


@pytest.mark.parametrize("backend", ["cpu", pytest.param("gpu", marks=gpu)])
def test_render_takes_another_size_and_sample_count_without_a_reload(backend):
    path = ROOT / "scenes" / "seed-fig3.toml"
    scene = glint.load(path, width=32, height=24)
    image = glint.render(scene, backend=backend, width=20, height=15, samples=2)
    want = glint.render(glint.load(path, width=20, height=15, samples=2), backend=backend)
    assert image.shape == (15, 20, 3) and image.tobytes() == want.tobytes()
    assert (scene.width, scene.height, scene.samples) == (32, 24, 1)
    assert glint.render(scene, backend=backend).shape == (24, 32, 3)
    with pytest.raises(ValueError, match="samples=0"):
        glint.render(scene, backend=backend, samples=0)


@gpu
def test_a_scene_rendered_at_another_size_follows_its_changes_in_place():
    scene = glint.load(ROOT / "scenes" / "seed-fig3.toml", width=32, height=24)
    r = glint.Renderer()
    r.render(scene, width=16, height=12, stats=True)
    scene.params["spheres[0].radius"] = 4.0
    image, stats = r.render(scene, width=16, height=12, stats=True)
    assert stats["update"] == "updated in place", stats["update"]
    fresh = glint.Scene.from_dict(scene.to_dict(), base=scene.base, width=16, height=12)
    assert image.tobytes() == glint.Renderer().render(fresh).tobytes()


def test_a_cpu_region_counts_its_rays():
    scene = small("seed-fig4.toml")
    _, stats = glint.render(scene, backend="cpu", region=(10, 5, 20, 10), stats=True)
    assert stats["rays"]["eye"] == 20 * 10
    assert stats["tests"] is not None and stats["by_ray"] is not None
