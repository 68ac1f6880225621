"""fdmsurf's Python API: the same meshes as the CLI, arrays without copies, structures, options."""

import gc
import inspect
import math
import re

import numpy as np
import pytest

import fdmsurf

# (input, keywords, the CLI's options): each must give the CLI's mesh, byte for byte.
CASES = [
    ("1crn.pdb", {}, []),
    ("1crn.cif", {"surface": "vdw"}, ["--surface", "vdw"]),
    ("1crn.xyzrn", {"color": "hydrophobicity", "no_cavities": True},
     ["--color", "hydrophobicity", "--no-cavities"]),
    ("3al1.pdb", {"chains": ["A"], "color": "chain", "spacing": 0.7},
     ["--chains", "A", "--color", "chain", "--spacing", "0.7"]),
    ("3al1.pdb", {"patch": "A", "color": (255, 0, 128)},
     ["--patch", "A", "--color", "#ff0080"]),
    ("4hhb.pdb.gz", {"spacing": 1.0, "color": "coulombic",
                     "properties": ["coulombic", "shape_index", "bfactor"]},
     ["--spacing", "1.0", "--color", "coulombic", "--properties",
      "coulombic,shape_index,bfactor"]),
    ("1d3z.pdb.gz", {"model": 2, "hydrogens": True, "paper": True, "level": 1.1,
                     "spacing": 0.8},
     ["--model", "2", "--hydrogens", "--paper", "--level", "1.1", "--spacing", "0.8"]),
    ("1crn.pdb", {"method": "edt", "refine": 1, "spacing": 1.0},
     ["--method", "edt", "--refine", "1", "--spacing", "1.0"]),
    ("4hhb.pdb.gz", {"surface": "sas", "probe": 1.2, "spacing": 1.0, "ligands": False},
     ["--surface", "sas", "--probe", "1.2", "--spacing", "1.0", "--no-ligands"]),
    ("1crn.pdb", {"surface": "vdw", "snap": False, "spacing": 0.7},
     ["--surface", "vdw", "--no-snap", "--spacing", "0.7"]),
    ("1crn.pdb", {"surface": "sas", "chord_tolerance": 0.05},
     ["--surface", "sas", "--chord-tolerance", "0.05"]),
    ("3al1.pdb", {"simplify": 0.3, "max_triangles": 20000, "optimize": True, "color": "chain",
                  "properties": ["bfactor"]},
     ["--simplify", "0.3", "--max-triangles", "20000", "--optimize", "--color", "chain",
      "--properties", "bfactor"]),
]


@pytest.mark.parametrize("name,keywords,options", CASES,
                         ids=[f"{c[0]}-{'-'.join(c[1]) or 'default'}" for c in CASES])
