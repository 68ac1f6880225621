"""Bad input raises clear exceptions: fdmsurf.Error subclasses with the CLI's messages, TypeError
for wrong types and unknown keywords."""

import os

import numpy as np
import pytest

import fdmsurf


def test_error_classes():
    assert issubclass(fdmsurf.InvalidArgumentError, fdmsurf.Error)
    assert issubclass(fdmsurf.InvalidArgumentError, ValueError)
    for cls in (fdmsurf.FileError, fdmsurf.FormatError, fdmsurf.EmptySelectionError):
        assert issubclass(cls, fdmsurf.InputError)
    assert issubclass(fdmsurf.FileError, OSError)
    for cls in (fdmsurf.NoDeviceError, fdmsurf.DeviceLimitError, fdmsurf.VulkanError,
                fdmsurf.FftError):
        assert issubclass(cls, fdmsurf.DeviceError)
    assert fdmsurf.FileError.__module__ == "fdmsurf"
    assert fdmsurf.FormatError.code == "format"


@pytest.mark.parametrize("xyz,radii,message", [
    (np.zeros((3, 2)), np.ones(3), r"xyz must have shape \(N, 3\), not \(3, 2\)"),
    (np.zeros(3), np.ones(1), r"xyz must have shape \(N, 3\), not \(3,\)"),
    (np.zeros((3, 3)), np.ones((3, 1)), r"radii must have shape \(N,\), not \(3, 1\)"),
    (np.zeros((3, 3)), np.ones(2), "xyz has 3 atoms but radii 2"),
    ([[0, 0, 0], [1, np.nan, 0]], [1, 1], r"xyz\[1\] is not finite"),
    ([[0, 0, 0], [1, np.inf, 0]], [1, 1], r"xyz\[1\] is not finite"),
    ([[0, 0, 0], [3, 0, 0]], [1.5, -1.0], r"radii\[1\] is -1.0+: radii must be positive"),
    ([[0, 0, 0], [3, 0, 0]], [1.5, 0.0], r"radii\[1\] is 0.0+: radii must be positive"),
])
def test_bad_arrays(xyz, radii, message):
    with pytest.raises(fdmsurf.InvalidArgumentError, match=message):
        fdmsurf.Structure(xyz, radii)


def test_bad_array_types(engine):
    with pytest.raises(TypeError, match="xyz must hold real numbers, not dtype complex128"):
        fdmsurf.Structure(np.zeros((2, 3), dtype=complex), np.ones(2))
    with pytest.raises(TypeError, match="radii must hold real numbers, not dtype <U1"):
        fdmsurf.Structure(np.zeros((2, 3)), np.array(["a", "b"]))
    with pytest.raises(TypeError, match="xyz must hold real numbers, not dtype bool"):
        fdmsurf.Structure(np.zeros((2, 3), dtype=bool), np.ones(2))
    with pytest.raises(TypeError, match="with radii="):
        engine.surface(np.zeros((2, 3)))
    with pytest.raises(TypeError, match="radii goes with an xyz array"):
        engine.surface("x.pdb", radii=np.ones(2))
    with pytest.raises(fdmsurf.InvalidArgumentError, match=r"xyz\[0\] is not finite"):
        engine.surface(np.full((1, 3), np.nan), radii=[1.0])
    with pytest.raises(fdmsurf.EmptySelectionError, match="no atoms"):
        engine.surface(np.zeros((0, 3)), radii=np.zeros(0))


def test_unknown_keywords_name_the_nearest(engine, data):
    with pytest.raises(TypeError, match=r"unknown keyword 'spacng' \(did you mean spacing\?\)"):
        engine.surface(data / "1crn.pdb", spacng=1.0)
    with pytest.raises(TypeError, match="unknown keyword 'model'"):
        engine.surface_models(data / "1d3z.pdb.gz", model=2)
    with pytest.raises(TypeError, match="unknown keyword 'spacing'"):
        fdmsurf.read_structure(data / "1crn.pdb", spacing=1.0)
    with pytest.raises(TypeError, match="unknown keyword 'colour'"):
        fdmsurf.surface(data / "1crn.pdb", colour="chain")


