#!/usr/bin/env python3
"""Reads each structure file with fdmsurf (its Python module) and with gemmi and, where installed,
Biopython and MDAnalysis, and compares what they read after the same selection rules: the first
model, the first alternate location of each atom, no waters, no hydrogens, ligands kept
(docs/structure.md). Compared: atom count, coordinates (to 0.002 Å, the PDB's precision), elements.
PQR files: atom count, coordinates and radii against Biopython's and MDAnalysis's PQR readers.
Radii: every fdmsurf radius > 0 (PDB/mmCIF radii come from fdmsurf's own table).

  scripts/cross-check-readers.py [FILE or FOLDER ...]     (default: tests/data)

PDB, mmCIF and PQR files are compared; XYZR and XYZRN only read by fdmsurf. Files another reader refuses are counted, not failed: the known differences are listed in
docs/structure.md (section "Other readers"). Exit status 1 when a file reads differently.
Libraries that are missing are skipped with a note. The fdmsurf module is found in
$FDMSURF_BUILD_DIR/python (default build/python).
"""
import glob
import math
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.environ.get("FDMSURF_BUILD_DIR", os.path.join(ROOT, "build")),
                                "python"))

WATERS = {"HOH", "WAT", "DOD", "H2O"}

# Files another reader is known to read differently, with the reason (docs/structure.md,
# "Other readers"): (file name pattern, reader or "*") -> why.
KNOWN = {
    # gemmi 0.5.7 reads the shifted columns as they stand (fdmsurf reads them field by field)
    (r"overflow\.pdb", "gemmi"): "fields past their columns",
    (r"gly\.pdb|free-format\.pdb", "gemmi"):
        "free-format records: gemmi reads the columns as they stand",
    # tests/data/lenient/amber-names.pdb shows the names-from-column-13 rule below; MDAnalysis
    # guesses carbon for the calcium ion CA
    (r"amber-names\.pdb", "*"): "names from column 13",
    (r"prot[34]\.pdb", "gemmi"): "OLIN in ADP: no element for gemmi, O (its first letter) here",
    # Names from column 13 without element columns (AMBER): gemmi and Biopython read CA in ALA
    # as calcium, HG2 as mercury, or no element; fdmsurf reads the name's first letter
    (r"helix_amber\.pdb", "gemmi"): "names from column 13",
    (r"helix_amber\.pdb", "biopython"): "names from column 13",
    (r"odd01\.pdb", "biopython"): "names of no element (XYZ, ABCD, CA in UKN): Biopython's X",
    # Biopython keeps one residue per number: a second residue name at the same number (a
    # C-terminal cap, chains without ids that restart their numbers) is taken for a point
    # mutation, and one of the two is kept
    (r"(complex|mol1|mol2)\.pqr|prot[34]\.pdb|achbp\.pqr|fas2\.pqr|mache\.pqr|"
     r"model_outNB\.(pqr|pdb)", "biopython"): "one residue per number",
    # Biopython's PQR reader takes the radius from fixed columns where the charge is wider
    (r"(491|small491|complex|acet)\.pqr", "biopython"): "PQR radius misread",
    (r"ion\.pqr", "biopython"): "Biopython reads no atom of a one-atom PQR without a chain",
    # The residue name a column left: Biopython takes the letters in column 17 for altlocs
    # of one atom; fdmsurf for atoms (the same letter: not alternates)
    (r"2-methylbutane\.pdb", "biopython"): "altloc column holds the residue name",
    # Microheterogeneity (two residues at one position): fdmsurf keeps the first residue's
    # alternate locations; gemmi's and Biopython's first-altloc readings differ
    (r"3JQH\.cif(\.gz)?", "*"): "microheterogeneity",
    (r"a_structure\.pdb(\.gz)?", "biopython"):
        "two atoms named CA in one residue, one from column 13: Biopython tells them apart",
    (r"box\.pdb", "mdanalysis"): "name Q, no element: MDAnalysis's element Q, fdmsurf's X",
}
EXTENSIONS = (".pdb", ".ent", ".cif", ".mmcif", ".pqr", ".xyzr", ".xyzrn")


def optional(module):
    try:
        return __import__(module)
    except ImportError:
        print(f"cross-check-readers: note: {module} is not installed; skipped")
        return None


