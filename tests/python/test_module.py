"""The Python module (src/python; docs/python.md), run by ctest with Debian's pytest.

Its images equal the command line's bit for bit for a seed; bad input raises InputError
with its file and line; Ctrl-C stops a render and hands back the image so far; the GIL is
released while rendering; memory is released after a render; the comparisons agree with
wavemmlt-img and tell a biased renderer from a fair one.
"""
import gc
import json
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import wavemmlt

BIN = os.environ["WAVEMMLT_BIN"]
IMG_BIN = os.environ["WAVEMMLT_IMG_BIN"]
DATA = os.environ["WAVEMMLT_TEST_DATA"]
MITSUBA_CBOX = os.path.join(DATA, "scenes/mitsuba/cornell-box/scene.xml")
PBRT_CBOX = os.path.join(DATA, "scenes/pbrt-v4/cornell-box/cornell-box.pbrt")
SEED_ROOM = os.path.join(DATA, "scenes/seed-room/seed-room.xml")


def cli(args, tmp_path, name="cli.pfm"):
    """The command line's image (and --stats) for the same arguments."""
    out, stats = tmp_path / name, tmp_path / (name + ".json")
    subprocess.run([BIN, *args, "-o", str(out), "--stats", str(stats), "--quiet"], check=True)
    return wavemmlt.read_image(str(out)), json.loads(stats.read_text())


@pytest.mark.parametrize(
    "path, load_kw, render_kw, args",
    [
        (None, {}, dict(tracer="pt", spp=16, seed=3), ["--tracer", "pt", "--spp", "16", "--seed", "3"]),
        (None, {}, dict(tracer="bpt", spp=4, seed=5, max_length=5), ["--tracer", "bpt", "--spp", "4", "--seed", "5", "--max-length", "5"]),
        (None, {}, dict(tracer="mmlt", spp=8, seed=7, chains=2048, p_large=0.25),
         ["--tracer", "mmlt", "--spp", "8", "--seed", "7", "--chains", "2048", "--p-large", "0.25"]),
        (MITSUBA_CBOX, dict(resx=48, resy=48, tracer="lt"), dict(spp=4, seed=1), ["-Dresx=48", "-Dresy=48", "--tracer", "lt", "--spp", "4", "--seed", "1"]),
        (PBRT_CBOX, dict(width=40, height=40), dict(tracer="pt", spp=4, spectral=True, seed=2),
         ["--width", "40", "--height", "40", "--tracer", "pt", "--spp", "4", "--spectral", "--seed", "2"]),
        (SEED_ROOM, dict(width=48, height=32), dict(tracer="pssmlt", spp=4, seed=9, eye=(0.5, 1.0, -3.5), fov=60.0),
         ["--width", "48", "--height", "32", "--tracer", "pssmlt", "--spp", "4", "--seed", "9", "--eye", "0.5,1.0,-3.5", "--fov", "60.0"]),
    ],
)
def test_image_equals_the_command_lines_bit_for_bit(tmp_path, path, load_kw, render_kw, args):
    size = {} if path else dict(width=64, height=48)
    scene = wavemmlt.load(path, **size, **load_kw)
    r = scene.render(threads=2, **render_kw)
    expected, stats = cli(([path] if path else []) + (["--width", "64", "--height", "48"] if not path else []) + args + ["--threads", "2"], tmp_path)
    assert r.image.dtype == np.float32 and r.image.shape == expected.shape
    assert np.array_equal(r.image, expected)
    assert set(r.stats) == set(stats)  # the same figures as --stats, as a dict
    assert r.stats["spp"] == stats["spp"] and r.stats["tracer"] == stats["tracer"]
    assert r.stats["rays_intersect"] == stats["rays_intersect"]


def test_the_image_is_the_renders_memory_and_outlives_it():
    r = wavemmlt.load(width=32, height=24).render(tracer="pt", spp=4)
    image = r.image
    assert not image.flags.owndata and image.base is not None  # a view, not a copy
    assert image.flags.c_contiguous
    del r
    gc.collect()
    assert np.isfinite(image).all() and image.mean() > 0  # still valid


