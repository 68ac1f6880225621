#!/usr/bin/python3
"""Cold start and the cost of canonical grid sizes (issue 17, goal 3; docs/performance.md).

    bench/cold_start.py [--exe build/fdmsurf] [--rounds 3] [--structures 1crn,3al1,...]

1. Cold: the README's first job (tests/data/1crn.pdb, default options) as a new user's first
   run, with fdmsurf's plan cache (FDMSURF_CACHE_DIR) and Mesa's shader cache
   (MESA_SHADER_CACHE_DIR) pointing at fresh folders, in three cases:
     no prepare        the first run compiles its FFT plan and every kernel;
     after prepare     `fdmsurf prepare` (what scripts/setup-debian.sh runs) first;
     natural grid      after prepare, with --natural-grid (a size prepare did not build);
   then a second run of each (warm). fdmsurf's own time (total_ms of --stats json) and the
   process's wall time; prepare's own wall time.
2. Warm: for each structure, the canonical grid against --natural-grid in alternating rounds
   (median of --rounds after one warm-up of each): grid points, fdmsurf's total, and the
   distance between the two meshes (`fdmsurf compare`: Hausdorff and RMSD, Å).

Structures: tests/data first, then ../shared/data (FDMSURF_SHARED moves it), which holds the
others; those not found are listed and skipped. Prints Markdown tables with the machine, the
device and the load.
"""

import argparse
import json
import os
import pathlib
import platform
import shutil
import statistics
import subprocess
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
SHARED = pathlib.Path(os.environ.get("FDMSURF_SHARED", ROOT.parent / "shared"))


def find(name):
    for folder in (ROOT / "tests" / "data", SHARED / "data"):
        for ext in (".pdb", ".pdb.gz", ".cif", ".cif.gz"):
            p = folder / (name + ext)
            if p.exists():
                return p
    return None


def run(cmd, env=None):
    t0 = time.perf_counter()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True,
                         env=None if env is None else {**os.environ, **env})
    return time.perf_counter() - t0, out.stdout


def surface(exe, src, out, extra=(), env=None):
    wall, text = run([exe, str(src), "-o", str(out), "--stats", "json", *extra], env)
    return wall, json.loads(text)


def load():
    return os.getloadavg()[0]


def cold(exe, tmp):
    src = ROOT / "tests" / "data" / "1crn.pdb"
    rows = []
    for case in ("no prepare", "after prepare", "natural grid, after prepare"):
        folder = tmp / case.replace(" ", "_").replace(",", "")
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        env = {"FDMSURF_CACHE_DIR": str(folder / "plans"),
               "MESA_SHADER_CACHE_DIR": str(folder / "mesa")}
        prepare_s = None
        if case != "no prepare":
            prepare_s, _ = run([exe, "prepare", "--quiet"], env)
        extra = ["--natural-grid"] if case.startswith("natural") else []
        first_wall, first = surface(exe, src, folder / "1crn.ply", extra, env)
        second_wall, second = surface(exe, src, folder / "1crn.ply", extra, env)
        rows.append((case, prepare_s, first["grid"]["dims"], first["total_ms"], first_wall,
                     second["total_ms"], second_wall, load()))
    return rows


def warm(exe, names, rounds, tmp):
    rows, missing = [], []
    for name in names:
        src = find(name)
        if src is None:
            missing.append(name)
            continue
        times = {"canonical": [], "natural": []}
        stats = {}
        for r in range(rounds + 1):
            for kind, extra in (("canonical", []), ("natural", ["--natural-grid"])):
                _, s = surface(exe, src, tmp / f"{name}-{kind}.ply", extra)
                stats[kind] = s
                if r > 0:  # the first round fills the caches
                    times[kind].append(s["total_ms"])
        _, text = run([exe, "compare", str(tmp / f"{name}-natural.ply"),
                       str(tmp / f"{name}-canonical.ply"), "--spacing", "0.5", "--stats", "json"])
        c = json.loads(text)
        dims = {k: stats[k]["grid"]["dims"] for k in stats}
        points = {k: dims[k][0] * dims[k][1] * dims[k][2] for k in dims}
        rows.append((name, stats["natural"].get("atoms_used"), dims["natural"], dims["canonical"],
                     points["canonical"] / points["natural"],
                     statistics.median(times["natural"]), statistics.median(times["canonical"]),
                     c["hausdorff"], c["rmsd"]))
    return rows, missing


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=str(ROOT / "build" / "fdmsurf"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--structures", default="1crn,3al1,1ubq,1aki,1rna,3ebz,4hhb")
    args = ap.parse_args()
    if not os.access(args.exe, os.X_OK):
        raise SystemExit(f"bench/cold_start.py: {args.exe} is missing (run scripts/setup-debian.sh)")
    with tempfile.TemporaryDirectory() as t:
        tmp = pathlib.Path(t)
        _, s = surface(args.exe, ROOT / "tests" / "data" / "1crn.pdb", tmp / "probe.ply")
        print(f"machine: {platform.machine()}, {os.cpu_count()} cores; device: {s.get('device')}; "
              f"1-minute load at start {load():.2f}\n")
        print("Cold: tests/data/1crn.pdb, default options, plan cache and Mesa's shader cache "
              "in fresh folders; fdmsurf's own time (total_ms) and process wall time, s\n")
        print("| case | prepare (s) | grid | first run: fdmsurf (s) | first run: wall (s) | "
              "second run: fdmsurf (s) | second run: wall (s) | load |")
        print("|---|---|---|---|---|---|---|---|")
        for case, prep, dims, t1, w1, t2, w2, ld in cold(args.exe, tmp):
            p = "–" if prep is None else f"{prep:.1f}"
            print(f"| {case} | {p} | {'×'.join(map(str, dims))} | {t1 / 1000:.2f} | {w1:.2f} | "
                  f"{t2 / 1000:.2f} | {w2:.2f} | {ld:.2f} |")
        rows, missing = warm(args.exe, args.structures.split(","), args.rounds, tmp)
        print(f"\nWarm: canonical grid against --natural-grid, median of {args.rounds} alternating "
              "rounds after a warm-up, fdmsurf's own time (ms); the meshes compared by "
              "`fdmsurf compare` (natural as reference)\n")
        print("| structure | atoms | natural grid | canonical grid | points × | natural (ms) | "
              "canonical (ms) | time × | Hausdorff (Å) | RMSD (Å) |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for name, atoms, dn, dc, px, tn, tc, hd, rm in rows:
            print(f"| {name.upper()} | {atoms if atoms is not None else '–'} | "
                  f"{'×'.join(map(str, dn))} | {'×'.join(map(str, dc))} | {px:.2f} | {tn:.0f} | "
                  f"{tc:.0f} | {tc / tn:.2f} | {hd:.5f} | {rm:.5f} |")
        if missing:
            print(f"\nnot found (tests/data, {SHARED}/data): {', '.join(missing)}")
        print(f"\n1-minute load at the end {load():.2f}")


if __name__ == "__main__":
    main()
