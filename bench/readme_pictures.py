"""The README's pictures: real scenes beside their own renderer's image, and an equal-time plot.

    PYTHONPATH=build/python /usr/bin/python3 bench/readme_pictures.py [--out docs/pictures] [--threads N]

(from the repository's root; /usr/bin/python3: Debian's Python, with python3-numpy and
python3-matplotlib). About 5 minutes on 2 cores, 10 the first time, when the plot's reference
is rendered (300 s of BPT, cached in build/bench-cache/ by bench/tracer_curves.py's functions).

1. For each of PAIRS: the scene file rendered by wavemmlt with the tracer and time named
   there, at its reference's size (Tungsten's 1024- and 1280-pixel references box-filtered
   down by 4, and rendered with a box pixel filter to match: the file's tent at a quarter of
   the resolution would blur the bright lights' edges), beside that reference: pbrt-v4's own
   render of the pbrt-v4 file, Tungsten's of the Mitsuba 3 file (Bitterli's). Both
   tone-mapped alike (linear RGB to sRGB, clamped, no exposure), written as OUT/<name>.png at
   one image pixel per screen pixel (256 colours, dithered, when RGB would pass 200 KB), with
   the relMSE (mean (x - ref)^2 / (ref^2 + 0.01)) and the ratio of the means printed and in
   the caption.
2. OUT/equal-time.png: relMSE against time of PT, BPT, PSSMLT and MMLT on the seed room
   (128 x 128, 1 / 2 / 4 / 8 s, 2 seeds), made by bench/tracer_curves.py's functions.

Scenes are read from ../shared/scenes/ beside the checkout, else from the copies in
tests/data/scenes/; one found in neither is named and skipped.
"""
import argparse
import os
import sys
import time

import numpy as np

import wavemmlt

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tracer_curves as tc  # noqa: E402

ROOTS = [tc.SHARED, os.path.join(tc.ROOT, "tests", "data", "scenes")]

# name, scene, its renderer's image, that renderer, downscale of that image, wavemmlt's tracer,
# seconds, render options, a note for the caption.
PAIRS = [
    ("pbrt-cornell-box", "pbrt-v4/cornell-box/cornell-box.pbrt", "pbrt-v4/cornell-box/reference/pbrt-cornell-box-256x256-1024spp.exr",
     "pbrt-v4", 1, "mmlt", 30, {}, "pbrt-v4's cornell-box.pbrt"),
    ("pbrt-killeroo-gold", "pbrt-v4/killeroos/killeroo-gold.pbrt", "pbrt-v4/killeroos/reference/pbrt-killeroo-gold-256x192-1024spp.exr",
     "pbrt-v4", 1, "pt", 40, {}, "pbrt-v4's killeroo-gold.pbrt"),
    ("mitsuba-veach-bidir", "mitsuba/veach-bidir/scene.xml", "mitsuba/veach-bidir/TungstenRender.exr",
     "Tungsten", 4, "bpt", 60, dict(max_length=6, filter="box"), "Bitterli's veach-bidir (Mitsuba 3 file), paths of up to 6 segments as Tungsten's"),
    ("mitsuba-veach-mis", "mitsuba/veach-mis/scene.xml", "mitsuba/veach-mis/TungstenRender.exr",
     "Tungsten", 4, "pt", 20, dict(max_length=2, filter="box"), "Bitterli's veach-mis (Mitsuba 3 file), direct light only as Tungsten's"),
]


def find(rel):
    """The first of ROOTS that has rel, else None (and says so)."""
    for root in ROOTS:
        if os.path.exists(os.path.join(root, rel)):
            return os.path.join(root, rel)
    print(f"{rel}: missing from {' and '.join(ROOTS)}; skipped")
    return None


