#!/usr/bin/python3
"""Per-residue SASA, fdmsurf against FreeSASA side by side (issue 13, item 5; docs/areas.md).

On each structure (the atoms fdmsurf reads, with its radii, given to FreeSASA through the
occupancy column), runs in turn, `--reps` times each, interleaved so that a change of load on
the machine hits every tool alike:

  freesasa-lr20    freesasa -O --lee-richards --format seq        (Lee-Richards, 20 slices: default)
  freesasa-lr100   freesasa -O --lee-richards --resolution 100 --format seq   (the reference)
  freesasa-sr100   freesasa -O --shrake-rupley --format seq      (100 points: its default)
  fdmsurf-areas    fdmsurf X --surface sas --areas X.csv          (exact patches, no mesh)
  fdmsurf-mesh     fdmsurf X --surface sas -o X.ply               (the surface alone, 0.5 Å)
  fdmsurf-both     fdmsurf X --surface sas -o X.ply --areas X.csv (the surface and its areas)

and reports the median wall time of each (whole process, as a user waits for it) and its CPU
time (user + system: less sensitive to other work on a shared machine), the areas' own stages from fdmsurf's --stats json (`areas`, `write-areas`) against the run without them,
and how far each tool's per-residue areas are from FreeSASA's at resolution 100 (mean absolute
difference and 99th percentile, Å²). FreeSASA runs on its default 2 threads, fdmsurf on all
(2 here); both read the same plain PDB file (fdmsurf with its own radii, the same values).
Needs build/fdmsurf, `freesasa` (Debian) and /usr/bin/python3 with numpy.

    bench/areas.py                              # 4hhb and 1aon, 3 repetitions
    bench/areas.py --structures 4hhb --reps 5 --out bench/out
"""
import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
STRUCTURES = {
    "1crn": os.path.join(ROOT, "tests", "data", "1crn.pdb"),
    "4hhb": os.path.join(ROOT, "tests", "data", "4hhb.pdb.gz"),
    "1aon": os.path.join(ROOT, "..", "shared", "data", "1aon.pdb.gz"),
}


