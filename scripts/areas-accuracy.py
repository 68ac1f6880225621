#!/usr/bin/python3
"""fdmsurf's per-atom and per-residue areas against FreeSASA on the same atoms and radii
(issue 13, items 3-4; docs/areas.md).

For each structure, runs

    build/fdmsurf X --surface S --spacing H -o X.ply --areas X.csv     (the mesh and the areas)

reads the atoms fdmsurf used (chain, residue, name, radius: the CSV's atom rows), writes them as
a PDB file whose occupancy column holds the radius, and runs FreeSASA 2.1.2 (Debian freesasa;
Lee-Richards, resolution 100, --radius-from-occupancy, probe 1.4 Å for sas and 1e-4 Å for vdw,
per-atom areas from its PDB output's B-factor column). Compares the totals, the per-residue areas
(mean absolute difference, 99th percentile and largest of |fdmsurf - FreeSASA|) and the per-atom
areas, for the exact sphere patches (`area`) and the mesh's split (`mesh_area`). With
--buried 'G1:G2;...' (chain ids, e.g. A:B), also the buried area against FreeSASA's
--chain-groups (which uses FreeSASA's own ProtOr radii whatever the options: fdmsurf then reads
the same radii from a PQR file).
Needs /usr/bin/python3 with numpy, and `freesasa` on the PATH.

    scripts/areas-accuracy.py                                  # 1crn 4hhb 1aon, sas, 0.5 Å
    scripts/areas-accuracy.py --structures 4hhb --buried 'A:B;A:D;A,C:B,D' --spacings 0.5
    scripts/areas-accuracy.py --structures 1crn --surfaces vdw --spacings 0.5,0.25
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRUCTURES = {
    "1crn": os.path.join(ROOT, "tests", "data", "1crn.pdb"),
    "4hhb": os.path.join(ROOT, "tests", "data", "4hhb.pdb.gz"),
    "1aon": os.path.join(ROOT, "..", "shared", "data", "1aon.pdb.gz"),
    "3al1": os.path.join(ROOT, "tests", "data", "3al1.pdb"),
}


def read_atoms(path):
    atoms, residues = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["record"] == "atom":
                atoms.append(row)
            elif row["record"] == "residue":
                residues.append(row)
    return atoms, residues


def write_pdb(atoms, path, chains=None):
    with open(path, "w") as f:
        serial = 0
        for a in atoms:
            if chains is not None and a["chain"] not in chains:
                continue
            serial += 1
            name = a["atom_name"] if len(a["atom_name"]) == 4 else " " + a["atom_name"]
            f.write("ATOM  %5d %-4.4s %3.3s %1.1s%4d%1.1s   %8.3f%8.3f%8.3f%6.2f%6.2f          %2s\n"
                    % (serial % 100000, name, a["residue_name"], a["chain"],
                       int(a["residue_number"]) % 10000, a["insertion_code"] or " ",
                       float(a["x"]), float(a["y"]), float(a["z"]), float(a["radius"]), 0.0,
                       a["element"][:2]))
        f.write("END\n")


def freesasa(pdb, probe, extra=()):
    t0 = time.time()
    out = subprocess.run(["freesasa", "--radius-from-occupancy", "--lee-richards", "--resolution",
                          "100", "--probe-radius", str(probe)] + list(extra) + [pdb],
                         check=True, capture_output=True, text=True).stdout
    return out, time.time() - t0


def freesasa_atoms(pdb, probe):
    out, dt = freesasa(pdb, probe, ["--format", "pdb"])
    area = [float(l[60:66]) for l in out.splitlines() if l.startswith("ATOM")]
    return np.array(area), dt


def freesasa_groups(pdb, probe, groups):
    """Totals of the groups, with FreeSASA's own radii (see main)."""
    out = subprocess.run(["freesasa", "--lee-richards", "--resolution", "100", "--probe-radius",
                          str(probe), "--chain-groups=" + groups, pdb],
                         check=True, capture_output=True, text=True).stdout
    totals = [float(l.split(":")[1]) for l in out.splitlines() if l.startswith("Total")]
    return totals[1:]


