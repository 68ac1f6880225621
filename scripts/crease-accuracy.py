#!/usr/bin/python3
"""Areas and volumes of fdmsurf's van der Waals and solvent-accessible meshes against FreeSASA
and a Monte-Carlo estimate of the union of balls (issue 13, item 1; docs/accuracy.md).

For each structure (an .xyzr file: x y z r per line, the atoms and radii given to both
programs), each surface (vdw: the balls of radius r, FreeSASA with a probe of 1e-4 Å; sas: the
balls of radius r + 1.4, FreeSASA with probe 1.4 Å), each spacing and each crease setting, runs

    build/fdmsurf X.xyzr -o X.ply --surface S --spacing H [--no-creases] --stats json

and compares the mesh's area with FreeSASA's total (Lee-Richards, resolution 100, the radii in
the occupancy column and --radius-from-occupancy), and its volume with the volume of the union
of the balls by stratified Monte Carlo (one uniform point per cell of a regular lattice, a
fixed seed; the standard error is printed). Needs /usr/bin/python3 with numpy and scipy, and
`freesasa` (Debian package freesasa) on the PATH.

    scripts/crease-accuracy.py                                 # 1crn, 4hhb, 1aon; 0.5 0.25 Å
    scripts/crease-accuracy.py --structures 1crn --spacings 0.5 --surfaces sas
"""
import argparse
import gzip
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.spatial import cKDTree

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED_SES = os.path.join(ROOT, "..", "shared", "reference", "ses")
PROBE = 1.4
VDW_PROBE = 1e-4  # FreeSASA's area of the balls themselves


def xyzr_path(name):
    for folder in (os.path.join(ROOT, "tests", "data"), SHARED_SES):
        for ext in (".xyzr", ".xyzr.gz"):
            p = os.path.join(folder, name + ext)
            if os.path.exists(p):
                return p
    raise SystemExit(f"no {name}.xyzr in tests/data or ../shared/reference/ses")


