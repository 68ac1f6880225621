#!/usr/bin/env python3
"""Side-by-side timing of two fdmsurf binaries (A, B), alternating, on the same inputs.

Runs each binary REPS times per input, alternating A B A B ... (B A B A ... on odd rounds), warm
(one untimed run of each fills the shader caches), and prints the median wall time and the median
of the stage times from `--stats json` ("times"). Usage:

    bench/density_ab.py OLD_BINARY NEW_BINARY [--reps N] [--spacing H] [--stages a,b] INPUT...
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def run(binary, path, spacing, out, extra):
    cmd = [binary, path, "-o", out, "--spacing", str(spacing), "--stats", "json"] + extra
    t0 = time.monotonic()
    res = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if res.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({res.returncode}): {res.stderr}")
    stats = json.loads(res.stdout)
    times = stats["times"]
    return wall, times, stats


def load1():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--stages", default="density,total")
    ap.add_argument("--extra", default="", help="extra fdmsurf arguments, space separated")
    args = ap.parse_args()
    extra = args.extra.split()
    stages = args.stages.split(",")
    tmp = tempfile.mkdtemp(prefix="density_ab.")
    for var in ("MESA_SHADER_CACHE_DIR", "FDMSURF_CACHE_DIR"):
        os.environ.setdefault(var, os.path.join(tmp, "cache", var.lower()))
    os.makedirs(os.path.join(tmp, "cache"), exist_ok=True)
    bins = {"old": args.old, "new": args.new}
    print(f"# load at start: {open('/proc/loadavg').read().strip()}")
    rows = []
    for path in args.inputs:
        name = os.path.basename(path).split(".")[0]
        for key, b in bins.items():  # warm-up: fills Mesa's and VkFFT's caches
            run(b, path, args.spacing, os.path.join(tmp, f"{name}-{key}.ply"), extra)
        res = {k: {"wall": [], "load": []} for k in bins}
        tri = {}
        for r in range(args.reps):
            order = ["old", "new"] if r % 2 == 0 else ["new", "old"]
            for key in order:
                res[key]["load"].append(load1())
                wall, times, stats = run(bins[key], path, args.spacing,
                                         os.path.join(tmp, f"{name}-{key}.ply"), extra)
                res[key]["wall"].append(wall)
                tri[key] = stats.get("mesh", {}).get("triangles", stats.get("triangles"))
                total = stats.get("total_ms", sum(times.values()))
                for s in stages:
                    v = total if s == "total" else times.get(s, 0.0)
                    res[key].setdefault(s, []).append(v)
        for key in bins:
            med = {s: statistics.median(res[key][s]) for s in stages}
            rows.append((name, key, statistics.median(res[key]["wall"]), med,
                         statistics.median(res[key]["load"]), res[key]["density"] if "density" in res[key] else [], tri[key]))
    print(f"# load at end: {open('/proc/loadavg').read().strip()}")
    print("| input | binary | median wall (s) | " + " | ".join(f"median {s} (ms)" for s in stages) +
          " | density runs (ms) | median load | triangles |")
    print("|---|---|---|" + "---|" * len(stages) + "---|---|---|")
    for name, key, wall, med, load, dens, tri in rows:
        print(f"| {name} | {key} | {wall:.2f} | " + " | ".join(f"{med[s]:.0f}" for s in stages) +
              f" | {', '.join(f'{d:.0f}' for d in dens)} | {load:.2f} | {tri} |")


if __name__ == "__main__":
    main()
