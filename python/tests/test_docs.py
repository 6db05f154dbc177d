"""Every ```python block of docs/python.md runs, in order, in one namespace
(as a notebook's cells do), from the repository's root; a block that
defines test functions has them called."""

import os
import re

import pytest

import glint
from conftest import ROOT

BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def blocks():
    return BLOCK.findall((ROOT / "docs/python.md").read_text())


def test_the_page_has_its_examples():
    # A page whose fences changed would otherwise run nothing and pass.
    assert len(blocks()) >= 7


@pytest.mark.skipif(not glint.GPU_BUILT, reason="the page's session renders on the GPU")
def test_every_python_block_of_docs_python_md_runs(monkeypatch, tmp_path):
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(ROOT)
    monkeypatch.setenv("MPLCONFIGDIR", str(tmp_path))
    namespace = {"__name__": "docs_python_md"}
    for i, code in enumerate(blocks()):
        before = set(namespace)
        exec(compile(code, f"docs/python.md block {i + 1}", "exec"), namespace)
        for name in sorted(set(namespace) - before):
            if name.startswith("test_") and callable(namespace[name]):
                namespace[name]()
