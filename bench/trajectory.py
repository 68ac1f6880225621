#!/usr/bin/env python3
"""Per-frame SASA and SES over a trajectory: fdmsurf's Engine.trajectory against mdtraj's
shrake_rupley, both measured against FreeSASA's Lee-Richards (docs/trajectories.md).

    PYTHONPATH=build/python python3 bench/trajectory.py [--frames 1000] [--ses-frames 20]

The trajectory is made from 4HHB (tests/data/4hhb.pdb.gz, 4,558 heavy atoms as fdmsurf reads
it): a seeded Ornstein-Uhlenbeck random walk of every atom about its crystal position,
x(t+1) = x(t) + theta (x0 - x(t)) + sigma N(0, 1) per axis with theta = 0.1 and sigma = 0.1 Å,
whose stationary spread (0.23 Å per axis, 0.4 Å RMS: a crystallographic B of about 4 Å²) is
that of thermal motion; frames are 100 steps apart, so that consecutive frames decorrelate.
Every tool gets the same coordinates (float32) and the same radii (fdmsurf's: Bondi, gemmi's
table for Fe).

Measured, side by side in one run and in alternating blocks of frames:
- per-atom SASA (probe 1.4 Å) per frame: fdmsurf (exact sphere patches, Engine.trajectory with
  ses=False) and mdtraj.shrake_rupley (960 points, its default; mdtraj's radii replaced by
  fdmsurf's through change_radii), ms per frame;
- the error of each against FreeSASA's Lee-Richards at --resolution 200 (slices per atom) on
  --ref-frames frames: mean absolute error per atom (Å²) and the total's relative error;
- SES area and volume per frame at 0.5 Å (Engine.trajectory, sasa=False): ms per frame and the
  stages that take the time;
- memory: the process's RSS after each frame of the SASA run; the mean of the first and of the
  last 10 % of frames.
"""

import argparse
import gzip
import os
import pathlib
import platform
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]


def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def make_walk(xyz0, frames, seed, theta=0.1, sigma=0.1, steps_per_frame=100):
    """(frames, atoms, 3) float32: the Ornstein-Uhlenbeck walk sampled every steps_per_frame
    steps (exactly: the walk's transition over k steps is a Gaussian of known mean and spread)."""
    rng = np.random.default_rng(seed)
    x0 = xyz0.astype(np.float64)
    decay = (1.0 - theta) ** steps_per_frame
    # Variance of the displacement after k steps of the AR(1) process, per axis.
    spread = sigma * np.sqrt((1.0 - (1.0 - theta) ** (2 * steps_per_frame)) /
                             (1.0 - (1.0 - theta) ** 2))
    out = np.empty((frames,) + x0.shape, np.float32)
    x = x0.copy()
    for f in range(frames):
        out[f] = x
        x = x0 + decay * (x - x0) + spread * rng.standard_normal(x0.shape)
    return out


def freesasa_areas(structure, xyz, workdir, resolution):
    """FreeSASA's Lee-Richards areas per atom (Å²) for `structure`'s atoms at `xyz`, with
    fdmsurf's radii (written into the occupancy column, --radius-from-occupancy)."""
    pdb = pathlib.Path(workdir) / "frame.pdb"
    lines = []
    for i in range(len(structure)):
        x, y, z = xyz[i]
        lines.append(f"{'HETATM' if structure.hetero[i] else 'ATOM  '}{(i + 1) % 100000:5d} "
                     f"{structure.name[i]:<4} {structure.residue_name[i]:>3} "
                     f"{structure.chain[i][:1]}{structure.residue_number[i] % 10000:4d}    "
                     f"{x:8.3f}{y:8.3f}{z:8.3f}{structure.radii[i]:6.2f}{0.0:6.2f}          "
                     f"{structure.element[i]:>2}")
    pdb.write_text("\n".join(lines) + "\nEND\n")
    done = subprocess.run(
        ["freesasa", "--lee-richards", f"--resolution={resolution}", "--probe-radius=1.4",
         "--radius-from-occupancy", "--hetatm", "--hydrogen", "--format=pdb",
         str(pdb)], capture_output=True, encoding="utf-8", check=True)
    areas = [float(line[60:66]) for line in done.stdout.splitlines()
             if line.startswith(("ATOM", "HETATM"))]
    if len(areas) != len(structure):
        raise RuntimeError(f"freesasa returned {len(areas)} atoms for {len(structure)}")
    return np.array(areas)


