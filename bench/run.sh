#!/bin/sh
# fdmsurf side-by-side benchmark against Mol*, PyMOL and EDTSurf (docs/performance.md).
#
#   bench/run.sh [--reps 3] [--reps-large 2] [--structures 1crn,4hhb,4yvs,1aon]
#                [--tools fdmsurf,molstar,pymol-q0,pymol-q1,edtsurf] [--skip 1aon:pymol-q1]
#                [--timeout 300] [--no-scaling] [--out bench/out]   (all options: --help)
#
# Needs build/fdmsurf (cd build && ninja), /usr/bin/python3 with python3-numpy, python3-scipy
# and python3-gemmi (for ../shared/tools/peers.py), GNU time, and for the peers the Debian
# packages edtsurf and python3-pymol, and node + npm for Mol*. As root, missing Debian packages
# are installed with apt-get (set BENCH_NO_APT=1 to skip); a peer that is still missing is
# left out with a note. Mol* is installed once with npm into bench/.cache/molstar (a copy of
# ../shared/tools/molstar, which is read-only; BENCH_MOLSTAR_DIR moves it). Results go to
# bench/out/ (report.md, results.json, bench.log, the meshes). Takes 14-20 minutes on 2 cores.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
shared=${FDMSURF_SHARED:-$root/../shared}

missing=""
[ -x /usr/bin/time ] || missing="$missing time"
/usr/bin/python3 -c 'import numpy, scipy' 2>/dev/null || missing="$missing python3-numpy python3-scipy"
/usr/bin/python3 -c 'import gemmi' 2>/dev/null || missing="$missing python3-gemmi"
/usr/bin/python3 -c 'import pymol' 2>/dev/null || missing="$missing python3-pymol"
command -v EDTSurf >/dev/null 2>&1 || missing="$missing edtsurf"
if [ -n "$missing" ] && [ "$(id -u)" = 0 ] && [ -z "${BENCH_NO_APT:-}" ]; then
    echo "bench: installing$missing" >&2
    apt-get install -y $missing >/dev/null 2>&1 || \
        { apt-get update >/dev/null 2>&1 && apt-get install -y $missing >/dev/null 2>&1; } || \
        echo "bench: could not install$missing; those peers are left out" >&2
fi
[ -x /usr/bin/time ] || { echo "bench: GNU time (/usr/bin/time) is required: apt-get install time" >&2; exit 1; }

ms=${BENCH_MOLSTAR_DIR:-$here/.cache/molstar}
if [ ! -d "$ms/node_modules/molstar" ] && command -v npm >/dev/null 2>&1; then
    echo "bench: installing Mol* (npm) into $ms" >&2
    { mkdir -p "$ms" && cp "$shared/tools/molstar/package.json" "$shared/tools/molstar/ms_surface.js" "$ms/" && \
        (cd "$ms" && npm install --no-audit --no-fund >/dev/null 2>&1); } || \
        echo "bench: npm install of Mol* failed; Mol* is left out" >&2
fi
if [ ! -x "$root/build/fdmsurf" ]; then
    echo "bench: build/fdmsurf missing: cd build && ninja" >&2
    exit 1
fi
exec /usr/bin/python3 "$here/bench.py" --shared "$shared" --molstar "$ms" "$@"