def run(cmd, cpu=None):
    """Wall time (s) and stdout of `cmd`; its CPU time (user + system, s) appended to `cpu`."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise SystemExit("failed: %s\n%s" % (" ".join(cmd), p.stderr))
    if cpu is not None:
        cpu.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return dt, p.stdout


def fdmsurf_atoms(fdmsurf, path, tmp):
    """The atoms fdmsurf reads (the JSON areas file), with their exact SASA."""
    out = os.path.join(tmp, "atoms.json")
    run([fdmsurf, path, "--surface", "sas", "--areas", out])
    with open(out) as f:
        return json.load(f)["atoms"]


def write_pdb(atoms, path):
    with open(path, "w") as f:
        for i, a in enumerate(atoms):
            name = a["name"] if len(a["name"]) == 4 else " " + a["name"]
            f.write("ATOM  %5d %-4.4s %3.3s %1.1s%4d%1.1s   %8.3f%8.3f%8.3f%6.2f%6.2f          %2s\n"
                    % ((i + 1) % 100000, name, a["residue_name"], a["chain"],
                       a["residue_number"] % 10000, a["insertion_code"] or " ", a["xyz"][0],
                       a["xyz"][1], a["xyz"][2], a["radius"], 0.0, a["element"][:2]))
        f.write("END\n")


def residue_index(atoms):
    index = {}
    return np.array([index.setdefault((a["chain"], a["residue_number"], a["insertion_code"],
                                       a["residue_name"]), len(index)) for a in atoms]), len(index)


def freesasa_atom_areas(args, pdb):
    _, out = run(["freesasa", "-O", "--format", "pdb"] + args + [pdb])
    return np.array([float(l[60:66]) for l in out.splitlines() if l.startswith("ATOM")])


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--structures", default="4hhb,1aon")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--spacing", default="0.5")
    ap.add_argument("--fdmsurf", default=os.path.join(ROOT, "build", "fdmsurf"))
    ap.add_argument("--out", default=os.path.join(HERE, "out"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    report = {"machine": {"nproc": os.cpu_count(), "platform": platform.platform(),
                          "load_before": os.getloadavg()}, "results": []}
    lines = ["| structure | atoms | residues | tool | median wall (s) | runs (s) | median CPU (s) | residue MAD vs LR 100 (Å²) | residue p99 (Å²) |",
             "|---|---|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.structures.split(","):
            path = STRUCTURES.get(name, name)
            atoms = fdmsurf_atoms(args.fdmsurf, path, tmp)
            pdb = os.path.join(tmp, name + ".pdb")
            write_pdb(atoms, pdb)
            rid, nres = residue_index(atoms)
            per_res = lambda v: np.bincount(rid, v, nres)
            ply, csv = os.path.join(tmp, name + ".ply"), os.path.join(tmp, name + ".csv")
            tools = {
                "freesasa-lr20": ["freesasa", "-O", "--lee-richards", "--format", "seq", pdb],
                "freesasa-lr100": ["freesasa", "-O", "--lee-richards", "--resolution", "100",
                                   "--format", "seq", pdb],
                "freesasa-sr100": ["freesasa", "-O", "--shrake-rupley", "--format", "seq", pdb],
                "fdmsurf-areas": [args.fdmsurf, pdb, "--surface", "sas", "--areas", csv,
                                  "--stats", "json"],
                "fdmsurf-mesh": [args.fdmsurf, pdb, "--surface", "sas", "--spacing",
                                 args.spacing, "-o", ply, "--stats", "json"],
                "fdmsurf-both": [args.fdmsurf, pdb, "--surface", "sas", "--spacing",
                                 args.spacing, "-o", ply, "--areas", csv, "--stats", "json"],
            }
            times = {t: [] for t in tools}
            cpus = {t: [] for t in tools}
            stages = {t: [] for t in tools}
            for rep in range(args.reps):
                for tool, cmd in tools.items():
                    dt, out = run(cmd, cpus[tool])
                    times[tool].append(dt)
                    if tool.startswith("fdmsurf"):
                        stages[tool].append(json.loads(out))
                    print("%s %s rep %d: %.2f s" % (name, tool, rep + 1, dt), flush=True)
            # Accuracy per residue against resolution 100.
            ref = per_res(freesasa_atom_areas(["--lee-richards", "--resolution", "100"], pdb))
            accuracy = {
                "freesasa-lr20": per_res(freesasa_atom_areas(["--lee-richards"], pdb)),
                "freesasa-lr100": ref,
                "freesasa-sr100": per_res(freesasa_atom_areas(["--shrake-rupley"], pdb)),
                "fdmsurf-areas": per_res(np.array([a["area"] for a in atoms])),
            }
            run(tools["fdmsurf-both"])
            import csv as csvmod
            with open(csv) as f:
                mesh = [float(r["mesh_area"]) for r in csvmod.DictReader(f) if r["record"] == "atom"]
            accuracy["fdmsurf-both"] = per_res(np.array(mesh))
            for tool in tools:
                med = statistics.median(times[tool])
                row = {"structure": name, "tool": tool, "atoms": len(atoms), "residues": nres,
                       "median_s": med, "runs_s": times[tool], "cpu_s": statistics.median(cpus[tool]),
                       "cpu_runs_s": cpus[tool]}
                acc = ""
                if tool in accuracy:
                    d = np.abs(accuracy[tool] - ref)
                    row["residue_mad"] = float(d.mean())
                    row["residue_p99"] = float(np.percentile(d, 99))
                    acc = "%.3f | %.3f" % (row["residue_mad"], row["residue_p99"])
                else:
                    acc = "– | –"
                if stages[tool]:
                    s = stages[tool]
                    row["stages_ms"] = {k: statistics.median(x["times"].get(k, 0.0) for x in s)
                                        for k in s[0]["times"]}
                    row["total_ms"] = statistics.median(x["total_ms"] for x in s)
                report["results"].append(row)
                lines.append("| %s | %d | %d | %s | %.2f | %s | %.2f | %s |"
                             % (name, len(atoms), nres, tool, med,
                                ", ".join("%.2f" % t for t in times[tool]), row["cpu_s"], acc))
            both = [r for r in report["results"] if r["structure"] == name]
            b = [r for r in both if r["tool"] == "fdmsurf-both"][0]
            m = [r for r in both if r["tool"] == "fdmsurf-mesh"][0]
            areas_ms = b["stages_ms"].get("areas", 0.0) + b["stages_ms"].get("write-areas", 0.0)
            lines.append("")
            lines.append("%s: areas stages %.0f ms (areas %.0f + write-areas %.0f) = %.1f%% of the "
                         "surface run without them (fdmsurf total %.0f ms); whole-process medians "
                         "%.2f s with, %.2f s without (%+.1f%%); CPU %.2f s with, %.2f s without "
                         "(%+.1f%%)"
                         % (name, areas_ms, b["stages_ms"].get("areas", 0.0),
                            b["stages_ms"].get("write-areas", 0.0),
                            100 * areas_ms / m["total_ms"], m["total_ms"], b["median_s"],
                            m["median_s"], 100 * (b["median_s"] / m["median_s"] - 1),
                            b["cpu_s"], m["cpu_s"], 100 * (b["cpu_s"] / m["cpu_s"] - 1)))
            lines.append("")
            print("\n".join(lines[-3:]), flush=True)
    report["machine"]["load_after"] = os.getloadavg()
    with open(os.path.join(args.out, "areas.json"), "w") as f:
        json.dump(report, f, indent=1)
    with open(os.path.join(args.out, "areas.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main())
