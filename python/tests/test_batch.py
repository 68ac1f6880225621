"""fdmsurf.batch on Dask's distributed scheduler: a LocalCluster of two workers, failed structures
as rows, re-runs that compute nothing, and a worker killed mid-run with every output written
once."""

import json
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

import fdmsurf

distributed = pytest.importorskip(
    "distributed", reason="Dask's distributed is not installed (Debian: python3-distributed)")

from fdmsurf import batch  # noqa: E402 - after the skip


def rows_of(outdir):
    with open(os.path.join(outdir, batch.MANIFEST), encoding="utf-8") as lines:
        return [json.loads(line) for line in lines]


def run_batch(*args):
    return subprocess.run([sys.executable, "-m", "fdmsurf.batch", *map(str, args)],
                          capture_output=True, encoding="utf-8", timeout=600)


def test_inputs_outputs_and_hash(data, tmp_path):
    found = [os.path.basename(p) for p in batch.find_inputs([data])]
    assert "1crn.pdb" in found and "1d3z.pdb.gz" in found and "1crn.xyzrn" in found
    assert "1crn-fdm-0.5.ply" not in found and "make_xyzrn.py" not in found
    listing = tmp_path / "set.txt"
    listing.write_text("# two structures\n1crn.pdb\n\n3al1.pdb\n")
    for name in ("1crn.pdb", "3al1.pdb"):
        (tmp_path / name).symlink_to(data / name)
    expected = [str(tmp_path / "1crn.pdb"), str(tmp_path / "3al1.pdb")]
    assert batch.find_inputs([listing]) == expected
    assert batch.find_inputs([f"@{listing}", tmp_path / "1crn.pdb"]) == expected
    assert batch.find_inputs(os.fsencode(listing)) == batch.find_inputs([listing])  # bytes
    for limit in ("auto", None, 0, "0", "0GB", "4GB", "0.5", 0.5, 2**33):
        batch._check_memory_limit(limit)  # as LocalCluster takes them
    for limit in ("bogus", -1, "-1", float("nan"), True):
        with pytest.raises(fdmsurf.InvalidArgumentError, match="memory limit must be"):
            batch._check_memory_limit(limit)
    assert batch.stem_of("/a/b/1abc.cif.gz") == "1abc"
    assert batch.stem_of("/a/b/1ABC.CIF.GZ") == "1ABC"  # .gz in any case, as the CLI
    h = batch.options_hash({}, "ply", False)
    assert h == batch.options_hash({"spacing": 0.5, "probe": 1.4, "level": None}, "ply", False)
    assert h != batch.options_hash({"spacing": 1.0}, "ply", False)
    assert h != batch.options_hash({}, "obj", False)
    assert h != batch.options_hash({"color": "chain"}, "ply", False)
    assert h != batch.options_hash({"simplify": 0.5}, "ply", False)
    assert h != batch.options_hash({"max_triangles": 1000}, "ply", False)
    assert h != batch.options_hash({"optimize": True}, "ply", False)
    assert h == batch.options_hash({"optimize": False, "simplify": None}, "ply", False)
    assert h == batch.options_hash({"snap": True, "chord_tolerance": None}, "ply", False)
    assert h != batch.options_hash({"snap": False}, "ply", False)
    assert h != batch.options_hash({"chord_tolerance": 0.0}, "ply", False)
    with pytest.raises(fdmsurf.InvalidArgumentError, match="spacing must be > 0"):
        batch.options_hash({"spacing": 0}, "ply", False)
    with pytest.raises(fdmsurf.InvalidArgumentError, match="mesh format must be ply, obj, glb, "
                                                           "stl or off, not 'xyz'"):
        batch.run([data / "1crn.pdb"], tmp_path / "out", mesh_format="xyz")
    args = batch._argument_parser().parse_args(["x.pdb", "-o", "out", "--simplify", "0.5",
                                                "--max-triangles", "100", "--optimize",
                                                "--mesh-format", "glb", "--no-snap"])
    assert (args.simplify, args.max_triangles, args.optimize) == (0.5, 100, True)
    assert args.snap is False
    assert args.mesh_format == "glb"


