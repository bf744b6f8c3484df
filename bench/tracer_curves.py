"""Equal-time error curves of PT, BPT, PSSMLT and MMLT, written with the Python module.

The study of bench/tracer_curves.sh (wavemmlt_bench_error + bench/plot_error.sh) as a script:
for each scene, a cached BPT reference, then every tracer at every time budget with REPS
seeds, each run's relMSE and RMSE against the reference, a plot, a CSV and a table. Run it
from the repository's root with the module of your build:

    PYTHONPATH=build/python /usr/bin/python3 bench/tracer_curves.py \\
        [--out DIR] [--budgets 2,4,8] [--reps 3] [--size 128] [--tracers pt,bpt,pssmlt,mmlt] \\
        [--ref-seconds 300] [--cache DIR] [--threads N] [scene ...]

(/usr/bin/python3: Debian's Python, with python3-numpy and python3-matplotlib.) With no
scene: the seed room, Bitterli's Cornell box and veach-bidir (its Mitsuba 3 file) from
../shared/scenes/; a scene that is missing is named and skipped. Each scene is rendered at
--size (N or WxH) with its own MaxPathLength, each run in rounds of 1 sample (or mutation)
per pixel until its budget (`time=`) is spent, seeds 1..REPS.

The reference: BPT for --ref-seconds in two halves with seeds no run uses, their mean
cached as <cache>/<scene>-<hash of its path>-<W>x<H>-L<max length>.exr (default cache:
build/bench-cache/) with a .json beside it: seconds, spp, and its own noise, estimated
from the halves A and B as bench_error.cpp does: relMSE = mean((A - B)^2 / (ref^2 + 0.01)) / 4
and RMSE = rms(A - B) / 2. A run's relMSE against it includes that much (the plot's dashed
line). Rendered once, reused: delete the file to render it again.

Writes OUT/curves.csv (a row per run: scene, tracer, budget_s, seed, seconds, spp, threads,
relmse, rmse), OUT/<scene>.png (relMSE against the measured seconds, log-log, a line per tracer
through the seeds' mean, bars from the least to the greatest run) and prints per scene a
table (means over the seeds; RMSE as the root of the mean MSE), the equal-time ratios
relMSE(mmlt) / relMSE(pssmlt) and relMSE(pt) / relMSE(bpt), and the tracer with the least
error at each budget. bench/readme_pictures.py imports these functions for the README's plot.
"""
import argparse
import csv
import hashlib
import json
import os
import sys

import numpy as np

import wavemmlt

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "scenes"))
DEFAULT_SCENES = ["seed-room/seed-room.xml", "bitterli-cornell/bitterli-cornell-256.xml", "mitsuba/veach-bidir/scene.xml"]
TRACERS = ["pt", "bpt", "pssmlt", "mmlt"]
REF_SEEDS = (0x5EED0000A, 0x5EED0000B)  # bench_error.cpp's: no run uses them


def scene_name(path):
    """The file's stem; a Mitsuba scene.xml is named by its folder."""
    stem = os.path.splitext(os.path.basename(path))[0]
    return os.path.basename(os.path.dirname(os.path.abspath(path))) if stem == "scene" else stem


def present(paths):
    """The scenes that exist; the others named and skipped."""
    found = [p for p in paths if os.path.isfile(p)]
    for p in sorted(set(paths) - set(found)):
        print(f"{p}: missing (the scenes are read from ../shared/scenes/ beside the checkout); skipped")
    return found


def reference(scene, path, cache, seconds=300, threads=0):
    """(image, info) of the scene's BPT reference at its size: from the cache, or rendered now."""
    length = scene.max_length
    key = hashlib.sha1(os.path.realpath(path).encode()).hexdigest()[:8]
    base = os.path.join(cache, f"{scene_name(path)}-{key}-{scene.width}x{scene.height}-L{length}")
    if os.path.exists(base + ".exr"):
        with open(base + ".json") as f:
            info = json.load(f)
        info["cached"] = True
    else:
        os.makedirs(cache, exist_ok=True)
        print(f"reference: rendering {base}.exr (BPT, {seconds:g} s in two halves) ...", flush=True)
        a, b = (scene.render(tracer="bpt", spp=1, time=seconds / 2, seed=s, threads=threads) for s in REF_SEEDS)
        ref = 0.5 * (a.image + b.image)
        d = a.image.astype(np.float64) - b.image
        info = dict(scene=os.path.realpath(path), width=scene.width, height=scene.height, max_length=length, tracer="bpt",
                    seconds=a.stats["seconds"] + b.stats["seconds"], spp=a.stats["spp"] + b.stats["spp"], threads=a.stats["threads"],
                    noise_relmse=float(np.mean(d * d / (ref.astype(np.float64) ** 2 + 0.01)) / 4),
                    noise_rmse=float(np.sqrt(np.mean(d * d)) / 2))
        wavemmlt.write_image(base + ".exr", ref)
        with open(base + ".json", "w") as f:
            json.dump(info, f, indent=1)
        info["cached"] = False
    info["path"] = base + ".exr"
    print(f"reference: {info['path']} ({'cached' if info['cached'] else 'rendered now'}): BPT, {info['spp']} spp in "
          f"{info['seconds']:.0f} s, MaxPathLength {length}; its own noise: relMSE {info['noise_relmse']:.3g}, RMSE {info['noise_rmse']:.3g}")
    return wavemmlt.read_image(info["path"]), info


