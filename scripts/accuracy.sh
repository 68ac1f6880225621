#!/usr/bin/env bash
# Accuracy of fdmsurf's SES against the analytical reference (NanoShaper) shipped in
# ../shared/reference/ses, with the exact atoms and radii of the .xyzr files.
# Prints a Markdown table in the layout of Giard & Macq (2010), Table 3.
# Usage: scripts/accuracy.sh [SPACINGS...]   (default: 1.0 0.5; 0.25 for 1crn only when given)
# Needs build/fdmsurf and /usr/bin/python3 with numpy and scipy (../shared/tools/meshstat.py).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
ref_dir=../shared/reference/ses
meshstat=../shared/tools/meshstat.py
spacings=("${@:-1.0 0.5}")
read -r -a spacings <<< "${spacings[*]}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| structure | spacing (Å) | settings | weighted RMSD (Å) | area beyond spacing | dA | dV | pieces (reference) | time (s) |"
echo "|---|---|---|---|---|---|---|---|---|"
for name in 1crn 4hhb; do
    ref_pieces=$([ "$name" = 1crn ] && echo 2 || echo 25)
    for h in "${spacings[@]}"; do
        for settings in default paper; do
            extra=()
            [ "$settings" = paper ] && extra=(--paper)
            start=$(date +%s.%N)
            build/fdmsurf "$ref_dir/$name.xyzr" -o "$tmp/$name.ply" --spacing "$h" --stats json \
                "${extra[@]}" > "$tmp/run.json"
            end=$(date +%s.%N)
            /usr/bin/python3 "$meshstat" --json compare "$ref_dir/$name-ses-nanoshaper.ply.gz" \
                "$tmp/$name.ply" --spacing "$h" > "$tmp/cmp.json"
            python3 - "$tmp/run.json" "$tmp/cmp.json" "$name" "$h" "$settings" "$ref_pieces" \
                "$start" "$end" <<'PY'
import json, sys
run = json.load(open(sys.argv[1])); cmp = json.load(open(sys.argv[2]))
name, h, settings, ref_pieces, t0, t1 = sys.argv[3:9]
print(f"| {name} | {h} | {settings} | {cmp['rmsd']:.3f} | {cmp['pct_area_beyond_spacing']:.2f}% "
      f"| {100*cmp['area_rel_err']:+.1f}% | {100*cmp['volume_rel_err']:+.1f}% "
      f"| {run['pieces']} ({ref_pieces}) | {float(t1)-float(t0):.1f} |")
PY
        done
    done
done
