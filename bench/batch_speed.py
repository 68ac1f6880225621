#!/usr/bin/env python3
"""A batch of 100 small proteins through one engine (the CLI's batch mode): structures per second
for one or two fdmsurf binaries, and the part of each structure's time that is host work.

    PYTHONPATH=build/python /usr/bin/python3 bench/batch_speed.py [--baseline OLD] [--exe build/fdmsurf]
                                                         [--reps 3] [--spacing 0.5] [--out DIR]

The set is bench/python_batch.py's (the ten NMR models of 1D3Z as PDB, the same with hydrogens as
XYZR, the 15 chain subsets of 4HHB, the single-model files of ../shared/data) with 29 random chain
subsets each of 1AON and of 4YVS (seed 14): 100 structures when ../shared/data is there (said so
when it is not, and then only the 35 made from tests/data). Each binary runs
`EXE SET/* -o OUT/ --quiet --stats json --spacing H` once untimed (Mesa's shader cache and
fdmsurf's plan cache), then --reps times, alternating A B / B A. Per run: the wall time, and from
the per-structure JSON lines each stage's sum. "Host work" is every stage that a GPU run keeps on
the host (parse, init, bin-atoms, stitch, snap, cavities, vertex-atoms, mesh-stats, write, ...):
all but density, read-field, filter-* and mc-* (on lavapipe those run on the CPU too, through
llvmpipe or fdmsurf's host paths, and are reported apart). With two binaries it also says whether
every mesh is the same bytes. Needs the Python module (the set is made with it).
"""
import argparse
import filecmp
import json
import os
import pathlib
import platform
import random
import shutil
import statistics
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import python_batch  # noqa: E402  (the set)
from host_speed import machine, uptime, version  # noqa: E402

DEVICE_STAGES = ("density", "read-field", "filter", "mc", "ses-distance")


def is_device_stage(name):
    return any(name == s or name.startswith(s + "-") for s in DEVICE_STAGES)


def run(exe, paths, out, spacing):
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    cmd = [exe, *paths, "-o", f"{out}/", "--quiet", "--stats", "json", "--spacing", str(spacing)]
    t0 = time.monotonic()
    res = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if res.returncode != 0:
        sys.exit(f"batch_speed.py: {exe} failed ({res.returncode}): {res.stderr[-2000:]}")
    rows = [json.loads(line) for line in res.stdout.splitlines() if line.startswith("{")]
    if len(rows) != len(paths):
        sys.exit(f"batch_speed.py: {exe} reported {len(rows)} structures of {len(paths)}")
    stages = {}
    for row in rows:
        for name, ms in row["times"].items():
            stages[name] = stages.get(name, 0.0) + ms
    return wall, stages, sum(row["triangles"] for row in rows), rows[0].get("device", "?")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--exe", default="build/fdmsurf")
    ap.add_argument("--baseline", help="a second binary, run alternating with --exe")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("batch-speed-bench"))
    ap.add_argument("--seed", type=int, default=14)
    args = ap.parse_args()

    paths, notes = python_batch.make_set(args.out / "set", random.Random(args.seed), subsets=29)
    exes = [("new", args.exe)] + ([("old", args.baseline)] if args.baseline else [])
    load_before = uptime()
    results = {name: [] for name, _ in exes}
    device = "?"
    for name, exe in exes:  # untimed warm-up
        run(exe, paths, args.out / f"warm-{name}", args.spacing)
    for rep in range(args.reps):
        order = exes if rep % 2 == 0 else exes[::-1]
        for name, exe in order:
            wall, stages, triangles, device = run(exe, paths, args.out / name, args.spacing)
            results[name].append((wall, stages, triangles))

    n = len(paths)
    print(f"{machine()}; device {device}; load {load_before} before, {uptime()} after")
    for name, exe in exes:
        print(f"{name}: {exe} ({version(exe)})")
    for note in notes:
        print(f"note: {note}")
    print(f"\n{n} structures, spacing {args.spacing} Å, {args.reps} alternating rounds, medians\n")
    header = "| | " + " | ".join(name for name, _ in exes) + (" | new ÷ old |" if args.baseline else " |")
    print(header)
    print("|---" * (len(exes) + 1 + bool(args.baseline)) + "|")

    def median(name, f):
        return statistics.median(f(r) for r in results[name])

    def host(stages):
        return sum(ms for s, ms in stages.items() if not is_device_stage(s))

    def device_ms(stages):
        return sum(ms for s, ms in stages.items() if is_device_stage(s))

    lines = [
        ("wall (s)", lambda r: r[0], "{:.2f}"),
        ("structures per second", lambda r: n / r[0], "{:.2f}"),
        ("ms per structure (wall)", lambda r: 1000 * r[0] / n, "{:.1f}"),
        ("host work per structure (ms)", lambda r: host(r[1]) / n, "{:.1f}"),
        ("device stages per structure (ms, CPU here)", lambda r: device_ms(r[1]) / n, "{:.1f}"),
        ("host work, share of the stages", lambda r: host(r[1]) / (host(r[1]) + device_ms(r[1])),
         "{:.2f}"),
    ]
    stage_names = sorted({s for rs in results.values() for r in rs for s in r[1]},
                         key=lambda s: -median(exes[0][0], lambda r: r[1].get(s, 0.0)))
    for s in stage_names:
        tag = " (device)" if is_device_stage(s) else ""
        lines.append((f"{s}{tag}, ms per structure", lambda r, s=s: r[1].get(s, 0.0) / n,
                      "{:.2f}"))
    for label, f, fmt in lines:
        vals = [median(name, f) for name, _ in exes]
        cells = [fmt.format(v) for v in vals]
        ratio = f" | {vals[0] / vals[1]:.2f}" if args.baseline and vals[1] else (
            " | " if args.baseline else "")
        print(f"| {label} | " + " | ".join(cells) + ratio + " |")
    if args.baseline:
        names = sorted(os.listdir(args.out / "new"))
        same = all(filecmp.cmp(args.out / "new" / f, args.out / "old" / f, shallow=False)
                   for f in names)
        print(f"\nMeshes the same bytes: {same} ({len(names)} files)")
    tri = results[exes[0][0]][0][2]
    print(f"Triangles in all: {tri:,}; {platform.python_version()}")


if __name__ == "__main__":
    main()
