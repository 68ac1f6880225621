"""Structures that users already hold as other libraries' objects (gemmi, Biopython, MDAnalysis,
mdtraj) turned into fdmsurf Structures with the same selection rules as fdmsurf's own readers.

Each object's atoms are written, in file order, as the ATOM/HETATM records of a PDB text that
fdmsurf's PDB reader then reads: waters, hydrogens, ligands, alternate locations, chains= and
select= are decided by the reader's own code, not by a copy of it. The record's serial number is
the atom's position in the object (1-based, hybrid-36 past 99,999), so the atoms the reader
keeps map back to the object; their coordinates are then taken from the object itself (float32
of its numbers, Å), so no precision is lost to the text's three decimals. None of the four
libraries is imported here: an object is recognised by the module its type comes from.
"""

import numpy as np

from . import _fdmsurf

SUPPORTED = ("a path, an fdmsurf.Structure, an xyz array (N, 3) with radii=(N,), a gemmi Structure "
             "or Model, a Biopython Structure, Model or Chain, an MDAnalysis Universe or "
             "AtomGroup, or an mdtraj Trajectory")

# Residues that mdtraj and MDAnalysis objects without record types write as ATOM records; the
# rest are HETATM, as the PDB writes them (the reader's ligand rule needs HETATM).
_POLYMER_RESIDUES = frozenset(
    "ALA ARG ASN ASP CYS GLN GLU GLY HIS ILE LEU LYS MET PHE PRO SER THR TRP TYR VAL "
    "HID HIE HIP HSD HSE HSP CYX CYM ASH GLH LYN ACE NME NMA SEC PYL UNK "
    "A C G U I DA DC DG DT DI RA RC RG RU".split())


def library_of(obj):
    """'gemmi', 'Bio', 'MDAnalysis' or 'mdtraj' when `obj` is one of theirs, else None (by the
    module its type is defined in; nothing is imported)."""
    module = type(obj).__module__ or ""
    for name in ("gemmi", "Bio", "MDAnalysis", "mdtraj"):
        if module == name or module.startswith(name + "."):
            return name
    return None


class Topology:
    """The records of one object's atoms: per-atom columns in file order (lists or arrays of N
    entries) and the atoms' coordinates (N, 3) in Å; `name` stands for the object in messages."""

    def __init__(self, name, columns, xyz):
        self.name = name
        self.columns = columns
        self.xyz = xyz

    def __len__(self):
        return len(self.columns["name"])


def _hy36(value, width):
    """`value` in `width` columns, hybrid-36 (upper case) once it no longer fits in decimal."""
    if value < 10 ** width:
        return str(value).rjust(width)
    value -= 10 ** width
    value += 10 * 36 ** (width - 1)
    digits = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"
    text = ""
    while value:
        value, d = divmod(value, 36)
        text = digits[d] + text
    if len(text) > width:
        raise _fdmsurf.InvalidArgumentError(f"{value} does not fit in {width} PDB columns")
    return text


def _seq(value):
    """A residue number in the PDB's four columns (hybrid-36 above 9999; gemmi reads both)."""
    value = int(value)
    if value < -999:
        raise _fdmsurf.InvalidArgumentError(f"residue number {value} is below -999, which a "
                                            "PDB record cannot hold")
    return str(value).rjust(4) if value <= 9999 else _hy36(value, 4)


def _coordinate(v):
    # The reader needs numbers in columns 31-54; coordinates are replaced by the object's own
    # afterwards, so values that do not fit eight columns (or NaN) stand in as 0.
    return f"{v:8.3f}" if -999.0 < v < 9999.0 else "   0.000"