def structure_files(paths):
    for path in paths:
        if os.path.isdir(path):
            for f in sorted(glob.glob(os.path.join(path, "**", "*"), recursive=True)):
                name = f[:-3] if f.endswith(".gz") else f
                if name.lower().endswith(EXTENSIONS) and os.path.isfile(f):
                    yield f
        else:
            yield path


def kind(path):
    name = path[:-3] if path.endswith(".gz") else path
    return os.path.splitext(name)[1].lower().lstrip(".")


def by_gemmi(gemmi, path):
    st = gemmi.read_structure(path)
    if len(st) == 0:
        raise ValueError("no model read")
    atoms, seen = [], {}
    for chain in st[0]:
        for res in chain:
            water = res.name in WATERS
            for a in res:
                key = (chain.name, res.seqid.num, res.seqid.icode, a.name)
                if a.altloc != "\0" and seen.setdefault(key, a.altloc) != a.altloc:
                    continue
                if water or a.element.name in ("H", "D"):
                    continue
                atoms.append((a.pos.x, a.pos.y, a.pos.z, a.element.name.upper()))
    return atoms


def by_biopython(bio, path):
    from Bio.PDB import MMCIFParser, PDBParser
    import gzip
    parser = MMCIFParser(QUIET=True) if kind(path) in ("cif", "mmcif") else PDBParser(QUIET=True)
    handle = gzip.open(path, "rt") if path.endswith(".gz") else open(path)
    with handle:
        st = parser.get_structure("x", handle)
    atoms = []
    model = next(iter(st))
    for atom in model.get_atoms():
        if atom.is_disordered():  # Biopython shows the highest occupancy; the rule is the first
            atom = atom.disordered_get_list()[0]
        res = atom.get_parent()
        if res.get_resname().strip() in WATERS or atom.element.upper() in ("H", "D"):
            continue
        x, y, z = (float(v) for v in atom.coord)
        atoms.append((x, y, z, atom.element.upper()))
    return atoms


def by_mdanalysis(mda, path):
    u = mda.Universe(path)
    atoms, first_altloc = [], {}
    for a in u.atoms:
        if a.resname in WATERS:
            continue
        if a.altLoc:  # MDAnalysis keeps every alternate location; the rule is the first
            key = (a.segid, a.chainID, a.resid, a.icode, a.name)
            if first_altloc.setdefault(key, a.altLoc) != a.altLoc:
                continue
        # MDAnalysis leaves the element empty without element columns: the name's first letter
        element = getattr(a, "element", "") or a.name.lstrip("0123456789")[:1]
        if element.upper() in ("H", "D"):
            continue
        atoms.append((float(a.position[0]), float(a.position[1]), float(a.position[2]),
                      element.upper()))
    return atoms


def pqr_by_biopython(bio, path):
    from Bio.PDB import PDBParser
    st = PDBParser(QUIET=True, is_pqr=True).get_structure("x", path)
    return [(*(float(v) for v in a.coord), float(a.get_radius()))
            for a in next(iter(st)).get_atoms()]


def pqr_by_mdanalysis(mda, path):
    u = mda.Universe(path)
    return [(*(float(v) for v in a.position), float(a.radius)) for a in u.atoms]


def compare(ours, theirs):
    """A one-line difference, or None."""
    if len(ours) != len(theirs):
        return f"{len(ours)} atoms against {len(theirs)}"
    # Readers order chains and ligands differently (gemmi puts a chain's HETATM after every
    # TER'd chain): each atom is paired with the other reader's nearest one.
    from scipy.spatial import cKDTree
    import numpy
    if ours:
        _, nearest = cKDTree(numpy.array([b[:3] for b in theirs])).query(
            numpy.array([a[:3] for a in ours]))
        if len(set(nearest.tolist())) == len(ours):
            theirs = [theirs[j] for j in nearest]
    for i, (a, b) in enumerate(zip(ours, theirs)):
        d = math.dist(a[:3], b[:3])
        if d > 0.002:
            return f"atom {i + 1} at {a[:3]} against {b[:3]} ({d:.3f} A apart)"
        if isinstance(b[3], float):
            if abs(a[3] - b[3]) > 1e-3:
                return f"atom {i + 1} radius {a[3]} against {b[3]}"
        elif b[3] and a[3] != b[3] and not (a[3] == "X" and b[3] in ("", "X")):
            return f"atom {i + 1} element {a[3]} against {b[3]}"
    return None


