#!/usr/bin/env python3
"""Runs the fdmsurf CLI over a corpus of real structure files (PDB, mmCIF, PQR, gzipped or not) and
sorts the outcomes into classes: a closed surface, an open one, a refusal (by its reason), a
crash, a hang. It also reads every file with scripts/cross-check-readers.py's comparison (gemmi,
Biopython, MDAnalysis where installed) and counts the differences.

  scripts/corpus.py [--fdmsurf BUILD/fdmsurf] [--jobs 2] [--timeout 300] [--markdown OUT.md]
                    [--list] [FILE or FOLDER ...]

Without paths it takes the folders of DEFAULT_FOLDERS that exist: the structure files that
Debian packages ship (scripts/corpus.sh installs them) and ../shared/data beside the
repository when it is there (a clone lacks it; the script says so). docs/structure.md
("A corpus of real files") has the latest table and the classes.

Exit status 1 when a file crashes, hangs, gives an open mesh, is refused for a reason outside
ALLOWED_REFUSALS (files without atoms, or whose atoms the selection rules all remove, with the
option that keeps them named), or reads differently from another reader (outside the known
differences of cross-check-readers.py).
"""
import argparse
import concurrent.futures
import importlib.util
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Where Debian packages put structure files (the package in the comment; scripts/corpus.sh
# installs them), then the wwPDB files beside the repository.
DEFAULT_FOLDERS = [
    "/usr/share/pymol",                                   # pymol-data
    "/usr/share/freesasa",                                # freesasa
    "/usr/share/doc/python-biopython-doc/Tests",          # python-biopython-doc
    "/usr/lib/python3/dist-packages/openmm/app/data",     # python3-simtk (OpenMM)
    "/usr/lib/python3/dist-packages/pdbfixer",            # python3-pdbfixer
    "/usr/lib/python3/dist-packages/csb/test/data",       # python3-csb
    "/usr/share/apbs/examples",                           # apbs
    "/usr/share/doc/garlic/examples",                     # garlic
    "/usr/share/doc/raster3d/examples",                   # raster3d-doc
    "/usr/share/doc/mustang/examples",                    # mustang
    "/usr/share/RDKit",                                   # rdkit-data
    "/usr/share/gromacs",                                 # gromacs-data
    os.path.join(os.path.dirname(ROOT), "shared", "data"),  # ../shared/data (wwPDB files)
]
EXTENSIONS = (".pdb", ".ent", ".cif", ".mmcif", ".pqr", ".pdb1")

# Refusals that are right: the file has no atoms, or nothing but what the selection rules
# remove (the message names the option that keeps it).
ALLOWED_REFUSALS = {"no atoms", "nothing left after selection", "empty file", "not a structure"}


def load_cross_check():
    spec = importlib.util.spec_from_file_location(
        "cross_check_readers", os.path.join(ROOT, "scripts", "cross-check-readers.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def corpus_files(paths):
    seen = set()
    for path in paths:
        if os.path.isdir(path):
            for folder, _, names in os.walk(path):
                for name in sorted(names):
                    bare = name[:-3] if name.endswith(".gz") else name
                    if bare.lower().endswith(EXTENSIONS):
                        full = os.path.join(folder, name)
                        real = os.path.realpath(full)
                        if real not in seen and os.path.isfile(full):
                            seen.add(real)
                            yield full
        elif os.path.isfile(path):
            yield path


def refusal_class(message):
    """The reason of a refusal, in a few words."""
    rules = [
        (r"is empty|empty file|0 bytes", "empty file"),
        (r"no atoms left after selection", "nothing left after selection"),
        (r"no atoms|no _atom_site|no ATOM/HETATM", "no atoms"),
        (r"binary|not a text|compressed|archive", "not a structure"),
        (r"too few fields|non-numeric|coordinate|column", "unreadable record"),
        (r"radius", "radius"),
    ]
    for pattern, name in rules:
        if re.search(pattern, message, re.IGNORECASE):
            return name
    return "other: " + message.split(": ", 1)[-1][:60]


def run_cli(fdmsurf, path, timeout, scratch):
    out = os.path.join(scratch, re.sub(r"[^A-Za-z0-9_.-]", "_", path.strip("/")) + ".ply")
    start = time.monotonic()
    try:
        proc = subprocess.run([fdmsurf, path, "-o", out, "--stats", "json", "--quiet"],
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"file": path, "outcome": "hang", "detail": f"over {timeout} s"}
    seconds = time.monotonic() - start
    partial = os.path.exists(out)
    line = proc.stdout.strip().splitlines()[-1] if proc.stdout.strip() else ""
    try:
        stats = json.loads(line)
    except ValueError:
        stats = None
    if proc.returncode < 0 or stats is None:
        return {"file": path, "outcome": "crash",
                "detail": f"exit {proc.returncode}: {proc.stderr.strip()[-200:]}"}
    if stats.get("status") != "ok":
        if partial:
            return {"file": path, "outcome": "crash", "detail": "refused but wrote " + out}
        return {"file": path, "outcome": "refused", "class": refusal_class(stats["error"]),
                "detail": stats["error"], "seconds": seconds}
    os.remove(out)
    result = {"file": path, "atoms": stats["atoms_used"], "triangles": stats["triangles"],
              "seconds": seconds, "warnings": len(stats.get("warnings", []))}
    if stats["closed_manifold"]:
        result["outcome"] = "closed"
    else:
        result["outcome"] = "open"
        result["detail"] = (f"{stats['boundary_edges']} boundary, "
                            f"{stats['nonmanifold_edges']} non-manifold edges")
    return result


def check_readers(cross, readers, path):
    """Differences between fdmsurf's reading of `path` and the other readers' (a list of lines)."""
    try:
        lines, _ = cross.check_file(path, readers)
    except Exception as e:  # the comparison itself failing is a difference to look at
        return [f"{path}: cross-check failed: {e}"]
    return lines


def markdown(results, differences, compared, machine):
    counts = {}
    for r in results:
        key = r["outcome"] if r["outcome"] != "refused" else "refused: " + r["class"]
        counts[key] = counts.get(key, 0) + 1
    rows = [f"| {key} | {n} |" for key, n in sorted(counts.items(), key=lambda kv: -kv[1])]
    closed = [r for r in results if r["outcome"] == "closed"]
    text = [f"{len(results)} files; {machine}", "", "| outcome | files |", "|---|---:|", *rows, "",
            f"Closed surfaces: {sum(1 for r in closed if r['warnings'])} with a warning; "
            f"{min((r['atoms'] for r in closed), default=0)} to "
            f"{max((r['atoms'] for r in closed), default=0)} atoms.", "",
            f"Other readers: {compared} comparisons, {len(differences)} difference(s)."]
    refused = [r for r in results if r["outcome"] != "closed"]
    if refused:
        text += ["", "| file | outcome | message |", "|---|---|---|"]
        text += [f"| `{os.path.basename(r['file'])}` | {r.get('class', r['outcome'])} | "
                 f"{r.get('detail', '')[:140]} |" for r in refused]
    return "\n".join(text) + "\n"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="*")
    parser.add_argument("--fdmsurf", default=os.path.join(
        os.environ.get("FDMSURF_BUILD_DIR", os.path.join(ROOT, "build")), "fdmsurf"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=300)
    parser.add_argument("--markdown", help="also write the tables to this file")
    parser.add_argument("--list", action="store_true", help="list the files and stop")
    args = parser.parse_args(argv)

    paths = args.paths
    if not paths:
        paths = [f for f in DEFAULT_FOLDERS if os.path.isdir(f)]
        shared = DEFAULT_FOLDERS[-1]
        if shared not in paths:
            print(f"corpus: note: {shared} is absent (a clone without ../shared); "
                  "the Debian packages' files only")
    files = list(corpus_files(paths))
    if args.list:
        print("\n".join(files))
        return 0
    if not files:
        print("corpus: no structure files found (run scripts/corpus.sh, which installs them)")
        return 1

    cross = load_cross_check()
    readers = cross.available_readers()
    with tempfile.TemporaryDirectory(prefix="fdmsurf-corpus-") as scratch:
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            results = list(pool.map(lambda f: run_cli(args.fdmsurf, f, args.timeout, scratch),
                                    files))
    differences, compared = [], 0
    for f in files:
        lines, n = cross.check_file(f, readers)
        compared += n
        differences += lines

    failures = [r for r in results if r["outcome"] in ("crash", "hang", "open") or
                (r["outcome"] == "refused" and r["class"] not in ALLOWED_REFUSALS)]
    for r in results:
        if r["outcome"] != "closed":
            print(f"{r['file']}: {r.get('class', r['outcome'])}: {r.get('detail', '')}")
    for line in differences:
        print(line)
    machine = f"fdmsurf {args.fdmsurf}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}"
    table = markdown(results, differences, compared, machine)
    print(table)
    if args.markdown:
        with open(args.markdown, "w") as out:
            out.write(table)
    if failures or differences:
        print(f"corpus: {len(failures)} file(s) not read as they should be, "
              f"{len(differences)} reading difference(s)")
        return 1
    print(f"corpus: {len(files)} files, every one a closed surface or a right refusal; "
          f"{compared} comparisons with other readers agree")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
