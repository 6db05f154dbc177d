"""The type stubs hold: stubtest checks them against the extension, and
mypy --strict checks the package and a user's calls (a misspelt keyword
must be caught)."""

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("mypy")


def mypy(*args, cwd):
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--cache-dir", str(Path(cwd) / ".mypy"), *args],
        capture_output=True, text=True, cwd=cwd,
    )


def test_the_stubs_match_the_extension(tmp_path):
    import glint

    if not glint.GPU_BUILT:
        # The CPU-only build's Renderer cannot be made, and its classes
        # carry no methods: the stubs describe the default build.
        pytest.skip("the stubs describe the build with the GPU renderer")
    run = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "glint._glint", "--mypy-config-file", "/dev/null"],
        capture_output=True, text=True, cwd=tmp_path,
    )
    assert run.returncode == 0, run.stdout + run.stderr


def test_the_package_is_strictly_typed(tmp_path):
    run = mypy("--strict", "-p", "glint", cwd=tmp_path)
    assert run.returncode == 0, run.stdout


USER = """
import glint
import numpy as np
import numpy.typing as npt

scene = glint.load("scenes/seed-fig4.toml", width=64)
image: npt.NDArray[np.float32] = glint.render(scene)
image2, stats = glint.render(scene, stats=True)
rays: int = stats["rays"]["eye"]
result = glint.compare(scene, image, rmse=1e-3)
ok: bool = result.passed
"""


def test_a_users_calls_are_checked(tmp_path):
    (tmp_path / "good.py").write_text(USER)
    run = mypy("--strict", "good.py", cwd=tmp_path)
    assert run.returncode == 0, run.stdout
    (tmp_path / "bad.py").write_text(USER.replace("width=64", "widht=64"))
    run = mypy("--strict", "bad.py", cwd=tmp_path)
    assert run.returncode != 0 and 'Unexpected keyword argument "widht"' in run.stdout, run.stdout
