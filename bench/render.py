#!/usr/bin/env python3
"""Cost of the pictures (issue 15; docs/rendering.md): render time against the surface's own.

For each structure, runs build/fdmsurf in rounds, alternating in one round so that load on a
shared machine hits both alike:
  picture  -o TMP.png --image-size WxH: the surface left on the device and drawn there
  mesh     -o TMP.ply: the usual run, the mesh read back, cavities removed, written
and prints a Markdown table of medians from --stats json:
  surface      the picture run's total less parse, init, the render stages and png (the
               surface computed on the device, in the same process as the render)
  mesh run     the mesh run's total less parse, init, write and mesh-stats (its surface)
  render       render-bounds + render-scene + render-shade + render-read + render-host: the
               picture from the device mesh to the host's RGBA bytes
  png          encoding and writing the file
  render ÷ surface, and (render + png) ÷ surface (goal: at most 25% on 1AON at 1024 x 768)
with the render stages apart (GPU timestamps on lavapipe).

  bench/render.py [--reps 3] [--structures 1crn,4hhb,1aon] [--size 1024x768] [-- EXTRA...]

Structures are read from tests/data, else ../shared/data (FDMSURF_SHARED moves it).
"""
import argparse, os, platform, statistics, sys, tempfile

from benchlib import ROOT, SHARED, find, run_json
RENDER = ("render-bounds", "render-scene", "render-shade", "render-read", "render-host")
NOT_SURFACE = ("parse", "init", "png", "write", "mesh-stats") + RENDER


def run(exe, args):
    return run_json(exe, args)[1]


def surface_ms(stats):
    return stats["total_ms"] - sum(stats["times"].get(n, 0.0) for n in NOT_SURFACE)


def render_ms(stats):
    return sum(stats["times"].get(n, 0.0) for n in RENDER)


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--structures", default="1crn,4hhb,1aon")
    ap.add_argument("--size", default="1024x768")
    ap.add_argument("extra", nargs="*", help="more fdmsurf options for both runs (after --)")
    args = ap.parse_args()
    exe = os.path.join(ROOT, "build", "fdmsurf")
    if not os.access(exe, os.X_OK):
        sys.exit("bench/render.py: build/fdmsurf is missing (run scripts/setup-debian.sh)")
    rows, device, loads = [], "", [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        png, ply = os.path.join(tmp, "s.png"), os.path.join(tmp, "s.ply")
        for name in args.structures.split(","):
            path = find(name)
            if path is None:
                print(f"note: {name} not found in tests/data or {os.path.abspath(SHARED)}/data: left out",
                      file=sys.stderr)
                continue
            base = [path, "--stats", "json"] + args.extra
            pic, mesh = [], []
            for _ in range(args.reps):
                pic.append(run(exe, base + ["-o", png, "--image-size", args.size]))
                mesh.append(run(exe, base + ["-o", ply]))
                loads.append(os.getloadavg()[0])
            device = pic[0]["device"]
            med = lambda runs, f: statistics.median(f(s) for s in runs)
            stage = lambda n: med(pic, lambda s: s["times"].get(n, 0.0))
            rows.append(dict(
                name=name, triangles=pic[0]["triangles"], surface=med(pic, surface_ms),
                mesh_surface=med(mesh, lambda s: s["total_ms"] - sum(s["times"].get(n, 0.0) for n in NOT_SURFACE)),
                render=med(pic, render_ms), png=stage("png"),
                share=med(pic, lambda s: render_ms(s) / surface_ms(s)),
                share_png=med(pic, lambda s: (render_ms(s) + s["times"].get("png", 0.0)) / surface_ms(s)),
                stages={n: stage(n) for n in RENDER}))
    if not rows:
        sys.exit("bench/render.py: nothing measured (no structure found)")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores ({cpu_model()}), load average "
          f"{min(loads):.2f}-{max(loads):.2f} during the runs; device: {device}; picture "
          f"{args.size}, median of {args.reps} alternating rounds, ms\n")
    print("| structure | triangles | surface (picture run) | surface (mesh run) | render | png | "
          "render ÷ surface | (render + png) ÷ surface | bounds | scene | shade | read | host |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        s = r["stages"]
        print(f"| {r['name']} | {r['triangles']:,} | {r['surface']:,.0f} | {r['mesh_surface']:,.0f} | "
              f"{r['render']:,.0f} | {r['png']:,.0f} | {100 * r['share']:.1f}% | {100 * r['share_png']:.1f}% | "
              f"{s['render-bounds']:,.0f} | {s['render-scene']:,.0f} | {s['render-shade']:,.0f} | "
              f"{s['render-read']:,.0f} | {s['render-host']:,.0f} |")


if __name__ == "__main__":
    main()
