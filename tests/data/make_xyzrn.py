#!/usr/bin/env python3
"""Writes an XYZRN file from a PDB file (same atoms, same order; waters and hydrogens left out).

Layout of MSMS-style pdb-to-xyzrn scripts (MaSIF's xyzrn.py): `x y z r 1 NAME` with NAME =
chain_resnum_icode_resname_atomname_color, icode `x` when blank, colour by the atom name's first
letter (N Blue, O Red, S Yellow, else Green). Radii: Bondi (C 1.70, N 1.55, O 1.52, S 1.80,
P 1.80, Fe 1.80 for want of a Bondi value), as fdmsurf gives them.

    python3 tests/data/make_xyzrn.py tests/data/1crn.pdb > tests/data/1crn.xyzrn
    python3 tests/data/make_xyzrn.py tests/data/4hhb.pdb.gz > tests/data/4hhb.xyzrn
"""
import gzip
import sys

bondi = {"C": 1.70, "N": 1.55, "O": 1.52, "S": 1.80, "P": 1.80, "FE": 1.80}
colours = {"N": "Blue", "O": "Red", "S": "Yellow"}
path = sys.argv[1]
opener = gzip.open if path.endswith(".gz") else open
with opener(path, "rt") as pdb:
    for line in pdb:
        if line.startswith("ENDMDL"):
            break
        if not line.startswith(("ATOM", "HETATM")) or line[17:20] == "HOH":
            continue
        element = line[76:78].strip().upper()
        if element in ("H", "D"):
            continue
        name = line[12:16].strip()
        icode = line[26].strip() or "x"
        resnum = int(line[22:26])
        colour = colours.get(name[0], "Green")
        full = f"{line[21]}_{resnum}_{icode}_{line[17:20].strip()}_{name}_{colour}"
        x, y, z = (float(line[c:c + 8]) for c in (30, 38, 46))
        print(f"{x:.3f} {y:.3f} {z:.3f} {bondi[element]:.2f} 1 {full}")
