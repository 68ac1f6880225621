"""Engine.trajectory: every frame's surface and areas over MDAnalysis, mdtraj and numpy sources,
one grid for the run, streaming, and the bad inputs (python/fdmsurf/trajectory.py)."""

import gzip
import warnings

import numpy as np
import pytest

import fdmsurf

warnings.filterwarnings("ignore", category=DeprecationWarning)


def walk(structure, frames, seed=7, step=0.1):
    """A seeded random walk of the atoms: (frames, atoms, 3) float32, Å."""
    rng = np.random.default_rng(seed)
    steps = rng.normal(scale=step, size=(frames, len(structure), 3))
    steps[0] = 0.0
    return (structure.xyz[None] + np.cumsum(steps, axis=0)).astype(np.float32)


@pytest.fixture(scope="module")
def crambin(data):
    return fdmsurf.read_structure(data / "1crn.pdb")


@pytest.fixture(scope="module")
def nmr_pdb(data, tmp_path_factory):
    """1D3Z's ten models as a plain PDB (the MD libraries read each model as a frame)."""
    path = tmp_path_factory.mktemp("nmr") / "1d3z.pdb"
    path.write_bytes(gzip.open(data / "1d3z.pdb.gz").read())
    return path


def test_arrays_give_each_frames_surface_and_areas(engine, crambin):
    frames = walk(crambin, 4)
    seen = []
    run = engine.trajectory(frames, topology=crambin, spacing=1.0,
                            callback=lambda row, result: seen.append(result.grid["dims"]))
    rows = list(run)
    assert [r.frame for r in rows] == [0, 1, 2, 3]
    # One grid for the run: the largest of the frames' own, so one FFT plan serves them all.
    own = [fdmsurf.plan_grid(fdmsurf.Structure(f, crambin.radii), spacing=1.0)["dims"]
           for f in frames]
    assert run.grid == tuple(np.max(own, axis=0))
    assert all(tuple(d) == run.grid for d in seen)
    for row, xyz in zip(rows, frames):
        alone = engine.surface(fdmsurf.Structure(xyz, crambin.radii), spacing=1.0,
                               min_grid=run.grid)
        assert row.ok and row.area == alone.area and row.volume == alone.volume
        assert np.array_equal(row.atom_area, alone.atom_areas())
        exact = fdmsurf.exact_areas(fdmsurf.Structure(xyz, crambin.radii))
        assert np.array_equal(row.atom_sasa, exact) and row.sasa == pytest.approx(exact.sum())
        assert len(row.residue_sasa) == len(run.residues) == 46
        assert row.residue_sasa.sum() == pytest.approx(row.sasa)
        assert row.residue_area.sum() == pytest.approx(row.area)
    assert rows[0].area != rows[3].area


def test_cavities_are_counted(engine, data):
    structure = fdmsurf.read_structure(data / "4hhb.pdb.gz")
    run = engine.trajectory(structure.xyz[None], topology=structure, spacing=1.0, sasa=False)
    row = next(iter(run))
    result = engine.surface(structure, spacing=1.0, min_grid=run.grid)
    cavities = [p["volume"] for p in result.piece_stats() if p["volume"] < 0]
    assert row.cavities == len(cavities) > 0
    assert row.cavity_volume == pytest.approx(-sum(cavities))
    assert row.pieces == result.pieces


def test_mdanalysis_frames_are_the_models(engine, data, nmr_pdb):
    mda = pytest.importorskip("MDAnalysis")
    universe = mda.Universe(str(nmr_pdb))
    assert len(universe.trajectory) == 10
    rows = list(engine.trajectory(universe, ses=False, start=2, stop=9, stride=3,
                                  hydrogens=True))
    assert [r.frame for r in rows] == [2, 5, 8]
    for row in rows:
        model = fdmsurf.read_structure(data / "1d3z.pdb.gz", model=row.frame + 1,
                                       hydrogens=True)
        assert np.allclose(row.atom_sasa, fdmsurf.exact_areas(model), rtol=1e-9, atol=1e-9)


def test_mdtraj_frames_and_selection(engine, data, nmr_pdb):
    md = pytest.importorskip("mdtraj")
    traj = md.load(str(nmr_pdb))
    run = engine.trajectory(traj, ses=False, select="A/1-20", stop=3)
    rows = list(run)
    assert len(rows) == 3 and len(run.residues) == 20
    for row in rows:
        model = fdmsurf.read_structure(data / "1d3z.pdb.gz", model=row.frame + 1,
                                       select="A/1-20")
        assert len(row.atom_sasa) == len(model)
        assert np.allclose(row.atom_sasa, fdmsurf.exact_areas(model), rtol=1e-4, atol=1e-3)


