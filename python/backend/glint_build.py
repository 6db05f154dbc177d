"""glint's build backend: maturin's, after two checks of its own.

- Without `cargo` it stops with one line that names ci/setup, where
  maturin would download a Rust toolchain of about 1 GB into ~/.cache
  and say nothing of it (issue 60).
- It says what the build does before it starts: pip shows these lines
  with `pip install -v ./python` (and on a failure, always).
- Cargo's target folder (some 600 MB) goes outside the source tree, to
  ~/.cache/glint-python-target, unless CARGO_TARGET_DIR names another.

Everything else is maturin's own hooks, unchanged.
"""

import os
import shutil
import sys

if not shutil.which("cargo"):
    raise SystemExit(
        "glint's Python module is built from Rust source and `cargo` is not on PATH: "
        "run ci/setup from the repository (it installs Rust and lavapipe), "
        "or put ~/.cargo/bin on PATH, then pip install ./python again"
    )

# maturin would install Rust itself where cargo is missing; it is not.
os.environ.setdefault("MATURIN_NO_INSTALL_RUST", "1")

from maturin import *  # noqa: E402,F401,F403  (the PEP 517 hooks)
from maturin import build_wheel as _build_wheel  # noqa: E402

if not os.environ.get("CARGO_TARGET_DIR"):
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    os.environ["CARGO_TARGET_DIR"] = os.path.join(cache, "glint-python-target")
_TARGET = os.environ["CARGO_TARGET_DIR"]


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    print(
        "glint: building the extension glint._glint with cargo (release): the glint crate, "
        "and on a first build glslang's C++ (5-8 minutes on 2 cores; later builds about a minute); "
        f"cargo's target folder: {_TARGET} (CARGO_TARGET_DIR moves it)",
        file=sys.stderr,
        flush=True,
    )
    return _build_wheel(wheel_directory, config_settings, metadata_directory)
