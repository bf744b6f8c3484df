#!/usr/bin/env python3
"""MMLT's bias where its pools are noisy: the mean brightness of many small MMLT renders, each
with its own seed, against BPT references (docs/mmlt-levers.md, "A bias in the pools").

    PYTHONPATH=build/python /usr/bin/python3 bench/mmlt_bias.py [--seeds 1000] [--size 32]
        [--lengths 3,4] [--spp 256] [--chains 256] [--bootstrap N] [--scene FILE]

The scene (default: the seed room from ../shared/scenes, else tests/data's copy) is rendered
at --size x --size with MinPathLength and MaxPathLength from --lengths: two BPT references
(seeds 900 and 901, 64 times the MMLT mutations per pixel each; their means must agree within
their noise) and --seeds MMLT renders of --spp mutations per pixel with --chains chains. It
prints the ratio of the MMLT renders' mean brightness to the references', its standard error
over the seeds, z, and the median ratio: an unbiased estimator's z is within +-3 but for one
run in 370. The default configuration has 4 passes of few chains each (before 2026-12-06 MMLT's
pools were biased there, the more so the smaller the pools and the more the passes; one pass
hid it). About 4 minutes for 1000 seeds on 2 cores. A heavy tail (a few seeds far above the
mean) makes fewer seeds read low: keep 1000.
"""
import argparse
import os
import sys
import time

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "build", "python"))
import wavemmlt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=1000)
    ap.add_argument("--size", type=int, default=32)
    ap.add_argument("--lengths", default="3,4")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--chains", type=int, default=256)
    ap.add_argument("--bootstrap", type=int, default=0, help="samples of every length (0: the default bootstrap)")
    ap.add_argument("--scene", default="")
    a = ap.parse_args()
    scene = a.scene
    if not scene:
        for c in (os.path.join(here, "..", "..", "shared", "scenes", "seed-room", "seed-room.xml"),
                  os.path.join(here, "..", "tests", "data", "scenes", "seed-room", "seed-room.xml")):
            if os.path.exists(c):
                scene = c
                break
    if not scene or not os.path.exists(scene):
        print("mmlt_bias.py: no scene (give --scene)", file=sys.stderr)
        return 2
    lo, hi = (int(x) for x in a.lengths.split(","))
    opts = dict(min_length=lo, max_length=hi, threads=2)
    sc = wavemmlt.load(scene, width=a.size, height=a.size)
    t0 = time.time()
    refs = [sc.render(tracer="bpt", spp=64 * a.spp, seed=900 + i, **opts).image.mean() for i in range(2)]
    ref = float(np.mean(refs))
    print(f"references (BPT, {64 * a.spp} spp each): {refs[0]:.6g} and {refs[1]:.6g} "
          f"(differ by {abs(refs[0] - refs[1]) / ref:.2%}), {time.time() - t0:.0f} s")
    extra = dict(chains=a.chains)
    if a.bootstrap:
        extra["bootstrap"] = a.bootstrap
    means, passes = [], 0
    for s in range(1, a.seeds + 1):
        r = sc.render(tracer="mmlt", spp=a.spp, seed=s, **opts, **extra)
        means.append(r.image.mean())
        passes = r.stats["mmlt_passes"]
    m = np.array(means) / ref
    se = m.std(ddof=1) / np.sqrt(len(m))
    print(f"MMLT, {a.seeds} seeds, {passes} passes, lengths {lo}..{hi}, {a.size} x {a.size}, "
          f"{a.spp} mutations per pixel, {a.chains} chains: mean / BPT {m.mean():.4f} +- {se:.4f} "
          f"(z {(m.mean() - 1) / se:+.1f}), median {np.median(m):.4f}, {time.time() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
