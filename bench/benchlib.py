"""Helpers shared by the bench scripts: where the structures are, and one fdmsurf run."""
import json, os, subprocess, sys, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.environ.get("FDMSURF_SHARED", os.path.join(ROOT, "..", "shared"))


def find(name):
    """The structure `name` (e.g. 1aon) in tests/data, else in ../shared/data; None if in neither."""
    for folder in (os.path.join(ROOT, "tests", "data"), os.path.join(SHARED, "data")):
        for ext in (".pdb", ".pdb.gz", ".cif.gz", ".cif"):
            p = os.path.join(folder, name + ext)
            if os.path.exists(p):
                return p
    return None


def run_json(exe, args):
    """Runs `exe args` (which must include --stats json); returns (wall seconds, parsed stats).
    Exits with fdmsurf's message when the run fails."""
    t0 = time.perf_counter()
    r = subprocess.run([exe] + args, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        sys.exit(f"fdmsurf {' '.join(args)} failed ({r.returncode}): {r.stderr.strip()}")
    return wall, json.loads(r.stdout)
