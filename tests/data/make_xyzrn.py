#!/usr/bin/env python3
"""Writes tests/data/1crn.xyzrn from 1crn.pdb (same atoms, same order).

Layout of MSMS-style pdb-to-xyzrn scripts (MaSIF's xyzrn.py): `x y z r 1 NAME` with NAME =
chain_resnum_icode_resname_atomname_color, icode `x` when blank, colour by the atom name's first
letter (N Blue, O Red, S Yellow, else Green). Radii: Bondi, as fdmsurf gives them.

    python3 tests/data/make_xyzrn.py > tests/data/1crn.xyzrn
"""
import os

here = os.path.dirname(os.path.abspath(__file__))
bondi = {"C": 1.70, "N": 1.55, "O": 1.52, "S": 1.80}
colours = {"N": "Blue", "O": "Red", "S": "Yellow"}
with open(os.path.join(here, "1crn.pdb")) as pdb:
    for line in pdb:
        if not line.startswith(("ATOM", "HETATM")):
            continue
        name = line[12:16].strip()
        icode = line[26].strip() or "x"
        resnum = int(line[22:26])
        colour = colours.get(name[0], "Green")
        full = f"{line[21]}_{resnum}_{icode}_{line[17:20].strip()}_{name}_{colour}"
        x, y, z = (float(line[c:c + 8]) for c in (30, 38, 46))
        r = bondi[line[76:78].strip()]
        print(f"{x:.3f} {y:.3f} {z:.3f} {r:.2f} 1 {full}")
