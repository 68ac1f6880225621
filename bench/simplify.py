#!/usr/bin/env python3
"""Cost and accuracy of --simplify (issue 12; docs/mesh.md#simplification).

For each structure, runs build/fdmsurf in rounds, alternating in one round so that load on a
shared machine hits both alike:
  full        the default surface
  simplified  --simplify RATIO --optimize
and prints a Markdown table of medians from --stats json: the surface's own time (the run's
total less parse, init, simplify, simplify-compare, optimize, write and mesh-stats, in the
same process as the simplification), the simplify stage and its share of the surface's time
(goal: at most 20% at 10% of the triangles on 1AON), the distance measurement
(simplify-compare) and optimize stages, the triangle counts, Hausdorff distance and RMSD to
the full mesh, and whether the result is a closed manifold. The last round's two meshes are
also compared by `fdmsurf compare`, the independent check of the distances.

  bench/simplify.py [--reps 3] [--structures 1aon] [--ratio 0.1] [--spacing 0.5]
                    [--exe build/fdmsurf] [--baseline OTHER_FDMSURF]
                    [--simplifiers collapse,meshopt]

--simplifiers runs the simplified run once per simplifier (--simplifier NAME) in each round,
after the same full run, in an order that turns from round to round; its rows are labelled by
the simplifier.

With --baseline, a second binary (another branch's build) runs in the same rounds, alternating
with --exe (full and simplified runs of each in turn), so that before and after see the same
load on a shared machine; its rows are labelled "before", the others "after". The 1-minute load
average is sampled at each round and its range printed.

Structures are read from tests/data, else ../shared/data (FDMSURF_SHARED moves it); 1AON is
only in ../shared/data: without it the script says so and measures nothing.
"""
import argparse, os, platform, statistics, sys, tempfile

from benchlib import ROOT, SHARED, find, run_json as run

OTHER_STAGES = ("parse", "init", "simplify", "simplify-compare", "optimize", "write", "mesh-stats")