@pytest.mark.parametrize("keywords,error,message", [
    ({"spacing": -1}, fdmsurf.InvalidArgumentError, r"spacing must be > 0 Å \(got -1.0\)"),
    ({"spacing": "0.5"}, TypeError, "spacing must be a number, not str"),
    ({"spacing": True}, TypeError, "spacing must be a number, not bool"),
    ({"refine": 1.5}, TypeError, "refine must be a whole number, not float"),
    ({"refine": 9}, fdmsurf.InvalidArgumentError, "refine must be"),
    ({"probe": -0.5}, fdmsurf.InvalidArgumentError, "probe must be >= 0"),
    ({"surface": "ses2"}, fdmsurf.InvalidArgumentError,
     r"unknown surface kind 'ses2' for surface \(expected ses, vdw or sas\)"),
    ({"method": "edt", "cutoff": 0.2}, fdmsurf.InvalidArgumentError,
     "cutoff is a setting of the FDM method"),
    ({"method": "edt", "surface": "vdw"}, fdmsurf.InvalidArgumentError,
     "it does not apply to surface vdw"),
    ({"properties": ["coulombic", "nope"]}, fdmsurf.InvalidArgumentError,
     "unknown vertex property 'nope' for properties"),
    ({"properties": 3}, TypeError, "properties must be a list of str"),
    ({"color": "pink"}, fdmsurf.InvalidArgumentError, "unknown colour scheme 'pink' for color"),
    ({"color": (300, 0, 0)}, TypeError, "an .r, g, b. tuple of whole numbers 0-255"),
    ({"model": 0}, fdmsurf.InvalidArgumentError, "model must be >= 1"),
    ({"chains": ["A B"]}, fdmsurf.InvalidArgumentError, "is not a comma-separated list"),
    ({"select": "A/(("}, fdmsurf.InvalidArgumentError, "select"),
    ({"patch": "A/(("}, fdmsurf.InvalidArgumentError, "patch"),
    ({"no_cavities": "yes"}, TypeError, "no_cavities must be True or False"),
    ({"density_cut": 2.0}, fdmsurf.InvalidArgumentError, r"density_cut must be in \(0, 1\)"),
    ({"min_grid": (1, 2)}, TypeError, "min_grid must be three whole numbers"),
    ({"simplify": 0}, fdmsurf.InvalidArgumentError,
     r"simplify must be the fraction of the triangles to keep, in \(0, 1\]"),
    ({"simplify": 1.5}, fdmsurf.InvalidArgumentError, "simplify must be"),
    ({"max_triangles": 0}, fdmsurf.InvalidArgumentError, "max_triangles must be a whole number"),
    ({"max_triangles": 10.5}, TypeError, "max_triangles must be a whole number, not float"),
    ({"optimize": "yes"}, TypeError, "optimize must be True or False"),
    ({"snap": "no"}, TypeError, "snap must be True or False"),
    ({"chord_tolerance": -0.1}, fdmsurf.InvalidArgumentError,
     r"chord_tolerance must be >= 0 Å \(got -0.1\)"),
])
def test_bad_options(engine, data, keywords, error, message):
    with pytest.raises(error, match=message):
        engine.surface(data / "1crn.pdb", **keywords)


def test_read_options_need_a_file(engine):
    with pytest.raises(fdmsurf.InvalidArgumentError, match="chains, model select atoms while "
                                                           "reading a file"):
        engine.surface(np.zeros((1, 3)), radii=[1.0], model=2, chains="A")


def test_file_errors_carry_the_cli_messages(engine, cli, data, tmp_path):
    missing = tmp_path / "missing.pdb"
    with pytest.raises(fdmsurf.FileError) as caught:
        engine.surface(missing)
    done = cli(missing, "-o", tmp_path / "x.ply", check=False)
    assert done.returncode == 3
    assert done.stderr.strip() == f"fdmsurf: error: {caught.value}"
    assert str(missing) in str(caught.value)
    assert caught.value.code == "io" and caught.value.vk_result == 0
    assert isinstance(caught.value, OSError) and isinstance(caught.value, fdmsurf.InputError)

    garbage = tmp_path / "garbage.pdb"
    garbage.write_text("this is not a structure\n")
    with pytest.raises(fdmsurf.FormatError) as caught:
        fdmsurf.read_structure(garbage)
    done = cli(garbage, "-o", tmp_path / "x.ply", check=False)
    assert done.stderr.strip() == f"fdmsurf: error: {caught.value}"

    with pytest.raises(fdmsurf.InvalidArgumentError) as caught:
        engine.surface(data / "3al1.pdb", chains=["Z"])
    done = cli(data / "3al1.pdb", "-o", tmp_path / "x.ply", "--chains", "Z", check=False)
    assert done.stderr.strip() == f"fdmsurf: error: {caught.value}"
    assert "A" in str(caught.value)  # lists the chains present

    with pytest.raises(fdmsurf.EmptySelectionError, match="patch 'B/1' matches none"):
        engine.surface(data / "1crn.pdb", patch="B/1")


def test_write_errors(engine, data, tmp_path):
    result = engine.surface(data / "1crn.pdb", spacing=1.0)
    # .stl, .off and .glb are formats too (test_api.py writes them); .xyz is none.
    with pytest.raises(fdmsurf.InvalidArgumentError, match=r"unknown output format '.xyz'"):
        result.write(tmp_path / "mesh.xyz")
    with pytest.raises(fdmsurf.InvalidArgumentError, match="unknown mesh format 'xyz' "
                                                           r"\(expected 'ply', 'obj', 'glb'"):
        result.write(tmp_path / "mesh.ply", format="xyz")
    with pytest.raises(fdmsurf.FileError, match="cannot write"):
        result.write(tmp_path / "no" / "such" / "folder.ply")
    assert list(tmp_path.iterdir()) == []


