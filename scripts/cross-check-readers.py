#!/usr/bin/env python3
"""Reads each structure file with fdmsurf (its Python module) and with gemmi and, where installed,
Biopython and MDAnalysis, and compares what they read after the same selection rules: the first
model, the first alternate location of each atom, no waters, no hydrogens, ligands kept
(docs/structure.md). Compared: atom count, coordinates (to 0.002 Å, the PDB's precision), elements.
Radii: every fdmsurf radius > 0 (PDB/mmCIF radii come from fdmsurf's own table).

  scripts/cross-check-readers.py [FILE or FOLDER ...]     (default: tests/data)

PDB and mmCIF files are compared; PQR, XYZR and XYZRN only read by fdmsurf (gemmi does not read
them). Files another reader refuses are counted, not failed: the known differences are listed in
docs/structure.md (section "Other readers"). Exit status 1 when a file reads differently.
Libraries that are missing are skipped with a note. The fdmsurf module is found in
$FDMSURF_BUILD_DIR/python (default build/python).
"""
import glob
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.environ.get("FDMSURF_BUILD_DIR", os.path.join(ROOT, "build")),
                                "python"))

WATERS = {"HOH", "WAT", "DOD", "H2O"}
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
    atoms, seen = [], set()
    for chain in st[0]:
        for res in chain:
            water = res.name in WATERS
            for a in res:
                key = (chain.name, res.seqid.num, res.seqid.icode, a.name)
                if a.altloc != "\0" and key in seen:
                    continue
                if a.altloc != "\0":
                    seen.add(key)
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
    for atom in model.get_atoms():  # Biopython keeps the first altloc (or the highest occupancy)
        res = atom.get_parent()
        if res.get_resname().strip() in WATERS or atom.element.upper() in ("H", "D"):
            continue
        x, y, z = (float(v) for v in atom.coord)
        atoms.append((x, y, z, atom.element.upper()))
    return atoms


def by_mdanalysis(mda, path):
    u = mda.Universe(path)
    atoms = []
    for a in u.atoms:
        if a.resname in WATERS:
            continue
        element = getattr(a, "element", "") or ""
        if element.upper() in ("H", "D"):
            continue
        atoms.append((float(a.position[0]), float(a.position[1]), float(a.position[2]),
                      element.upper()))
    return atoms


def compare(ours, theirs):
    """A one-line difference, or None."""
    if len(ours) != len(theirs):
        return f"{len(ours)} atoms against {len(theirs)}"
    for i, (a, b) in enumerate(zip(ours, theirs)):
        d = math.dist(a[:3], b[:3])
        if d > 0.002:
            return f"atom {i + 1} at {a[:3]} against {b[:3]} ({d:.3f} A apart)"
        if b[3] and a[3] != b[3] and not (a[3] == "X" and b[3] in ("", "X")):
            return f"atom {i + 1} element {a[3]} against {b[3]}"
    return None


def main(argv):
    paths = argv or [os.path.join(ROOT, "tests", "data")]
    try:
        import fdmsurf
    except ImportError as e:
        print(f"cross-check-readers: the fdmsurf module is not built ({e}); nothing compared")
        return 0
    readers = []
    gemmi = optional("gemmi")
    if gemmi:
        readers.append(("gemmi", lambda p: by_gemmi(gemmi, p)))
    bio = optional("Bio")
    if bio:
        readers.append(("biopython", lambda p: by_biopython(bio, p)))
    mda = optional("MDAnalysis")
    if mda:
        readers.append(("mdanalysis", lambda p: by_mdanalysis(mda, p)))
    differences = compared = 0
    for path in structure_files(paths):
        try:
            s = fdmsurf.read_structure(path)
        except Exception as e:  # a refusal: reported, compared with nothing
            print(f"{path}: fdmsurf refuses: {e}")
            continue
        radii = [float(r) for r in s.radii]
        if not all(r > 0 for r in radii):
            print(f"{path}: fdmsurf gives a radius <= 0")
            differences += 1
        if kind(path) not in ("pdb", "ent", "cif", "mmcif"):
            continue
        ours = [(float(x), float(y), float(z), str(e).upper())
                for (x, y, z), e in zip(s.xyz.tolist(), s.element)]
        for name, read in readers:
            try:
                theirs = read(path)
            except Exception as e:
                print(f"{path}: {name} refuses: {str(e).splitlines()[0] if str(e) else type(e).__name__}")
                continue
            compared += 1
            diff = compare(ours, theirs)
            if diff:
                differences += 1
                print(f"{path}: fdmsurf and {name} differ: {diff}")
    print(f"cross-check-readers: {compared} comparisons, {differences} difference(s)")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