def surface_ms(stats):
    return stats["total_ms"] - sum(stats["times"].get(n, 0.0) for n in OTHER_STAGES)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--structures", default="1aon")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fdmsurf"))
    ap.add_argument("--baseline", help="a second fdmsurf binary, run alternating with --exe")
    ap.add_argument("--simplifiers", help="comma-separated --simplifier values, each run in every round")
    args = ap.parse_args()
    simplifiers = args.simplifiers.split(",") if args.simplifiers else [None]
    exes = [("after", args.exe)] if args.baseline else [("", args.exe)]
    if args.baseline:
        exes.insert(0, ("before", args.baseline))
    for _, exe in exes:
        if not os.access(exe, os.X_OK):
            sys.exit(f"bench/simplify.py: {exe} is missing (run scripts/setup-debian.sh)")
    if not os.path.isdir(SHARED):
        print(f"bench/simplify.py: {os.path.abspath(SHARED)} is absent (set FDMSURF_SHARED to the "
              "shared folder): 1AON and the other large structures are only there", file=sys.stderr)
    rows = []
    device = ""
    loads = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.structures.split(","):
            path = find(name)
            if path is None:
                print(f"note: {name} not found in tests/data or {os.path.abspath(SHARED)}/data: left out",
                      file=sys.stderr)
                continue
            base = [path, "--spacing", str(args.spacing), "--stats", "json"]
            variants = [(" ".join(x for x in (label, which) if x), label, exe, which)
                        for label, exe in exes for which in simplifiers]
            fulls = {label: [] for label, _ in exes}
            simples = {v[0]: [] for v in variants}
            mesh = lambda label, kind: os.path.join(tmp, f"{kind}-{label or 'x'}.ply".replace(" ", "-"))
            for rep in range(args.reps):
                loads.append(os.getloadavg()[0])
                for label, exe in exes:
                    fulls[label].append(run(exe, base + ["-o", mesh(label, "full")])[1])
                    mine = [v for v in variants if v[1] == label]
                    # The simplifiers' order turns from round to round: a run's place after the
                    # full run moved its surface time by up to 15% on 27 November.
                    mine = mine[rep % len(mine):] + mine[:rep % len(mine)]
                    for vlabel, _, _, which in mine:
                        extra = ["--simplifier", which] if which else []
                        simples[vlabel].append(run(exe, base + ["-o", mesh(vlabel, "simplified"), "--simplify",
                                                                str(args.ratio), "--optimize"] + extra)[1])
            for vlabel, label, exe, _ in variants:
                full, simple = fulls[label], simples[vlabel]
                _, check = run(exe, ["compare", mesh(label, "full"), mesh(vlabel, "simplified"),
                                     "--spacing", str(args.spacing), "--stats", "json"])
                device = full[0]["device"]
                med = lambda runs, f: statistics.median(f(s) for s in runs)
                stage = lambda n: med(simple, lambda s: s["times"].get(n, 0.0))
                q = simple[-1]["simplify"]
                surf = med(simple, surface_ms)
                rows.append(dict(
                    name=(f"{name} {vlabel}" if vlabel else name), tri_in=q["triangles_in"], tri_out=q["triangles_out"], target=q["target_triangles"],
                    full_total=med(full, lambda s: s["total_ms"]), full_surface=med(full, surface_ms),
                    surface=surf, simplify=stage("simplify"),
                    share=med(simple, lambda s: s["times"]["simplify"] / surface_ms(s)),
                    compare=stage("simplify-compare"), optimize=stage("optimize"),
                    hausdorff=q["hausdorff"], rmsd=q["rmsd"], error=q["error"],
                    check_rmsd=check["rmsd"], check_h=check["hausdorff"], dA=check["area_rel_err"],
                    dV=check["volume_rel_err"], closed=simple[-1]["closed_manifold"],
                    full_closed=full[-1]["closed_manifold"], kept=q["topology_kept"],
                    frozen=q["frozen_triangles"], regions=q["regions"], attempts=q["attempts"]))
    if not rows:
        sys.exit("bench/simplify.py: nothing measured (no structure found)")
    load = os.getloadavg()[0]
    loads.append(load)
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, 1-minute load "
          f"{min(loads):.1f}-{max(loads):.1f} over the rounds, {load:.2f} at the end; "
          f"device: {device}; spacing {args.spacing} Å, --simplify {args.ratio} --optimize, "
          f"median of {args.reps} alternating rounds, ms\n")
    print("| structure | triangles | simplified (target) | surface | simplify | simplify ÷ surface | "
          "simplify-compare | optimize | Hausdorff (Å) | RMSD (Å) | simplifier's estimate (Å) | dA | dV | "
          "closed manifold | frozen triangles | regions (runs) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        closed = "yes" if r["closed"] else ("no (input not closed either)" if not r["full_closed"] else "**no**")
        print(f"| {r['name']} | {r['tri_in']:,} | {r['tri_out']:,} ({r['target']:,}) | {r['surface']:,.0f} | "
              f"{r['simplify']:,.0f} | {100 * r['share']:.1f}% | {r['compare']:,.0f} | {r['optimize']:,.0f} | "
              f"{r['hausdorff']:.3f} | {r['rmsd']:.3f} | {r['error']:.3f} | {100 * r['dA']:+.2f}% | "
              f"{100 * r['dV']:+.2f}% | {closed} | {r['frozen']:,} | {r['regions']} ({r['attempts']}) |")
    print("\n'surface': the simplified run's total less parse, init, simplify, simplify-compare, optimize, "
          "write and mesh-stats (the full run's: " +
          ", ".join(f"{r['name']} {r['full_surface']:,.0f} ms, total {r['full_total']:,.0f} ms" for r in rows) +
          "). Hausdorff and RMSD: the simplify summary's, from every full-mesh vertex to the simplified "
          "triangles; `fdmsurf compare` on the written meshes gives " +
          ", ".join(f"{r['name']} RMSD {r['check_rmsd']:.3f} Å, Hausdorff {r['check_h']:.3f} Å" for r in rows) +
          "; dA, dV from it.")


if __name__ == "__main__":
    main()
