"""Shared fixtures: the repository's scenes, one renderer for the session
(validation follows GLINT_VALIDATION=1, which ci/test sets, so a
validation message fails the test that caused it) and the GPU marker."""

from pathlib import Path

import pytest

import glint

ROOT = Path(__file__).resolve().parents[2]

gpu = pytest.mark.skipif(
    not glint.GPU_BUILT, reason="this glint was built without the GPU renderer"
)
cpu_only = pytest.mark.skipif(
    glint.GPU_BUILT, reason="checks the build without the GPU renderer"
)


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def renderer():
    if not glint.GPU_BUILT:
        pytest.skip("this glint was built without the GPU renderer")
    return glint.Renderer()


def small(name: str, width: int = 80, height: int = 60) -> glint.Scene:
    return glint.load(ROOT / "scenes" / name, width=width, height=height)
