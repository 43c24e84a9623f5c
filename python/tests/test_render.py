"""glint.render: the same pixels as the CLI, the array it returns, and its settings."""

import subprocess
import threading
import time

import numpy as np
import pytest

import glint

SMALL = {"width": 32, "height": 24, "progress": False}


def cli_render(glint_bin, scene, output, *flags):
    subprocess.run([glint_bin, "render", str(scene), "-o", str(output), "-q", *flags], check=True)


@pytest.mark.parametrize(
    "name, settings",
    [
        ("cornell-path.glint", {"spp": 4, "seed": 7}),
        ("default.glint", {"spp": 2, "seed": 3}),
        ("cornell-whitted.glint", {"integrator": "path", "spp": 3, "max_depth": 4}),
    ],
)
def test_same_pixels_as_the_cli(glint_bin, scenes, tmp_path, name, settings):
    flags = ["--width", "32", "--height", "24"]
    for key, value in settings.items():
        flags += [f"--{key.replace('_', '-')}", str(value)]
    cli_render(glint_bin, scenes / name, tmp_path / "cli.exr", *flags)
    cli_render(glint_bin, scenes / name, tmp_path / "cli.png", *flags)

    image = glint.render(glint.load(scenes / name), **SMALL, **settings)

    assert np.array_equal(image, glint.read(tmp_path / "cli.exr")), "float pixels differ"
    glint.write(tmp_path / "py.png", image)
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def test_returns_a_float32_array_height_by_width_by_3(scenes):
    image = glint.render(scenes / "default.glint", **SMALL)
    assert isinstance(image, np.ndarray) and isinstance(image, glint.Image)
    assert image.shape == (24, 32, 3)
    assert image.dtype == np.float32
    assert image.flags.c_contiguous
    assert image.max() > 0 and np.isfinite(image).all()
    assert type(image.mean()) is not glint.Image


def test_settings_override_the_scene(scenes):
    scene = glint.load(scenes / "cornell-path.glint")
    assert (scene.width, scene.height, scene.spp, scene.integrator) == (256, 256, 64, "path")
    a = glint.render(scene, spp=2, seed=1, **SMALL)
    b = glint.render(scene, spp=2, seed=2, **SMALL)
    assert not np.array_equal(a, b), "the seed changes the noise"
    assert np.array_equal(a, glint.render(scene, spp=2, seed=1, threads=1, **SMALL))
    whitted = glint.render(scene, integrator="whitted", **SMALL)
    assert not np.array_equal(a, whitted)
    assert glint.render(scene, spp=1, width=8, height=4, progress=False).shape == (4, 8, 3)
    assert (scene.width, scene.spp) == (256, 64), "rendering leaves the scene as it was"


def test_bad_settings_raise_value_errors_naming_them(scenes):
    scene = glint.default_scene()
    with pytest.raises(ValueError, match="integrator='photon'"):
        glint.render(scene, integrator="photon", **SMALL)
    with pytest.raises(ValueError, match="rr_depth applies only to the path integrator"):
        glint.render(scene, rr_depth=3, **SMALL)
    with pytest.raises(ValueError, match="max_depth"):
        glint.render(scene, max_depth="deep", **SMALL)
    with pytest.raises(ValueError, match="camera 1 was asked for, but the scene has 1 camera"):
        glint.render(scene, camera=1, **SMALL)
    assert np.array_equal(glint.render(scene, camera=0, **SMALL), glint.render(scene, **SMALL))
    with pytest.raises(glint.SceneError, match="spp 0 is out of range"):
        glint.render(scene, spp=0, **SMALL)
    with pytest.raises(OverflowError):
        glint.render(scene, width=-5, progress=False)


def test_progress_reports_tiles_on_the_calling_thread():
    calls = []
    caller = threading.get_ident()

    def progress(done, total):
        calls.append((done, total, threading.get_ident()))

    glint.render(glint.default_scene(), width=64, height=48, spp=1, progress=progress)
    assert calls, "progress was reported"
    assert calls[-1][:2] == (12, 12), "64x48 is 4x3 tiles of 16"
    assert all(thread == caller for *_, thread in calls)


def test_the_gil_is_released_while_tracing():
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    try:
        glint.render(glint.default_scene(), width=320, height=240, spp=16, progress=False)
    finally:
        done.set()
        counter.join()
    assert len(ticks) > 10, "another Python thread ran during the render"


def test_ctrl_c_cancels_the_render():
    import _thread

    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        glint.render(glint.default_scene(), width=800, height=600, spp=1024, progress=False)
    timer.cancel()
    assert time.monotonic() - start < 20, "the render stopped soon after Ctrl-C"


def test_progress_goes_through_tqdm_when_it_is_installed(monkeypatch):
    import sys
    import types

    bars = []

    class FakeTqdm:
        def __init__(self, total, **kwargs):
            self.total, self.n, self.closed = total, 0, False
            bars.append(self)

        def update(self, step):
            self.n += step

        def close(self):
            self.closed = True

    fake = types.ModuleType("tqdm.auto")
    fake.tqdm = FakeTqdm
    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", fake)
    glint.render(glint.default_scene(), width=64, height=48, spp=1)
    assert len(bars) == 1
    assert (bars[0].n, bars[0].total, bars[0].closed) == (12, 12, True)
