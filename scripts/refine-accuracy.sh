#!/usr/bin/env bash
# What --refine gains against the analytical SES (NanoShaper, ../shared/reference/ses), with the
# exact atoms and radii of the .xyzr files: a Markdown table per structure, spacing and level.
# Usage: scripts/refine-accuracy.sh [LEVELS...]   (default: 0 1 2)
# Spacings: 1.0 and 0.5 Å for 1CRN and 4HHB, and 0.25 Å for 1CRN. Needs build/fdmsurf and
# /usr/bin/python3 with numpy (folded-triangle count).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
ref_dir=../shared/reference/ses
levels=("${@:-0 1 2}")
read -r -a levels <<< "${levels[*]}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "| structure | spacing (Å) | refine | weighted RMSD (Å) | area beyond spacing | dA | dV | triangles | folded | refine stage (s) | total (s) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for name in 1crn 4hhb; do
    spacings=(1.0 0.5)
    [ "$name" = 1crn ] && spacings+=(0.25)
    for h in "${spacings[@]}"; do
        for r in "${levels[@]}"; do
            build/fdmsurf "$ref_dir/$name.xyzr" -o "$tmp/$name.ply" --spacing "$h" --refine "$r" \
                --stats json > "$tmp/run.json"
            build/fdmsurf compare "$ref_dir/$name-ses-nanoshaper.ply.gz" "$tmp/$name.ply" \
                --spacing "$h" --stats json > "$tmp/cmp.json"
            /usr/bin/python3 - "$tmp/run.json" "$tmp/cmp.json" "$tmp/$name.ply" "$name" "$h" "$r" <<'PY'
import json, sys
import numpy as np
run = json.load(open(sys.argv[1])); cmp = json.load(open(sys.argv[2]))
name, h, r = sys.argv[4:7]
# Folded triangles: geometric normal against the mean of the vertex normals (binary PLY as
# fdmsurf writes it: float x y z nx ny nz, then uchar 3 + int32 indices).
with open(sys.argv[3], 'rb') as f:
    nv = nf = 0
    while (line := f.readline().decode().strip()) != 'end_header':
        if line.startswith('element vertex'): nv = int(line.split()[2])
        if line.startswith('element face'): nf = int(line.split()[2])
    v = np.frombuffer(f.read(nv * 24), dtype='<f4').reshape(nv, 6).astype(np.float64)
    t = np.frombuffer(f.read(nf * 13), dtype=np.dtype([('n', 'u1'), ('i', '<i4', 3)]))['i']
p, n = v[:, :3], v[:, 3:]
g = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
folded = int(np.sum(np.einsum('ij,ij->i', g, n[t[:, 0]] + n[t[:, 1]] + n[t[:, 2]]) < 0))
refine_s = run['times'].get('refine', 0.0) / 1000
print(f"| {name} | {h} | {r} | {cmp['rmsd']:.4f} | {cmp['pct_area_beyond_spacing']:.2f}% "
      f"| {100*cmp['area_rel_err']:+.2f}% | {100*cmp['volume_rel_err']:+.2f}% "
      f"| {run['triangles']:,} | {folded:,} | {refine_s:.2f} | {run['total_ms']/1000:.1f} |")
PY
        done
    done
done