def box_down(image, f):
    """Mean of f x f pixel blocks."""
    h, w, _ = image.shape
    return image[: h // f * f, : w // f * f].reshape(h // f, f, w // f, f, 3).mean(axis=(1, 3))


def srgb(x):
    x = np.clip(x, 0, 1)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def side_by_side(png, left, right, left_title, right_title, caption):
    """Two images at one pixel per pixel, a title above each, a caption line below; RGB PNG."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    h, w, _ = left.shape
    gap, top, bottom, dpi = 6, 22, 30, 100
    W, H = 2 * w + gap, h + top + bottom
    fig = plt.figure(figsize=(W / dpi, H / dpi), dpi=dpi)
    for i, (img, title) in enumerate(((left, left_title), (right, right_title))):
        ax = fig.add_axes([i * (w + gap) / W, bottom / H, w / W, h / H])
        ax.imshow(srgb(img), interpolation="none")
        ax.set_axis_off()
        fig.text((i * (w + gap) + w / 2) / W, 1 - 4 / H, title, ha="center", va="top", fontsize=9, weight="bold")
    fig.text(0.5, 3 / H, caption, ha="center", va="bottom", fontsize=7, linespacing=1.3)
    fig.canvas.draw()
    picture = Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[..., :3])
    plt.close(fig)
    picture.save(png, optimize=True)
    if os.path.getsize(png) > 200 << 10:  # noise compresses badly: 256 colours, dithered
        picture.quantize(256, dither=Image.Dither.FLOYDSTEINBERG).save(png, optimize=True)
        print(f"{png}: over 200 KB as RGB, written with 256 colours")


def pictures(out, threads):
    for name, scene_rel, ref_rel, renderer, down, tracer, seconds, options, note in PAIRS:
        scene_path, ref_path = find(scene_rel), find(ref_rel)
        if not scene_path or not ref_path:
            continue
        ref = box_down(wavemmlt.read_image(ref_path), down)
        h, w, _ = ref.shape
        r = wavemmlt.load(scene_path, width=w, height=h).render(tracer=tracer, spp=1, time=seconds, seed=1, threads=threads, **options)
        relmse, ratio = wavemmlt.relmse(r.image, ref), float(r.image.mean() / ref.mean())
        png = os.path.join(out, name + ".png")
        side_by_side(png, r.image, ref, f"wavemmlt ({tracer.upper()}, {seconds} s)", renderer,
                     f"{note}\n{w} x {h}, {renderer}'s image {'box-filtered from ' + str(w * down) + ' pixels wide' if down > 1 else 'as rendered'}: "
                     f"relMSE {relmse:.3g}, mean ratio {ratio:.3f}")
        print(f"{png}: {scene_path}, {w}x{h}, {tracer} {r.stats['seconds']:.1f} s ({r.stats['spp']} spp, {r.stats['threads']} threads) "
              f"against {renderer}'s {ref_path}{f' box-filtered by {down}' if down > 1 else ''}: relMSE {relmse:.4g}, "
              f"mean ratio {ratio:.4f} (R G B: {', '.join(f'{x:.4f}' for x in r.image.reshape(-1, 3).mean(0) / ref.reshape(-1, 3).mean(0))}), "
              f"{os.path.getsize(png) // 1024} KB", flush=True)


def equal_time(out, threads, budgets=(1, 2, 4, 8), reps=2, size=128):
    path = find("seed-room/seed-room.xml")
    if not path:
        return
    scene = wavemmlt.load(path, width=size, height=size)
    ref, info = tc.reference(scene, path, os.path.join(tc.ROOT, "build", "bench-cache"), 300, threads)
    rows = tc.curves(scene, "seed room", ref, budgets, reps, threads=threads)
    tc.table(rows, "seed room")
    tc.plot(rows, info, os.path.join(out, "equal-time.png"),
            f"The seed room ({size} x {size}, light hidden above the ceiling): error against time\n"
            f"{reps} seeds per point, bars from the least to the greatest; {rows[0]['threads']} threads")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", default=os.path.join(tc.ROOT, "docs", "pictures"), help="[docs/pictures]")
    p.add_argument("--threads", type=int, default=0, help="worker threads, 0: all [0]")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    start = time.monotonic()
    pictures(a.out, a.threads)
    equal_time(a.out, a.threads)
    print(f"done in {time.monotonic() - start:.0f} s")


if __name__ == "__main__":
    main()
