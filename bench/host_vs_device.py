#!/usr/bin/env python3
"""The stages a CPU device hands to the host, against the device's passes (issue 17, goals 2 and
4; docs/performance.md).

Runs build/fdmsurf on each structure in several modes, alternating within each round:
  device  --host-filter off --host-mc off --host-atoms off --host-ses off   VkFFT forward, mask,
                                           inverse; the marching-cubes passes; the vertex-atoms
                                           pass; the exact SES's pass (--method edt)
  filter  --host-filter auto, the others off   the Gaussian filter on the host (27 November,
                                           third session: bench/host_filter.py then)
  ses-device  all auto but --host-ses off  the exact SES's field on the device, the rest on the
                                           host (27 November, fourth session)
  host    all four auto                    the default: the filter, marching cubes, the vertex
                                           atoms and the exact SES's field on the host
and prints the slab count, the medians of fdmsurf's own total, of the filter stages, of the
marching-cubes stages, of the vertex atoms, of the density, of the exact SES's features, field
and snap, and the triangle count and area of each mode (the surfaces should agree to float
rounding). `auto` hands a stage to the host only on a CPU device
(lavapipe): on a GPU the modes are the same but for `device`'s explicit off.

  bench/host_vs_device.py [--reps 3] [--structures 1aon,4yvs] [--spacing 0.5] [--assembly]
                          [--modes device,host] [--extra "--method edt"]

Structures are read from tests/data, else ../shared/data (FDMSURF_SHARED moves it); 1AON is
only in ../shared/data: without it the script says so and measures what it finds.
"""
import argparse, os, platform, shlex, statistics, sys, tempfile

from benchlib import ROOT, SHARED, find, run_json

FILTER_STAGES = ("fft-forward", "mask", "fft-inverse", "filter-host")
MC_STAGES = ("upload-part", "mc-occupancy", "mc-count", "mc-scan", "mc-vertices", "mc-triangles",
             "read-back", "unpack-mesh", "mc-host")
ATOM_STAGES = ("vertex-atoms", "vertex-atoms-host")
SES_STAGES = ("ses-boxes", "ses-distance", "ses-host")
MODES = {"device": ["--host-filter", "off", "--host-mc", "off", "--host-atoms", "off", "--host-ses", "off",
                    "--host-density", "off"],
         "filter": ["--host-filter", "auto", "--host-mc", "off", "--host-atoms", "off", "--host-ses", "off",
                    "--host-density", "off"],
         "ses-device": ["--host-filter", "auto", "--host-mc", "auto", "--host-atoms", "auto",
                        "--host-ses", "off"],
         "host": ["--host-filter", "auto", "--host-mc", "auto", "--host-atoms", "auto", "--host-ses", "auto"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--structures", default="1aon,4yvs")
    ap.add_argument("--spacing", type=float, default=0.5)
    ap.add_argument("--assembly", action="store_true", help="--assembly 1 (4YVS: 317,160 atoms)")
    ap.add_argument("--modes", default="device,host", help="of " + ", ".join(MODES))
    ap.add_argument("--extra", default="", help="more fdmsurf options, e.g. \"--method edt\"")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "fdmsurf"))
    args = ap.parse_args()
    modes = args.modes.split(",")
    for m in modes:
        if m not in MODES:
            sys.exit(f"bench/host_vs_device.py: unknown mode {m} (expected {', '.join(MODES)})")
    rows, loads, device = [], [], ""
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.structures.split(","):
            path = find(name)
            if path is None:
                print(f"note: {name} not found in tests/data or {os.path.abspath(SHARED)}/data: left out",
                      file=sys.stderr)
                continue
            base = [path, "--spacing", str(args.spacing), "--stats", "json", "-o", os.path.join(tmp, "m.ply")]
            base += shlex.split(args.extra)
            if args.assembly:
                base += ["--assembly", "1"]
            runs = {m: [] for m in modes}
            for rep in range(args.reps):
                loads.append(os.getloadavg()[0])
                # The order turns from round to round: no mode always runs after the same one.
                for m in modes[rep % len(modes):] + modes[:rep % len(modes)]:
                    runs[m].append(run_json(args.exe, base + MODES[m])[1])
            for m in modes:
                stats = runs[m]
                device = stats[0]["device"]
                med = lambda f: statistics.median(f(s) for s in stats)
                stages = lambda s, names: sum(s["times"].get(k, 0.0) for k in names)
                rows.append(dict(name=f"{name}{' assembly' if args.assembly else ''}", mode=m,
                                 slabs=stats[0]["grid"]["slabs"],
                                 total=med(lambda s: s["total_ms"]),
                                 filt=med(lambda s: stages(s, FILTER_STAGES)),
                                 mc=med(lambda s: stages(s, MC_STAGES)),
                                 atoms=med(lambda s: stages(s, ATOM_STAGES)),
                                 density=med(lambda s: s["times"].get("density", 0.0)
                                             + s["times"].get("density-host", 0.0)),
                                 features=med(lambda s: s["times"].get("ses-features", 0.0)),
                                 ses=med(lambda s: stages(s, SES_STAGES)),
                                 snap=med(lambda s: s["times"].get("snap", 0.0)),
                                 tri=stats[-1]["triangles"], area=stats[-1]["area"]))
    if not rows:
        sys.exit("bench/host_vs_device.py: nothing measured")
    loads.append(os.getloadavg()[0])
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, 1-minute load {min(loads):.1f}-{max(loads):.1f}; "
          f"device: {device}; spacing {args.spacing} Å{' ' + args.extra if args.extra else ''}, "
          f"median of {args.reps} alternating rounds, ms\n")
    print("| structure | mode | slabs | total | filter stages | marching cubes | vertex atoms | density | "
          "SES features | SES field | snap | triangles | area (Å²) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['name']} | {r['mode']} | {r['slabs']} | {r['total']:,.0f} | {r['filt']:,.0f} | {r['mc']:,.0f} | {r['atoms']:,.0f} | "
              f"{r['density']:,.0f} | {r['features']:,.0f} | {r['ses']:,.0f} | {r['snap']:,.0f} | "
              f"{r['tri']:,} | {r['area']:,.2f} |")
    print("\n'filter stages': fft-forward + mask + fft-inverse, or filter-host; 'marching cubes': the device's "
          "passes with the part's upload, read-back and unpacking, or mc-host; 'vertex atoms': the pass and "
          "its host work, or the search on the host; 'SES field': ses-boxes + ses-distance, or ses-host; "
          "'total': fdmsurf's own total_ms "
          "of --stats json.")


if __name__ == "__main__":
    main()
