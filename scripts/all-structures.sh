#!/usr/bin/env bash
# Runs build/fdmsurf on every structure in ../shared/data (SES at 0.5 Å unless the extra
# arguments say otherwise) and prints Markdown tables: mesh statistics per file, then the time
# of each pipeline stage. Builds nothing (run scripts/setup-debian.sh first).
#
#   scripts/all-structures.sh                  # ses, spacing 0.5 Å
#   scripts/all-structures.sh --spacing 1.0    # extra arguments go to every fdmsurf run
#
# Environment: FDMSURF_DATA_DIR (default ../shared/data), FDMSURF_BIN (default build/fdmsurf),
# FDMSURF_MESH_DIR (keep the meshes there; default: a temporary folder, removed at the end).
# Progress, warnings and errors go to stderr, the tables to stdout. Exit status 1 when a run
# failed or a mesh is not a closed manifold.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
data_dir=${FDMSURF_DATA_DIR:-../shared/data}
bin=${FDMSURF_BIN:-build/fdmsurf}

if [[ ! -x $bin ]]; then
    echo "all-structures: $bin not found; build first (scripts/setup-debian.sh)" >&2
    exit 2
fi
shopt -s nullglob
files=("$data_dir"/*.pdb "$data_dir"/*.cif "$data_dir"/*.pdb.gz "$data_dir"/*.cif.gz)
shopt -u nullglob
if ((${#files[@]} == 0)); then
    echo "all-structures: no *.pdb, *.cif, *.pdb.gz or *.cif.gz in $data_dir" >&2
    exit 2
fi
mapfile -t files < <(printf '%s\n' "${files[@]}" | sort)

if [[ -n ${FDMSURF_MESH_DIR:-} ]]; then
    mesh_dir=$FDMSURF_MESH_DIR
    mkdir -p "$mesh_dir"
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
else
    work=$(mktemp -d)
    mesh_dir=$work
    trap 'rm -rf "$work"' EXIT
fi

# GNU time gives the peak resident memory; on lavapipe that includes the "device" buffers.
timer=()
if [[ -x /usr/bin/time ]] && /usr/bin/time -v true >/dev/null 2>&1; then
    timer=(/usr/bin/time -v -o)
fi

runs=()
for f in "${files[@]}"; do
    name=$(basename "$f")
    stem=${name%.gz}
    stem=${stem%.*}
    out="$mesh_dir/$stem.ply"
    echo "all-structures: $name ..." >&2
    rc=0
    if ((${#timer[@]})); then
        "${timer[@]}" "$work/$name.time" "$bin" "$f" -o "$out" --stats json --surface ses \
            --spacing 0.5 "$@" >"$work/$name.json" 2>"$work/$name.err" </dev/null || rc=$?
    else
        "$bin" "$f" -o "$out" --stats json --surface ses --spacing 0.5 "$@" \
            >"$work/$name.json" 2>"$work/$name.err" </dev/null || rc=$?
    fi
    sed "s/^/  $name: /" "$work/$name.err" >&2
    runs+=("$name" "$rc")
done

python3 - "$work" "${#timer[@]}" "${runs[@]}" <<'PY'
import json, os, sys

work, timed, rest = sys.argv[1], sys.argv[2] != "0", sys.argv[3:]
runs = list(zip(rest[0::2], (int(rc) for rc in rest[1::2])))


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def merge_pairs(pairs):
    # A stage timed more than once (one entry per slab) is summed, not overwritten.
    out = {}
    for key, value in pairs:
        if key in out and isinstance(value, (int, float)) and isinstance(out[key], (int, float)):
            out[key] += value
        else:
            out[key] = value
    return out


def peak_mib(name):
    try:
        with open(os.path.join(work, name + ".time")) as f:
            for line in f:
                if "Maximum resident set size" in line:
                    return "%d" % round(int(line.rsplit(":", 1)[1]) / 1024)
    except (OSError, ValueError):
        pass
    return "–"


head = ["file", "atoms used", "grid", "slabs", "vertices", "triangles", "pieces",
        "closed pieces", "boundary edges", "non-manifold edges", "closed manifold", "area (Å²)",
        "volume (Å³)", "total (s)"] + (["peak RSS (MiB)"] if timed else []) + ["status"]
print("| " + " | ".join(head) + " |")
print("|" + "---|" * len(head))

failed = False
stage_rows = []
stage_names = []
for name, rc in runs:
    err_lines = []
    try:
        with open(os.path.join(work, name + ".err"), errors="replace") as f:
            err_lines = [l.strip() for l in f if l.strip()]
    except OSError:
        pass
    doc = None
    if rc == 0:
        try:
            with open(os.path.join(work, name + ".json")) as f:
                doc = json.load(f, object_pairs_hook=merge_pairs)
        except (OSError, ValueError) as e:
            err_lines.append("unreadable --stats json output: %s" % e)
    if doc is None:
        failed = True
        errors = [l for l in err_lines if "error" in l] or err_lines or ["no output"]
        msg = errors[0].removeprefix("fdmsurf: error: ")
        row = [name] + ["–"] * (len(head) - 2 - timed) + ([peak_mib(name)] if timed else []) + \
              ["error (exit %d): %s" % (rc, msg)]
        print("| " + " | ".join(cell(c) for c in row) + " |")
        continue
    grid = doc.get("grid", {})
    closed = bool(doc.get("closed_manifold"))
    failed = failed or not closed
    status = "ok"
    if doc.get("warnings"):
        status += " (%d warning%s)" % (len(doc["warnings"]), "" if len(doc["warnings"]) == 1 else "s")
    row = [
        name,
        "{:,}".format(doc.get("atoms_used", 0)),
        " × ".join(str(d) for d in grid.get("dims", [])),
        grid.get("slabs", 1),
        "{:,}".format(doc.get("vertices", 0)),
        "{:,}".format(doc.get("triangles", 0)),
        doc.get("pieces", "–"),
        doc.get("closed_pieces", "–"),
        doc.get("boundary_edges", "–"),
        doc.get("nonmanifold_edges", "–"),
        "yes" if closed else "no",
        "{:,.1f}".format(doc.get("area", 0.0)),
        "{:,.1f}".format(doc.get("volume", 0.0)),
        "%.2f" % (doc.get("total_ms", 0.0) / 1000.0),
    ] + ([peak_mib(name)] if timed else []) + [status]
    print("| " + " | ".join(cell(c) for c in row) + " |")
    times = {}
    for stage, ms in doc.get("times", {}).items():
        times[stage] = times.get(stage, 0.0) + ms
        if stage not in stage_names:
            stage_names.append(stage)
    stage_rows.append((name, times, doc.get("total_ms", 0.0)))

if stage_rows:
    print()
    print("| file | " + " | ".join(stage_names) + " | total |")
    print("|" + "---|" * (len(stage_names) + 2))
    for name, times, total in stage_rows:
        cells = ["%.2f" % (times[s] / 1000.0) if s in times else "–" for s in stage_names]
        print("| " + name + " | " + " | ".join(cells) + " | %.2f |" % (total / 1000.0))
    print()
    print("Stage times in seconds, from --stats json (GPU timestamps where the device has them).")

sys.exit(1 if failed else 0)
PY