def available_readers():
    """(kind, name, read) for each installed reader: kind "model" (PDB, mmCIF) or "pqr"."""
    readers = []
    gemmi = optional("gemmi")
    if gemmi:
        readers.append(("model", "gemmi", lambda p: by_gemmi(gemmi, p)))
    bio = optional("Bio")
    if bio:
        readers.append(("model", "biopython", lambda p: by_biopython(bio, p)))
        readers.append(("pqr", "biopython", lambda p: pqr_by_biopython(bio, p)))
    mda = optional("MDAnalysis")
    if mda:
        import warnings
        warnings.filterwarnings("ignore")  # MDAnalysis warns about every guessed attribute
        readers.append(("model", "mdanalysis", lambda p: by_mdanalysis(mda, p)))
        readers.append(("pqr", "mdanalysis", lambda p: pqr_by_mdanalysis(mda, p)))
    return readers


def known(path, name):
    """The reason another reader is known to differ on this file (docs/structure.md), or None."""
    base = os.path.basename(path)
    for (file_pattern, reader), why in KNOWN.items():
        if reader in (name, "*") and re.fullmatch(file_pattern, base):
            return why
    return None


def check_file(path, readers):
    """(lines describing differences, number of comparisons) for one file."""
    import fdmsurf
    lines, compared = [], 0
    try:
        s = fdmsurf.read_structure(path)
    except Exception as e:  # a refusal: reported by the caller's own run, compared with nothing
        return lines, compared
    radii = [float(r) for r in s.radii]
    if not all(r > 0 for r in radii):
        lines.append(f"{path}: fdmsurf gives a radius <= 0")
    k = kind(path)
    if k in ("pdb", "ent", "cif", "mmcif"):
        ours = [(float(x), float(y), float(z), str(e).upper())
                for (x, y, z), e in zip(s.xyz.tolist(), s.element)]
        wanted = "model"
    elif k == "pqr" and not path.endswith(".gz"):
        # element radii replaced a file's zeros
        pqr_warned = any("have radius 0" in w for w in s.info["warnings"])
        ours = [(float(x), float(y), float(z), 0.0 if pqr_warned else r)
                for (x, y, z), r in zip(s.xyz.tolist(), radii)]
        wanted = "pqr"
    else:
        return lines, compared
    # Biopython keeps one atom per residue id (hetero flag, chain, number, insertion code) and
    # name: files that number every molecule 1 (lipid and ion boxes) lose the repeats there.
    keys = list(zip(s.hetero.tolist(), s.chain, s.residue_number.tolist(),
                    s.insertion_code, s.name))
    first_of_key = []
    seen = set()
    for key in keys:
        first_of_key.append(key not in seen)
        seen.add(key)
    for reader_kind, name, read in readers:
        if reader_kind != wanted or (name == "mdanalysis" and k in ("cif", "mmcif")):
            continue  # MDAnalysis 2.4 reads no mmCIF
        mine = ours if name != "biopython" else [a for a, f in zip(ours, first_of_key) if f]
        try:
            theirs = read(path)
            if wanted == "pqr" and not pqr_warned:  # fdmsurf leaves out atoms of radius 0
                theirs = [t for t in theirs if t[3] > 0]
        except Exception as e:
            if not known(path, name):
                first = str(e).splitlines()[0] if str(e) else type(e).__name__
                print(f"{path}: {name} refuses ({first}); fdmsurf reads it")
            continue
        compared += 1
        diff = compare(mine, theirs)
        if diff and not known(path, name):
            lines.append(f"{path}: fdmsurf and {name} differ: {diff}")
    return lines, compared


def main(argv):
    paths = argv or [os.path.join(ROOT, "tests", "data")]
    try:
        import fdmsurf  # noqa: F401
    except ImportError as e:
        print(f"cross-check-readers: the fdmsurf module is not built ({e}); nothing compared")
        return 0
    readers = available_readers()
    differences, compared = [], 0
    for path in structure_files(paths):
        lines, n = check_file(path, readers)
        differences += lines
        compared += n
    for line in differences:
        print(line)
    print(f"cross-check-readers: {compared} comparisons, {len(differences)} difference(s)")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