def test_frames_are_read_as_they_are_processed(engine, crambin):
    frames = walk(crambin, 5)
    read = []

    def source():
        for i, f in enumerate(frames):
            read.append(i)
            yield f

    rows = iter(engine.trajectory(source(), topology=crambin, spacing=1.0, grid="grow"))
    first = next(rows)
    assert read == [0] and first.frame == 0
    assert [r.frame for r in rows] == [1, 2, 3, 4] and read == [0, 1, 2, 3, 4]


def test_nan_frames_stop_or_are_reported(engine, crambin):
    frames = walk(crambin, 4)
    frames[2, 10, 1] = np.nan
    rows = list(engine.trajectory(frames, topology=crambin, ses=False, on_error="skip"))
    assert [r.ok for r in rows] == [True, True, False, True]
    assert "frame 2: NaN" in rows[2].error and np.isnan(rows[2].sasa)
    with pytest.raises(fdmsurf.InvalidArgumentError, match="frame 2: NaN"):
        list(engine.trajectory(frames, topology=crambin, ses=False))


def test_wrong_atom_counts(engine, crambin, tmp_path):
    bad = np.zeros((3, len(crambin) + 1, 3), np.float32)
    out = tmp_path / "meshes"
    with pytest.raises(fdmsurf.InvalidArgumentError, match="328 atoms, the topology 327"):
        engine.trajectory(bad, topology=crambin, write=str(out / "f{frame}.ply"))
    assert not out.exists()
    frames = list(walk(crambin, 3))
    frames[1] = frames[1][:-1]
    rows = list(engine.trajectory(iter(frames), topology=crambin, ses=False, on_error="skip"))
    assert [r.ok for r in rows] == [True, False, True]
    assert "frame 1 has shape (326, 3)" in rows[1].error


def test_meshes_written_by_pattern(engine, crambin, tmp_path):
    frames = walk(crambin, 2)
    rows = list(engine.trajectory(frames, topology=crambin, spacing=1.0, sasa=False,
                                  write=str(tmp_path / "out" / "frame-{frame:03d}.ply")))
    assert [r.path for r in rows] == [str(tmp_path / "out" / f"frame-00{i}.ply") for i in (0, 1)]
    mesh = fdmsurf.read_mesh(rows[1].path)
    assert mesh.area == pytest.approx(rows[1].area, rel=1e-6)
    with pytest.raises(ValueError, match="names every frame's file the same"):
        engine.trajectory(frames, topology=crambin, write=str(tmp_path / "same.ply"))
    assert not (tmp_path / "same.ply").exists()
    with pytest.raises(fdmsurf.InvalidArgumentError, match="extension must be .ply"):
        engine.trajectory(frames, topology=crambin, write=str(tmp_path / "f{frame}.xyz"))


def test_bad_sources_and_selections(engine, data, crambin):
    gemmi = pytest.importorskip("gemmi")
    with pytest.raises(TypeError, match="MDAnalysis Universe or AtomGroup, an mdtraj"):
        engine.trajectory(gemmi.read_structure(str(data / "1crn.pdb")))
    with pytest.raises(TypeError, match="MDAnalysis Universe or AtomGroup, an mdtraj"):
        engine.trajectory(str(data / "1crn.pdb"))
    with pytest.raises(TypeError, match="radii=.*or topology="):
        engine.trajectory(walk(crambin, 2))
    with pytest.raises(fdmsurf.EmptySelectionError):
        engine.trajectory(walk(crambin, 2), topology=data / "1crn.pdb", select="(HOH)")
    with pytest.raises(fdmsurf.InvalidArgumentError, match="stride"):
        engine.trajectory(walk(crambin, 2), radii=crambin.radii, stride=0)


def test_radii_and_fixed_grid(engine, crambin):
    frames = walk(crambin, 2)
    run = engine.trajectory(frames, radii=crambin.radii, spacing=1.0, grid=(64, 64, 64),
                            keep_mesh=True)
    rows = list(run)
    assert all(tuple(r.mesh.grid["dims"]) == (64, 64, 64) for r in rows)
    assert rows[0].residue_sasa is None          # arrays have no residues
    table = run.table()
    assert [t["frame"] for t in table] == [0, 1] and table[0]["area"] == rows[0].area


