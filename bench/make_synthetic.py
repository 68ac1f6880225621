#!/usr/bin/env python3
"""Writes a synthetic XYZR structure of about N atoms for scale tests of fdmsurf.

Two kinds (deterministic for a given --seed):

  blobs   (default) a cubic lattice of protein-like globules: each globule holds
          --blob-atoms atoms drawn uniformly in a sphere whose radius gives protein
          density (--density, 0.05 heavy atoms per cubic angstrom: 1000 atoms in a
          sphere of 16.8 A), the globule centres --pitch A apart (default: the
          globule diameter plus 6 A, so that neighbours do not fuse), each shifted
          by up to 1 A at random. Radii in the proportions of a protein's heavy
          atoms: C 1.70 (63%), N 1.55 (17%), O 1.52 (19%), S 1.80 (1%).
          1,000,000 atoms = 10 x 10 x 10 globules of 1,000, in a 400 A box.
  uniform one box filled uniformly at --density with the same radii (a porous
          sponge rather than a protein: a worst case for the mesh size).
  shell   a capsid-like shell: --copies copies of the XYZR structure --unit (default
          the 4YVS asymmetric unit of ../shared/reference/ses, 26,430 atoms), centred,
          each turned so that its z axis points along its own direction of a
          Fibonacci sphere and twisted about it by the golden angle, centres on a
          sphere of --radius A. 92 copies on 300 A: 2.43 million atoms (issue 36).
          --atoms is ignored.

  python3 bench/make_synthetic.py --atoms 1000000 -o /tmp/synthetic-1m.xyzr
  build/fdmsurf /tmp/synthetic-1m.xyzr -o /tmp/synthetic-1m.ply --spacing 1.0 --stats json
  python3 bench/make_synthetic.py --kind shell -o /tmp/shell.xyzr
  python3 bench/make_synthetic.py --kind shell --format pqr -o /tmp/shell.pqr
  python3 bench/make_synthetic.py --kind shell --format xyzrn -o /tmp/shell.xyzrn

Plain Python 3, no packages.
"""

import argparse
import gzip
import math
import os
import random
import sys

RADII = [1.70, 1.55, 1.52, 1.80]  # C, N, O, S
SHARES = [0.63, 0.17, 0.19, 0.01]


def point_in_ball(rng, radius):
    while True:
        x, y, z = (rng.uniform(-1.0, 1.0) for _ in range(3))
        if x * x + y * y + z * z <= 1.0:
            return x * radius, y * radius, z * radius


def blobs(rng, atoms, blob_atoms, density, pitch):
    blob_radius = math.cbrt(3.0 * blob_atoms / (4.0 * math.pi * density))
    if pitch is None:
        pitch = 2.0 * blob_radius + 6.0
    count = max(1, round(atoms / blob_atoms))
    side = math.ceil(round(count ** (1.0 / 3.0), 9))
    centres = [(i, j, k) for i in range(side) for j in range(side) for k in range(side)][:count]
    for i, j, k in centres:
        c = [pitch * i + rng.uniform(-1.0, 1.0), pitch * j + rng.uniform(-1.0, 1.0),
             pitch * k + rng.uniform(-1.0, 1.0)]
        for _ in range(blob_atoms):
            x, y, z = point_in_ball(rng, blob_radius)
            yield c[0] + x, c[1] + y, c[2] + z


def blobs_info(atoms, blob_atoms, density, pitch):
    blob_radius = math.cbrt(3.0 * blob_atoms / (4.0 * math.pi * density))
    if pitch is None:
        pitch = 2.0 * blob_radius + 6.0
    count = max(1, round(atoms / blob_atoms))
    side = math.ceil(round(count ** (1.0 / 3.0), 9))
    return (f"{count} globules of {blob_atoms} atoms (radius {blob_radius:.1f} A) on a "
            f"{side}^3 lattice of pitch {pitch:.1f} A")


def uniform(rng, atoms, density):
    side = math.cbrt(atoms / density)
    for _ in range(atoms):
        yield rng.uniform(0.0, side), rng.uniform(0.0, side), rng.uniform(0.0, side)


