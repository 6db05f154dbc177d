"""A seeded fuzz of what a notebook hands the module: `params` keys and
values (names with quotes, dots, backslashes and control characters),
arrays of every dtype and shape as meshes and textures, and AOV lists.
Every case gives a value or one of the documented exceptions (KeyError,
TypeError, ValueError, glint.Error), never another exception or a crash,
and every key `params` lists reads back."""

import random

import numpy as np
import pytest

import glint

ALLOWED = (KeyError, TypeError, ValueError, glint.Error)

NAME_PARTS = ['a', 'red glass', 'x.y', 'say "hi"', 'back\\slash', 'tab\there', '[0]', 'é', '""', '.', ' ']


def _name(rng):
    return "".join(rng.choice(NAME_PARTS) for _ in range(rng.randint(1, 3)))


def _scene(rng):
    names = list({_name(rng) for _ in range(3)})
    return {
        "image": {"width": 8, "height": 6},
        "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "vfov": 40},
        "materials": {n: {"diffuse": [rng.random(), 0.5, 0.5]} for n in names},
        "spheres": [{"center": [0, 0, 0], "radius": 1, "material": names[0]}],
        "lights": [{"type": "point", "position": [1, 2, 3]}],
    }


VALUES = [0, 1.5, -1e300, float("nan"), [1, 2, 3], [1, 2], "text", None, True, [[1]], {"a": 1}, 2**70]


def test_params_keys_and_values_are_taken_or_refused_in_one_of_the_documented_ways():
    rng = random.Random(73)
    for _ in range(60):
        scene = glint.Scene.from_dict(_scene(rng))
        listed = dict(scene.params)
        for key, value in listed.items():
            assert scene.params[key] == value, key
        keys = list(listed) + [_name(rng), "materials." + _name(rng) + ".diffuse", "spheres[9].radius"]
        for _ in range(6):
            key, value = rng.choice(keys), rng.choice(VALUES)
            generation = scene.generation
            try:
                scene.params[key] = value
            except ALLOWED:
                assert scene.generation == generation, "a refused change changed the scene"
        glint.render(scene, backend="cpu")


DTYPES = ["float16", "float32", "float64", "int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64", "bool", "complex64", "object"]
SHAPES = [(0,), (3,), (0, 3), (4, 3), (4, 2), (2, 2, 3), (2, 2, 4), (1, 1, 3), (4, 3, 1)]


def test_arrays_of_every_dtype_and_shape_are_taken_or_refused():
    rng = random.Random(74)
    quad_faces = np.array([[0, 1, 2], [0, 2, 3]])
    for dtype in DTYPES:
        for shape in SHAPES:
            a = np.zeros(shape, dtype=dtype) if dtype != "object" else np.full(shape, None, dtype=object)
            if a.size and dtype not in ("object", "bool"):
                a = (np.arange(a.size).reshape(shape) % 3).astype(dtype)
            d = _scene(rng)
            d["meshes"] = [{"vertices": a, "faces": quad_faces, "material": next(iter(d["materials"]))}]
            try:
                glint.render(glint.Scene.from_dict(d), backend="cpu")
            except ALLOWED:
                pass
            else:
                assert dtype not in ("complex64", "bool", "object"), (dtype, shape)
            d = _scene(rng)
            d["textures"] = {"t": {"image": a}}
            next(iter(d["materials"].values()))["texture"] = "t"
            try:
                glint.render(glint.Scene.from_dict(d), backend="cpu")
            except ALLOWED:
                pass


def test_aov_lists_are_taken_or_refused():
    rng = random.Random(75)
    scene = glint.Scene.from_dict(_scene(rng))
    names = ["depth", "normal", "albedo", "prim_id", "rays", "colour", "", "depth"]
    for _ in range(30):
        asked = rng.sample(names, rng.randint(0, 4))
        try:
            out = glint.render(scene, backend="cpu", aovs=asked)
        except ALLOWED:
            continue
        assert list(out) == ["color"] + asked
