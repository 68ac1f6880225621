#!/usr/bin/env python3
"""Long run of one process (issue: hardening, item 6): N surfaces of small generated structures
through one fdmsurf.Engine, the resident memory (VmRSS) and the time per surface recorded every
`--every` surfaces; then the same structures through one Engine per thread in 2 threads, whose
meshes must equal one thread's. Prints a table; --csv writes the curve.

    PYTHONPATH=build/python /usr/bin/python3 bench/long_run.py [--surfaces 10000] [--every 100]

Flat means: the mean RSS of the last 10% of samples within 5% of the first 10% after warm-up
(the first 100 surfaces), and the same for the time per surface.
"""
import argparse
import os
import sys
import threading
import time

import numpy as np

import fdmsurf


def rss_mib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def structure(k):
    """A small random chain (20-80 atoms), different for every k, reproducible."""
    rng = np.random.default_rng(k)
    n = int(rng.integers(20, 81))
    steps = rng.normal(size=(n, 3))
    steps *= (1.3 + 0.3 * rng.random((n, 1))) / np.linalg.norm(steps, axis=1, keepdims=True)
    xyz = np.cumsum(steps, axis=0).astype(np.float32)
    radii = (1.2 + 0.8 * rng.random(n)).astype(np.float32)
    return xyz, radii


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--surfaces", type=int, default=10000)
    ap.add_argument("--every", type=int, default=100)
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--surface", default="ses", help="ses (fdm: an FFT plan per grid size), vdw or sas")
    ap.add_argument("--csv", default="")
    ap.add_argument("--threads-check", type=int, default=200, help="structures compared in 2 threads")
    args = ap.parse_args()

    engine = fdmsurf.Engine()
    print(f"device: {engine.device['name']}; {args.surfaces} {args.surface} surfaces, spacing {args.spacing} Å",
          flush=True)
    samples = []  # (surfaces done, rss MiB, wall ms and process CPU ms per surface, last block)
    t_block = time.perf_counter()
    c_block = time.process_time()
    for k in range(args.surfaces):
        xyz, radii = structure(k)
        r = engine.surface(xyz, radii=radii, spacing=args.spacing, surface=args.surface)
        if not r.closed_manifold:
            print(f"structure {k}: not a closed manifold", file=sys.stderr)
            return 1
        if (k + 1) % args.every == 0:
            now, cpu = time.perf_counter(), time.process_time()
            samples.append((k + 1, rss_mib(), 1000.0 * (now - t_block) / args.every,
                            1000.0 * (cpu - c_block) / args.every))
            t_block, c_block = now, cpu
            if len(samples) % 10 == 0:
                print(f"  {k + 1:6d} surfaces: RSS {samples[-1][1]:.1f} MiB, {samples[-1][2]:.1f} ms/surface "
                      f"(CPU {samples[-1][3]:.1f} ms)", flush=True)
    if args.csv:
        with open(args.csv, "w") as f:
            f.write("surfaces,rss_mib,wall_ms_per_surface,cpu_ms_per_surface\n")
            for s in samples:
                f.write(f"{s[0]},{s[1]:.2f},{s[2]:.3f},{s[3]:.3f}\n")
    warm = [s for s in samples if s[0] > 100]
    tenth = max(1, len(warm) // 10)
    first, last = warm[:tenth], warm[-tenth:]
    rss0, rss1 = np.mean([s[1] for s in first]), np.mean([s[1] for s in last])
    t0, t1 = np.mean([s[2] for s in first]), np.mean([s[2] for s in last])
    c0, c1 = np.mean([s[3] for s in first]), np.mean([s[3] for s in last])
    print()
    print("| | first 10% after warm-up | last 10% | change |")
    print("|---|---|---|---|")
    print(f"| RSS (MiB) | {rss0:.1f} | {rss1:.1f} | {100 * (rss1 / rss0 - 1):+.1f}% |")
    print(f"| wall time per surface (ms) | {t0:.1f} | {t1:.1f} | {100 * (t1 / t0 - 1):+.1f}% |")
    print(f"| process CPU time per surface (ms) | {c0:.1f} | {c1:.1f} | {100 * (c1 / c0 - 1):+.1f}% |")
    flat = abs(rss1 / rss0 - 1) <= 0.05

    # One engine per thread, two threads: the same meshes as one thread.
    m = args.threads_check
    single = [engine.surface(structure(k)[0], radii=structure(k)[1], spacing=args.spacing, surface=args.surface)
              for k in range(m)]
    out = [None] * m

    def work(offset):
        e = fdmsurf.Engine()
        for k in range(offset, m, 2):
            xyz, radii = structure(k)
            out[k] = e.surface(xyz, radii=radii, spacing=args.spacing, surface=args.surface)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    same = all(np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
               for a, b in zip(single, out))
    print(f"\n2 threads, one engine each, {m} structures: meshes {'identical' if same else 'DIFFER'} to one thread's")
    print(f"RSS flat within 5%: {'yes' if flat else 'NO'}")
    return 0 if (flat and same) else 1


if __name__ == "__main__":
    sys.exit(main())
