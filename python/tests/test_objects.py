"""Structures held as gemmi, Biopython, MDAnalysis and mdtraj objects: the same atoms, radii and
metadata as fdmsurf's reader gives for the file they were read from, and the same meshes, byte
for byte where the coordinates are the same floats (python/fdmsurf/_objects.py)."""

import gzip
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import fdmsurf

warnings.filterwarnings("ignore", category=DeprecationWarning)


def plain_pdb(data, name, tmp_path):
    """A path to the uncompressed PDB file (Biopython and mdtraj do not read .gz)."""
    path = data / name
    if name.endswith(".gz"):
        out = tmp_path / name[:-3]
        out.write_bytes(gzip.open(path).read())
        return out
    return path


def read_gemmi(path):
    gemmi = pytest.importorskip("gemmi")
    return gemmi.read_structure(str(path))


def read_biopython(path):
    pdb = pytest.importorskip("Bio.PDB")
    return pdb.PDBParser(QUIET=True).get_structure("x", str(path))


def read_mdanalysis(path):
    mda = pytest.importorskip("MDAnalysis")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return mda.Universe(str(path))


def read_mdtraj(path):
    md = pytest.importorskip("mdtraj")
    return md.load(str(path))


READERS = {"gemmi": read_gemmi, "biopython": read_biopython, "mdanalysis": read_mdanalysis,
           "mdtraj": read_mdtraj}

# (file, read keywords): every selection rule of the reader (waters, hydrogens, ligands,
# alternate locations, chains, select, models).
CASES = [
    ("1crn.pdb", {}),
    ("4hhb.pdb.gz", {}),
    ("4hhb.pdb.gz", {"waters": True}),
    ("4hhb.pdb.gz", {"ligands": False, "chains": ["A", "C"]}),
    ("4hhb.pdb.gz", {"select": "(HEM)"}),
    ("3al1.pdb", {}),                      # alternate locations
    ("1d3z.pdb.gz", {"hydrogens": True, "model": 3}),
]


def metadata(s):
    return (list(s.chain), list(s.residue_name), list(s.residue_number), list(s.name),
            list(s.element), list(s.insertion_code))


def assert_same_atoms(got, want, exact_xyz=True):
    assert len(got) == len(want)
    if exact_xyz:
        assert metadata(got) == metadata(want)
    else:
        # mdtraj keeps no chain ids (its chains, its ligands' too, are lettered in order) and
        # gives atoms its own standard names (H for H1...): the rest is the file's.
        assert [metadata(got)[k] for k in (1, 2, 4, 5)] == [metadata(want)[k]
                                                            for k in (1, 2, 4, 5)]
    assert np.array_equal(got.radii, want.radii)
    if exact_xyz:
        assert np.array_equal(got.xyz, want.xyz)
    else:  # nm in float32 and back: within a few ulps of the file's numbers
        assert np.abs(got.xyz - want.xyz).max() < 1e-4


@pytest.mark.parametrize("library,name,keywords", [
    (library, name, keywords) for library in sorted(READERS) for name, keywords in CASES
    if not (library == "mdtraj" and "chains" in keywords)])   # no chain ids in mdtraj
def test_object_gives_the_readers_atoms(library, name, keywords, data, tmp_path):
    keywords = dict(keywords)
    model = keywords.get("model", 1)
    path = plain_pdb(data, name, tmp_path)
    want = fdmsurf.read_structure(data / name, **keywords)
    obj = READERS[library](path)
    if library == "mdanalysis" and model != 1:
        obj.trajectory[model - 1]          # the Universe's current frame is the model
        keywords.pop("model")
    got = fdmsurf.as_structure(obj, **keywords)
    assert_same_atoms(got, want, exact_xyz=library != "mdtraj")
    assert got.info["waters_skipped"] == want.info["waters_skipped"]
    assert got.info["altlocs_skipped"] == want.info["altlocs_skipped"] or library == "mdtraj"
    # Each kept atom's serial is its 1-based position in the object.
    assert got.serial.min() >= 1


@pytest.mark.parametrize("library", sorted(READERS))
def test_object_surface_is_the_files_byte_for_byte(library, engine, data, tmp_path):
    path = plain_pdb(data, "4hhb.pdb.gz", tmp_path)
    options = {"spacing": 1.0}
    want = engine.surface(data / "4hhb.pdb.gz", **options)
    got = engine.surface(READERS[library](path), **options)
    if library == "mdtraj":  # coordinates through nm: the same surface, not the same floats
        assert got.area == pytest.approx(want.area, rel=1e-4)
        assert got.volume == pytest.approx(want.volume, rel=1e-4)
        return
    assert np.array_equal(got.vertices, want.vertices)
    assert np.array_equal(got.faces, want.faces)
    assert np.array_equal(got.atoms, want.atoms)
    want.write(tmp_path / "file.ply")
    got.write(tmp_path / "object.ply")
    assert (tmp_path / "file.ply").read_bytes() == (tmp_path / "object.ply").read_bytes()