def pdb_text(topology):
    """The PDB text of a Topology's records. A 'ter' column (True after a polymer part) writes
    TER records, which the reader takes as the end of a polymer, as in the file read."""
    c = topology.columns
    xyz = np.asarray(topology.xyz, dtype=np.float64)
    n = len(topology)
    ter = c.get("ter")
    lines = []
    for i in range(n):
        name = c["name"][i]
        element = (c["element"][i] or "").strip().upper()
        if len(name) > 4 or len(c["residue_name"][i]) > 3 or len(c["chain"][i]) > 2:
            raise _fdmsurf.InvalidArgumentError(
                f"{topology.name}: atom {i + 1} ({c['chain'][i]}/{c['residue_name'][i]}/{name}) "
                "has a name longer than a PDB record holds (atom 4, residue 3, chain 2 "
                "characters)")
        # Atom names of one-letter elements start in column 14, as the PDB writes them.
        padded = name.ljust(4) if len(name) == 4 or len(element) == 2 else (" " + name).ljust(4)
        x, y, z = xyz[i]
        lines.append(
            f"{'HETATM' if c['hetero'][i] else 'ATOM  '}{_hy36(i + 1, 5)} {padded}"
            f"{(c['altloc'][i] or ' ')[:1]}{c['residue_name'][i]:>3}{c['chain'][i]:>2}"
            f"{_seq(c['residue_number'][i])}{(c['insertion_code'][i] or ' ')[:1]}   "
            f"{_coordinate(x)}{_coordinate(y)}{_coordinate(z)}"
            f"{float(c['occupancy'][i]):6.2f}{float(c['b_factor'][i]):6.2f}          "
            f"{element:>2}")
        if ter is not None and ter[i]:
            lines.append("TER")
    lines.append("END")
    return "\n".join(lines) + "\n"


def _columns(n):
    return {"name": [], "residue_name": [], "chain": [], "residue_number": [],
            "insertion_code": [], "altloc": [], "hetero": [], "element": [], "occupancy": [],
            "b_factor": [], "ter": [], "serial": []}


def _ordered(topology):
    """The records in the order of their serial numbers when the object kept them all, distinct
    (the file's order), else in the object's order."""
    serial = topology.columns.pop("serial")
    if len(serial) and all(s is not None for s in serial):
        s = np.asarray(serial, dtype=np.int64)
        if len(np.unique(s)) == len(s) and np.any(s[1:] < s[:-1]):
            order = np.argsort(s, kind="stable")
            topology.columns = {k: [v[i] for i in order] for k, v in topology.columns.items()}
            topology.xyz = np.asarray(topology.xyz)[order]
            topology.order = order
            return topology
    topology.order = None
    return topology


# --- gemmi -------------------------------------------------------------------------------------

def _gemmi_topology(obj, model):
    kind = type(obj).__name__
    if kind == "Structure":
        if model > len(obj):
            raise _fdmsurf.InvalidArgumentError(
                f"gemmi Structure: model {model} requested, but it has {len(obj)} model(s)")
        obj = obj[model - 1]
    elif kind != "Model":
        return None
    cols = _columns(0)
    xyz = []
    for chain in obj:
        residues = list(chain)
        for k, res in enumerate(residues):
            etype = str(res.entity_type).rsplit(".", 1)[-1]
            # TER after the last residue of a polymer part, as the reader of a file saw one.
            polymer = etype == "Polymer"
            last_of_polymer = polymer and (
                k + 1 == len(residues)
                or str(residues[k + 1].entity_type).rsplit(".", 1)[-1] != "Polymer")
            atoms = list(res)
            for j, atom in enumerate(atoms):
                cols["name"].append(atom.name)
                cols["residue_name"].append(res.name)
                cols["chain"].append(chain.name)
                cols["residue_number"].append(res.seqid.num)
                cols["insertion_code"].append(res.seqid.icode.strip())
                cols["altloc"].append(atom.altloc.strip("\0 "))
                cols["hetero"].append(res.het_flag == "H")
                cols["element"].append("" if atom.element.name == "X" else atom.element.name)
                cols["occupancy"].append(atom.occ)
                cols["b_factor"].append(atom.b_iso)
                cols["ter"].append(last_of_polymer and j + 1 == len(atoms))
                # gemmi's Python reader merges the parts of a chain (its HETATM records after
                # the other chains join the chain's polymer): the serials give the file's order.
                cols["serial"].append(atom.serial)
                xyz.append((atom.pos.x, atom.pos.y, atom.pos.z))
    return Topology(f"gemmi {kind}", cols, np.array(xyz, dtype=np.float64).reshape(-1, 3))