def machine():
    cpu = "?"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"],
                            capture_output=True, encoding="utf-8").stdout.strip()
    return cpu, os.cpu_count(), commit


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=1000, help="frames of the SASA run")
    parser.add_argument("--mdtraj-frames", type=int, default=100,
                        help="frames mdtraj computes (its time per frame is flat)")
    parser.add_argument("--ses-frames", type=int, default=20, help="frames of the SES run")
    parser.add_argument("--ref-frames", type=int, default=5, help="frames FreeSASA computes")
    parser.add_argument("--resolution", type=int, default=200,
                        help="FreeSASA Lee-Richards slices per atom")
    parser.add_argument("--block", type=int, default=20, help="frames per alternating block")
    parser.add_argument("--seed", type=int, default=2026)
    args = parser.parse_args()

    import fdmsurf
    import mdtraj as md

    structure = fdmsurf.read_structure(REPO / "tests/data/4hhb.pdb.gz")
    n = len(structure)
    frames = make_walk(structure.xyz, args.frames, args.seed)
    engine = fdmsurf.Engine()

    # mdtraj: the same atoms (a topology of the structure's records), fdmsurf's radii.
    with tempfile.TemporaryDirectory() as tmp:
        plain = pathlib.Path(tmp) / "4hhb.pdb"
        plain.write_bytes(gzip.open(REPO / "tests/data/4hhb.pdb.gz").read())
        whole = md.load(str(plain))
    selected = fdmsurf.as_structure(whole)
    assert len(selected) == n, (len(selected), n)
    index = selected.serial.astype(np.int64) - 1
    top = whole.atom_slice(index).topology
    radii_nm = {}
    for atom, r in zip(top.atoms, structure.radii):
        radii_nm[atom.element.symbol] = float(r) / 10.0
    traj = md.Trajectory(frames[: args.mdtraj_frames] / np.float32(10.0), top)

    # 1. SASA per frame, alternating blocks: fdmsurf then mdtraj on the same frames.
    fd_ms, md_ms, fd_cpu, md_cpu, rss = [], [], [], [], []
    fd_areas_first = None
    run = engine.trajectory(frames, topology=structure, ses=False, progress=False)
    rows = iter(run)
    done = 0
    while done < args.frames:
        block = min(args.block, args.frames - done)
        t, c = time.perf_counter(), time.process_time()
        for _ in range(block):
            row = next(rows)
            rss.append(rss_mb())
            if row.frame == 0:
                fd_areas_first = row.atom_sasa.copy()
        fd_ms.append((time.perf_counter() - t) * 1000.0 / block)
        fd_cpu.append((time.process_time() - c) * 1000.0 / block)
        if done < args.mdtraj_frames:
            b = min(block, args.mdtraj_frames - done)
            t, c = time.perf_counter(), time.process_time()
            md.shrake_rupley(traj[done: done + b], probe_radius=0.14, n_sphere_points=960,
                             mode="atom", change_radii=radii_nm)
            md_ms.append((time.perf_counter() - t) * 1000.0 / b)
            md_cpu.append((time.process_time() - c) * 1000.0 / b)
        done += block

    # 2. Accuracy against FreeSASA Lee-Richards on --ref-frames frames spread over the run.
    picks = np.linspace(0, min(args.frames, args.mdtraj_frames) - 1, args.ref_frames).astype(int)
    errors = {"fdmsurf": [], "mdtraj": [], "fdmsurf-sr1000": []}
    with tempfile.TemporaryDirectory() as tmp:
        for f in picks:
            ref = freesasa_areas(structure, frames[f], tmp, args.resolution)
            moved = fdmsurf.Structure(frames[f], structure.radii)
            ours = fdmsurf.exact_areas(moved)
            sampled = fdmsurf.sas_areas(moved, points=1000)
            theirs = md.shrake_rupley(traj[int(f)], probe_radius=0.14, n_sphere_points=960,
                                      mode="atom", change_radii=radii_nm)[0] * 100.0
            for name, a in (("fdmsurf", ours), ("mdtraj", theirs), ("fdmsurf-sr1000", sampled)):
                errors[name].append((np.abs(a - ref).mean(), abs(a.sum() - ref.sum()) / ref.sum(),
                                     ref.sum()))

    # 3. SES area and volume per frame at 0.5 Å, with its stages.
    stage_ms = {}
    ses_ms = []
    ses_rows = []

    def stages(row, result):
        for name, ms in result.times.items():
            stage_ms[name] = stage_ms.get(name, 0.0) + ms

    t0 = time.perf_counter()
    ses_run = engine.trajectory(frames[: args.ses_frames], topology=structure, sasa=False,
                                spacing=0.5, callback=stages, progress=False)
    prepass = None
    for row in ses_run:
        if prepass is None:
            prepass = (time.perf_counter() - t0) * 1000.0 - row.ms
        ses_ms.append(row.ms)
        ses_rows.append(row)

    cpu, cores, commit = machine()
    load = os.getloadavg()[0]
    first = np.mean(rss[: max(1, len(rss) // 10)])
    last = np.mean(rss[-max(1, len(rss) // 10):])
    print(f"# bench/trajectory.py: 4HHB, {n} atoms, {args.frames} frames (seed {args.seed}); "
          f"commit {commit}; {cpu}, {cores} cores; device {engine.device['name']}; "
          f"load {load:.2f}; {time.strftime('%Y-%m-%d %H:%M')}")
    print()
    print("| per-atom SASA per frame (probe 1.4 Å) | wall ms/frame (median of blocks) | CPU ms/frame "
          "(all threads) | frames | mean abs. error per atom vs Lee-Richards (Å²) | total's rel. "
          "error |")
    print("|---|---|---|---|---|---|")
    fd, mt = np.median(fd_ms), np.median(md_ms)
    e = {k: np.mean(v, axis=0) for k, v in errors.items()}
    print(f"| fdmsurf Engine.trajectory (exact sphere patches) | {fd:.1f} | "
          f"{np.median(fd_cpu):.1f} | {args.frames} | "
          f"{e['fdmsurf'][0]:.3f} | {e['fdmsurf'][1]:.2e} |")
    print(f"| mdtraj.shrake_rupley (960 points) | {mt:.1f} | {np.median(md_cpu):.1f} | "
          f"{args.mdtraj_frames} | "
          f"{e['mdtraj'][0]:.3f} | {e['mdtraj'][1]:.2e} |")
    print(f"| (fdmsurf.sas_areas, Shrake-Rupley 1000 points, accuracy only) | | | | "
          f"{e['fdmsurf-sr1000'][0]:.3f} | {e['fdmsurf-sr1000'][1]:.2e} |")
    print()
    print(f"fdmsurf is {mt / fd:.1f}x faster than mdtraj per frame in wall time, "
          f"{np.median(md_cpu) / np.median(fd_cpu):.1f}x in CPU time. Reference: FreeSASA "
          f"Lee-Richards, resolution {args.resolution}, frames {list(map(int, picks))}, total "
          f"{np.mean([x[2] for x in errors['fdmsurf']]):.1f} Å².")
    print()
    top_stages = sorted(stage_ms.items(), key=lambda kv: -kv[1])[:5]
    print(f"SES at 0.5 Å, {len(ses_ms)} frames: {np.median(ses_ms):.0f} ms/frame (median), grid "
          f"{ses_run.grid}, first pass over the frames for the grid {prepass:.0f} ms; area "
          f"{np.mean([r.area for r in ses_rows]):.1f} Å², volume "
          f"{np.mean([r.volume for r in ses_rows]):.1f} Å³, cavities "
          f"{np.mean([r.cavities for r in ses_rows]):.1f}")
    print("stages (ms per frame): " + ", ".join(
        f"{k} {v / len(ses_ms):.0f}" for k, v in top_stages))
    print()
    print(f"memory (RSS over the SASA run): first 10 % of frames {first:.1f} MB, last 10 % "
          f"{last:.1f} MB ({(last - first) / first * 100:+.2f} %)")
    if fd_areas_first is None:
        sys.exit("no frame 0")


if __name__ == "__main__":
    main()