def test_set_view_moves_the_camera_for_the_next_renders(tmp_path):
    scene = wavemmlt.load(SEED_ROOM, width=48, height=32, max_length=7)
    assert (scene.width, scene.height, scene.max_length, scene.min_length, scene.tracer) == (48, 32, 7, 1, "mmlt")
    before = scene.camera
    scene.set_view(eye=(1.0, 1.0, -3.5), look_at=(0.0, -1.0, 1.0), fov=45)
    assert scene.camera["eye"] == (1.0, 1.0, -3.5) and scene.camera["fov"] == 45
    assert scene.camera["up"] == before["up"]
    r = scene.render(tracer="pt", spp=4, seed=1)
    expected, _ = cli([SEED_ROOM, "--width", "48", "--height", "32", "--max-length", "7", "--eye", "1,1,-3.5", "--look-at", "0,-1,1", "--fov", "45",
                       "--tracer", "pt", "--spp", "4", "--seed", "1"], tmp_path)
    assert np.array_equal(r.image, expected)
    with pytest.raises(wavemmlt.InputError, match="same point"):
        scene.set_view(eye=(0, -1, 1))
    with pytest.raises(TypeError):
        scene.set_view(spp=3)


def test_bad_input_raises_input_error_with_file_and_line(tmp_path):
    with pytest.raises(wavemmlt.InputError) as e:
        wavemmlt.load(str(tmp_path / "missing.xml"))
    assert e.value.file.endswith("missing.xml") and e.value.line == 0
    assert isinstance(e.value, ValueError)

    bad = tmp_path / "bad.xml"
    bad.write_text('<?xml version="1.0"?>\n<Scene>\n  <Settings>\n    <Width value="-3"/>\n  </Settings>\n</Scene>\n')
    with pytest.raises(wavemmlt.InputError) as e:
        wavemmlt.load(str(bad))
    assert e.value.file == str(bad) and e.value.line > 0, str(e.value)
    assert str(e.value).startswith(f"{bad}:{e.value.line}: ")

    scene = wavemmlt.load(width=16, height=16)
    with pytest.raises(wavemmlt.InputError, match="--spp"):
        scene.render(spp=0)
    with pytest.raises(wavemmlt.InputError, match="--tracer"):
        scene.render(tracer="whitted")
    with pytest.raises(TypeError):
        scene.render(sp=4)
    # NumPy's scalars are values like Python's (a sweep over np.arange)
    assert scene.render(tracer="pt", spp=np.int64(2), time=np.float32(0.5)).stats["spp"] >= 2
    with pytest.raises(wavemmlt.InputError, match="Mitsuba"):
        wavemmlt.load(SEED_ROOM, resx=3)  # a <default> for a file that is not Mitsuba's
    with pytest.raises(TypeError):
        wavemmlt.load(resx=3)  # the built-in scene has none
    with pytest.raises(wavemmlt.InputError, match="shape"):
        wavemmlt.relmse(np.zeros((4, 4)), np.zeros((4, 4)))
    with pytest.raises(wavemmlt.InputError, match="size"):
        wavemmlt.diff(np.zeros((4, 4, 3)), np.zeros((4, 5, 3)))
    with pytest.raises(wavemmlt.InputError):
        wavemmlt.read_image(str(bad))


def test_ctrl_c_stops_the_render_and_keeps_the_image_so_far():
    scene = wavemmlt.load(width=64, height=48)
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt) as e:
        scene.render(tracer="pt", spp=4, time=60)
    elapsed = time.monotonic() - start
    timer.join()
    assert elapsed < 10, elapsed  # not the minute asked for
    r = e.value.render
    assert r.stats["cancelled"] is True and r.stats["spp"] > 0
    assert r.image.shape == (48, 64, 3) and r.image.mean() > 0


def test_progress_is_called_on_the_callers_thread_and_its_exception_stops_the_render():
    scene = wavemmlt.load(width=64, height=48)
    seen, threads = [], set()

    def progress(f):
        seen.append(f)
        threads.add(threading.get_ident())

    scene.render(tracer="pt", spp=4, time=1.0, progress=progress)
    assert seen and all(0 <= f <= 1 for f in seen) and seen == sorted(seen)
    assert threads == {threading.get_ident()}

    class Stop(Exception):
        pass

    def stop(f):
        raise Stop()

    start = time.monotonic()
    with pytest.raises(Stop) as e:
        scene.render(tracer="pt", spp=4, time=60, progress=stop)
    assert time.monotonic() - start < 10
    assert e.value.render.stats["cancelled"] is True