def stats(ours, ref, key):
    d = np.abs(ours - ref)
    return {"total": float(ours.sum()), "reference": float(ref.sum()),
            "dA": float(ours.sum() / ref.sum() - 1.0),
            key + "_mad": float(d.mean()), key + "_p99": float(np.percentile(d, 99)),
            key + "_max": float(d.max())}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--structures", default="1crn,4hhb,1aon")
    ap.add_argument("--surfaces", default="sas")
    ap.add_argument("--spacings", default="0.5")
    ap.add_argument("--buried", default="", help="chain groups G1:G2, separated by ';'")
    ap.add_argument("--fdmsurf", default=os.path.join(ROOT, "build", "fdmsurf"))
    ap.add_argument("--extra", default="", help="more fdmsurf options for the surfaces, e.g. '--refine 1'")
    ap.add_argument("--json", help="write every figure to this file")
    args = ap.parse_args()
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.structures.split(","):
            path = STRUCTURES.get(name, name)
            for surface in args.surfaces.split(","):
                probe = 1.4 if surface == "sas" else 1e-4
                ref_atoms = None
                for h in args.spacings.split(","):
                    csv_path = os.path.join(tmp, "a.csv")
                    cmd = [args.fdmsurf, path, "--surface", surface, "--spacing", h, "-o",
                           os.path.join(tmp, "m.ply"), "--areas", csv_path, "--stats", "json"]
                    cmd += args.extra.split()
                    t0 = time.time()
                    run = subprocess.run(cmd, check=True, capture_output=True, text=True)
                    wall = time.time() - t0
                    summary = json.loads(run.stdout)
                    atoms, _ = read_atoms(csv_path)
                    if ref_atoms is None:
                        pdb = os.path.join(tmp, "in.pdb")
                        write_pdb(atoms, pdb)
                        ref_atoms, fs_time = freesasa_atoms(pdb, probe)
                    exact = np.array([float(a["area"]) for a in atoms])
                    mesh = np.array([float(a["mesh_area"]) for a in atoms])
                    keys = [(a["chain"], a["residue_number"], a["insertion_code"], a["residue_name"])
                            for a in atoms]
                    index = {}
                    rid = np.array([index.setdefault(k, len(index)) for k in keys])
                    res = lambda v: np.bincount(rid, v, len(index))
                    row = {"structure": name, "surface": surface, "spacing": float(h),
                           "extra": args.extra,
                           "atoms": len(atoms), "residues": len(index), "fdmsurf_s": wall,
                           "freesasa_s": fs_time, "mesh_area": summary["area"]}
                    for label, v in (("exact", exact), ("mesh", mesh)):
                        r = stats(res(v), res(ref_atoms), "residue")
                        a = stats(v, ref_atoms, "atom")
                        row[label] = {**r, **{k: a[k] for k in a if k.startswith("atom")}}
                    results.append(row)
                    for label in ("exact", "mesh"):
                        s = row[label]
                        print("%-5s %s %s Å%s %-5s total %11.1f vs %11.1f (%+.3f%%)  residue MAD %.3f "
                              "p99 %.3f max %.2f  atom MAD %.3f p99 %.3f Å²"
                              % (name, surface, h, (" " + args.extra) if args.extra else "",
                                 label, s["total"], s["reference"],
                                 100 * s["dA"], s["residue_mad"], s["residue_p99"],
                                 s["residue_max"], s["atom_mad"], s["atom_p99"]), flush=True)
            if args.buried:
                # FreeSASA 2.1.2 gives --chain-groups its own radii (ProtOr) even with
                # --radius-from-occupancy: fdmsurf gets those radii through a PQR file.
                json_path = os.path.join(tmp, "atoms.json")
                subprocess.run([args.fdmsurf, path, "--surface", "sas", "--areas", json_path],
                               check=True, capture_output=True, text=True)
                with open(json_path) as f:
                    atoms = [{"chain": a["chain"], "residue_number": a["residue_number"],
                              "insertion_code": a["insertion_code"],
                              "residue_name": a["residue_name"], "atom_name": a["name"],
                              "element": a["element"], "x": a["xyz"][0], "y": a["xyz"][1],
                              "z": a["xyz"][2], "radius": a["radius"]}
                             for a in json.load(f)["atoms"]]
                pdb = os.path.join(tmp, "g.pdb")
                write_pdb(atoms, pdb)
                out = subprocess.run(["freesasa", "--format", "pdb", pdb], check=True,
                                     capture_output=True, text=True).stdout
                radii = [float(l[54:60]) for l in out.splitlines() if l.startswith("ATOM")]
                assert len(radii) == len(atoms)
                pqr = os.path.join(tmp, "protor.pqr")
                with open(pqr, "w") as f:
                    for i, (a, r) in enumerate(zip(atoms, radii)):
                        f.write("ATOM %6d %-4s %-4s %s %5d %9.3f %9.3f %9.3f 0.0 %.2f\n"
                                % (i + 1, a["atom_name"], a["residue_name"], a["chain"],
                                   a["residue_number"], a["x"], a["y"], a["z"], r))
            for spec in [g for g in args.buried.split(";") if g]:
                g1, g2 = spec.split(":")
                json_path = os.path.join(tmp, "b.json")
                h = args.spacings.split(",")[0]
                t0 = time.time()
                subprocess.run([args.fdmsurf, pqr, "--surface", "sas", "--spacing", h, "-o",
                                os.path.join(tmp, "b.ply"), "--areas", json_path,
                                "--buried", spec], check=True, capture_output=True, text=True)
                wall = time.time() - t0
                with open(json_path) as f:
                    b = json.load(f)["buried"]
                c1, c2 = g1.replace(",", ""), g2.replace(",", "")
                t0 = time.time()
                t = freesasa_groups(pdb, 1.4, "%s+%s+%s" % (c1, c2, c1 + c2))
                fs_wall = time.time() - t0
                ref = t[0] + t[1] - t[2]
                row = {"structure": name, "buried": spec, "spacing": float(h),
                       "exact": b["buried_area"], "mesh": b["mesh_buried_area"], "freesasa": ref,
                       "freesasa_groups": t, "fdmsurf_s": wall, "freesasa_s": fs_wall,
                       "groups": b["groups"]}
                results.append(row)
                print("%-5s buried %-9s exact %8.1f, mesh (%s Å) %8.1f vs FreeSASA --chain-groups "
                      "%8.1f Å² (exact %+.3f%%, mesh %+.3f%%)"
                      % (name, spec, row["exact"], h, row["mesh"], ref,
                         100 * (row["exact"] / ref - 1), 100 * (row["mesh"] / ref - 1)),
                      flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    sys.exit(main())
