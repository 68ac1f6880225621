#!/usr/bin/env python3
"""The host's stages of fdmsurf runs in ns per unit, against a memory copy: one or two binaries.

Runs each binary --reps times per input, alternating A B / B A (one untimed warm-up run of each
first), and prints per stage the median ms, ns per triangle (per atom for the atom stages, MB/s
for parse and the write) and the floor that memory bandwidth puts under it: the bytes the stage
must at least read and write (stated per row), at the bandwidth of a plain copy measured here
(memcpy of 256 MiB, best of 5; read + write bytes per second). Heads the table with the machine,
its load (uptime) before and after, and each binary's --version. With two binaries it also says
whether their meshes are the same bytes (cmp). Usage:

    bench/host_speed.py [--baseline OLD] [--exe build/fdmsurf] [--reps 3] [--spacing H]
                        [--extra "ARGS"] INPUT...

The shell of issue 36: python3 bench/make_synthetic.py --kind shell -o /tmp/shell.xyzr, then
bench/host_speed.py --baseline OLD --spacing 1 --reps 1 /tmp/shell.xyzr (about 1 min and 2 GB a
run on two cores). Standard library only.
"""
import argparse
import atexit
import filecmp
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

# Stage -> (unit, bytes per unit the stage must at least move, what those bytes are).
# t = triangles, v = vertices, a = atoms, B = input or output bytes.
STAGES = {
    "parse": ("B", 1.0, "the file once"),
    "bin-atoms": ("a", 32.0, "atoms in (16 B), bins out (16 B)"),
    "density-host": ("a", 16.0, "atoms once (the grid's points: 4 B each, not counted)"),
    "stitch": ("t", 24.0, "indices in and out (12 + 12 B per triangle)"),
    "snap": ("t", 24.0, "positions in and out (2 x 12 B per vertex, 2 triangles per vertex)"),
    "pieces": ("t", 18.0, "indices and positions once (12 + 6 B per triangle)"),
    "cavities": ("t", 12.0, "indices once (12 B per triangle)"),
    "vertex-atoms": ("v", 16.0, "positions in, atom out (12 + 4 B per vertex)"),
    "mesh-stats": ("t", 18.0, "indices and positions once (12 + 6 B per triangle)"),
    "write": ("B", 2.0, "the mesh's bytes read and written"),
    "ses-features": ("a", 16.0, "atoms once"),
}
# The host stages after the device's work (issue 36, goal 3): on a GPU these stay on the host.
# "pieces": the pieces and their statistics, found once for the cavity removal and the statistics.
AFTER_DEVICE = ["stitch", "snap", "pieces", "cavities", "mesh-stats", "write"]


def copy_bandwidth():
    """Bytes read + written per second by a memcpy of 256 MiB (best of 5)."""
    n = 256 << 20
    src = bytearray(os.urandom(1 << 20)) * 256
    dst = bytearray(n)
    view_s, view_d = memoryview(src), memoryview(dst)
    best = 1e9
    for _ in range(5):
        t0 = time.perf_counter()
        view_d[:] = view_s
        best = min(best, time.perf_counter() - t0)
    return 2.0 * n / best


def machine():
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = ""
    try:
        with open("/proc/meminfo") as f:
            mem = f"{int(f.readline().split()[1]) / 2**20:.1f} GiB"
    except OSError:
        pass
    return f"{platform.node()}: {cpu}, {os.cpu_count()} logical CPUs, {mem}, {platform.release()}"


def uptime():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def run(exe, path, out, spacing, extra):
    cmd = [exe, path, "-o", out, "--stats", "json"] + (
        ["--spacing", str(spacing)] if spacing else []) + extra
    t0 = time.monotonic()
    res = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if res.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({res.returncode}): {res.stderr}")
    return wall, json.loads(res.stdout)


def version(exe):
    res = subprocess.run([exe, "--version"], capture_output=True, text=True)
    if res.returncode != 0:
        return "?"
    return "; ".join((res.stdout or res.stderr).strip().splitlines())


