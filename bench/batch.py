#!/usr/bin/python3
"""A ten-structure batch through one engine against ten single runs (issue 17, goal 4).

    bench/batch.py [--exe build/fdmsurf] [--rounds 3] [--out bench/out/batch]

The ten models of tests/data/1d3z.pdb.gz (NMR, 1,231 atoms each with hydrogens dropped):
  batch:   fdmsurf 1d3z.pdb.gz --models all -o OUT/batch/     (one process, one engine)
  singles: fdmsurf 1d3z.pdb.gz --model K -o OUT/K.ply, K = 1..10 (ten processes)
after one untimed warm-up of each (Mesa's shader cache and the plan cache filled), rounds
alternating. Per-process start-up, from each single run: its wall time less fdmsurf's own
total plus its `init` stage (Vulkan instance and device, pipelines): what a batch pays once.
Prints a Markdown table with the machine, the device and the load.
"""

import argparse
import json
import os
import pathlib
import platform
import shutil
import statistics
import subprocess
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
INPUT = ROOT / "tests" / "data" / "1d3z.pdb.gz"


def run(cmd):
    t0 = time.perf_counter()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return time.perf_counter() - t0, out.stdout


def singles(exe, out):
    walls, startups = [], []
    for k in range(1, 11):
        wall, text = run([exe, str(INPUT), "--model", str(k), "-o", str(out / f"{k}.ply"),
                          "--stats", "json"])
        stats = json.loads(text)
        walls.append(wall)
        startups.append(wall - stats["total_ms"] / 1000 + stats["times"].get("init", 0) / 1000)
    return sum(walls), statistics.median(startups)


def batch(exe, out):
    folder = out / "batch"
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    wall, _ = run([exe, str(INPUT), "--models", "all", "-o", str(folder) + "/", "--quiet"])
    return wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=str(ROOT / "build" / "fdmsurf"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "bench" / "out" / "batch"))
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    device = json.loads(run([args.exe, str(INPUT), "--model", "1", "-o", str(out / "w.ply"),
                             "--stats", "json"])[1])["device"]
    batch(args.exe, out)  # warm-up of the batch's grid size too
    rows, loads = [], []
    for _ in range(args.rounds):
        loads.append(os.getloadavg()[0])
        s, startup = singles(args.exe, out)
        b = batch(args.exe, out)
        rows.append((s, b, startup))
    s = statistics.median(r[0] for r in rows)
    b = statistics.median(r[1] for r in rows)
    startup = statistics.median(r[2] for r in rows)
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores; device: {device}; "
          f"1-minute load {min(loads):.1f}-{max(loads):.1f}; median of {args.rounds} rounds")
    print()
    print("| ten single runs (s) | one batch (s) | saved (s) | per-process start-up (s) | saved ≥ start-up |")
    print("|---|---|---|---|---|")
    print(f"| {s:.2f} | {b:.2f} | {s - b:.2f} | {startup:.2f} | {'yes' if s - b >= startup else 'no'} |")


if __name__ == "__main__":
    main()