def test_dask_ranges_give_the_series_in_frame_order(engine, data, crambin, tmp_path):
    pytest.importorskip("distributed")
    import functools
    from fdmsurf import batch
    frames = walk(crambin, 7)
    path = tmp_path / "frames.npy"
    np.save(path, frames)
    source = functools.partial(np.load, str(path), mmap_mode="r")
    rows = batch.trajectory(source, topology=str(data / "1crn.pdb"), chunk=3, workers=2,
                            spacing=1.0, progress=None)
    here = list(engine.trajectory(frames, topology=str(data / "1crn.pdb"), spacing=1.0))
    assert [r.frame for r in rows] == list(range(7))
    for got, want in zip(rows, here):
        assert got.area == want.area and got.volume == want.volume
        assert np.array_equal(got.atom_sasa, want.atom_sasa)
        assert np.array_equal(got.residue_area, want.residue_area)


def test_cli_models_table_without_a_mesh(cli, data, tmp_path):
    import csv
    table = tmp_path / "models.csv"
    done = cli(data / "1d3z.pdb.gz", "--models", "all", "--areas", table)
    assert "table of 10 models" in done.stdout
    rows = list(csv.DictReader(table.open()))
    assert [int(r["model"]) for r in rows] == list(range(1, 11))
    for r in rows:
        model = fdmsurf.read_structure(data / "1d3z.pdb.gz", model=int(r["model"]))
        exact = fdmsurf.exact_areas(model)
        assert r["status"] == "ok" and int(r["atoms"]) == len(model)
        assert float(r["sasa"]) == pytest.approx(exact.sum(), rel=1e-12)
        assert float(r["sasa_A"]) == pytest.approx(exact.sum(), rel=1e-12)
        assert r["area"] == "" and r["volume"] == ""     # no -o: no mesh
    assert len({r["sasa"] for r in rows}) == 10


def test_cli_models_table_with_meshes(cli, engine, data, tmp_path):
    import json
    table = tmp_path / "models.jsonl"
    done = cli(data / "1d3z.pdb.gz", "--models", "all", "-o", f"{tmp_path}/meshes/",
               "--areas", table, "--spacing", "1.0", "--probe", "1.2", "--stats", "json")
    rows = [json.loads(line) for line in table.read_text().splitlines()]
    stats = [json.loads(line) for line in done.stdout.splitlines()]
    models = engine.surface_models(data / "1d3z.pdb.gz", spacing=1.0, probe=1.2)
    assert [r["model"] for r in rows] == list(range(1, 11)) == [s["model"] for s in stats]
    for row, stat, result in zip(rows, stats, models):
        assert row["area"] == pytest.approx(result.area, rel=1e-12) == stat["area"]
        assert row["volume"] == pytest.approx(result.volume, rel=1e-12)
        cavities = [p["volume"] for p in result.piece_stats() if p["volume"] < 0]
        assert row["cavities"] == len(cavities) and row["pieces"] == result.pieces
        assert row["sasa"] == pytest.approx(fdmsurf.exact_areas(result.structure, probe=1.2).sum(),
                                            rel=1e-12)
        assert row["chain_sasa"] == {"A": pytest.approx(row["sasa"])}


def test_cli_models_table_refusals(cli, data, tmp_path):
    table = tmp_path / "t.csv"
    for args in (
        [data / "1d3z.pdb.gz", data / "1crn.pdb", "--models", "all", "--areas", table],
        [data / "1d3z.pdb.gz", "--models", "all", "--areas", table, "--relative", "tien2013"],
        [data / "1crn.pdb", "--surface", "sas", "--areas", tmp_path / "t.jsonl"],
    ):
        done = cli(*args, check=False)
        assert done.returncode == 2, done.stderr
        assert "--areas" in done.stderr
    assert list(tmp_path.iterdir()) == []


def test_progress_goes_to_stderr_when_asked(engine, crambin, capsys):
    list(engine.trajectory(walk(crambin, 3), topology=crambin, ses=False, progress=True))
    err = capsys.readouterr().err
    assert "3/3 frames" in err and err.endswith("\n")
    list(engine.trajectory(walk(crambin, 3), topology=crambin, ses=False))  # not a terminal
    assert capsys.readouterr().err == ""
