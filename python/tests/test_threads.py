"""A render lets other Python threads run, and Ctrl-C stops it."""

import signal
import subprocess
import sys
import threading
import time

import pytest

import glint
from conftest import ROOT

BACKENDS = [
    pytest.param("gpu", marks=pytest.mark.skipif(not glint.GPU_BUILT, reason="no GPU renderer in this build")),
    "cpu",
]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_thread_keeps_counting_while_a_render_runs(backend):
    scene = glint.load(ROOT / "scenes/seed-fig5.toml", width=640, height=480, samples=2)
    if backend == "gpu":
        prepared = glint.Renderer().prepare(scene)
        run = prepared.render
    else:
        run = lambda: glint.render(scene, backend="cpu", precision="f64")
    ticks = 0
    stop = threading.Event()

    def count():
        nonlocal ticks
        while not stop.is_set():
            ticks += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    try:
        time.sleep(0.02)
        before, t0 = ticks, time.monotonic()
        run()
        during, seconds = ticks - before, time.monotonic() - t0
    finally:
        stop.set()
        counter.join()
    # Were the GIL held, the counter could not tick while the render ran:
    # once at most, at its start.
    assert seconds > 0.03, "the render was too short to say anything"
    assert during >= 10, f"{during} ticks in {seconds:.3f} s"


CHILD = r"""
import sys, time
import glint
backend = sys.argv[1]
scene = glint.load(sys.argv[2], width=4096, height=3072, samples=4)
if backend == "gpu":
    renderer = glint.Renderer()
    prepared = renderer.prepare(scene)
    run = prepared.render
else:
    run = lambda: glint.render(scene, backend="cpu", precision="f64")
print("ready", flush=True)
try:
    run()
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
# The renderer is still there for the next render.
small = glint.load(sys.argv[2], width=16, height=12)
image = renderer.render(small) if backend == "gpu" else glint.render(small, backend="cpu")
print("again", image.shape, flush=True)
"""


@pytest.mark.parametrize("backend", BACKENDS)
def test_ctrl_c_stops_a_long_render(backend):
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, backend, str(ROOT / "scenes/seed-fig5.toml")],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout.readline().strip() == "ready", child.stderr.read()
        time.sleep(0.5)
        child.send_signal(signal.SIGINT)
        sent = time.monotonic()
        out, err = child.communicate(timeout=60)
        seconds = time.monotonic() - sent
    finally:
        child.kill()
    # The whole render is 4096x3072 at 16 rays a pixel: minutes, not the
    # moments it took to stop.
    assert out.splitlines()[0] == "interrupted", (out, err)
    assert out.splitlines()[1] == "again (12, 16, 3)", (out, err)
    assert child.returncode == 0, err
    print(f"{backend}: stopped and exited {seconds:.3f} s after SIGINT")


def test_two_threads_setting_one_scenes_params_finish():
    # The second waited for the scene's lock with the GIL held while the
    # first, holding the lock, waited for the GIL: the interpreter hung.
    code = """
import threading, glint
scene = glint.load(%r, width=16, height=12)
def move(dx):
    for i in range(40):
        x, y, z = scene.params["spheres[0].center"]
        scene.params["spheres[0].center"] = [x + dx, y, z]
threads = [threading.Thread(target=move, args=(d,)) for d in (0.001, -0.001, 0.002)]
for t in threads: t.start()
for t in threads: t.join()
print(scene.generation)
""" % str(ROOT / "scenes" / "seed-fig3.toml")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "120"


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_interpreter_exits_while_a_daemon_thread_renders(backend):
    # CPython ended the daemon thread with pthread_exit as it came back
    # for the GIL; glint's catch_unwind took that unwind for an exception:
    # "FATAL: exception not rethrown", SIGABRT, exit 134, 3 of 3 times.
    code = """
import threading, time, glint
scene = glint.load(%r, width=16, height=12)
def work():
    i = 0
    while True:
        i += 1
        scene.params["spheres[0].radius"] = 1.0 + (i %% 7) * 0.01
        if i %% 5 == 0:
            glint.render(scene, backend=%r)
threading.Thread(target=work, daemon=True).start()
time.sleep(0.3)
print("exiting")
""" % (str(ROOT / "scenes" / "seed-fig5.toml"), backend)
    for _ in range(3):
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
        assert done.stdout.strip() == "exiting"