def count(stats, key):
    for where in (stats.get("mesh", {}), stats):
        if key in where:
            return where[key]
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--exe", default="build/fdmsurf")
    ap.add_argument("--baseline", help="a second binary, run alternating with --exe")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--spacing", type=float, default=None)
    ap.add_argument("--extra", default="", help="extra fdmsurf arguments, space separated")
    ap.add_argument("--no-warmup", action="store_true", help="skip the untimed first runs")
    args = ap.parse_args()
    extra = args.extra.split()
    exes = {"B": os.path.abspath(args.exe)}
    if args.baseline:
        exes = {"A": os.path.abspath(args.baseline), **exes}
    tmp = tempfile.mkdtemp(prefix="host_speed.")
    # The meshes (2.2 GB a pair on the shell) and caches go with the run.
    atexit.register(shutil.rmtree, tmp, ignore_errors=True)
    for var in ("MESA_SHADER_CACHE_DIR", "FDMSURF_CACHE_DIR"):
        os.environ.setdefault(var, os.path.join(tmp, "cache", var.lower()))
    os.makedirs(os.path.join(tmp, "cache"), exist_ok=True)

    bw = copy_bandwidth()
    print(f"machine: {machine()}")
    print(f"load (1, 5, 15 min) at start: {uptime()}")
    for k, exe in exes.items():
        print(f"{k}: {exe}: {version(exe)}")
    print(f"memory copy: {bw / 1e9:.2f} GB/s (read + write, memcpy of 256 MiB, best of 5)")
    print(f"runs: {args.reps} per binary, alternating; spacing {args.spacing or 'default'}; "
          f"extra {' '.join(extra) or '-'}\n")

    for path in args.inputs:
        name = os.path.basename(path).split(".")[0]
        outs = {k: os.path.join(tmp, f"{name}-{k}.ply") for k in exes}
        if not args.no_warmup:
            for k, exe in exes.items():
                run(exe, path, outs[k], args.spacing, extra)
        times = {k: {} for k in exes}
        walls = {k: [] for k in exes}
        loads = []
        stats = {}
        for r in range(args.reps):
            order = list(exes) if r % 2 == 0 else list(reversed(exes))
            for k in order:
                loads.append(float(uptime().split()[0]))
                wall, st = run(exes[k], path, outs[k], args.spacing, extra)
                walls[k].append(wall)
                stats[k] = st
                for stage, ms in st["times"].items():
                    times[k].setdefault(stage, []).append(ms)
                times[k].setdefault("total", []).append(st.get("total_ms", 0.0))
        ref = stats[list(exes)[-1]]
        tri = count(ref, "triangles") or 0
        vert = count(ref, "vertices") or 0
        atoms = ref.get("atoms_used") or ref.get("atoms") or 0
        in_bytes = os.path.getsize(path)
        out_bytes = os.path.getsize(outs[list(exes)[-1]])
        units = {"t": tri, "v": vert, "a": atoms, "B": None}
        same = ""
        if len(exes) == 2:
            same = "same mesh bytes: " + ("yes" if filecmp.cmp(*outs.values(), shallow=False)
                                          else "NO")
        print(f"## {name}: {atoms} atoms, {vert} vertices, {tri} triangles, input {in_bytes} B, "
              f"mesh {out_bytes} B; median load {statistics.median(loads):.2f}; {same}")
        ks = list(exes)
        head = "| stage | " + " | ".join(f"{k} ms" for k in ks)
        head += (" | B ÷ A" if len(ks) == 2 else "") + " | per unit | floor ms | floor bytes |"
        print(head)
        print("|---" * (head.count("|") - 1) + "|")
        med = {k: {s: statistics.median(v) for s, v in times[k].items()} for k in ks}
        # Every stage of either binary (a stage one of them no longer has reads 0 there).
        stages = [s for s in dict.fromkeys(x for k in ks for x in med[k]) if s != "total"]
        stages.sort(key=lambda s: -max(med[k].get(s, 0.0) for k in ks))
        for s in stages + ["after-device", "total"]:
            if s == "after-device":
                row = {k: sum(med[k].get(x, 0.0) for x in AFTER_DEVICE) for k in ks}
            else:
                row = {k: med[k].get(s, 0.0) for k in ks}
            unit, per, what = STAGES.get(s, ("t", 0.0, ""))
            b = row[ks[-1]]
            if unit == "B":
                n = in_bytes if s == "parse" else out_bytes
                rate = n / (b / 1e3) / 1e6 if b > 0 else 0.0
                per_unit = f"{rate:.0f} MB/s"
            else:
                n = units[unit]
                per_unit = f"{b * 1e6 / n:.1f} ns/{unit}" if n else "-"
            floor = n * per / bw * 1e3 if per and n else 0.0
            cells = " | ".join(f"{row[k]:.0f}" for k in ks)
            ratio = f" | {row['B'] / row['A']:.2f}" if len(ks) == 2 and row["A"] > 0 else (
                " | -" if len(ks) == 2 else "")
            print(f"| {s} | {cells}{ratio} | {per_unit} | "
                  f"{floor:.0f} | {what} |" if floor else
                  f"| {s} | {cells}{ratio} | {per_unit} | - | |")
        for k in ks:
            print(f"\n{k}: wall {statistics.median(walls[k]):.2f} s (median)", end="")
        print("\n")
    print(f"load (1, 5, 15 min) at end: {uptime()}")


if __name__ == "__main__":
    main()
