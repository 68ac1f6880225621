#!/usr/bin/env python3
"""Cost of the vertex-property stage, side by side (issue 11; docs/properties.md).

For each structure, runs build/fdmsurf in rounds, alternating the variants in one round so that
load on a shared machine hits them alike:
  plain       the default surface (the atom of each vertex is always computed: vertex-atoms)
  chain       --color chain (per-atom colours gathered in the same pass)
  coulombic   --color coulombic --properties coulombic
  all         --color coulombic --properties coulombic,hydrophobicity,bfactor,
              mean_curvature,gaussian_curvature,shape_index
and prints a Markdown table of median whole-process times and the stage times (--stats json).

  bench/properties.py [--reps 3] [--structures 1crn,4hhb,1aon] [--spacing 0.5]

Structures are read from tests/data, else ../shared/data (FDMSURF_SHARED moves it); a
structure found in neither is left out with a note.
"""
import argparse, os, platform, statistics, sys, tempfile

from benchlib import ROOT, SHARED, find, run_json
VARIANTS = {
    "plain": [],
    "chain": ["--color", "chain"],
    "coulombic": ["--color", "coulombic", "--properties", "coulombic"],
    "all": ["--color", "coulombic", "--properties",
            "coulombic,hydrophobicity,bfactor,mean_curvature,gaussian_curvature,shape_index"],
}


def run(exe, path, extra, spacing, out):
    return run_json(exe, [path, "-o", out, "--spacing", str(spacing), "--stats", "json"] + extra)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--structures", default="1crn,4hhb,1aon")
    ap.add_argument("--spacing", type=float, default=0.5)
    args = ap.parse_args()
    exe = os.path.join(ROOT, "build", "fdmsurf")
    if not os.access(exe, os.X_OK):
        sys.exit("bench/properties.py: build/fdmsurf is missing (run scripts/setup-debian.sh)")
    rows = []
    device = ""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "mesh.ply")
        for name in args.structures.split(","):
            path = find(name)
            if path is None:
                print(f"note: {name} not found in tests/data or {SHARED}/data: left out", file=sys.stderr)
                continue
            results = {v: [] for v in VARIANTS}
            for _ in range(args.reps):
                for v, extra in VARIANTS.items():
                    results[v].append(run(exe, path, extra, args.spacing, out))
            device = results["plain"][0][1]["device"]
            med = lambda v, f: statistics.median(f(s) for s in results[v])
            total = lambda v: med(v, lambda s: s[1]["total_ms"])
            stage = lambda v, n: med(v, lambda s: s[1]["times"].get(n, 0.0))
            plain = total("plain")
            va = stage("plain", "vertex-atoms") + stage("plain", "vertex-atoms-host")
            rows.append((name, results["plain"][0][1]["vertices"], plain, va, 100 * va / (plain - va),
                         total("chain"), total("coulombic"),
                         stage("coulombic", "coulombic") + stage("coulombic", "coulombic-host"),
                         total("coulombic") / (plain - va), total("all"), stage("all", "curvature")))
    load = os.getloadavg()[0]
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, load {load:.2f}; device: {device}; "
          f"spacing {args.spacing} Å, median of {args.reps} alternating rounds, whole-process ms (fdmsurf's total)\n")
    print("| structure | vertices | plain total | vertex-atoms | vertex-atoms ÷ rest | --color chain | "
          "coulombic total | coulombic stage | coulombic ÷ uncoloured | all properties | curvature |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]:,} | {r[2]:,.0f} | {r[3]:,.0f} | {r[4]:.1f}% | {r[5]:,.0f} | {r[6]:,.0f} | "
              f"{r[7]:,.0f} | {r[8]:.2f}x | {r[9]:,.0f} | {r[10]:,.0f} |")
    print("\n'vertex-atoms' and 'coulombic' include their host parts (binning, ordering, "
          "scattering: *-host stages). 'uncoloured' is the plain run less vertex-atoms: the run as "
          "it was before the stage existed.")


if __name__ == "__main__":
    main()
