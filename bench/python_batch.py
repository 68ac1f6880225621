#!/usr/bin/python3
"""Throughput of the Python module and of fdmsurf.batch on Dask against the CLI's batch mode.

    PYTHONPATH=build/python python3 bench/python_batch.py [--spacing 0.5] [--out DIR]

Generates a set of structures (fixed seed) in OUT/set:
  - the 10 models of tests/data/1d3z.pdb.gz as PDB files, and the same with their hydrogens
    as XYZR files;
  - every non-empty subset of the four chains of tests/data/4hhb.pdb.gz (15 PDB files);
  - from ../shared/data when it is there (said so when it is not): its single-model files as
    they are (1CRN, 1UBQ, 1AKI, 1RNA, 3AL1, 3EBZ, 4HHB), and random subsets of 1-3 chains of
    1AON (21 chains) and of the 4YVS asymmetric unit (15 chains).
Then times, on the same set and options, each after one untimed warm-up pass of the CLI (so
that Mesa's shader cache and fdmsurf's VkFFT plan cache hold every pipeline and grid size):
  1. the CLI's batch mode, `fdmsurf SET/* -o OUT/` (one process, one engine);
  2. the module in one process: one Engine, surface() and write() per file;
  3. fdmsurf.batch.run on a LocalCluster of 1 worker, then of 2 workers.
Prints a Markdown table (structures per second, overheads per structure) and writes
OUT/results.json. Needs fdmsurf (PYTHONPATH=build/python), numpy and python3-distributed.
"""

import argparse
import itertools
import json
import os
import pathlib
import platform
import random
import shutil
import subprocess
import sys
import time

import numpy as np

import fdmsurf
from fdmsurf import batch

REPO = pathlib.Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared" / "data"


def write_pdb(structure, path):
    """A minimal PDB file of `structure` (ATOM/HETATM records): enough for fdmsurf to read the
    same atoms back (elements give the radii)."""
    lines = []
    for i in range(len(structure)):
        name, element = structure.name[i], structure.element[i]
        padded = f" {name:<3}" if len(name) < 4 and len(element) == 1 else f"{name:<4}"
        x, y, z = structure.xyz[i]
        record = "HETATM" if structure.hetero[i] else "ATOM"
        lines.append(
            f"{record:<6}{(i + 1) % 100000:>5} {padded} {structure.residue_name[i]:>3} "
            f"{structure.chain[i][:1]:1}{structure.residue_number[i] % 10000:>4}"
            f"{structure.insertion_code[i] or ' ':1}   {x:8.3f}{y:8.3f}{z:8.3f}"
            f"{structure.occupancy[i]:6.2f}{structure.b_factor[i]:6.2f}          "
            f"{element:>2}")
    path.write_text("\n".join(lines + ["END", ""]))


def write_xyzr(structure, path):
    path.write_text("".join(f"{x:.3f} {y:.3f} {z:.3f} {r:.3f}\n"
                            for (x, y, z), r in zip(structure.xyz, structure.radii)))


def chain_subsets(path, name, count, rng, folder):
    structure = fdmsurf.read_structure(path)
    chains = structure.chains
    made = set()
    while len(made) < count:
        pick = tuple(sorted(rng.sample(chains, rng.randint(1, min(3, len(chains))))))
        if pick in made:
            continue
        made.add(pick)
        part = structure.subset(np.isin(structure.chain, list(pick)))
        write_pdb(part, folder / f"{name}-{''.join(pick)}.pdb")


def make_set(folder, rng, subsets=6):
    """The set's files in `folder` (sorted paths) and notes; `subsets` random chain subsets
    each of 1AON and of 4YVS when ../shared/data holds them."""
    folder.mkdir(parents=True, exist_ok=True)
    notes = []
    data = REPO / "tests" / "data"
    for model in fdmsurf.read_models(data / "1d3z.pdb.gz"):
        write_pdb(model, folder / f"1d3z-m{model.info['model']}.pdb")
    for model in fdmsurf.read_models(data / "1d3z.pdb.gz", hydrogens=True):
        write_xyzr(model, folder / f"1d3z-h-m{model.info['model']}.xyzr")
    hb = fdmsurf.read_structure(data / "4hhb.pdb.gz")
    for k in range(1, 5):
        for pick in itertools.combinations("ABCD", k):
            part = hb.subset(np.isin(hb.chain, list(pick)))
            write_pdb(part, folder / f"4hhb-{''.join(pick)}.pdb")
    if SHARED.is_dir():
        for name in ("1crn.pdb", "1ubq.pdb", "1aki.pdb", "1rna.cif", "3al1.pdb", "3ebz.cif",
                     "4hhb.cif"):
            if (SHARED / name).exists():
                shutil.copy(SHARED / name, folder / f"shared-{name}")
        if (SHARED / "1aon.pdb.gz").exists():
            chain_subsets(SHARED / "1aon.pdb.gz", "1aon", subsets, rng, folder)
        if (SHARED / "4yvs.cif.gz").exists():
            chain_subsets(SHARED / "4yvs.cif.gz", "4yvs", subsets, rng, folder)
    else:
        notes.append(f"{SHARED} is absent: the set has only the structures made from tests/data")
    return sorted(str(p) for p in folder.iterdir()), notes