def read_xyzr(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        for line in f:
            fields = line.split()
            if len(fields) >= 4 and not line.startswith("#"):
                yield tuple(float(v) for v in fields[:4])


def shell(unit, copies, radius):
    """Yields (x, y, z, r) of `copies` turned copies of `unit` centred on a sphere."""
    n = len(unit)
    c = [sum(a[k] for a in unit) / n for k in range(3)]
    local = [(a[0] - c[0], a[1] - c[1], a[2] - c[2], a[3]) for a in unit]
    golden = math.pi * (3.0 - math.sqrt(5.0))
    for i in range(copies):
        # Fibonacci sphere direction w; u, v complete a right-handed frame, twisted by i*golden.
        z = 1.0 - (2.0 * i + 1.0) / copies
        s = math.sqrt(max(0.0, 1.0 - z * z))
        w = (s * math.cos(golden * i), s * math.sin(golden * i), z)
        helper = (1.0, 0.0, 0.0) if abs(w[0]) < 0.9 else (0.0, 1.0, 0.0)
        u = (helper[1] * w[2] - helper[2] * w[1], helper[2] * w[0] - helper[0] * w[2],
             helper[0] * w[1] - helper[1] * w[0])
        norm = math.sqrt(sum(x * x for x in u))
        u = tuple(x / norm for x in u)
        v = (w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0])
        t = golden * i
        u, v = (tuple(math.cos(t) * a + math.sin(t) * b for a, b in zip(u, v)),
                tuple(-math.sin(t) * a + math.cos(t) * b for a, b in zip(u, v)))
        for x, y, zz, r in local:
            yield (radius * w[0] + x * u[0] + y * v[0] + zz * w[0],
                   radius * w[1] + x * u[1] + y * v[1] + zz * w[1],
                   radius * w[2] + x * u[2] + y * v[2] + zz * w[2], r)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--atoms", type=int, default=1_000_000)
    parser.add_argument("--kind", choices=["blobs", "uniform", "shell"], default="blobs")
    parser.add_argument("--unit", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "reference", "ses",
        "4yvs.xyzr.gz"), help="shell: the XYZR(.gz) structure copied")
    parser.add_argument("--copies", type=int, default=92, help="shell: copies of --unit")
    parser.add_argument("--radius", type=float, default=300.0, help="shell: sphere radius, A")
    parser.add_argument("--blob-atoms", type=int, default=1000)
    parser.add_argument("--density", type=float, default=0.05, help="atoms per cubic angstrom")
    parser.add_argument("--pitch", type=float, default=None, help="globule spacing, A")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--format", choices=["xyzr", "pqr", "xyzrn"], default="xyzr",
                        help="pqr: the same atoms as pdb2pqr's ATOM records (a chain per "
                        "26 x 10,000 residues of 10 atoms, charge 0), for the PQR reader; "
                        "xyzrn: the same atoms with MSMS-style names (chain_residue_x_ALA_atom)")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()

    rng = random.Random(args.seed)
    if args.kind == "blobs":
        points = blobs(rng, args.atoms, args.blob_atoms, args.density, args.pitch)
        info = blobs_info(args.atoms, args.blob_atoms, args.density, args.pitch)
    elif args.kind == "shell":
        unit = list(read_xyzr(args.unit))
        points = shell(unit, args.copies, args.radius)
        info = (f"{args.copies} copies of {os.path.basename(args.unit)} ({len(unit)} atoms) on a "
                f"sphere of {args.radius:g} A")
    else:
        points = uniform(rng, args.atoms, args.density)
        info = f"{args.atoms} atoms uniform in a {math.cbrt(args.atoms / args.density):.1f} A box"
    lo = [math.inf] * 3
    hi = [-math.inf] * 3
    n = 0
    with open(args.output, "w") as out:
        comment = "REMARK   1" if args.format == "pqr" else "#"
        out.write(f"{comment} fdmsurf synthetic structure: {info}; seed {args.seed}\n")
        lines = []
        for p in points:
            r = p[3] if len(p) > 3 else rng.choices(RADII, SHARES)[0]
            element = {1.55: "N", 1.52: "O", 1.80: "S"}.get(round(r, 2), "C")
            chain = chr(ord("A") + (n // 100000) % 26)
            if args.format == "xyzrn":
                lines.append(f"{p[0]:.3f} {p[1]:.3f} {p[2]:.3f} {r:.2f} 1 "
                             f"{chain}_{n // 10 % 10000}_x_ALA_{element}\n")
            elif args.format == "pqr":
                lines.append(f"ATOM  {n + 1:>7} {element:<4} ALA {chain}{n // 10 % 10000:>5}    "
                             f"{p[0]:8.3f} {p[1]:8.3f} {p[2]:8.3f} {0.0:7.4f} {r:6.4f}\n")
            else:
                lines.append(f"{p[0]:.3f} {p[1]:.3f} {p[2]:.3f} {r:.2f}\n")
            for a in range(3):
                lo[a] = min(lo[a], p[a])
                hi[a] = max(hi[a], p[a])
            n += 1
            if len(lines) == 65536:
                out.writelines(lines)
                lines.clear()
        out.writelines(lines)
    print(f"{args.output}: {n} atoms, {info}; extent "
          f"{hi[0] - lo[0]:.0f} x {hi[1] - lo[1]:.0f} x {hi[2] - lo[2]:.0f} A", file=sys.stderr)


if __name__ == "__main__":
    main()
