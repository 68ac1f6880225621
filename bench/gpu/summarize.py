#!/usr/bin/env python3
"""Tables from bench/gpu/run.sh's results folder (bench.jsonl, compare.jsonl): per label
(structure-method-spacing) the median warm whole-process wall time, the device work (the sum of
the GPU-timestamped stages), the transfers, the host stages, the peak device memory that
nvidia-smi saw (minus its first sample), the mesh, and the per-stage medians. Standard library
only, so it runs under any python3 (the GPU machine's too).

    python3 bench/gpu/summarize.py RESULTS_DIR
"""
import json
import statistics
import sys
from collections import defaultdict
from pathlib import Path

# Stages timed with device timestamps (EngineImpl's CommandRecorder marks), without transfers.
GPU = {"density", "fft-forward", "mask", "fft-inverse", "mc-occupancy", "mc-count", "mc-scan",
       "mc-vertices", "mc-triangles", "ses-distance", "vertex-atoms", "coulombic"}
TRANSFER = {"read-back", "read-field", "upload-mesh", "upload-part"}


def median(xs):
    return statistics.median(xs) if xs else float("nan")


def main():
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else "gpu-out")
    rows = [json.loads(line) for line in (folder / "bench.jsonl").read_text().splitlines() if line.strip()]
    by = defaultdict(list)
    order = []
    for r in rows:
        key = (r["label"], r["phase"])
        if key not in by:
            order.append(key)
        by[key].append(r)
    print("| run | phase | n | rc | wall ms | device ms | transfer ms | init ms | host ms | peak MiB | grid | slabs | triangles | area | device |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    stage_rows = []
    for key in order:
        rs = by[key]
        ok = [r for r in rs if r.get("rc") == 0]
        label, phase = key
        if not ok:
            err = rs[-1].get("stderr", "").strip().splitlines()
            print(f"| {label} | {phase} | {len(rs)} | {rs[-1].get('rc')} | failed: {err[-1] if err else ''} |")
            continue

        def med(f):
            return median([f(r) for r in ok])
        times = [r.get("times", {}) for r in ok]
        gpu = med(lambda r: sum(v for k, v in r["times"].items() if k in GPU))
        tr = med(lambda r: sum(v for k, v in r["times"].items() if k in TRANSFER))
        init = med(lambda r: r["times"].get("init", 0.0))
        host = med(lambda r: sum(v for k, v in r["times"].items()
                                 if k not in GPU and k not in TRANSFER and k != "init"))
        r0 = ok[0]
        g = r0.get("grid", {})
        dims = "x".join(str(d) for d in g.get("dims", []))
        peak = max(r["gpu_mem_peak_mib"] - r["gpu_mem_base_mib"] for r in ok)
        print(f"| {label} | {phase} | {len(ok)} | 0 | {med(lambda r: r['wall_ms']):.0f} | {gpu:.1f} | {tr:.1f} | "
              f"{init:.0f} | {host:.0f} | {peak} | {dims} | {g.get('slabs', '')} | {r0.get('triangles', '')} | "
              f"{r0.get('area', 0):.1f} | {r0.get('device', '')} |")
        if phase == "warm":
            stages = defaultdict(list)
            for t in times:
                for k, v in t.items():
                    stages[k].append(v)
            stage_rows.append((label, {k: median(v) for k, v in stages.items()}))
    print()
    print("Per-stage medians, warm runs (ms):")
    for label, st in stage_rows:
        print(f"- {label}: " + ", ".join(f"{k} {v:.2f}" for k, v in st.items()))
    ab = defaultdict(dict)
    for (label, phase), rs in by.items():
        ok = [r for r in rs if r.get("rc") == 0]
        if phase == "warm" and "@" in label and ok:
            base, variant = label.rsplit("@", 1)
            ab[base][variant] = ok
    if ab:
        print()
        print("Before/after (median warm wall ms; host = stages other than device, transfers, init):")
        print("| run | base wall | new wall | new/base | base host | new host | base mesh-stats | new mesh-stats |")
        print("|---|---|---|---|---|---|---|---|")
        for base, v in ab.items():
            if "base" not in v or "new" not in v:
                continue
            def wall(rs):
                return median([r["wall_ms"] for r in rs])
            def host(rs):
                return median([sum(x for k, x in r["times"].items()
                                   if k not in GPU and k not in TRANSFER and k != "init") for r in rs])
            def st(rs, name):
                return median([r["times"].get(name, 0.0) for r in rs])
            b, n = v["base"], v["new"]
            print(f"| {base} | {wall(b):.0f} | {wall(n):.0f} | {wall(n) / wall(b):.2f} | {host(b):.0f} | "
                  f"{host(n):.0f} | {st(b, 'mesh-stats'):.0f} | {st(n, 'mesh-stats'):.0f} |")
    comp = folder / "compare.jsonl"
    if comp.exists():
        print()
        print("GPU mesh against lavapipe's (fdmsurf compare):")
        for line in comp.read_text().splitlines():
            if line.strip():
                print("- " + line.strip()[:600])


if __name__ == "__main__":
    main()