def test_gemmi_model_and_biopython_chain(data, tmp_path):
    gemmi = pytest.importorskip("gemmi")
    st = gemmi.read_structure(str(data / "1d3z.pdb.gz"))
    want = fdmsurf.read_structure(data / "1d3z.pdb.gz", model=4)
    assert_same_atoms(fdmsurf.as_structure(st[3]), want)
    assert_same_atoms(fdmsurf.as_structure(st, model=4), want)
    bio = read_biopython(plain_pdb(data, "4hhb.pdb.gz", tmp_path))
    want = fdmsurf.read_structure(data / "4hhb.pdb.gz", chains=["B"])
    assert_same_atoms(fdmsurf.as_structure(bio[0]["B"]), want)
    with pytest.raises(fdmsurf.InvalidArgumentError, match="model 11 requested"):
        fdmsurf.as_structure(st, model=11)


def test_mdtraj_frame_is_the_model(data, tmp_path):
    traj = read_mdtraj(plain_pdb(data, "1d3z.pdb.gz", tmp_path))
    want = fdmsurf.read_structure(data / "1d3z.pdb.gz", model=5, hydrogens=True)
    assert_same_atoms(fdmsurf.as_structure(traj, model=5, hydrogens=True), want, exact_xyz=False)
    assert_same_atoms(fdmsurf.as_structure(traj[4], hydrogens=True), want, exact_xyz=False)


def test_areas_take_objects(data):
    st = read_gemmi(data / "1crn.pdb")
    structure = fdmsurf.read_structure(data / "1crn.pdb")
    assert np.array_equal(fdmsurf.exact_areas(st), fdmsurf.exact_areas(structure))
    assert np.array_equal(fdmsurf.sas_areas(st, points=200), fdmsurf.sas_areas(structure,
                                                                               points=200))


def test_exact_areas_agree_with_sampled(data):
    structure = fdmsurf.read_structure(data / "1crn.pdb")
    exact = fdmsurf.exact_areas(structure)
    sampled = fdmsurf.sas_areas(structure, points=4000)
    assert exact.sum() == pytest.approx(sampled.sum(), rel=2e-3)
    assert np.abs(exact - sampled).max() < 2.0   # Å² per atom


def test_unsupported_objects_are_type_errors(data):
    gemmi = pytest.importorskip("gemmi")
    st = gemmi.read_structure(str(data / "1crn.pdb"))
    with pytest.raises(TypeError, match="gemmi Structure or Model.*mdtraj Trajectory"):
        fdmsurf.surface(st[0]["A"][0])       # a gemmi Residue
    with pytest.raises(TypeError, match="MDAnalysis Universe"):
        fdmsurf.surface(object())
    with pytest.raises(TypeError, match="radii come from the elements"):
        fdmsurf.surface(st, radii=np.ones(327))
    with pytest.raises(fdmsurf.InvalidArgumentError, match="assembly"):
        fdmsurf.as_structure(st, assembly=1)


def test_empty_selection_is_an_error(data):
    st = read_gemmi(data / "1crn.pdb")
    with pytest.raises(fdmsurf.EmptySelectionError, match="no atoms left"):
        fdmsurf.as_structure(st, select="(HOH)")


def test_libraries_are_imported_only_for_their_objects(data):
    # A surface from arrays and a file imports none of the four libraries.
    code = ("import sys, numpy as np, fdmsurf\n"
            "s = fdmsurf.read_structure(sys.argv[1])\n"
            "fdmsurf.as_structure(s); fdmsurf.exact_areas(s)\n"
            "try:\n    fdmsurf.as_structure(object())\nexcept TypeError:\n    pass\n"
            "bad = [m for m in ('gemmi', 'Bio', 'MDAnalysis', 'mdtraj') if m in sys.modules]\n"
            "print(','.join(bad))\n")
    done = subprocess.run([sys.executable, "-c", code, str(data / "1crn.pdb")],
                          capture_output=True, encoding="utf-8", env=dict(os.environ))
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == ""


def test_nan_coordinates_in_an_object(data):
    u = read_mdanalysis(data / "1crn.pdb")
    xyz = u.atoms.positions
    xyz[5, 2] = np.nan
    u.atoms.positions = xyz
    with pytest.raises(fdmsurf.InvalidArgumentError, match="atom 6 has NaN"):
        fdmsurf.as_structure(u)