def test_the_gil_is_released_while_rendering():
    # Python work on another thread runs throughout a 1-second render: its longest pause
    # is far below the render's length (holding the GIL, the render would stop it for 1 s).
    scene = wavemmlt.load(width=64, height=48)
    done, started = threading.Event(), threading.Event()
    gaps = []

    def count():
        last = time.monotonic()
        longest = 0.0
        started.set()
        while not done.is_set():
            now = time.monotonic()
            longest = max(longest, now - last)
            last = now
        gaps.append(longest)

    t = threading.Thread(target=count)
    t.start()
    started.wait()
    start = time.monotonic()
    scene.render(tracer="pt", spp=4, time=1.0, threads=1)
    rendered = time.monotonic() - start
    done.set()
    t.join()
    assert rendered > 0.9
    assert gaps[0] < 0.3, f"the other thread stopped for {gaps[0]:.2f} s of a {rendered:.2f} s render"


def test_memory_is_released_after_renders():
    def rss():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")

    scene = wavemmlt.load(width=256, height=256)
    for _ in range(3):  # warm up: thread pools, allocator arenas
        scene.render(tracer="mmlt", spp=1, chains=4096, length_images=True)
    gc.collect()
    before = rss()
    for _ in range(15):  # each holds 16 images of 0.75 MiB and 4096 chains
        r = scene.render(tracer="mmlt", spp=1, chains=4096, length_images=True)
        del r
    gc.collect()
    grown = rss() - before
    assert grown < 24 << 20, f"{grown / 2**20:.1f} MiB more after 15 renders"


def test_length_and_strategy_images_add_up_to_the_image():
    scene = wavemmlt.load(width=32, height=24)
    r = scene.render(tracer="bpt", spp=4, max_length=4, length_images=True, strategy_images=True)
    assert sorted(r.length_images) == [1, 2, 3, 4]
    total = sum(r.length_images[k].astype(np.float64) for k in r.length_images)
    np.testing.assert_allclose(total, r.image, rtol=1e-4, atol=1e-6)
    weighted = sum(w.astype(np.float64) for w, _ in r.strategy_images.values())
    np.testing.assert_allclose(weighted, r.image, rtol=1e-4, atol=1e-6)
    assert all(s + t - 1 <= 4 for s, t in r.strategy_images)
    with pytest.raises(wavemmlt.InputError, match="bpt"):
        scene.render(tracer="pt", spp=1, strategy_images=True)


def test_diff_agrees_with_wavemmlt_img(tmp_path):
    scene = wavemmlt.load(width=48, height=32)
    a = scene.render(tracer="pt", spp=4, seed=1)
    b = scene.render(tracer="pt", spp=16, seed=2)
    a.write(str(tmp_path / "a.pfm"))
    b.write(str(tmp_path / "b.pfm"))
    out = subprocess.run([IMG_BIN, "diff", str(tmp_path / "a.pfm"), str(tmp_path / "b.pfm"), "--json"], check=True, capture_output=True, text=True)
    expected = json.loads(out.stdout)
    got = wavemmlt.diff(a.image, b.image)
    for key in ("rmse", "relmse", "mae", "max_abs", "nonfinite"):
        assert got[key] == pytest.approx(expected[key], rel=1e-8), key
    assert wavemmlt.relmse(a.image, b.image) == got["relmse"] and wavemmlt.rmse(a.image, b.image) == got["rmse"]
    assert got["relmse"] > 0


def test_compare_blocks_tells_a_biased_renderer_from_a_fair_one():
    # PT and BPT render the same image (K = 6 seeds each); BPT with 4% more light does not.
    scene = wavemmlt.load(width=32, height=32)
    pt = [scene.render(tracer="pt", spp=16, seed=s).image for s in range(6)]
    bpt = [scene.render(tracer="bpt", spp=16, seed=100 + s).image for s in range(6)]
    fair = wavemmlt.compare_blocks(pt, bpt, block=8)
    assert fair["passed"], fair["summary"]
    assert fair["blocks"] == 3 * 16
    biased = wavemmlt.compare_blocks(pt, [1.04 * x for x in bpt], block=8)
    assert not biased["passed"], biased["summary"]
    assert biased["mean_ratio"] == pytest.approx(fair["mean_ratio"] / 1.04, rel=1e-6)
    with pytest.raises(wavemmlt.InputError):
        wavemmlt.compare_blocks(pt[:1], bpt[:1])