def cli_path():
    path = os.environ.get("FDMSURF_CLI") or str(REPO / "build" / "fdmsurf")
    if not os.path.exists(path):
        sys.exit(f"python_batch.py: {path} not found (build first, or set FDMSURF_CLI)")
    return path


def time_cli(paths, out, spacing):
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    start = time.perf_counter()
    subprocess.run([cli_path(), *paths, "-o", f"{out}/", "--quiet", "--spacing", str(spacing)],
                   check=True)
    return time.perf_counter() - start


def time_module(paths, out, spacing):
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    start = time.perf_counter()
    engine = fdmsurf.Engine()
    init = time.perf_counter() - start
    engine_ms = gpu_ms = 0.0
    atoms = 0
    for path in paths:
        result = engine.surface(path, spacing=spacing)
        result.write(out / f"{batch.stem_of(path)}.ply")
        engine_ms += result.total_ms
        gpu_ms += sum(ms for _, ms, gpu in result.stages if gpu)
        atoms += len(result.structure)
    wall = time.perf_counter() - start
    engine.close()
    return wall, init, engine_ms / 1000.0, gpu_ms / 1000.0, atoms


def time_dask(paths, out, spacing, workers):
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    summary = batch.run(paths, out, workers=workers, spacing=spacing, progress=None)
    wall = time.perf_counter() - start
    assert summary["failed"] == 0, summary["rows"]
    return wall, summary["startup_seconds"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spacing", type=float, default=0.5)
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("python-batch-bench"))
    parser.add_argument("--seed", type=int, default=14)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    paths, notes = make_set(args.out / "set", rng)
    n = len(paths)
    device = fdmsurf.Engine().device
    print(f"{n} structures, spacing {args.spacing} Å, device {device['name']}, "
          f"{os.cpu_count()} cores", file=sys.stderr)
    for note in notes:
        print(f"note: {note}", file=sys.stderr)

    time_cli(paths, args.out / "warm-up", args.spacing)  # fills the shader and plan caches
    cli = time_cli(paths, args.out / "cli", args.spacing)
    module, init, engine_s, gpu_s, atoms = time_module(paths, args.out / "module", args.spacing)
    dask1, start1 = time_dask(paths, args.out / "dask1", args.spacing, 1)
    dask2, start2 = time_dask(paths, args.out / "dask2", args.spacing, 2)

    def same(folder):
        names = sorted(os.listdir(args.out / "cli"))
        return all((args.out / folder / f).read_bytes() == (args.out / "cli" / f).read_bytes()
                   for f in names)

    identical = {f: same(f) for f in ("module", "dask1", "dask2")}
    rows = [
        ("CLI batch mode (`fdmsurf SET/* -o OUT/`), 1 process", cli, None),
        ("Python module, 1 Engine, surface() + write() per file", module, None),
        ("fdmsurf.batch, LocalCluster, 1 worker", dask1, start1),
        ("fdmsurf.batch, LocalCluster, 2 workers", dask2, start2),
    ]
    print(f"\n{n} structures ({atoms:,} atoms in all), spacing {args.spacing} Å, "
          f"{device['name']}, {os.cpu_count()} cores, {platform.node()}\n")
    print("| run | wall (s) | structures/s | ms per structure | of which start-up (s) |")
    print("|---|---|---|---|---|")
    for name, wall, startup in rows:
        up = "" if startup is None else f"{startup:.1f}"
        print(f"| {name} | {wall:.1f} | {n / wall:.2f} | {1000 * wall / n:.0f} | {up} |")
    mesh_bytes = sum(os.path.getsize(args.out / "cli" / f) for f in os.listdir(args.out / "cli"))
    print(f"\nEngine work (Engine.surface's own time, summed): {engine_s:.1f} s, "
          f"{1000 * engine_s / n:.0f} ms per structure, of which device stages (GPU "
          f"timestamps) {gpu_s:.1f} s; everything else in the module run (reading, host stages, "
          f"set-up between submissions, writing, Python): {1000 * (module - gpu_s) / n:.0f} ms "
          f"per structure. Engine creation: {init:.2f} s. Meshes: {mesh_bytes / n / 1e6:.2f} MB "
          f"per structure (binary PLY).")
    print(f"Module overhead against the CLI: {1000 * (module - cli) / n:+.1f} ms per structure; "
          f"Dask (1 worker) against the module: {1000 * (dask1 - module) / n:+.1f} ms per "
          f"structure, {1000 * (dask1 - start1 - module + init) / n:+.1f} ms without start-up.")
    print(f"Meshes byte-identical to the CLI's: {identical}")
    results = {"structures": n, "atoms": atoms, "spacing": args.spacing,
               "device": device["name"], "cores": os.cpu_count(), "notes": notes,
               "cli_s": cli, "module_s": module, "engine_init_s": init,
               "engine_s": engine_s, "engine_gpu_stages_s": gpu_s, "mesh_bytes": mesh_bytes,
               "dask1_s": dask1,
               "dask1_startup_s": start1, "dask2_s": dask2, "dask2_startup_s": start2,
               "identical": identical, "paths": paths}
    (args.out / "results.json").write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
