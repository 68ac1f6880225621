#!/usr/bin/python3
"""Page faults: huge pages on and off, and an optional baseline program (docs/performance.md).

    bench/memory_pages.py [--exe build/fdmsurf] [--baseline OTHER_FDMSURF] [--rounds 3]
                          [--structures 1crn,4hhb,4yvs,1aon] [--method fdm] [--stages a,b]

Runs each structure with default options in alternating rounds (one warm-up round first, not
counted): the program as it starts by default (restarting with huge pages where the host allows,
src/cli/huge_pages.hpp), the same program with FDMSURF_HUGE_PAGES=0, and, with --baseline, that
other build with FDMSURF_HUGE_PAGES=0 (an older fdmsurf ignores the variable). For each: the
median of fdmsurf's own time (total_ms), process wall time, system CPU time, minor page faults
and peak resident memory (from wait4's rusage), the stages named by --stages (ms, `times` of
--stats json), and whether the PLY files are byte-identical to the first case's.

Structures: tests/data first, then ../shared/data (FDMSURF_SHARED moves it); those not found are
listed and skipped. Prints a Markdown table with the machine, the device and the load.
"""

import argparse
import json
import os
import pathlib
import platform
import statistics
import tempfile
import time

from cold_start import ROOT, SHARED, find  # bench/cold_start.py: tests/data, then ../shared/data


def run_case(exe, src, out, env, extra, tmp):
    """One run, its stdout and stderr in files; wait4 gives the child's own rusage."""
    cmd = [exe, str(src), "-o", str(out), "--stats", "json", *extra]
    so, se = tmp / "stdout", tmp / "stderr"
    flags = os.O_WRONLY | os.O_CREAT | os.O_TRUNC
    t0 = time.perf_counter()
    pid = os.posix_spawn(exe, cmd, {**os.environ, **env},
                         file_actions=[(os.POSIX_SPAWN_OPEN, 1, str(so), flags, 0o644),
                                       (os.POSIX_SPAWN_OPEN, 2, str(se), flags, 0o644)])
    _, status, ru = os.wait4(pid, 0)
    wall = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{se.read_text()}")
    return {"wall": wall, "stats": json.loads(so.read_text()), "sys": ru.ru_stime,
            "faults": ru.ru_minflt, "rss_mb": ru.ru_maxrss / 1024, "ply": out.read_bytes()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default=str(ROOT / "build" / "fdmsurf"))
    ap.add_argument("--baseline", help="another fdmsurf program, run with small pages")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--structures", default="1crn,4hhb,4yvs,1aon")
    ap.add_argument("--method", default="fdm")
    ap.add_argument("--stages", default="density,fft-forward,upload-part,stitch,mesh-stats")
    args = ap.parse_args()
    if not os.access(args.exe, os.X_OK):
        raise SystemExit(f"bench/memory_pages.py: {args.exe} is missing "
                         "(run scripts/setup-debian.sh)")
    cases = [("huge pages (default)", args.exe, {}),
             ("FDMSURF_HUGE_PAGES=0", args.exe, {"FDMSURF_HUGE_PAGES": "0"})]
    if args.baseline:
        cases.append((f"baseline {args.baseline}, small pages", args.baseline,
                      {"FDMSURF_HUGE_PAGES": "0"}))
    stages = [s for s in args.stages.split(",") if s]
    extra = ["--method", args.method]
    with open("/sys/kernel/mm/transparent_hugepage/enabled") as f:
        thp = f.read().strip()
    rows, missing = [], []
    device = None
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as t:
        tmp = pathlib.Path(t)
        for name in args.structures.split(","):
            src = find(name)
            if src is None:
                missing.append(name)
                continue
            results = {c[0]: [] for c in cases}
            for r in range(args.rounds + 1):
                for label, exe, env in cases:
                    res = run_case(exe, src, tmp / f"{name}.ply", env, extra, tmp)
                    device = res["stats"].get("device")
                    if r > 0:
                        results[label].append(res)
                loads.append(os.getloadavg()[0])
            first = results[cases[0][0]][-1]["ply"]
            for label, _, _ in cases:
                rs = results[label]
                med = lambda f: statistics.median(f(x) for x in rs)  # noqa: E731
                rows.append((name, label, med(lambda x: x["stats"]["total_ms"]),
                             med(lambda x: x["wall"]), med(lambda x: x["sys"]),
                             med(lambda x: x["faults"]), med(lambda x: x["rss_mb"]),
                             [med(lambda x, s=s: x["stats"]["times"].get(s, 0.0)) for s in stages],
                             rs[-1]["ply"] == first))
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, kernel {platform.release()}; "
          f"device: {device}; transparent_hugepage/enabled: {thp}; 1-minute load "
          f"{min(loads):.2f}-{max(loads):.2f}\n")
    print(f"--method {args.method}, median of {args.rounds} alternating rounds after a warm-up\n")
    print("| structure | case | fdmsurf (ms) | wall (s) | system CPU (s) | minor faults | "
          "peak RSS (MB) | " + " | ".join(f"{s} (ms)" for s in stages) + " | same PLY |")
    print("|---|---|---|---|---|---|---|" + "---|" * len(stages) + "---|")
    for name, label, total, wall, sys_s, faults, rss, st, same in rows:
        print(f"| {name.upper()} | {label} | {total:.0f} | {wall:.2f} | {sys_s:.2f} | "
              f"{faults:.0f} | {rss:.0f} | " + " | ".join(f"{v:.0f}" for v in st) +
              f" | {'yes' if same else 'NO'} |")
    if missing:
        print(f"\nnot found (tests/data, {SHARED}/data): {', '.join(missing)}")


if __name__ == "__main__":
    main()
