#!/usr/bin/python3
"""How much arithmetic does fdmsurf's density pass do? (docs/performance.md, "what bounds it")

Replays, on the CPU with numpy/scipy, the candidate logic of shaders/density_tiles.comp for one
structure and grid: for every 4x4x4 workgroup box, U = min(pi_cut, min over the atoms near the
box of their largest power distance in the box), then the candidate list = atoms whose smallest
power distance to the box is <= U, and the pair evaluations = points of the box x list length.
The "near" atoms of step 1 are taken as those within r_max + bin/2 of the box (the shader scans
whole bins, a superset, so its U can only be smaller or equal: the figures here are an upper
bound within a few per cent). Prints the totals and, given the density stage time, the time per
pair evaluation.

usage: /usr/bin/python3 bench/density_work.py ATOMS.xyzr[.gz] [--fdmsurf build/fdmsurf]
           [--spacing 0.5] [--sigma 3] [--density-cut 0.01]
"""

import argparse
import gzip
import json
import math
import os
import subprocess
import sys

import numpy as np
from scipy.spatial import cKDTree

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("xyzr")
    ap.add_argument("--fdmsurf", default=os.path.join(ROOT, "build", "fdmsurf"))
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--sigma", type=float, default=3.0)
    ap.add_argument("--density-cut", type=float, default=0.01)
    a = ap.parse_args()

    op = gzip.open if a.xyzr.endswith(".gz") else open
    with op(a.xyzr, "rt") as fh:
        atoms = np.array([[float(t) for t in ln.split()[:4]] for ln in fh if ln.strip()])
    # fdmsurf's own grid (dims, origin) and density time for this input
    out = subprocess.run([a.fdmsurf, a.xyzr, "-o", "/tmp/density_work.ply", "--spacing", str(a.spacing),
                          "--stats", "json", "--quiet", "--host-density", "off"], stdout=subprocess.PIPE, check=True, text=True).stdout
    js = json.loads(out.strip().splitlines()[-1])
    nx, ny, nz = js["grid"]["dims"]
    origin = np.array(js["grid"]["origin"])
    h = js["grid"]["spacing"]
    density_ms = js["times"]["density"]
    pi_cut = a.sigma ** 2 * math.log(1.0 / a.density_cut)
    xyz, r2 = atoms[:, :3], atoms[:, 3] ** 2
    rmax = math.sqrt(r2.max())
    bin_size = rmax + 0.5
    near = rmax + 0.5 * bin_size
    tree = cKDTree(xyz)

    bx, by, bz = (nx + 3) // 4, (ny + 3) // 4, (nz + 3) // 4
    boxes = bx * by * bz
    pairs = 0          # point x candidate evaluations
    nonempty = 0
    sum_n = 0
    longest = 0
    hist = np.zeros(8, dtype=np.int64)   # list length: 0, 1-15, 16-31, 32-63, 64-127, 128-255, 256-511, 512+
    reach_max = math.sqrt(pi_cut + rmax * rmax)
    for k in range(bz):
        for j in range(by):
            idx = np.arange(bx)
            first = np.stack([idx * 4, np.full(bx, j * 4), np.full(bx, k * 4)], axis=1)
            last = np.minimum(first + 3, np.array([nx, ny, nz]) - 1)
            lo = origin + h * first
            hi = origin + h * last
            centre = 0.5 * (lo + hi)
            half = 0.5 * np.linalg.norm(hi - lo, axis=1)
            cand = tree.query_ball_point(centre, reach_max + half.max())
            npts = np.prod(last - first + 1, axis=1)
            for i in range(bx):
                c = cand[i]
                if not c:
                    hist[0] += 1
                    continue
                p, w = xyz[c], r2[c]
                gap = np.maximum(np.maximum(lo[i] - p, p - hi[i]), 0.0)
                gap2 = (gap * gap).sum(1)
                far = np.maximum(np.abs(p - lo[i]), np.abs(p - hi[i]))
                far_pd = (far * far).sum(1) - w
                sel = gap2 <= near * near
                u = min(pi_cut, far_pd[sel].min()) if sel.any() else pi_cut
                u += 1e-3 * (1.0 + abs(u))
                n = int(((gap2 - w) <= u).sum())
                if n:
                    nonempty += 1
                    sum_n += n
                longest = max(longest, n)
                pairs += n * int(npts[i])
                hist[0 if n == 0 else min(7, int(math.log2(n)) - 2) if n >= 16 else 1] += 1
    points = nx * ny * nz
    print(json.dumps({
        "input": a.xyzr, "atoms": len(atoms), "grid": [nx, ny, nz], "points": points,
        "workgroups": boxes, "workgroups_with_candidates": nonempty,
        "mean_list_nonempty": sum_n / max(1, nonempty),
        "pair_evaluations": pairs, "pairs_per_point": pairs / points, "longest_list": longest,
        "list_length_histogram": {"0": int(hist[0]), "1-15": int(hist[1]), "16-31": int(hist[2]),
                                  "32-63": int(hist[3]), "64-127": int(hist[4]), "128-255": int(hist[5]),
                                  "256-511": int(hist[6]), "512+": int(hist[7])},
        "density_ms": density_ms, "ns_per_point": density_ms * 1e6 / points,
        "ns_per_pair": density_ms * 1e6 / max(1, pairs),
    }, indent=1))


if __name__ == "__main__":
    sys.exit(main())
