"""What the module holds itself to in memory and on the stack: what does
not fit raises and the interpreter lives, a dict that holds itself or nests
deep is a ValueError, and a scene from a dict takes about what its text
does."""

import pytest

import glint
from conftest import ROOT

ROOT_SCENE = ROOT / "scenes" / "seed-fig4.toml"


def _declared_png(path, side):
    """A PNG that declares side x side RGB pixels, all zero: a few hundred
    KB that inflate to side * side * 3 bytes."""
    import struct
    import zlib

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    z = zlib.compressobj(9)
    row = b"\0" * (1 + 3 * side)
    idat = b"".join(z.compress(row) for _ in range(side)) + z.flush()
    header = struct.pack(">IIBBBBB", side, side, 8, 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", idat) + chunk(b"IEND", b""))


def test_what_does_not_fit_in_memory_raises_and_the_interpreter_lives(tmp_path):
    """A render at 16384x16384, or a small PNG that
    declares 16384x16384, under a 3 GiB cap aborted the interpreter."""
    import subprocess
    import sys

    png = tmp_path / "declares.png"
    _declared_png(png, 16384)
    child = f"""
import resource, glint
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
scene = glint.load({str(ROOT_SCENE)!r}, width=16384, height=16384)
for call in (lambda: glint.render(scene, backend="cpu"), lambda: glint.read({str(png)!r})):
    try:
        call()
        print("rendered")
    except (MemoryError, glint.Error) as e:
        print(type(e).__name__, "reading its 16384x16384 pixels" in str(e), str(e)[:60])
print("alive")
"""
    out = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[-1] == "alive", out.stdout
    assert lines[0].startswith("MemoryError False a 16384x16384 render needs"), out.stdout
    assert lines[1].startswith("ImageError True"), out.stdout


def test_a_dict_that_holds_itself_or_nests_deep_is_a_value_error():
    """These overflowed the stack (SIGSEGV)."""
    d = {"image": {"width": 8, "height": 8}}
    d["camera"] = d
    with pytest.raises(ValueError, match="nested more than"):
        glint.Scene.from_dict(d)
    deep = [1.0]
    for _ in range(10_000):
        deep = [deep]
    with pytest.raises(ValueError, match="nested more than"):
        glint.Scene.from_dict({"image": {"width": 8, "height": 8, "x": deep}})


def test_a_dict_of_many_spheres_takes_about_what_its_text_does():
    """200,000 spheres from a dict took 630 MB where
    glint.loads of the same scene took 40 MB."""
    import subprocess
    import sys

    # Measured from the memory in use once the list is built to the
    # child's own high-water mark (VmHWM): ru_maxrss counts the memory of
    # the process it was forked from too, the whole pytest run in CI, so
    # its growth could read 0 whatever the conversion took.
    child = """
import glint
def status(key): return int(open('/proc/self/status').read().split(key)[1].split()[0]) * 1024
spheres = [{"center": [i % 100, (i // 100) % 100, i // 10000], "radius": 0.3, "material": "m"} for i in range(200000)]
d = {"image": {"width": 8, "height": 8}, "camera": {"eye": [50, 50, -50], "look_at": [50, 50, 0], "vfov": 40},
     "materials": {"m": {"diffuse": [1, 1, 1]}}, "spheres": spheres}
before = status('VmRSS:')
glint.Scene.from_dict(d)
print((status('VmHWM:') - before) >> 20)
"""
    out = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert int(out.stdout.split()[-1]) < 200, f"{out.stdout} MB"