# --- Biopython ---------------------------------------------------------------------------------

def _bio_atoms(entity):
    """Every atom under a Biopython entity, each alternate location (and each residue of a
    point mutation) included, with its residue and chain."""
    for chain in ([entity] if entity.level == "C" else entity):
        residues = []
        for res in chain:
            residues.extend(res.disordered_get_list() if res.is_disordered() == 2 else [res])
        for res in residues:
            for atom in res:
                for a in (atom.disordered_get_list() if atom.is_disordered() else [atom]):
                    yield chain, res, a


def _bio_topology(obj, model):
    level = getattr(obj, "level", None)
    if level == "S":
        models = list(obj)
        if model > len(models):
            raise _fdmsurf.InvalidArgumentError(
                f"Biopython Structure: model {model} requested, but it has {len(models)} "
                "model(s)")
        obj = models[model - 1]
    elif level not in ("M", "C"):
        return None
    cols = _columns(0)
    xyz = []
    for chain, res, atom in _bio_atoms(obj):
        hetfield, number, icode = res.id
        cols["name"].append(atom.get_name())
        cols["residue_name"].append(res.get_resname().strip())
        cols["chain"].append(chain.id.strip())
        cols["residue_number"].append(number)
        cols["insertion_code"].append(icode.strip())
        cols["altloc"].append(atom.get_altloc().strip())
        cols["hetero"].append(hetfield.strip() != "")
        cols["element"].append("" if atom.element in (None, "X") else atom.element)
        cols["occupancy"].append(atom.get_occupancy() or 0.0)
        cols["b_factor"].append(atom.get_bfactor() or 0.0)
        cols["ter"].append(False)
        cols["serial"].append(atom.get_serial_number())
        xyz.append(atom.get_coord())
    return Topology(f"Biopython {type(obj).__name__}", cols,
                    np.array(xyz, dtype=np.float32).reshape(-1, 3))


# --- MDAnalysis --------------------------------------------------------------------------------

def _md_attribute(group, name):
    try:
        return getattr(group, name)
    except (AttributeError, ValueError):  # MDAnalysis' NoDataError is both
        return None


def _mda_topology(obj):
    kind = type(obj).__name__
    if kind == "Universe":
        group = obj.atoms
    elif kind in ("AtomGroup", "UpdatingAtomGroup"):
        group = obj
    else:
        return None
    n = len(group)
    names = list(group.names)
    resnames = list(group.resnames)
    resids = _md_attribute(group, "resnums")
    if resids is None:
        resids = group.resids
    chain = _md_attribute(group, "chainIDs")
    if chain is None:
        segids = _md_attribute(group, "segids")
        chain = [s if len(s) <= 2 else "" for s in segids] if segids is not None else [""] * n
    elements = _md_attribute(group, "elements")
    if elements is None or not any(elements):
        elements = _md_attribute(group, "types")  # guessed from the names by MDAnalysis
    records = _md_attribute(group, "record_types")
    hetero = ([r == "HETATM" for r in records] if records is not None
              else [r not in _POLYMER_RESIDUES for r in resnames])
    def column(attr, default):
        value = _md_attribute(group, attr)
        return list(value) if value is not None else [default] * n
    ids = _md_attribute(group, "ids")
    cols = {
        "name": names, "residue_name": resnames, "chain": [str(c).strip() for c in chain],
        "residue_number": [int(r) for r in resids],
        "insertion_code": [str(i).strip() for i in column("icodes", "")],
        "altloc": [str(a).strip() for a in column("altLocs", "")], "hetero": hetero,
        "element": [str(e).strip() for e in elements], "occupancy": column("occupancies", 1.0),
        "b_factor": column("tempfactors", 0.0), "ter": [False] * n,
        "serial": list(ids) if ids is not None else [None] * n,
    }
    return Topology(f"MDAnalysis {kind}", cols, group.positions)