def test_engine_errors(data):
    with pytest.raises(fdmsurf.NoDeviceError) as caught:
        fdmsurf.Engine(device="no such device")
    assert isinstance(caught.value, fdmsurf.DeviceError)
    with pytest.raises(TypeError, match="device must be"):
        fdmsurf.Engine(device=1.5)
    engine = fdmsurf.Engine()
    engine.close()
    assert engine.closed and "closed" in repr(engine)
    with pytest.raises(fdmsurf.InvalidArgumentError, match="this Engine was closed"):
        engine.surface(data / "1crn.pdb")


def test_paths_with_nul_or_bytes_that_are_not_utf8(engine, data, tmp_path):
    # A NUL inside a path is refused as open() refuses it: the name cut short there would read
    # or replace another file.
    for call in (lambda: fdmsurf.read_structure(f"{data / '1crn.pdb'}\0.xyzr"),
                 lambda: engine.surface(f"{data / '1crn.pdb'}\0x", spacing=1.0),
                 lambda: fdmsurf.read_mesh(f"{data / '1crn-fdm-0.5.ply'}\0zz")):
        with pytest.raises(ValueError, match="embedded null byte"):
            call()
    r = engine.surface(data / "1crn.pdb", spacing=1.0)
    with pytest.raises(ValueError, match="embedded null byte"):
        r.write(str(tmp_path / "a\0b.ply"))
    assert os.listdir(tmp_path) == []
    # A file name that is not UTF-8, as bytes or as os.fsdecode's str: read, written, named in
    # warnings and errors with U+FFFD.
    odd = tmp_path / os.fsdecode(b"\xff.xyzr")
    odd.write_text("0 0 0 1.5\n3 0 0 0\n")
    for path in (os.fsencode(odd), odd, str(odd)):
        s = fdmsurf.read_structure(path)
        assert len(s) == 1 and "\ufffd.xyzr" in s.info["warnings"][0]
    r = engine.surface(os.fsencode(odd), spacing=0.5)
    for path in (os.fsencode(tmp_path / os.fsdecode(b"\xfe.ply")),
                 str(tmp_path / os.fsdecode(b"\xfd.ply"))):
        r.write(path)
        assert fdmsurf.read_mesh(path).triangle_count == r.triangle_count
    with pytest.raises(fdmsurf.FileError, match="\ufffd"):
        fdmsurf.read_mesh(os.fsencode(tmp_path / os.fsdecode(b"\xfc.ply")))


def test_wrong_types_are_type_errors_and_bad_atoms_value_errors(engine, data, tmp_path):
    r = engine.surface(data / "1crn.pdb", spacing=1.0, no_cavities=np.True_)  # numpy's bool
    with pytest.raises(TypeError, match="format must be a str"):
        r.write(str(tmp_path / "y.ply"), format=1)
    with pytest.raises(TypeError, match="element must hold element symbols"):
        fdmsurf.Structure(np.zeros((2, 3)), np.ones(2), element=[1, 2])
    assert list(fdmsurf.Structure(np.zeros((2, 3)), np.ones(2),
                                  element=np.array([b"C", b"n"])).element) == ["C", "N"]
    with pytest.raises(TypeError, match="no_cavities must be True or False"):
        engine.surface(data / "1crn.pdb", spacing=1.0, no_cavities=2)
    with pytest.raises(fdmsurf.InvalidArgumentError, match="below 2\\*\\*32"):
        engine.surface(data / "1crn.pdb", spacing=1.0, min_grid=(2**32, 1, 1))
    s = fdmsurf.read_structure(data / "1crn.pdb")
    s.xyz[1, 2] = np.nan
    with pytest.raises(fdmsurf.InvalidArgumentError, match="atom 2 has a non-finite coordinate"):
        fdmsurf.sas_areas(s)
    assert os.listdir(tmp_path) == []


def test_fdm_settings_at_their_defaults_go_with_the_exact_ses(engine, data):
    # Every keyword at its default, as a config file might list them, works with method="edt";
    # another value is still refused, as by the CLI.
    r = engine.surface(data / "1crn.pdb", spacing=1.0, method="edt", sigma=3.0, cutoff=0.0,
                       filter="gaussian", level=None)
    assert r.triangle_count > 0
    assert fdmsurf.plan_grid(data / "1crn.pdb", method="EDT", sigma=3.0)["dims"]  # any case
    with pytest.raises(fdmsurf.InvalidArgumentError, match="sigma"):
        engine.surface(data / "1crn.pdb", spacing=1.0, method="edt", sigma=2.0)