def read_xyzr(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        rows = [line.split()[:4] for line in f if line.strip()]
    a = np.array(rows, dtype=float)
    return a[:, :3], a[:, 3]


def write_pdb(xyz, radius, path):
    """ATOM records whose occupancy column holds the radius (FreeSASA --radius-from-occupancy).
    Residues of up to 9999 atoms' worth are numbered in turn; chains cycle A-Z."""
    with open(path, "w") as f:
        for i, (p, r) in enumerate(zip(xyz, radius)):
            serial = i % 100000
            resseq = (i // 10) % 10000
            chain = chr(ord("A") + (i // 100000) % 26)
            f.write("ATOM  %5d  C   ALA %s%4d    %8.3f%8.3f%8.3f%6.2f%6.2f           C\n"
                    % (serial, chain, resseq, p[0], p[1], p[2], r, 0.0))
        f.write("END\n")


def freesasa_total(xyz, radius, probe, tmp):
    pdb = os.path.join(tmp, "atoms.pdb")
    write_pdb(xyz, radius, pdb)
    t0 = time.time()
    out = subprocess.run(["freesasa", "--radius-from-occupancy", "--lee-richards",
                          "--resolution", "100", "--probe-radius", str(probe), "--format",
                          "json", pdb], check=True, capture_output=True, text=True).stdout
    dt = time.time() - t0
    total = json.loads(out)["results"][0]["structure"][0]["area"]["total"]
    return float(total), dt


def union_volume(xyz, radius, cell=0.35, seed=13):
    """Volume of the union of balls: one uniform random point in each cell of a lattice over
    the bounding box (stratified Monte Carlo), tested against the balls whose centres are among
    its 32 nearest within the largest radius (k-d tree). Returns (volume, standard error, from
    the spread of 16 interleaved sub-lattices)."""
    rng = np.random.default_rng(seed)
    lo = (xyz - radius[:, None]).min(axis=0) - cell
    hi = (xyz + radius[:, None]).max(axis=0) + cell
    n = np.ceil((hi - lo) / cell).astype(int)
    tree = cKDTree(xyz)
    rmax = float(radius.max())
    r2 = np.append(radius * radius, -1.0)  # index len(xyz): no neighbour
    inside_by_group = np.zeros(16)
    counts_by_group = np.zeros(16)
    ys, xs = np.meshgrid(np.arange(n[1]), np.arange(n[0]), indexing="ij")
    plane = np.stack([xs.ravel(), ys.ravel()], axis=1).astype(float)
    for k in range(n[2]):
        pts = np.empty((plane.shape[0], 3))
        pts[:, :2] = lo[:2] + (plane + rng.random(plane.shape)) * cell
        pts[:, 2] = lo[2] + (k + rng.random(plane.shape[0])) * cell
        d, idx = tree.query(pts, k=32, distance_upper_bound=rmax, workers=-1)
        inside = np.any(d * d <= r2[idx], axis=1)
        g = (np.arange(len(pts)) + k) % 16
        inside_by_group += np.bincount(g, weights=inside, minlength=16)
        counts_by_group += np.bincount(g, minlength=16)
    v_cell = cell ** 3
    volume = inside_by_group.sum() * v_cell
    per_group = inside_by_group / counts_by_group * counts_by_group.sum() * v_cell
    stderr = per_group.std(ddof=1) / np.sqrt(16)
    return volume, stderr


def run_fdmsurf(fdmsurf, path, surface, spacing, creases, tmp):
    mesh = os.path.join(tmp, "mesh.ply")
    cmd = [fdmsurf, path, "-o", mesh, "--surface", surface, "--spacing", str(spacing),
           "--stats", "json", "--quiet"]
    if surface == "sas":
        cmd += ["--probe", str(PROBE)]
    if not creases:
        cmd.append("--no-snap")
    t0 = time.time()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    wall = time.time() - t0
    s = json.loads(out)
    creases_ms = s["times"].get("snap", 0.0)
    return s, wall, creases_ms


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fdmsurf", default=os.path.join(ROOT, "build", "fdmsurf"))
    ap.add_argument("--structures", default="1crn,4hhb,1aon")
    ap.add_argument("--surfaces", default="sas,vdw")
    ap.add_argument("--spacings", nargs="+", type=float, default=[0.5, 0.25])
    ap.add_argument("--creases", default="on,off", help="on, off or on,off")
    ap.add_argument("--mc-cell", type=float, default=0.35,
                    help="lattice cell of the Monte-Carlo volume (Å)")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.structures.split(","):
            path = xyzr_path(name)
            xyz, radius = read_xyzr(path)
            for surface in args.surfaces.split(","):
                probe = PROBE if surface == "sas" else VDW_PROBE
                area_ref, t_fs = freesasa_total(xyz, radius, probe, tmp)
                balls = radius + (PROBE if surface == "sas" else 0.0)
                t0 = time.time()
                vol_ref, vol_err = union_volume(xyz, balls, args.mc_cell)
                print(f"# {name} {surface}: FreeSASA {area_ref:.1f} Å² ({t_fs:.2f} s), "
                      f"Monte-Carlo volume {vol_ref:.1f} ± {vol_err:.1f} Å³ "
                      f"({time.time() - t0:.0f} s)", file=sys.stderr, flush=True)
                for h in args.spacings:
                    for setting in args.creases.split(","):
                        s, wall, c_ms = run_fdmsurf(args.fdmsurf, path, surface, h,
                                                    setting == "on", tmp)
                        row = (name, surface, h, setting, s["area"], area_ref,
                               100 * (s["area"] / area_ref - 1), s["volume"], vol_ref,
                               100 * (s["volume"] / vol_ref - 1), 100 * vol_err / vol_ref,
                               s["triangles"], s["closed_manifold"], c_ms / 1000, wall)
                        rows.append(row)
                        print("| %s | %s | %g | %s | %.1f | %.1f | %+.2f%% | %.1f | %.1f | "
                              "%+.2f%% (±%.2f%%) | %s | %s | %.2f | %.1f |"
                              % (row[:11] + (f"{row[11]:,}", "yes" if row[12] else "NO")
                                 + row[13:]), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