# --- mdtraj ------------------------------------------------------------------------------------

def _mdtraj_topology(obj, frame):
    if type(obj).__name__ != "Trajectory":
        return None
    frame = 0 if frame is None else frame
    if not -obj.n_frames <= frame < obj.n_frames:
        raise _fdmsurf.InvalidArgumentError(
            f"mdtraj Trajectory: frame {frame} requested, but it has {obj.n_frames} frame(s)")
    cols = _columns(0)
    chain_letters = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789"
    for atom in obj.topology.atoms:
        res = atom.residue
        cols["name"].append(atom.name)
        cols["residue_name"].append(res.name)
        # mdtraj keeps no chain identifiers: chains are lettered in order, as its PDB writer does.
        cols["chain"].append(chain_letters[res.chain.index % len(chain_letters)])
        cols["residue_number"].append(res.resSeq)
        cols["insertion_code"].append("")
        cols["altloc"].append("")
        cols["hetero"].append(not (res.is_protein or res.name in _POLYMER_RESIDUES))
        element = atom.element
        cols["element"].append("" if element is None or element.symbol in ("VS", "")
                               else element.symbol)
        cols["occupancy"].append(1.0)
        cols["b_factor"].append(0.0)
        cols["ter"].append(False)
        cols["serial"].append(atom.serial)
    xyz = obj.xyz[frame] * np.float32(10.0)  # nm -> Å
    return Topology("mdtraj Trajectory", cols, xyz)


def topology_of(obj, model=1, frame=None):
    """The records of a supported object (gemmi, Biopython, MDAnalysis, mdtraj), or None when
    `obj` is none of theirs; a TypeError for one of their objects that fdmsurf does not take."""
    library = library_of(obj)
    if library is None:
        return None
    if library == "gemmi":
        topology = _gemmi_topology(obj, model)
    elif library == "Bio":
        topology = _bio_topology(obj, model)
    elif library == "MDAnalysis":
        topology = _mda_topology(obj)
    else:
        # A multi-model PDB read by mdtraj has a frame per model: model k is frame k - 1.
        topology = _mdtraj_topology(obj, model - 1 if frame is None else frame)
    if topology is None:
        raise TypeError(f"fdmsurf takes {SUPPORTED}; not a {type(obj).__module__}."
                        f"{type(obj).__name__}")
    if len(topology) == 0:
        raise _fdmsurf.EmptySelectionError(f"{topology.name}: no atoms")
    return _ordered(topology)


class Selected:
    """A Structure read from an object's records, and for each of its atoms the index of that
    atom in the object (`index`, into the object's own atom order)."""

    def __init__(self, structure, index):
        self.structure = structure
        self.index = index


def structure_of_object(obj, options, model=1, frame=None, name=None):
    """A Selected for a supported object (None for any other): the object's atoms read by
    fdmsurf's PDB reader with the selection options (waters, hydrogens, ligands, chains,
    select; `options` as _options.parse gives them), with the object's own coordinates."""
    topology = topology_of(obj, model, frame)
    if topology is None:
        return None
    text = pdb_text(topology)
    label = name or topology.name.replace(" ", "-") + ".pdb"
    structure = _fdmsurf._parse_structure(text, label, options)
    position = structure.serial.astype(np.int64) - 1   # record index, in the written order
    index = position if topology.order is None else topology.order[position]
    xyz = np.asarray(topology.xyz)[position]
    if not np.all(np.isfinite(xyz)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(xyz), axis=1))[0])
        raise _fdmsurf.InvalidArgumentError(
            f"{topology.name}: atom {int(index[bad]) + 1} has NaN or infinite coordinates")
    structure.xyz[:] = xyz
    return Selected(structure, index)