def test_stale_temporaries_are_recognised_also_when_cut_short(tmp_path):
    """The batch removes the temporary files of its meshes, also those whose names the atomic
    writer cut short (names of 239 to 255 bytes), and no one else's."""
    hexa = ".tmp.0123456789ab"
    assert batch.is_temporary_of("1abc.ply" + hexa, "1abc", "ply")
    assert batch.is_temporary_of("1abc-m2.ply" + hexa, "1abc", "ply")
    assert not batch.is_temporary_of("1abcd.ply" + hexa, "1abc", "ply")
    assert not batch.is_temporary_of("1abc.obj" + hexa, "1abc", "ply")
    assert not batch.is_temporary_of("1abc.ply.tmp.xyz", "1abc", "ply")
    long_stem = "s" * 240
    for final in (long_stem + ".ply", long_stem + "-m12.ply"):
        cut = final[:255 - len(hexa)] + hexa  # as AtomicFile names it
        assert len(cut) == 255
        assert batch.is_temporary_of(cut, long_stem, "ply"), final
        assert not batch.is_temporary_of(cut, "t" * 240, "ply")
    other = "s" * 230 + "x" * 20 + ".ply"  # differs within the part kept
    assert not batch.is_temporary_of(other[:255 - len(hexa)] + hexa, long_stem, "ply")
    (tmp_path / ("1abc.ply" + hexa)).write_text("x")
    (tmp_path / ((long_stem + ".ply")[:238] + hexa)).write_text("x")
    (tmp_path / ("other.ply" + hexa)).write_text("x")
    batch.remove_stale_temporaries(str(tmp_path), ["1abc", long_stem], "ply")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["other.ply" + hexa]


def test_local_cluster_of_two_workers_then_a_rerun_that_computes_nothing(cli, data, tmp_path):
    garbage = tmp_path / "garbage.pdb"
    garbage.write_text("not a structure\n")
    inputs = [data / "1crn.pdb", data / "3al1.pdb", data / "4hhb.pdb.gz", data / "1d3z.pdb.gz",
              garbage, tmp_path / "missing.cif"]
    out = tmp_path / "out"
    done = run_batch(*inputs, "-o", out, "--workers", "2", "--spacing", "1.0",
                     "--color", "chain")
    assert done.returncode == 1, done.stderr  # two structures failed, the rest are done
    assert "2 worker(s)" in done.stderr and "[6/6]" in done.stderr
    rows = {os.path.basename(r["input"]): r for r in rows_of(out)}
    assert len(rows) == 6 == len(rows_of(out))
    for name in ("1crn.pdb", "3al1.pdb", "4hhb.pdb.gz", "1d3z.pdb.gz"):
        row = rows[name]
        assert row["status"] == "ok" and row["error"] is None
        assert os.path.exists(row["output"]) and row["closed"] is True
        assert row["atoms"] > 0 and row["triangles"] > 0 and row["area"] > 0
        assert row["volume"] > 0 and ("density" in row["times"] or "density-host" in row["times"]) and "read" in row["times"]
    assert rows["garbage.pdb"]["status"] == "failed"
    assert rows["garbage.pdb"]["error_class"] == "FormatError"
    assert rows["missing.cif"]["error_class"] == "FileError"
    assert "missing.cif" in rows["missing.cif"]["error"]
    assert len({r["options_hash"] for r in rows.values()}) == 1
    # The meshes are the CLI's.
    cli(data / "1crn.pdb", "-o", tmp_path / "cli.ply", "--quiet", "--spacing", "1.0",
        "--color", "chain")
    assert (out / "1crn.ply").read_bytes() == (tmp_path / "cli.ply").read_bytes()
    assert sorted(os.listdir(out)) == sorted(
        ["1crn.ply", "3al1.ply", "4hhb.ply", "1d3z.ply", batch.MANIFEST])

    # The same options again: nothing to compute, nothing written, no cluster started.
    stamps = {p: os.stat(out / p).st_mtime_ns for p in os.listdir(out)}
    again = run_batch(*inputs, "-o", out, "--workers", "2", "--spacing", "1", "--colour",
                      "chain")
    assert again.returncode == 1  # the two failures stand
    assert "6 done already (2 of them failed: --retry-failed retries them), 0 to compute" \
        in again.stderr
    assert "worker" not in again.stderr
    assert {p: os.stat(out / p).st_mtime_ns for p in os.listdir(out)} == stamps

    # --retry-failed recomputes the failures only.
    retry = run_batch(*inputs, "-o", out, "--workers", "1", "--spacing", "1", "--color",
                      "chain", "--retry-failed", "--quiet")
    assert retry.returncode == 1 and retry.stderr == ""
    assert len(rows_of(out)) == 8


def test_every_model_in_one_task(data, tmp_path):
    summary = batch.run([data / "1d3z.pdb.gz"], tmp_path, workers=1, all_models=True,
                        spacing=1.0, progress=None)
    assert summary["computed"] == 1 and summary["failed"] == 0
    (row,) = rows_of(tmp_path)
    assert row["model"] == list(range(1, 11))
    assert row["output"] == [str(tmp_path / f"1d3z-m{m}.ply") for m in range(1, 11)]
    assert all(os.path.exists(p) for p in row["output"])
    assert len({tuple(g) for g in row["grid"]}) == 1  # one grid for the ensemble
    again = batch.run([data / "1d3z.pdb.gz"], tmp_path, workers=1, all_models=True,
                      spacing=1.0, progress=None)
    assert again["computed"] == 0 and again["skipped"] == 1


def write_xyzr(structure, path):
    with open(path, "w", encoding="ascii") as out:
        for (x, y, z), r in zip(structure.xyz, structure.radii):
            out.write(f"{x:.3f} {y:.3f} {z:.3f} {r:.2f}\n")


