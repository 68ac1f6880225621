#!/usr/bin/env python3
"""The Gaussian filter of grids in slabs on the host against VkFFT (issue 17, goals 2 and 4;
docs/performance.md).

Runs build/fdmsurf on each structure with `--host-filter off` (VkFFT forward, mask, inverse)
and `--host-filter on` (a separable convolution on the host), alternating within each round,
and prints the slab count, the medians of fdmsurf's own total and of the filter stages, and the
triangle count and area of each (the surfaces should agree to float rounding).

  bench/host_filter.py [--reps 3] [--structures 1aon,4yvs] [--spacing 0.5] [--assembly]

Structures are read from tests/data, else ../shared/data (FDMSURF_SHARED moves it); 1AON is
only in ../shared/data: without it the script says so and measures what it finds.
"""
import argparse, json, os, platform, statistics, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("FDMSURF_SHARED", os.path.join(ROOT, "..", "shared"))
FILTER_STAGES = ("fft-forward", "mask", "fft-inverse", "filter-host")


def find(name):
    for folder in (os.path.join(ROOT, "tests", "data"), os.path.join(SHARED, "data")):
        for ext in (".pdb", ".pdb.gz", ".cif.gz", ".cif"):
            p = os.path.join(folder, name + ext)
            if os.path.exists(p):
                return p
    return None


def run(exe, args):
    r = subprocess.run([exe] + args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"fdmsurf {' '.join(args)} failed ({r.returncode}): {r.stderr.strip()}")
    return json.loads(r.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--structures", default="1aon,4yvs")
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--assembly", action="store_true", help="--assembly 1 (4YVS: 317,160 atoms)")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fdmsurf"))
    args = ap.parse_args()
    rows, loads, device = [], [], ""
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.structures.split(","):
            path = find(name)
            if path is None:
                print(f"note: {name} not found in tests/data or {os.path.abspath(SHARED)}/data: left out",
                      file=sys.stderr)
                continue
            base = [path, "--spacing", str(args.spacing), "--stats", "json", "-o", os.path.join(tmp, "m.ply")]
            if args.assembly:
                base += ["--assembly", "1"]
            runs = {"off": [], "on": []}
            for _ in range(args.reps):
                loads.append(os.getloadavg()[0])
                for mode in ("off", "on"):
                    runs[mode].append(run(args.exe, base + ["--host-filter", mode]))
            for mode in ("off", "on"):
                stats = runs[mode]
                device = stats[0]["device"]
                med = lambda f: statistics.median(f(s) for s in stats)
                rows.append(dict(name=f"{name}{' assembly' if args.assembly else ''} {mode}",
                                 slabs=stats[0]["grid"]["slabs"] if "grid" in stats[0] else "",
                                 total=med(lambda s: s["total_ms"]),
                                 filt=med(lambda s: sum(s["times"].get(k, 0.0) for k in FILTER_STAGES)),
                                 density=med(lambda s: s["times"].get("density", 0.0)),
                                 tri=stats[-1]["triangles"], area=stats[-1]["area"]))
    if not rows:
        sys.exit("bench/host_filter.py: nothing measured")
    loads.append(os.getloadavg()[0])
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, 1-minute load {min(loads):.1f}-{max(loads):.1f}; "
          f"device: {device}; spacing {args.spacing} Å, median of {args.reps} alternating rounds, ms\n")
    print("| structure, host filter | slabs | total | filter stages | density | triangles | area (Å²) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['name']} | {r['slabs']} | {r['total']:,.0f} | {r['filt']:,.0f} | {r['density']:,.0f} | "
              f"{r['tri']:,} | {r['area']:,.2f} |")
    print("\n'filter stages': fft-forward + mask + fft-inverse (off) or filter-host (on); 'total': fdmsurf's own "
          "total_ms of --stats json.")


if __name__ == "__main__":
    main()