def test_surface_is_the_cli_mesh(engine, cli, data, tmp_path, name, keywords, options):
    cli(data / name, "-o", tmp_path / "cli.ply", "--quiet", *options)
    result = engine.surface(data / name, **keywords)
    result.write(tmp_path / "api.ply")
    assert (tmp_path / "api.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    # The arrays are the mesh written.
    back = fdmsurf.read_mesh(tmp_path / "cli.ply")
    np.testing.assert_array_equal(result.vertices, back.vertices)
    np.testing.assert_array_equal(result.normals, back.normals)
    np.testing.assert_array_equal(result.faces, back.faces)
    np.testing.assert_array_equal(result.atoms, back.atoms)
    if "color" in keywords:
        np.testing.assert_array_equal(result.colors, back.colors)
    else:
        assert result.colors is None
    assert list(result.properties) == list(back.properties)
    for key, values in result.properties.items():
        np.testing.assert_array_equal(values, back.properties[key])


def test_obj_is_the_cli_obj(engine, cli, data, tmp_path):
    cli(data / "1crn.pdb", "-o", tmp_path / "cli.obj", "--quiet", "--color", "element")
    engine.surface(data / "1crn.pdb", color="element").write(tmp_path / "api.obj")
    assert (tmp_path / "api.obj").read_text() == (tmp_path / "cli.obj").read_text()
    engine.surface(data / "1crn.pdb", color="element").write(tmp_path / "api.txt", format="obj")
    assert (tmp_path / "api.txt").read_text() == (tmp_path / "cli.obj").read_text()


@pytest.mark.parametrize("extension", ["glb", "stl", "off"])
def test_other_formats_are_the_cli_files(engine, cli, data, tmp_path, extension):
    cli(data / "1crn.pdb", "-o", tmp_path / f"cli.{extension}", "--quiet", "--spacing", "1.0",
        "--color", "element")
    result = engine.surface(data / "1crn.pdb", spacing=1.0, color="element")
    result.write(tmp_path / f"api.{extension}")
    expected = (tmp_path / f"cli.{extension}").read_bytes()
    assert (tmp_path / f"api.{extension}").read_bytes() == expected
    result.write(tmp_path / "api.mesh", format=extension)  # the CLI's --output-format names
    assert (tmp_path / "api.mesh").read_bytes() == expected
    back = fdmsurf.read_mesh(tmp_path / f"api.{extension}")
    assert back.triangle_count == result.triangle_count
    assert back.area == pytest.approx(result.area, rel=1e-5)


def test_simplify_and_optimize_change_the_mesh(engine, data):
    full = engine.surface(data / "1crn.pdb")
    assert full.simplify is None and not full.optimized
    half = engine.surface(data / "1crn.pdb", simplify=0.5)
    report = half.simplify
    assert report["triangles_in"] == full.triangle_count and report["ratio"] == 0.5
    assert report["target_triangles"] == round(full.triangle_count / 2)
    assert half.triangle_count == report["triangles_out"]
    # About half (the closedness guard may keep a few more), still closed, same pieces.
    assert 0.5 <= half.triangle_count / full.triangle_count < 0.55
    assert half.closed_manifold and half.pieces == full.pieces and report["topology_kept"]
    assert half.area == pytest.approx(full.area, rel=0.01)
    assert half.volume == pytest.approx(full.volume, rel=0.01)
    assert 0 < report["rmsd"] < report["hausdorff"] < 0.5
    assert "simplify" in half.times and not half.warnings
    # Vertices are a subset of the full mesh's, each with its atom.
    full_atoms = {tuple(v): a for v, a in zip(full.vertices.tolist(), full.atoms.tolist())}
    assert all(full_atoms[tuple(v)] == a
               for v, a in zip(half.vertices.tolist(), half.atoms.tolist()))

    capped = engine.surface(data / "1crn.pdb", max_triangles=4000)
    assert capped.simplify["target_triangles"] == 4000 and capped.simplify["ratio"] == 1.0
    assert 4000 <= capped.triangle_count < 4400 and capped.closed_manifold
    both = engine.surface(data / "1crn.pdb", simplify=0.5, max_triangles=4000)
    assert both.simplify["target_triangles"] == 4000  # the smaller target
    # A target no collapse can reach: as far as it goes, with the CLI's warning saying why.
    one = engine.surface(data / "1crn.pdb", max_triangles=1)
    assert one.simplify["target_triangles"] == 1 and one.closed_manifold
    assert any("for a target of 1: every collapse left" in w for w in one.warnings), one.warnings

    # optimize: the same triangles (each corner order kept up to rotation), in another order.
    ordered = engine.surface(data / "1crn.pdb", optimize=True)
    assert ordered.optimized and ordered.simplify is None and "optimize" in ordered.times
    assert ordered.triangle_count == full.triangle_count
    assert not np.array_equal(ordered.faces, full.faces)

    def triangles(mesh):
        corners = mesh.vertices[mesh.faces].tolist()
        out = []
        for t in corners:
            first = min(range(3), key=lambda i: t[i])
            out.append(tuple(tuple(t[(first + i) % 3]) for i in range(3)))
        return sorted(out)
    assert triangles(ordered) == triangles(full)


def test_summary_matches_the_cli_json(engine, cli, data, tmp_path):
    import json
    done = cli(data / "1crn.pdb", "-o", tmp_path / "cli.ply", "--stats", "json")
    summary = json.loads(done.stdout)
    result = engine.surface(data / "1crn.pdb")
    assert result.vertex_count == summary["vertices"]
    assert result.triangle_count == summary["triangles"]
    assert result.pieces == summary["pieces"]
    assert result.closed_manifold == summary["closed_manifold"]
    assert result.area == pytest.approx(summary["area"], rel=1e-9)
    assert result.volume == pytest.approx(summary["volume"], rel=1e-9)
    assert list(result.grid["dims"]) == summary["grid"]["dims"]
    assert result.grid["spacing"] == pytest.approx(summary["grid"]["spacing"])
    assert result.device == summary["device"]
    assert set(result.times) <= set(summary["times"])


def test_every_model_is_the_cli_mesh(engine, cli, data, tmp_path):
    cli(data / "1d3z.pdb.gz", "--models", "all", "-o", f"{tmp_path}/", "--quiet",
        "--spacing", "1.0")
    results = engine.surface_models(data / "1d3z.pdb.gz", spacing=1.0)
    assert len(results) == 10
    assert len({tuple(r.grid["dims"]) for r in results}) == 1  # one grid, one FFT plan
    for model, result in enumerate(results, start=1):
        assert result.structure.info["model"] == model
        result.write(tmp_path / "api.ply")
        expected = (tmp_path / f"1d3z-m{model}.ply").read_bytes()
        assert (tmp_path / "api.ply").read_bytes() == expected


def test_arrays_share_the_mesh_memory_and_outlive_the_result(engine, data):
    result = engine.surface(data / "1crn.pdb", color="chain", properties=["mean_curvature"])
    v = result.vertices
    assert v.dtype == np.float32 and v.shape == (result.vertex_count, 3)
    assert result.normals.dtype == np.float32 and result.normals.shape == v.shape
    assert result.faces.dtype == np.uint32 and result.faces.shape == (result.triangle_count, 3)
    assert result.atoms.dtype == np.uint32 and result.atoms.shape == (result.vertex_count,)
    assert result.colors.dtype == np.uint8 and result.colors.shape == v.shape
    curvature = result.properties["mean_curvature"]
    assert curvature.dtype == np.float32 and curvature.shape == (result.vertex_count,)
    for array in (v, result.faces, result.atoms, result.colors, curvature):
        assert array.flags.c_contiguous
        assert type(array.base).__name__ == "PyCapsule"  # over the mesh's memory, not a copy
    # Two reads of an array are two views of the same memory: no copy of the mesh is made.
    assert np.shares_memory(result.vertices, v)
    assert result.vertices.__array_interface__["data"] == v.__array_interface__["data"]
    expected = (v.copy(), result.faces.copy(), curvature.copy())
    faces = result.faces
    del result
    gc.collect()
    np.testing.assert_array_equal(v, expected[0])
    np.testing.assert_array_equal(faces, expected[1])
    np.testing.assert_array_equal(curvature, expected[2])


def test_write_writes_the_arrays_as_edited(engine, data, tmp_path):
    result = engine.surface(data / "1crn.pdb", spacing=1.0)
    result.vertices[:] += np.float32(10.0)
    result.write(tmp_path / "moved.ply")
    moved = fdmsurf.read_mesh(tmp_path / "moved.ply")
    np.testing.assert_array_equal(moved.vertices, result.vertices)


def test_sources_path_structure_and_arrays_agree(engine, data):
    from_path = engine.surface(data / "1crn.pdb")
    structure = fdmsurf.read_structure(data / "1crn.pdb")
    from_structure = engine.surface(structure)
    from_arrays = engine.surface(structure.xyz, radii=structure.radii)
    from_tuple = engine.surface((structure.xyz.astype(np.float64), structure.radii))
    for other in (from_structure, from_arrays, from_tuple):
        np.testing.assert_array_equal(other.vertices, from_path.vertices)
        np.testing.assert_array_equal(other.faces, from_path.faces)
    assert len(from_arrays.structure) == 327 and from_arrays.structure.chain is None


def test_one_atom_is_a_sphere(engine):
    xyz = np.zeros((1, 3))
    result = engine.surface(xyz, radii=[2.0], surface="vdw", spacing=0.25)
    assert result.closed_manifold and result.pieces == 1
    assert result.area == pytest.approx(4 * math.pi * 4.0, rel=0.02)
    assert result.volume == pytest.approx(4 / 3 * math.pi * 8.0, rel=0.02)
    radius = np.linalg.norm(result.vertices, axis=1)
    assert np.all(np.abs(radius - 2.0) < 0.05)
    assert np.all(result.atoms == 0)


def test_snap_and_chord_tolerance_change_the_mesh(engine):
    # Two balls of 1.5 Å, 2 Å apart: a union whose area is known (two spheres less two caps of
    # height 0.5 Å) and whose crease is the circle where the spheres meet.
    xyz = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    radii = [1.5, 1.5]
    exact = 2 * (4 * math.pi * 1.5**2 - 2 * math.pi * 1.5 * 0.5)
    snapped = engine.surface(xyz, radii=radii, surface="vdw")
    plain = engine.surface(xyz, radii=radii, surface="vdw", snap=False)
    creases = engine.surface(xyz, radii=radii, surface="vdw", chord_tolerance=0)
    for mesh in (snapped, plain, creases):
        assert mesh.closed_manifold and mesh.pieces == 1
    assert "snap" in snapped.times and "snap" not in plain.times

    def distances(mesh):  # of each vertex to each sphere, Å
        return np.abs(np.linalg.norm(mesh.vertices[:, None, :] - xyz[None], axis=2) - 1.5)

    def on_the_crease(mesh):  # vertices on both spheres
        return int(np.sum(np.all(distances(mesh) < 1e-5, axis=1)))
    for mesh in (snapped, creases):
        assert distances(mesh).min(axis=1).max() < 1e-5  # every vertex on its ball
    # Crease vertices placed on the circle (marching cubes hits it only by chance: 4 here).
    assert on_the_crease(snapped) >= 20 and on_the_crease(creases) >= 20
    assert on_the_crease(plain) < on_the_crease(creases)
    # Chords split to spacing / 50: 0.25% short of the union's area, marching cubes 2.8%.
    assert snapped.area == pytest.approx(exact, rel=0.005)
    assert plain.area < 0.98 * exact and creases.area < 0.98 * exact
    assert snapped.triangle_count > creases.triangle_count > plain.triangle_count


def test_result_describes_the_run(engine, data):
    result = engine.surface(data / "1crn.pdb", spacing=1.0)
    assert set(result.grid) == {"dims", "spacing", "origin", "cutoff", "slabs", "host_filter",
                                "host_density", "host_marching_cubes", "host_ses_distance"}
    # On a CPU device the density, the filter and marching cubes run on the host.
    cpu = engine.device["type"] == "CPU"
    assert result.grid["host_filter"] is cpu and result.grid["host_density"] is cpu
    assert result.grid["host_marching_cubes"] is cpu
    assert result.grid["host_ses_distance"] is False  # the FDM surface
    assert result.grid["spacing"] == 1.0 and result.grid["cutoff"] == pytest.approx(0.232, 1e-2)
    assert ("density-host" if cpu else "density") in result.times
    assert all(ms >= 0 for ms in result.times.values())
    density = "density-host" if cpu else "density"
    assert (density, result.times[density], not cpu) in result.stages
    assert sum(ms for _, ms, _ in result.stages) == pytest.approx(sum(result.times.values()))
    assert isinstance(result.warnings, list)
    assert result.device == engine.device["name"]
    assert result.stats["closed_manifold"] is True and result.stats["boundary_edges"] == 0
    assert result.stats["area"] == result.area
    assert result.total_ms > 0
    assert "SurfaceResult" in repr(result) and "closed manifold: yes" in repr(result)
    assert len(result) == result.triangle_count
    grid = fdmsurf.plan_grid(data / "1crn.pdb", spacing=1.0)
    assert grid["dims"] == result.grid["dims"]
    assert set(grid) == {"dims", "spacing", "origin", "cutoff"}  # no run, no places
    simplified = engine.surface(data / "1crn.pdb", spacing=1.0, simplify=0.5)
    assert simplified.simplify["simplifier"] == "collapse"  # as --stats json


def test_colours_and_properties(engine, data):
    plain = engine.surface(data / "3al1.pdb", spacing=1.0)
    assert plain.colors is None and plain.properties == {}
    coloured = engine.surface(data / "3al1.pdb", spacing=1.0, color="chain",
                              properties="hydrophobicity,bfactor")
    assert list(coloured.properties) == ["hydrophobicity", "bfactor"]
    chain = coloured.structure.chain[coloured.atoms]
    # One colour per chain.
    for c in np.unique(chain):
        assert len(np.unique(coloured.colors[chain == c], axis=0)) == 1
    bfactor = coloured.structure.b_factor[coloured.atoms]
    np.testing.assert_array_equal(coloured.properties["bfactor"], bfactor)
    uniform = engine.surface(data / "3al1.pdb", spacing=1.0, color="#102030")
    assert np.all(uniform.colors == [0x10, 0x20, 0x30])


def test_read_structure_is_as_lenient_as_the_cli(data):
    """The Python reader is the library's: each lenient case is read, with its warning."""
    cases = {
        "label-only.cif": "no auth_seq_id",
        "minimal.cif": "no occupancy",
        "models-repeated.pdb": "repeats a model number",
        "old-charge.pdb": "unreadable charge",
        "overflow.pdb": "fields past their columns",
        "free-format.pdb": "in free format",
        "amber-names.pdb": "named from column 13",
        "columns.pqr": "fixed columns",
        "zero-radii.pqr": "have radius 0",
    }
    for name, warning in cases.items():
        s = fdmsurf.read_structure(data / "lenient" / name)
        assert len(s) > 0 and np.all(s.radii > 0), name
        assert any(warning in w for w in s.info["warnings"]), (name, s.info["warnings"])
    with pytest.raises(fdmsurf.FormatError, match=r"non-numeric x coordinate .*columns 31-38"):
        fdmsurf.parse_structure(
            "ATOM      1  CA  GLY A   1      15.1x5  11.555   5.265  1.00 10.00           C\n",
            "bad.pdb")


def test_read_structure_metadata(data):
    s = fdmsurf.read_structure(data / "1crn.pdb")
    assert len(s) == 327 and s.xyz.shape == (327, 3) and s.xyz.dtype == np.float32
    assert s.radii.shape == (327,) and np.all(s.radii > 0)
    assert s.chains == ["A"] and set(s.chain) == {"A"}
    assert s.residue_name[0] == "THR" and s.name[0] == "N" and s.element[0] == "N"
    assert s.residue_number.dtype == np.int32 and s.residue_number[0] == 1
    assert s.serial[0] == 1 and s.hetero.dtype == bool and not s.hetero.any()
    assert s.b_factor.dtype == np.float32 and s.occupancy[0] == 1.0
    assert s.info["format"] == "pdb" and s.info["atoms_in_file"] == 327
    assert s.chain is s.chain  # built once
    # Read-only: the library reads the metadata it was given, so an edit would change nothing.
    for field in ("b_factor", "serial", "name", "chain", "element", "hetero"):
        assert not getattr(s, field).flags.writeable, field
    with pytest.raises(ValueError, match="read-only"):
        s.b_factor[:] = 99.0
    with_h = fdmsurf.read_structure(data / "1d3z.pdb.gz", model=3, hydrogens=True)
    assert with_h.info["model"] == 3 and "H" in set(with_h.element)
    assert len(fdmsurf.read_models(data / "1d3z.pdb.gz")) == 10
    chain_a = fdmsurf.read_structure(data / "3al1.pdb", chains="A")
    assert chain_a.chains == ["A"]
    part = fdmsurf.read_structure(data / "1crn.pdb", select="A/1-10")
    assert set(part.residue_number) == set(range(1, 11))
    xyzr = fdmsurf.read_structure(data / "1crn.xyzr")
    assert len(xyzr) == 327 and xyzr.chain is None and xyzr.element is None
    text = (data / "1crn.pdb").read_text()
    assert len(fdmsurf.parse_structure(text, "crambin.pdb")) == 327


def test_structure_views_subsets_and_selections(data):
    s = fdmsurf.read_structure(data / "3al1.pdb")
    a = s.select("A")
    assert a.chains == ["A"] and len(a) == int(np.sum(s.chain == "A"))
    np.testing.assert_array_equal(a.xyz, s.xyz[s.chain == "A"])
    b = s.subset(s.chain == "B")
    assert b.chains == ["B"] and len(a) + len(b) <= len(s)
    own = fdmsurf.Structure([[0, 0, 0], [1.5, 0, 0]], [1.7, 1.5], element=["c", "o"])
    assert list(own.element) == ["C", "O"]
    own.xyz[1, 0] = 2.0  # a view: edits reach the structure
    assert own.xyz[1, 0] == 2.0
    assert "2 atoms" in repr(own)


def test_engine_places_its_stages(engine, data):
    # The CLI's --host-filter/--host-mc/--host-atoms/--host-ses: "on" and "off" whatever the
    # device, "auto" (the engine fixture's) on the host exactly on a CPU device.
    with fdmsurf.Engine(host_ses="off", host_mc="on") as e:
        r = e.surface(data / "1crn.xyzr", method="edt", spacing=1.0)
        assert r.grid["host_ses_distance"] is False and "ses-distance" in r.times
        assert r.grid["host_marching_cubes"] is True and "mc-host" in r.times
    with fdmsurf.Engine(host_ses="ON", host_mc="off", host_atoms="off") as e:
        r = e.surface(data / "1crn.xyzr", method="edt", spacing=1.0)
        assert r.grid["host_ses_distance"] is True and "ses-host" in r.times
        assert r.grid["host_marching_cubes"] is False and "mc-host" not in r.times
        same = engine.surface(data / "1crn.xyzr", method="edt", spacing=1.0)
        assert r.triangle_count == same.triangle_count
        assert r.area == pytest.approx(same.area, rel=1e-6)
    with pytest.raises(ValueError, match="host_mc"):
        fdmsurf.Engine(host_mc="gpu")
    with pytest.raises(ValueError, match="host_ses"):
        fdmsurf.Engine(host_ses=True)
    # The density: on the host where the filter and marching cubes are, else on the device.
    with fdmsurf.Engine(host_density="off", host_filter="on", host_mc="on") as e:
        r = e.surface(data / "1crn.xyzr", spacing=0.5)
        assert r.grid["host_density"] is False and "density" in r.times
        assert r.grid["host_filter"] is True
    with fdmsurf.Engine(host_density="on", host_filter="on", host_mc="on") as e:
        h = e.surface(data / "1crn.xyzr", spacing=0.5)
        assert h.grid["host_density"] is True and "density-host" in h.times
        assert "density" not in h.times
        assert h.area == pytest.approx(r.area, rel=1e-6)
    with pytest.raises(ValueError, match="host_density"):
        fdmsurf.Engine(host_density="yes")


def test_compare_and_read_mesh(engine, data, tmp_path):
    result = engine.surface(data / "1crn.pdb")
    result.write(tmp_path / "1crn.ply")
    same = fdmsurf.compare(result, tmp_path / "1crn.ply", spacing=0.5)
    assert same["rmsd_weighted"] == 0.0 and same["hausdorff"] == 0.0
    exact = engine.surface(data / "1crn.xyzr", method="edt")
    assert exact.grid["host_ses_distance"] is (engine.device["type"] == "CPU")
    assert ("ses-host" in exact.times) is exact.grid["host_ses_distance"]
    vs = fdmsurf.compare(str(data / "1crn-ses-nanoshaper.ply.gz"), exact, 0.5)
    assert vs["rmsd_weighted"] < 0.05 and abs(vs["area_rel_error"]) < 0.02
    mesh = fdmsurf.read_mesh(data / "1crn-ses-nanoshaper.ply.gz")
    assert mesh.vertex_count > 0 and mesh.atoms is None and "Mesh" in repr(mesh)


def test_areas_per_atom(engine, data):
    result = engine.surface(data / "1crn.pdb", spacing=1.0)
    areas = result.atom_areas()
    assert areas.shape == (327,) and areas.dtype == np.float64
    assert areas.sum() == pytest.approx(result.area, rel=1e-9)
    one = fdmsurf.Structure([[0, 0, 0]], [1.6])
    assert fdmsurf.sas_areas(one, probe=1.4)[0] == pytest.approx(4 * math.pi * 9.0, rel=1e-9)
    sas = fdmsurf.sas_areas(result.structure, probe=1.4)
    vs_mesh = engine.surface(data / "1crn.pdb", surface="sas", spacing=0.5)
    # 0.02 % apart at 0.5 Å with the snapped mesh (3.2 % with snap=False: the chords and the
    # creases that marching cubes cuts across).
    assert sas.sum() == pytest.approx(vs_mesh.area, rel=0.005)


def test_keywords_are_the_cli_options_with_their_defaults(cli):
    """Every surface and input option of `fdmsurf --help` is a keyword of Engine.surface with
    the same name, and each keyword's default is the library's."""
    help_text = cli("--help").stdout
    sections = help_text.split("\nDevice:")[0]
    options = set(re.findall(r"^  (--[a-z-]+)", sections, flags=re.M))
    not_keywords = {"--models"}  # Engine.surface_models
    # the keyword's default is True
    negated = {"--no-ligands": "ligands", "--no-snap": "snap", "--natural-grid": "canonical_grid"}
    parameters = inspect.signature(fdmsurf.Engine.surface).parameters
    for option in options - not_keywords:
        name = negated.get(option, option[2:].replace("-", "_"))
        assert name in parameters, f"{option} has no keyword"
    for option, name in negated.items():
        assert option in options and parameters[name].default is True, option
    from fdmsurf import _options
    resolved = _options.parse({}).describe()
    for name, parameter in parameters.items():
        if parameter.default is inspect.Parameter.empty or name == "radii":
            continue
        if parameter.default is None or name == "cutoff":
            continue  # resolved by the library from the other settings (0: from the probe)
        if isinstance(parameter.default, float):
            assert resolved[name] == pytest.approx(parameter.default, rel=1e-6), name
        elif name not in ("paper", "no_cavities"):  # flags, not settings
            assert resolved[name] == parameter.default, name


def test_help_reads_well():
    doc = fdmsurf.Engine.surface.__doc__
    signature = str(inspect.signature(fdmsurf.Engine.surface))
    assert signature.startswith("(self, source, radii=None, *, surface='ses', method='fdm', "
                                "spacing=0.5, probe=1.4")
    assert "spacing=0.5 [--spacing]\n        grid spacing, Å (> 0)." in doc
    assert "{keywords}" not in doc
    for name in ("source", "InvalidArgumentError", "GIL"):
        assert name in doc
    for function in (fdmsurf.surface, fdmsurf.read_structure, fdmsurf.read_models,
                     fdmsurf.compare, fdmsurf.list_devices, fdmsurf.Engine,
                     fdmsurf.SurfaceResult, fdmsurf.Structure, fdmsurf.Mesh.write):
        assert function.__doc__ and len(function.__doc__) > 40, function


def test_stubs_declare_the_api():
    import ast
    import pathlib
    stub = ast.parse(pathlib.Path(fdmsurf.__file__).with_suffix(".pyi").read_text())
    declared = {node.name for node in stub.body if isinstance(node, (ast.FunctionDef,
                                                                     ast.ClassDef))}
    assert set(fdmsurf.__all__) - {"__version__"} <= declared
    engine = next(n for n in stub.body if isinstance(n, ast.ClassDef) and n.name == "Engine")
    methods = {n.name for n in engine.body if isinstance(n, ast.FunctionDef)}
    public = {n for n in dir(fdmsurf.Engine) if not n.startswith("_")}
    assert public <= methods
    surface = next(n for n in engine.body if getattr(n, "name", "") == "surface")
    stubbed = [a.arg for a in surface.args.kwonlyargs]
    assert stubbed == list(inspect.signature(fdmsurf.Engine.surface).parameters)[3:]
    # Every stubbed function and method written in Python takes the parameters its stub names,
    # in the same order and kinds (positional, *args, keyword-only, **kwargs), with the same
    # literal defaults (Engine.__init__ once lacked the host_* places).
    def stub_params(args):
        positional = args.posonlyargs + args.args
        pad = [None] * (len(positional) - len(args.defaults))
        listed = [(x.arg, "positional", d) for x, d in zip(positional, pad + args.defaults)]
        listed += [(args.vararg.arg, "*", None)] if args.vararg else []
        listed += [(x.arg, "keyword", d) for x, d in zip(args.kwonlyargs, args.kw_defaults)]
        return listed + ([(args.kwarg.arg, "**", None)] if args.kwarg else [])

    kinds = {inspect.Parameter.POSITIONAL_ONLY: "positional",
             inspect.Parameter.POSITIONAL_OR_KEYWORD: "positional",
             inspect.Parameter.VAR_POSITIONAL: "*", inspect.Parameter.KEYWORD_ONLY: "keyword",
             inspect.Parameter.VAR_KEYWORD: "**"}

    def same(stubbed, runtime, where):
        name, kind, default = stubbed
        assert (name, kind) == (runtime.name, kinds[runtime.kind]), where
        if default is None:
            assert runtime.default is inspect.Parameter.empty or runtime.name == "self", where
            return
        try:
            value = ast.literal_eval(default)
        except ValueError:
            return  # not a literal (a name): not compared
        assert runtime.default == value, f"{where}: {name}"

    checked = set()
    for owner, nodes in [(fdmsurf, stub.body)] + [
            (getattr(fdmsurf, c.name, None), c.body) for c in stub.body
            if isinstance(c, ast.ClassDef)]:
        for node in nodes:
            if not isinstance(node, ast.FunctionDef) or owner is None:
                continue
            runtime = getattr(owner, node.name, None)
            if isinstance(runtime, property):
                runtime = runtime.fget
            if not inspect.isfunction(runtime):
                continue  # compiled (no signature) or not a plain function
            where = f"{getattr(owner, '__name__', owner)}.{node.name}"
            stubbed = stub_params(node.args)
            params = list(inspect.signature(runtime).parameters.values())
            if stubbed and stubbed[-1][1] == "**" and all(p.kind != p.VAR_KEYWORD for p in params):
                # `**keywords` in a stub stands for the runtime's keyword-only options.
                stubbed = stubbed[:-1]
                assert all(p.kind == p.KEYWORD_ONLY for p in params[len(stubbed):]), where
                params = params[:len(stubbed)]
            assert len(stubbed) == len(params), where
            for a, b in zip(stubbed, params):
                same(a, b, where)
            checked.add(where)
    assert {"Engine.__init__", "Engine.surface", "fdmsurf.plan_grid"} <= checked, checked


def test_devices_and_version(engine, cli):
    devices = fdmsurf.list_devices()
    assert any(d["usable"] for d in devices)
    assert engine.device["name"] in [d["name"] for d in devices]
    assert cli("--version").stdout.splitlines()[0] == f"fdmsurf {fdmsurf.__version__}"
    assert "Engine on" in repr(engine)


def test_default_engine_shortcut(data):
    result = fdmsurf.surface(data / "1crn.pdb", spacing=1.0)
    assert result.closed_manifold
    assert fdmsurf.default_engine() is fdmsurf.default_engine()