def curves(scene, name, ref, budgets, reps, tracers=TRACERS, threads=0):
    """Every tracer at every budget with seeds 1..reps: a dict per run."""
    rows = []
    for tracer in tracers:
        for budget in budgets:
            for seed in range(1, reps + 1):
                r = scene.render(tracer=tracer, spp=1, time=budget, seed=seed, threads=threads)
                rows.append(dict(scene=name, tracer=tracer, budget_s=budget, seed=seed, seconds=r.stats["seconds"], spp=r.stats["spp"],
                                 threads=r.stats["threads"], relmse=wavemmlt.relmse(r.image, ref), rmse=wavemmlt.rmse(r.image, ref)))
                print(f"  {tracer:6} {budget:5g} s  seed {seed}: relMSE {rows[-1]['relmse']:.4g}", flush=True)
    return rows


def summary(rows):
    """{(tracer, budget): figures over the seeds}, in the rows' order."""
    out = {}
    for r in rows:
        out.setdefault((r["tracer"], r["budget_s"]), []).append(r)
    return {k: dict(seconds=np.mean([r["seconds"] for r in v]), spp=np.mean([r["spp"] for r in v]),
                    relmse=np.mean([r["relmse"] for r in v]), least=min(r["relmse"] for r in v), most=max(r["relmse"] for r in v),
                    rmse=np.sqrt(np.mean([r["rmse"] ** 2 for r in v])), runs=len(v)) for k, v in out.items()}


def table(rows, name):
    """The printed table, the equal-time ratios and the least error per budget."""
    s = summary(rows)
    print(f"\n{name}: {'tracer':6} {'budget':>7} {'seconds':>8} {'spp':>8} {'relMSE':>10} {'(least..most)':>21} {'RMSE':>10}")
    for (tracer, budget), x in s.items():
        print(f"{'':{len(name) + 2}}{tracer:6} {budget:7g} {x['seconds']:8.2f} {x['spp']:8.0f} {x['relmse']:10.4g} "
              f"{x['least']:10.4g}..{x['most']:<10.4g} {x['rmse']:10.4g}")
    budgets = sorted({b for _, b in s})
    for num, den in (("mmlt", "pssmlt"), ("pt", "bpt")):
        ratios = [f"{b:g} s: {s[num, b]['relmse'] / s[den, b]['relmse']:.3f}" for b in budgets if (num, b) in s and (den, b) in s]
        if ratios:
            print(f"equal-time relMSE({num}) / relMSE({den}): " + ", ".join(ratios))
    for b in budgets:
        best = min((t for t, bb in s if bb == b), key=lambda t: s[t, b]["relmse"])
        print(f"least relMSE at {b:g} s: {best}")


def plot(rows, ref_info, png, title):
    """relMSE against seconds, log-log: a line per tracer, bars from the least to the greatest run."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    s = summary(rows)
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=100)
    for tracer in dict.fromkeys(t for t, _ in s):
        pts = sorted((x["seconds"], x["relmse"], x["least"], x["most"]) for (t, _), x in s.items() if t == tracer)
        sec, mean, lo, hi = map(np.array, zip(*pts))
        ax.errorbar(sec, mean, yerr=[mean - lo, hi - mean], marker="o", capsize=3, lw=2, label=tracer.upper())
    ax.axhline(ref_info["noise_relmse"], color="gray", ls="--", lw=1, label="the reference's own noise")
    ax.set_xscale("log")
    ax.set_yscale("log")
    budgets = sorted({b for _, b in s})
    ax.set_xticks(budgets, [f"{b:g}" for b in budgets])
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("relMSE: mean (x - ref)$^2$ / (ref$^2$ + 0.01)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=9)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)
    print(f"wrote {png}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("scenes", nargs="*", help="scene files (default: three from ../shared/scenes/)")
    p.add_argument("--out", default="bench-tracers", help="folder for curves.csv and the plots [bench-tracers]")
    p.add_argument("--budgets", default="2,4,8", help="time budgets in seconds [2,4,8]")
    p.add_argument("--reps", type=int, default=3, help="seeds per point [3]")
    p.add_argument("--size", default="128", help="image size, N or WxH [128]")
    p.add_argument("--tracers", default=",".join(TRACERS), help="[pt,bpt,pssmlt,mmlt]")
    p.add_argument("--ref-seconds", type=float, default=300, help="the reference's BPT budget, when it is rendered [300]")
    p.add_argument("--cache", default=os.path.join(ROOT, "build", "bench-cache"), help="reference cache [build/bench-cache]")
    p.add_argument("--threads", type=int, default=0, help="worker threads, 0: all [0]")
    a = p.parse_args()
    budgets = [float(b) for b in a.budgets.split(",")]
    w, _, h = a.size.partition("x")
    width, height = int(w), int(h or w)
    if not a.scenes:
        a.scenes = [os.path.join(SHARED, s) for s in DEFAULT_SCENES]
        print(f"no scene given: the default ones from {SHARED}/")
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for path in present(a.scenes):
        name = scene_name(path)
        print(f"\n== {name}: {width}x{height}, budgets {a.budgets} s, {a.reps} seed(s)")
        scene = wavemmlt.load(path, width=width, height=height)
        ref, info = reference(scene, path, a.cache, a.ref_seconds, a.threads)
        scene_rows = curves(scene, name, ref, budgets, a.reps, a.tracers.split(","), a.threads)
        table(scene_rows, name)
        plot(scene_rows, info, os.path.join(a.out, name + ".png"),
             f"{name}, {width}x{height}: relMSE against render time\n({a.reps} seeds; bars: least..greatest run; reference BPT {info['seconds']:.0f} s)")
        rows += scene_rows
    if rows:
        with open(os.path.join(a.out, "curves.csv"), "w", newline="") as f:
            out = csv.DictWriter(f, fieldnames=list(rows[0]))
            out.writeheader()
            out.writerows(rows)
        print(f"\nwrote {os.path.join(a.out, 'curves.csv')} ({len(rows)} rows)")


if __name__ == "__main__":
    sys.exit(main())
