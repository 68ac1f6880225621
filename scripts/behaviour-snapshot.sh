#!/usr/bin/env bash
# Writes the outputs of a fixed set of fdmsurf runs into a folder and their SHA-256 sums into
# FOLDER/SHA256SUMS, so that two builds can be shown to behave the same (byte-identical files):
#
#   scripts/behaviour-snapshot.sh BUILD_DIR OUT_DIR
#   diff before/SHA256SUMS after/SHA256SUMS
#
# The set: 1CRN and 4HHB (tests/data) as fdm SES, exact SES (edt), vdw and sas, --color chain,
# --properties, --areas (csv and json), `fdmsurf msms` files, a GLB, an OBJ, an STL, an OFF and a
# PNG. Each run's standard output (its time line taken out) is kept too, so a changed summary
# shows. Used for restructurings that must not change behaviour (CONTRIBUTING.md).
set -euo pipefail

if (($# != 2)); then
    echo "usage: $0 BUILD_DIR OUT_DIR" >&2
    exit 2
fi
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bin=$(realpath "$1")/fdmsurf
out=$2
mkdir -p "$out"
out=$(realpath "$out")
# The inputs from one fixed folder, so that outputs that name their input (summaries, MSMS
# headers, areas files) are the same whichever checkout runs the script.
data=/tmp/fdmsurf-snapshot-data
mkdir -p "$data"
cp tests/data/1crn.pdb tests/data/4hhb.pdb.gz tests/data/1crn.xyzrn tests/data/4hhb.xyzrn "$data/"
cd "$out"  # outputs are named relative to it, so that two snapshots name them alike

run() {  # run NAME ARGS...: fdmsurf ARGS, its standard output kept as NAME.log (times removed)
    local name=$1
    shift
    "$bin" "$@" | sed -E -e '/^  time /d' -e 's/[0-9]+(\.[0-9]+)? ?(ms|s)\b/T/g' \
        >"$name.log"
}

for s in 1crn 4hhb; do
    in=$data/$s.pdb
    [[ -f $in ]] || in=$data/$s.pdb.gz
    run "$s-fdm" "$in" -o "$s-fdm.ply"
    run "$s-edt" "$in" -o "$s-edt.ply" --method edt
    run "$s-vdw" "$in" -o "$s-vdw.ply" --surface vdw
    run "$s-sas" "$in" -o "$s-sas.ply" --surface sas
    run "$s-chain" "$in" -o "$s-chain.ply" --color chain
    run "$s-props" "$in" -o "$s-props.ply" \
        --properties coulombic,hydrophobicity,shape_index,mean_curvature
    run "$s-areas-sas" "$in" --surface sas --areas "$s-sas-areas.csv"
    run "$s-areas-ses" "$in" -o "$s-areas.ply" --areas "$s-ses-areas.json"
    run "$s-glb" "$in" -o "$s.glb" --color chain --properties coulombic
    run "$s-obj" "$in" -o "$s.obj"
    run "$s-stl" "$in" -o "$s.stl"
    run "$s-off" "$in" -o "$s.off"
    run "$s-stats" "$in" -o "$s-stats.ply" --stats json
    run "$s-msms" msms -if "$data/$s.xyzrn" -of "$s-msms" -af "$s-msms"
done
run 1crn-png "$data/1crn.pdb" -o "1crn.png" --color element
run 4hhb-buried "$data/4hhb.pdb.gz" --surface sas --areas "4hhb-AB.csv" --buried A:B

# --stats json carries timings: keep its keys and the values that are not times.
for f in "$out"/*-stats.log; do
    python3 - "$f" <<'EOF'
import json, sys
path = sys.argv[1]
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items()
                if not any(w in k for w in ("time", "seconds", "_ms", "_s", "stages", "peak"))}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
lines = []
for line in open(path):
    line = line.strip()
    if line.startswith("{"):
        lines.append(json.dumps(strip(json.loads(line)), sort_keys=True))
    else:
        lines.append(line)
open(path, "w").write("\n".join(lines) + "\n")
EOF
done

find . -type f ! -name SHA256SUMS | sort | xargs sha256sum >SHA256SUMS
echo "behaviour-snapshot: $(wc -l <SHA256SUMS) files in $out (SHA256SUMS)"
