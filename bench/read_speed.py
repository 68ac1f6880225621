#!/usr/bin/env python3
"""The structure readers' speed, one or two builds side by side (issue 36: 300 MB/s for XYZR and
PQR, 150 MB/s for PDB and mmCIF, gemmi's own speed the bound of those).

Runs each build's fdmsurf_bench_host on each input --reps times, alternating A B / B A, each run
a fresh process that reads the structure once (read_structure, as the CLI's parse stage; the
host stages then run on a one-triangle mesh, --mesh, and are not timed here), with the CLI's
transparent huge pages (GLIBC_TUNABLES=glibc.malloc.hugetlb=1). Prints per input the median ms
and MB/s of the file, and the machine's load before and after. With --gemmi, gemmi's read alone
of the PDB and mmCIF inputs (fdmsurf_bench_gemmi_read of the new build) as a third column, a
fresh process a run as the others, then both side by side in one process. Usage:

    bench/read_speed.py [--baseline OLD_BUILD_DIR] [--build build] [--reps 5] [--gemmi] INPUT...

The inputs of docs/performance.md: python3 bench/make_synthetic.py --kind shell -o shell.xyzr
and --format pqr -o shell.pqr; 1AON's PDB and 4YVS's mmCIF of ../shared/data, gunzipped.
Standard library only.
"""
import argparse
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile

TRIANGLE = """ply
format ascii 1.0
element vertex 3
property float x
property float y
property float z
element face 1
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
0 1 0
3 0 1 2
"""


def load():
    return os.getloadavg()[0]


def is_gemmi_format(path):
    return re.search(r"\.(pdb|ent|cif|mmcif)$", path, re.I) is not None


def read_ms(build, structure, mesh):
    """One fresh process's read; build "gemmi:DIR": gemmi's read alone, by DIR's bench."""
    env = dict(os.environ, GLIBC_TUNABLES="glibc.malloc.hugetlb=1")
    if build.startswith("gemmi:"):
        command = [os.path.join(build[6:], "fdmsurf_bench_gemmi_read"), structure, "--reps", "1",
                   "--only", "gemmi"]
    else:
        command = [os.path.join(build, "fdmsurf_bench_host"), structure, "--mesh", mesh, "--only",
                   "write", "--reps", "1", "--out", os.path.dirname(mesh)]
    out = subprocess.run(command, env=env, check=True, capture_output=True, text=True).stdout
    return float(re.search(r"^read .*: ([0-9.]+) ms", out, re.M).group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--baseline", help="build directory of the old build")
    parser.add_argument("--build", default="build", help="build directory of the new build")
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--gemmi", action="store_true", help="gemmi's read of PDB/mmCIF inputs")
    parser.add_argument("inputs", nargs="+")
    args = parser.parse_args()
    builds = [("new", args.build)] + ([("old", args.baseline)] if args.baseline else [])
    if args.gemmi:
        builds.append(("gemmi", "gemmi:" + args.build))
    load_before = load()
    with tempfile.TemporaryDirectory() as tmp:
        mesh = os.path.join(tmp, "triangle.ply")
        with open(mesh, "w") as f:
            f.write(TRIANGLE)
        times = {(b, i): [] for b, _ in builds for i in args.inputs}
        for r in range(args.reps):
            order = builds if r % 2 == 0 else builds[::-1]
            for structure in args.inputs:
                for name, build in order:
                    if name != "gemmi" or is_gemmi_format(structure):
                        times[(name, structure)].append(read_ms(build, structure, mesh))
    load_after = load()
    print(f"{platform.node()}, {os.cpu_count()} threads; 1-minute load {load_before:.2f} before, "
          f"{load_after:.2f} after; {args.reps} alternating runs, medians\n")
    head = "| input | MB |" + "".join(f" {n} ms | {n} MB/s |" for n, _ in builds)
    print(head + (" new / old |" if args.baseline else ""))
    print("|---" * (2 + 2 * len(builds) + (1 if args.baseline else 0)) + "|")
    for structure in args.inputs:
        mb = os.path.getsize(structure) / 1e6
        row = f"| {os.path.basename(structure)} | {mb:.1f} |"
        med = {}
        for name, _ in builds:
            if not times[(name, structure)]:
                row += " | |"
                continue
            med[name] = statistics.median(times[(name, structure)])
            row += f" {med[name]:.1f} | {mb / (med[name] / 1e3):.0f} |"
        if args.baseline:
            row += f" {med['new'] / med['old']:.2f} |"
        print(row)
    if args.gemmi:
        gemmi_inputs = [i for i in args.inputs if is_gemmi_format(i)]
        if gemmi_inputs:
            print()
            sys.stdout.flush()
            env = dict(os.environ, GLIBC_TUNABLES="glibc.malloc.hugetlb=1")
            subprocess.run([os.path.join(args.build, "fdmsurf_bench_gemmi_read"), *gemmi_inputs,
                            "--reps", str(max(args.reps, 5))], env=env, check=True)
            print(f"\n1-minute load after gemmi's reads: {load():.2f}")


if __name__ == "__main__":
    main()