def test_a_worker_killed_mid_run(data, tmp_path):
    """SIGKILL a worker while it computes: Dask reruns its task on the other worker (then on
    the restarted one), and every structure still gets one mesh and one manifest row."""
    inputs = []
    for model in fdmsurf.read_models(data / "1d3z.pdb.gz"):
        path = tmp_path / f"1d3z-model{model.info['model']}.xyzr"
        write_xyzr(model, path)
        inputs.append(path)
    inputs += [data / "4hhb.pdb.gz", data / "3al1.pdb"]
    out = tmp_path / "out"
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", silence_logs=50)
    client = distributed.Client(cluster)
    try:
        pids = client.run(os.getpid)
        summary = {}
        thread = threading.Thread(target=lambda: summary.update(
            batch.run(inputs, out, client=client, progress=None)))
        thread.start()
        victim, interrupted = None, []
        deadline = time.monotonic() + 120
        while victim is None and time.monotonic() < deadline and thread.is_alive():
            busy = [w for w, tasks in client.processing().items() if tasks and w in pids]
            # Once a worker is on a task and one structure is done (the engines are up),
            # kill a worker that is computing.
            manifest = out / batch.MANIFEST
            if busy and os.path.exists(manifest) and os.path.getsize(manifest) > 0:
                victim = busy[0]
                time.sleep(0.1)
                interrupted = list(client.processing()[victim])
                os.kill(pids[victim], signal.SIGKILL)
            time.sleep(0.02)
        thread.join(timeout=600)
        assert victim is not None, "no worker was seen computing"
        assert not thread.is_alive()
    finally:
        client.close()
        cluster.close()
    rows = rows_of(out)
    assert summary["failed"] == 0 and summary["computed"] == len(inputs)
    assert sorted(r["input"] for r in rows) == sorted(map(str, inputs))  # one row each
    assert all(r["status"] == "ok" for r in rows)
    outputs = sorted(os.listdir(out))
    expected = sorted([batch.stem_of(str(p)) + ".ply" for p in inputs] + [batch.MANIFEST])
    assert outputs == expected  # every mesh, and no temporary file left
    # The task the killed worker was on ran again elsewhere.
    by_stem = {batch.stem_of(r["input"]): r for r in rows}
    assert interrupted
    for key in interrupted:  # fdmsurf-STEM-HASH-RANDOM
        row = by_stem[key[len("fdmsurf-"):].rsplit("-", 2)[0]]
        assert row["status"] == "ok" and row["worker"] != victim
    for row in rows:
        mesh = fdmsurf.read_mesh(row["output"])
        assert mesh.triangle_count == row["triangles"] and mesh.closed_manifold


def test_joining_a_running_cluster(data, tmp_path):
    """--scheduler ADDRESS: the run uses that cluster's workers and leaves the cluster up."""
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", silence_logs=50)
    try:
        done = run_batch(data / "1crn.pdb", data / "3al1.pdb", "-o", tmp_path,
                         "--scheduler", cluster.scheduler_address, "--spacing", "1.0")
        assert done.returncode == 0, done.stderr
        workers = set(cluster.scheduler_info["workers"])
        rows = rows_of(tmp_path)
        assert len(rows) == 2 and all(r["status"] == "ok" for r in rows)
        assert {r["worker"] for r in rows} <= workers
        assert cluster.scheduler_info["workers"]  # still up
    finally:
        cluster.close()


def test_one_path_a_name_that_is_not_utf8_and_bad_cluster_options(data, tmp_path):
    # Refused before any cluster starts: exit 2 naming the option.
    for bad in (["--workers", "-1"], ["--workers", "0"], ["--memory-limit", "bogus"]):
        done = run_batch(data / "1crn.pdb", "-o", tmp_path / "no", *bad)
        assert done.returncode == 2, (bad, done.stderr)
        assert ("workers must be" if bad[0] == "--workers" else "memory limit must be") \
            in done.stderr
    assert not (tmp_path / "no").exists()
    # One path given as a str is one input (not its characters), here a file name that is not
    # UTF-8: its row goes through Dask and into the manifest, which reads it back.
    name = os.fsdecode(b"\xff-1crn.pdb")
    (tmp_path / name).symlink_to(data / "1crn.pdb")
    summary = batch.run(str(tmp_path / name), tmp_path / "out", workers=1, spacing=1.0,
                        progress=None)
    assert (summary["inputs"], summary["computed"], summary["failed"]) == (1, 1, 0)
    (row,) = rows_of(tmp_path / "out")
    assert row["status"] == "ok" and row["input"] == str(tmp_path / name)
    assert os.path.exists(row["output"]) and row["output"].endswith(name[:-4] + ".ply")
    again = batch.run(str(tmp_path / name), tmp_path / "out", workers=1, spacing=1.0,
                      progress=None)
    assert again["skipped"] == 1 and again["computed"] == 0
