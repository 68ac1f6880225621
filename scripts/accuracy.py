#!/usr/bin/python3
"""Accuracy of fdmsurf against the analytical SES (NanoShaper) of ../shared/reference/ses.

For every structure with a reference mesh (1CRN, 4HHB), every spacing and every method, runs
build/fdmsurf on the reference's own atoms and radii (.xyzr), measures the mesh with
`fdmsurf compare REF MESH --spacing H --stats json` and prints Markdown tables in the layout
of Giard & Macq (2010), Table 3 (weighted RMSD and share of area farther than the spacing,
per spacing), then area, volume, pieces and time. With --molstar, Mol*'s molecular surface
is run at the same spacings as a peer (node + bench/.cache/molstar or ../shared/tools/molstar
with node_modules). Standard library only; run with /usr/bin/python3 or any python3.

    scripts/accuracy.py                        # 1crn and 4hhb, 1.0 0.5 0.25 Å, all methods
    scripts/accuracy.py --spacings 1.0 0.5 --methods fdm,edt --structures 1crn

With --exact-reference H the structures are files of ../shared/data (1ubq, 1aki, ...: the first
of NAME.pdb, NAME.cif, NAME.pdb.gz, NAME.cif.gz), read with fdmsurf's own selection and radii,
and the reference is fdmsurf's exact SES of the same atoms at spacing H (`--method edt`), which
is 0.006-0.009 Å from NanoShaper's on 1CRN and 4HHB at 0.25 Å: a check of the FDM defaults on
structures they were not tuned on.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REF_DIR = os.path.join(ROOT, "..", "shared", "reference", "ses")

# Closed pieces of each reference mesh (../shared/reference/ses/README.md).
REF_PIECES = {"1crn": 2, "4hhb": 25}

# name -> (label, extra fdmsurf arguments)
METHODS = {
    "fdm": ("fdm (defaults)", []),
    "fdm-refine": ("fdm + refine 1", ["--refine", "1"]),
    "edt": ("edt (exact SES)", ["--method", "edt"]),
    "edt-refine": ("edt + refine 1", ["--method", "edt", "--refine", "1"]),
    "paper": ("fdm, paper settings", ["--paper"]),
}

# The peers measured on the same atoms at about 0.5 Å (../shared/reference/ses/README.md):
# (RMSD, dA) per structure. Quoted, not re-measured by this script.
PUBLISHED_05 = [
    ("NanoShaper grid 2 (published)", {"1crn": (0.024, -0.5), "4hhb": (0.026, -0.6)}),
    ("Mol* 0.5 Å (published)", {"1crn": (0.034, -1.5), "4hhb": (0.046, -2.0)}),
    ("PyMOL surface_quality 1 (published)", {"1crn": (0.45, -4.0), "4hhb": (0.44, -6.2)}),
    ("EDTSurf scale 4 (published)", {"1crn": (0.25, -8.9), "4hhb": (0.59, -10.4)}),
]


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw)


def compare(fdmsurf, ref, mesh, h):
    out = run([fdmsurf, "compare", ref, mesh, "--spacing", str(h), "--stats", "json"]).stdout
    return json.loads(out)


def molstar_script():
    for base in (os.path.join(ROOT, "bench", ".cache", "molstar"),
                 os.path.join(ROOT, "..", "shared", "tools", "molstar")):
        script = os.path.join(base, "ms_surface.js")
        if os.path.exists(script) and os.path.isdir(os.path.join(base, "node_modules")):
            return script
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--fdmsurf", default=os.path.join(ROOT, "build", "fdmsurf"))
    ap.add_argument("--structures", default="1crn,4hhb")
    ap.add_argument("--spacings", nargs="+", type=float, default=[1.0, 0.5, 0.25])
    ap.add_argument("--methods", default="fdm,fdm-refine,edt,edt-refine,paper",
                    help="comma-separated: " + ", ".join(METHODS))
    ap.add_argument("--molstar", action="store_true", help="also run Mol* at each spacing")
    ap.add_argument("--json", help="write every row to this file")
    ap.add_argument("--exact-reference", type=float, metavar="H",
                    help="reference: fdmsurf --method edt at spacing H, structures from ../shared/data")
    args = ap.parse_args()

    methods = [m for m in args.methods.split(",") if m]
    for m in methods:
        if m not in METHODS:
            sys.exit(f"accuracy.py: unknown method '{m}' (known: {', '.join(METHODS)})")
    structures = [s for s in args.structures.split(",") if s]
    ms_script = molstar_script() if args.molstar else None
    if args.molstar and ms_script is None:
        sys.exit("accuracy.py: --molstar needs Mol* installed: bench/run.sh installs it into "
                 "bench/.cache/molstar")

    device = run([args.fdmsurf, "--list-devices"]).stdout.strip().splitlines()
    rows = []
    tmp = tempfile.mkdtemp(prefix="fdmsurf-accuracy-")
    try:
        for name in structures:
            xyzr = os.path.join(REF_DIR, f"{name}.xyzr")
            ref = os.path.join(REF_DIR, f"{name}-ses-nanoshaper.ply.gz")
            ref_pieces = REF_PIECES.get(name)
            if args.exact_reference:
                data = os.path.join(ROOT, "..", "shared", "data")
                found = [os.path.join(data, name + e) for e in (".pdb", ".cif", ".pdb.gz", ".cif.gz")
                         if os.path.exists(os.path.join(data, name + e))]
                if not found:
                    sys.exit(f"accuracy.py: no {name}.pdb/.cif(.gz) in {data}")
                xyzr = found[0]
                ref = os.path.join(tmp, f"{name}-exact.ply")
                out = run([args.fdmsurf, xyzr, "-o", ref, "--method", "edt", "--spacing",
                           str(args.exact_reference), "--stats", "json"]).stdout
                ref_pieces = json.loads(out.strip().splitlines()[-1])["closed_pieces"]
            for h in args.spacings:
                tools = [(m, METHODS[m][0]) for m in methods]
                if ms_script:
                    tools.append(("molstar", "Mol* (measured)"))
                for key, label in tools:
                    mesh = os.path.join(tmp, f"{name}-{key}-{h}.ply")
                    t0 = time.monotonic()
                    pieces, stages = None, {}
                    if key == "molstar":
                        mesh = mesh[:-4] + ".off"
                        run(["node", ms_script, xyzr, mesh, str(h)])
                    else:
                        out = run([args.fdmsurf, xyzr, "-o", mesh, "--spacing", str(h),
                                   "--stats", "json"] + METHODS[key][1]).stdout
                        report = json.loads(out.strip().splitlines()[-1])
                        pieces = report["closed_pieces"]
                        stages = report["times"]
                    seconds = time.monotonic() - t0
                    c = compare(args.fdmsurf, ref, mesh, h)
                    row = dict(structure=name, spacing=h, method=key, label=label,
                               rmsd=c["rmsd"], beyond=c["pct_area_beyond_spacing"],
                               dA=100 * c["area_rel_err"], dV=100 * c["volume_rel_err"],
                               hausdorff=c["hausdorff"], mean_signed=c["mean_signed"],
                               triangles=c["test_triangles"], pieces=pieces,
                               ref_pieces=ref_pieces, seconds=seconds, times=stages)
                    rows.append(row)
                    print(f"  {name} {h} {key}: RMSD {row['rmsd']:.3f} dA {row['dA']:+.2f}% "
                          f"dV {row['dV']:+.2f}% ({seconds:.1f} s)", file=sys.stderr)
                    os.remove(mesh)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    print_tables(rows, args.spacings, device)


def print_tables(rows, spacings, device):
    def fmt_h(h):
        return f"{h:g} Å"

    keys = []
    for r in rows:
        if (r["structure"], r["method"]) not in keys:
            keys.append((r["structure"], r["method"]))
    get = {(r["structure"], r["method"], r["spacing"]): r for r in rows}

    print(f"Device: {'; '.join(device)}\n")
    print("Weighted RMSD (Å) and share of the reference area farther than the spacing "
          "(Giard & Macq 2010, Table 3 layout):\n")
    head = ["structure", "method"] + [f"RMSD {fmt_h(h)}" for h in spacings] + \
        [f"> h, {fmt_h(h)}" for h in spacings]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for s, m in keys:
        label = next(r["label"] for r in rows if r["structure"] == s and r["method"] == m)
        cells = [s.upper(), label]
        for h in spacings:
            r = get.get((s, m, h))
            cells.append(f"{r['rmsd']:.3f}" if r else "–")
        for h in spacings:
            r = get.get((s, m, h))
            cells.append(f"{r['beyond']:.2f}%" if r else "–")
        print("| " + " | ".join(cells) + " |")
    for label, figures in PUBLISHED_05:
        for s in dict.fromkeys(r["structure"] for r in rows):
            if s not in figures:
                continue
            cells = [s.upper(), label]
            for h in spacings:
                cells.append(f"{figures[s][0]:.3f}" if abs(h - 0.5) < 1e-9 else "–")
            cells += ["–"] * len(spacings)
            print("| " + " | ".join(cells) + " |")

    print("\nArea and volume error (dA, dV against the reference), closed pieces (reference), "
          "wall time of the fdmsurf run:\n")
    head = ["structure", "method", "spacing", "dA", "dV", "pieces (ref.)", "triangles",
            "Hausdorff (Å)", "time (s)"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for s, m in keys:
        for h in spacings:
            r = get.get((s, m, h))
            if not r:
                continue
            pieces = "–" if r["pieces"] is None else f"{r['pieces']} ({r['ref_pieces']})"
            print(f"| {s.upper()} | {r['label']} | {fmt_h(h)} | {r['dA']:+.2f}% | {r['dV']:+.2f}% "
                  f"| {pieces} | {r['triangles']:,} | {r['hausdorff']:.2f} | {r['seconds']:.1f} |")


if __name__ == "__main__":
    main()
