#!/usr/bin/python3
"""fdmsurf side-by-side benchmark: fdmsurf, Mol*, PyMOL and EDTSurf on the same structures.

Run through bench/run.sh (which installs the Mol* peer first); see docs/performance.md.

What it does, in one run:

1. Peers and fdmsurf, SES with a 1.4 Å probe at 0.5 Å, on 1CRN, 4HHB, 4YVS (asymmetric unit)
   and 1AON. fdmsurf and Mol* read the .xyzr atoms of ../shared/reference/ses (NanoShaper's
   reference atoms and PyMOL radii); PyMOL and EDTSurf read the PDB/mmCIF cleaned by
   ../shared/tools/peers.py (model 1, no H, waters, HETATM, first altloc: the same atoms; PyMOL
   gives them the same radii, EDTSurf its own table). Per structure: one fdmsurf run with empty
   shader and plan caches (cold), then REPS rounds in which every tool runs once, the order
   rotated each round (alternating). Each run is timed by GNU time -v (wall, peak RSS, CPU).
2. Mesh size and, where a NanoShaper reference exists (1CRN, 4HHB), accuracy by
   `fdmsurf compare REF MESH --spacing 0.5 --stats json`; for 4YVS and 1AON, area and volume
   against NanoShaper's published figures (../shared/reference/ses/README.md).
3. Scaling: fdmsurf's stage times against voxels (4HHB at 1.0, 0.7, 0.5 Å) and against atoms
   (random atoms in a fixed 80 Å box: 2k, 8k, 32k), plus a least-squares fit of the density
   time to voxels and atoms.

Prints Markdown tables on stdout and writes OUT/report.md and OUT/results.json. Standard library
only (peers.py, imported for its input clean-up and PyMOL script, needs python3-gemmi).
"""

from __future__ import annotations

import argparse
import datetime
import gzip
import json
import os
import random
import re
import shutil
import signal
import statistics
import subprocess
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)

STRUCTURES = {
    # name: structure file for the peers (in SHARED/data), atoms for fdmsurf/Mol*
    # (SHARED/reference/ses), reference mesh, NanoShaper's published (area, volume) at grid 2
    "1crn": {"pdb": "1crn.pdb", "xyzr": "1crn.xyzr", "ref": "1crn-ses-nanoshaper.ply.gz",
             "ns": (2314.4, 4662.7)},
    "4hhb": {"pdb": "4hhb.pdb", "xyzr": "4hhb.xyzr", "ref": "4hhb-ses-nanoshaper.ply.gz",
             "ns": (27254.6, 66442.4)},
    "4yvs": {"pdb": "4yvs.cif.gz", "xyzr": "4yvs.xyzr.gz", "ref": None, "ns": (151395.0, 417653.0)},
    "1aon": {"pdb": "1aon.pdb.gz", "xyzr": "1aon.xyzr.gz", "ref": None, "ns": (362675.0, 869528.0),
             "large": True},
}
NANOSHAPER_S = {"4hhb": 0.8, "1aon": 10.7}   # ../shared/reference/ses/README.md, 2 cores
SKIP_WHY = {"1aon:pymol-q1": "skipped by default (--skip): a trial run on this machine was killed "
                             "unfinished after 358 s at 4.0 GB"}
ALL_TOOLS = ["fdmsurf", "fdmsurf-edt", "molstar", "pymol-q0", "pymol-q1", "edtsurf"]
LABEL = {"fdmsurf": "fdmsurf (SES 0.5 Å)", "fdmsurf-edt": "fdmsurf --method edt (exact SES 0.5 Å)",
         "molstar": "Mol* (0.5 Å)",
         "pymol-q0": "PyMOL (surface_quality 0)", "pymol-q1": "PyMOL (surface_quality 1)",
         "edtsurf": "EDTSurf (-f 4)"}
STAGE_ORDER = ["parse", "init", "bin-atoms", "density", "density-host", "fft-forward", "mask", "fft-inverse",
               "read-field", "filter-host", "assemble-field", "upload-part", "mc-occupancy", "mc-count",
               "mc-scan", "mc-vertices", "mc-triangles", "mc-emit", "read-back", "unpack-mesh", "mc-host",
               "stitch", "pieces", "cavities", "vertex-atoms", "vertex-atoms-host", "write", "mesh-stats"]

LOG = None


def log(msg):
    """Progress on stderr and into OUT/bench.log."""
    line = f"[{time.strftime('%H:%M:%S')}] {msg}"
    print(line, file=sys.stderr, flush=True)
    if LOG:
        with open(LOG, "a") as fh:
            fh.write(line + "\n")


def sh(cmd, **kw):
    """Output of a short command, or '' when it fails."""
    try:
        return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=60, **kw).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def parse_time_v(path):
    """Wall (s), peak RSS (MiB), user+sys CPU (s) and CPU share from GNU time -v's report."""
    with open(path) as fh:
        txt = fh.read()
    out = {}
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", txt)
    if m:
        secs = 0.0
        for part in m.group(1).split(":"):
            secs = secs * 60 + float(part)
        out["wall_s"] = secs
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", txt)
    if m:
        out["rss_mib"] = int(m.group(1)) / 1024.0
    u = re.search(r"User time \(seconds\): ([\d.]+)", txt)
    s = re.search(r"System time \(seconds\): ([\d.]+)", txt)
    if u and s:
        out["cpu_s"] = float(u.group(1)) + float(s.group(1))
    m = re.search(r"Percent of CPU this job got: (\d+)%", txt)
    if m:
        out["cpu_pct"] = int(m.group(1))
    return out


def timed(cmd, cwd, timeout, env=None, tag=""):
    """Run cmd under /usr/bin/time -v; kill its process group after `timeout` seconds."""
    tfile = os.path.join(cwd, ".time-v.txt")
    if os.path.exists(tfile):
        os.remove(tfile)
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    p = subprocess.Popen(["/usr/bin/time", "-v", "-o", tfile] + cmd, cwd=cwd, env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                         start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
        status = "ok" if p.returncode == 0 else f"exit {p.returncode}"
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)   # the group of the child started here, nothing else
        out, err = p.communicate()
        status = "timeout"
    elapsed = time.perf_counter() - t0
    res = {"status": status, "load1": load, "wall_py_s": elapsed,
           "stdout": out.decode("utf-8", "replace"), "stderr": err.decode("utf-8", "replace")}
    if status == "timeout":
        res["wall_s"] = float(timeout)
    elif os.path.exists(tfile):
        res.update(parse_time_v(tfile))
    res.setdefault("wall_s", elapsed)
    with open(LOG, "a") as fh:
        fh.write(f"$ {' '.join(cmd)}   [{tag}] {status} {res['wall_s']:.2f} s "
                 f"{res.get('rss_mib', 0):.0f} MiB load {load:.2f}\n")
        if status != "ok":
            fh.write(res["stdout"][-3000:] + res["stderr"][-3000:] + "\n")
    return res


def json_line(text, prefix=""):
    """The last stdout line that starts with prefix + '{', parsed."""
    for line in reversed(text.splitlines()):
        line = line.strip()
        if line.startswith(prefix + "{"):
            return json.loads(line[len(prefix):])
    return None


def read_xyzr(path):
    op = gzip.open if path.endswith(".gz") else open
    with op(path, "rt") as fh:
        return [tuple(float(t) for t in ln.split()[:4]) for ln in fh if ln.strip()]


def pymol_obj_to_off(obj, off):
    """PyMOL's exported OBJ (faces 'f a//n ...' without vn lines) as OFF, duplicates kept:
    `fdmsurf compare` welds them."""
    verts, faces = [], []
    with open(obj) as fh:
        for ln in fh:
            if ln.startswith("v "):
                verts.append(ln[2:].strip())
            elif ln.startswith("f "):
                idx = [int(t.split("/")[0]) - 1 for t in ln.split()[1:]]
                for k in range(1, len(idx) - 1):
                    faces.append(f"3 {idx[0]} {idx[k]} {idx[k + 1]}")
    with open(off, "w") as fh:
        fh.write(f"OFF\n{len(verts)} {len(faces)} 0\n")
        fh.write("\n".join(verts) + "\n")
        fh.write("\n".join(faces) + "\n")


def pymol_frame(structure):
    """The affine map (A, t) from a PDB/mmCIF file's coordinates to PyMOL's, or None.

    PyMOL re-orthogonalises coordinates whose SCALE matrix is not the standard one for the cell
    (4HHB's is not): x' = orth_std(SCALE x + U). The reference .xyzr atoms were written by PyMOL,
    so they are in that frame, while EDTSurf writes its mesh in the file's frame."""
    import gemmi
    st = gemmi.read_structure(structure)
    c = st.cell
    if not c.is_crystal():
        return None
    std = gemmi.UnitCell(c.a, c.b, c.c, c.alpha, c.beta, c.gamma)

    def f(x, y, z):
        q = std.orthogonalize(c.fractionalize(gemmi.Position(x, y, z)))
        return (q.x, q.y, q.z)
    o = f(0.0, 0.0, 0.0)
    cols = [tuple(b - a for a, b in zip(o, f(*e))) for e in ((1.0, 0, 0), (0, 1.0, 0), (0, 0, 1.0))]
    A = [[cols[j][i] for j in range(3)] for i in range(3)]
    ident = all(abs(A[i][j] - (i == j)) < 1e-6 for i in range(3) for j in range(3))
    if ident and all(abs(v) < 1e-6 for v in o):
        return None
    return A, o


def apply_frame(frame, p):
    A, t = frame
    return tuple(sum(A[i][j] * p[j] for j in range(3)) + t[i] for i in range(3))


def max_set_distance(points, ref, cell=1.0):
    """Largest distance from a point of `points` to its nearest point of `ref` (grid hash)."""
    grid = {}
    for q in ref:
        grid.setdefault((int(q[0] // cell), int(q[1] // cell), int(q[2] // cell)), []).append(q)
    worst = 0.0
    for p in points:
        c = (int(p[0] // cell), int(p[1] // cell), int(p[2] // cell))
        best = float("inf")
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for q in grid.get((c[0] + dx, c[1] + dy, c[2] + dz), ()):
                        best = min(best, (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 + (p[2] - q[2]) ** 2)
        worst = max(worst, best ** 0.5)
    return worst


def ply_ascii_to_off(ply, off, frame=None):
    """EDTSurf's ASCII PLY (x y z r g b; faces '3 a b c') as OFF, vertices optionally mapped."""
    with open(ply) as fh:
        nv = nf = 0
        for ln in fh:
            if ln.startswith("element vertex"):
                nv = int(ln.split()[2])
            elif ln.startswith("element face"):
                nf = int(ln.split()[2])
            elif ln.startswith("end_header"):
                break
        with open(off, "w") as out:
            out.write(f"OFF\n{nv} {nf} 0\n")
            for _ in range(nv):
                p = tuple(float(t) for t in fh.readline().split()[:3])
                if frame:
                    p = apply_frame(frame, p)
                out.write("%.4f %.4f %.4f\n" % p)
            for _ in range(nf):
                out.write(fh.readline())


def write_probe_mesh(path):
    """A small octahedron: `fdmsurf compare PROBE MESH` then costs little and reports MESH's
    welded vertex and triangle counts, area and volume."""
    v = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    with open(path, "w") as fh:
        fh.write(f"OFF\n{len(v)} {len(f)} 0\n")
        for p in v:
            fh.write("%g %g %g\n" % p)
        for t in f:
            fh.write("3 %d %d %d\n" % t)


def fdm_compare(fdm, ref, mesh, spacing=0.5):
    p = subprocess.run([fdm, "compare", ref, mesh, "--spacing", str(spacing), "--stats", "json"],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=900)
    if p.returncode != 0:
        raise RuntimeError(p.stderr.strip())
    return json.loads(p.stdout)


def synth_xyzr(path, n, box=80.0, radius=1.7, dmin=2.0, seed=20261122):
    """n random atoms in a box: random sequential addition, centres at least dmin apart."""
    rng = random.Random(seed + n)
    cell, d2 = dmin, dmin * dmin
    grid, pts, tries = {}, [], 0
    while len(pts) < n:
        tries += 1
        if tries > 1000 * n:
            raise RuntimeError(f"cannot place {n} atoms {dmin} Å apart in {box} Å")
        p = (rng.uniform(0, box), rng.uniform(0, box), rng.uniform(0, box))
        c = (int(p[0] // cell), int(p[1] // cell), int(p[2] // cell))
        ok = True
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for q in grid.get((c[0] + dx, c[1] + dy, c[2] + dz), ()):
                        if (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 + (p[2] - q[2]) ** 2 < d2:
                            ok = False
                            break
                    if not ok:
                        break
                if not ok:
                    break
            if not ok:
                break
        if ok:
            grid.setdefault(c, []).append(p)
            pts.append(p)
    with open(path, "w") as fh:
        for p in pts:
            fh.write(f"{p[0]:.3f} {p[1]:.3f} {p[2]:.3f} {radius:.2f}\n")


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def fmt(v, f="{:.2f}", none="–"):
    return none if v is None else f.format(v)


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def lstsq(rows, ys):
    """Least squares with the normal equations (few unknowns), plus R²."""
    k = len(rows[0])
    a = [[sum(r[i] * r[j] for r in rows) for j in range(k)] for i in range(k)]
    b = [sum(r[i] * y for r, y in zip(rows, ys)) for i in range(k)]
    for c in range(k):                       # Gauss-Jordan with partial pivoting
        piv = max(range(c, k), key=lambda i: abs(a[i][c]))
        a[c], a[piv], b[c], b[piv] = a[piv], a[c], b[piv], b[c]
        for i in range(k):
            if i != c and a[c][c]:
                f = a[i][c] / a[c][c]
                a[i] = [x - f * y for x, y in zip(a[i], a[c])]
                b[i] -= f * b[c]
    if len(ys) <= k or any(abs(a[i][i]) < 1e-12 for i in range(k)):
        return None, None, None
    coef = [b[i] / a[i][i] for i in range(k)]
    pred = [sum(c * x for c, x in zip(coef, r)) for r in rows]
    mean = sum(ys) / len(ys)
    ss_tot = sum((y - mean) ** 2 for y in ys) or 1.0
    ss_res = sum((y - p) ** 2 for y, p in zip(ys, pred))
    return coef, 1.0 - ss_res / ss_tot, pred


class Bench:
    def __init__(self, a):
        self.a = a
        self.fdm = os.path.abspath(a.fdmsurf)
        self.shared = os.path.abspath(a.shared)
        self.refdir = os.path.join(self.shared, "reference", "ses")
        self.out = os.path.abspath(a.out)
        self.results = {"meta": {}, "structures": {}, "scaling": []}
        self.probe = os.path.join(self.out, "probe-octahedron.off")
        self.notes = []

    # ---------------------------------------------------------------- setup
    def machine(self):
        cpu = ""
        try:
            with open("/proc/cpuinfo") as fh:
                cpu = next((ln.split(":", 1)[1].strip() for ln in fh if ln.startswith("model name")), "")
        except OSError:
            pass
        mem = ""
        try:
            with open("/proc/meminfo") as fh:
                kb = int(fh.readline().split()[1])
                mem = f"{kb / 1024 / 1024:.1f} GiB"
        except (OSError, ValueError, IndexError):
            pass
        dpkg = sh(["dpkg-query", "-W", "-f", "${Package} ${Version}\n", "edtsurf", "python3-pymol",
                   "python3-gemmi", "mesa-vulkan-drivers"])
        molver = ""
        try:
            with open(os.path.join(self.a.molstar, "node_modules", "molstar", "package.json")) as fh:
                molver = json.load(fh).get("version", "")
        except (OSError, ValueError):
            pass
        return {
            "date_utc": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "nproc": os.cpu_count(), "cpu": cpu, "memory": mem,
            "kernel": sh(["uname", "-sr"]),
            "uptime_start": sh(["uptime"]),
            "fdmsurf_version": sh([self.fdm, "--version"]),
            "devices": sh([self.fdm, "--list-devices"]),
            "git": sh(["git", "-C", ROOT, "describe", "--always", "--dirty"]),
            "fdmsurf_built": time.strftime("%Y-%m-%d %H:%M", time.gmtime(os.path.getmtime(self.fdm_src))),
            "packages": dpkg, "node": sh(["node", "--version"]), "molstar": molver,
            "command": " ".join(sys.argv),
        }

    def available(self):
        tools = [t for t in self.a.tools.split(",") if t]
        bad = [t for t in tools if t not in ALL_TOOLS]
        if bad:
            raise SystemExit(f"unknown tools {bad}; known: {ALL_TOOLS}")
        ok = []
        peers_ok = True
        try:
            sys.path.insert(0, os.path.join(self.shared, "tools"))
            import peers  # noqa: F401  (needs meshstat -> numpy, and gemmi for prepare)
            import gemmi  # noqa: F401
            self.peers = peers
        except ImportError as e:
            peers_ok = False
            self.notes.append(f"peers.py unusable ({e}): PyMOL and EDTSurf skipped "
                              "(apt-get install python3-gemmi python3-numpy python3-scipy)")
        for t in tools:
            if t.startswith("fdmsurf"):
                if not os.access(self.fdm, os.X_OK):
                    raise SystemExit(f"{self.fdm} not built (cd build && ninja)")
                ok.append(t)
            elif t == "molstar":
                js = os.path.join(self.a.molstar, "ms_surface.js")
                if shutil.which("node") and os.path.isdir(os.path.join(self.a.molstar, "node_modules", "molstar")) \
                        and os.path.exists(js):
                    ok.append(t)
                else:
                    self.notes.append(f"Mol* skipped: no node or no npm install in {self.a.molstar}")
            elif t.startswith("pymol"):
                if peers_ok and subprocess.run(["/usr/bin/python3", "-c", "import pymol"],
                                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode == 0:
                    ok.append(t)
                elif f"PyMOL skipped" not in " ".join(self.notes):
                    self.notes.append("PyMOL skipped: python3-pymol not installed")
            elif t == "edtsurf":
                if peers_ok and shutil.which("EDTSurf"):
                    ok.append(t)
                else:
                    self.notes.append("EDTSurf skipped: package edtsurf not installed")
        return ok

    def prepare(self, name, spec, tools):
        wd = os.path.join(self.out, name)
        os.makedirs(wd, exist_ok=True)
        info = {"dir": wd, "xyzr": os.path.join(self.refdir, spec["xyzr"])}
        atoms = read_xyzr(info["xyzr"])
        info["atoms"] = len(atoms)
        plain = os.path.join(wd, name + ".xyzr")          # Mol* reads plain text
        with open(plain, "w") as fh:
            fh.writelines(f"{x} {y} {z} {r}\n" for x, y, z, r in atoms)
        info["xyzr_plain"] = plain
        if any(t.startswith("pymol") or t == "edtsurf" for t in tools):
            clean, n = self.peers.prepare(os.path.join(self.shared, "data", spec["pdb"]), wd)
            info["clean"], info["peer_atoms"] = clean, n
            script = os.path.join(wd, "pymol_surface.py")
            with open(script, "w") as fh:
                fh.write(self.peers.PYMOL_SCRIPT)
            info["pymol_script"] = script
        if "edtsurf" in tools:
            # EDTSurf's mesh is in the file's frame, the reference atoms in PyMOL's
            frame = pymol_frame(info["clean"])
            edt_atoms = [p[:3] for p in read_xyzr(os.path.join(wd, "radii_edtsurf.xyzr"))]
            mapped = [apply_frame(frame, p) for p in edt_atoms] if frame else edt_atoms
            info["frame_check"] = max_set_distance(mapped, [p[:3] for p in atoms])
            info["frame"] = frame
        return info

    # ---------------------------------------------------------------- one run of one tool
    def run_tool(self, tool, name, info, cache, tag):
        wd = info["dir"]
        timeout = self.a.timeout
        if tool.startswith("fdmsurf"):
            mesh = os.path.join(wd, f"{tool}.ply")
            env = dict(os.environ, MESA_SHADER_CACHE_DIR=os.path.join(cache, "mesa"),
                       FDMSURF_CACHE_DIR=os.path.join(cache, "fdmsurf"))
            method = ["--method", "edt"] if tool == "fdmsurf-edt" else []
            r = timed([self.fdm, info["xyzr"], "-o", mesh, "--stats", "json", "--quiet"] + method, wd,
                      timeout, env, f"{name} {tool} {tag}")
            js = json_line(r["stdout"]) if r["status"] == "ok" else None
            if js:
                r.update(vertices=js["vertices"], triangles=js["triangles"], times=js["times"],
                         total_ms=js["total_ms"], grid=js["grid"]["dims"], slabs=js["grid"].get("slabs"),
                         closed_manifold=js["closed_manifold"], area=js["area"], volume=js["volume"])
        elif tool == "molstar":
            mesh = os.path.join(wd, "molstar.off")
            r = timed(["node", os.path.join(self.a.molstar, "ms_surface.js"), info["xyzr_plain"], mesh, "0.5"],
                      wd, timeout, None, f"{name} {tool} {tag}")
            js = json_line(r["stdout"]) if r["status"] == "ok" else None
            if js:
                r.update(gen_s=js["gen_s"])
        elif tool.startswith("pymol"):
            q = tool[-1]
            mesh = os.path.join(wd, f"pymol_q{q}.obj")
            r = timed(["/usr/bin/python3", info["pymol_script"], info["clean"], "0", q, mesh,
                       os.path.join(wd, "radii_pymol_used.xyzr")], wd, timeout, None, f"{name} {tool} {tag}")
            js = json_line(r["stdout"], "PYMOL_JSON ") if r["status"] == "ok" else None
            if js:
                r.update(gen_s=js["gen_s"])
        elif tool == "edtsurf":
            prefix = os.path.join(wd, "edtsurf")
            mesh = prefix + ".ply"
            r = timed(["EDTSurf", "-i", info["clean"], "-o", prefix, "-s", "3", "-f", "4", "-p", "1.4"],
                      wd, timeout, None, f"{name} {tool} {tag}")
            m = re.search(r"scale factor\s+([\d.]+)", r["stdout"])
            if m:
                r["edt_scale"] = float(m.group(1))
        r["mesh"] = mesh
        for k in ("stdout", "stderr"):
            r[k] = r[k][-2000:]
        return r

    # ---------------------------------------------------------------- main comparison
    def structure(self, name, tools):
        spec = STRUCTURES[name]
        log(f"{name}: preparing inputs")
        info = self.prepare(name, spec, tools)
        res = {"atoms": info["atoms"], "peer_atoms": info.get("peer_atoms"), "runs": {t: [] for t in tools},
               "notes": []}
        if "frame_check" in info:
            res["notes"].append(
                (f"the PDB file's frame differs from PyMOL's (non-standard SCALE records); EDTSurf's mesh "
                 f"is mapped into PyMOL's frame, that of the reference atoms, before it is measured. "
                 if info["frame"] else "")
                + f"EDTSurf's atoms{' (mapped)' if info['frame'] else ''} lie within "
                f"{info['frame_check']:.3f} Å of the reference .xyzr atoms ({info['peer_atoms']} atoms; "
                "EDTSurf gives them its own radii)")
        self.frames = getattr(self, "frames", {})
        self.frames[name] = info.get("frame")
        self.results["structures"][name] = res
        reps = self.a.reps_large if spec.get("large") else self.a.reps
        res["reps"] = reps
        cache = os.path.join(self.out, "cache", name)
        shutil.rmtree(cache, ignore_errors=True)
        os.makedirs(cache)
        if "fdmsurf" in tools:
            log(f"{name}: fdmsurf cold (empty Mesa shader cache and fdmsurf plan cache)")
            res["cold"] = self.run_tool("fdmsurf", name, info, cache, "cold")
            log(f"{name}: fdmsurf cold {res['cold']['wall_s']:.2f} s")
        stopped = {}
        skip = {s.split(":")[1] for s in self.a.skip.split(",") if s.startswith(name + ":")}
        for t in skip:
            stopped[t] = SKIP_WHY.get(f"{name}:{t}", "skipped (--skip)")
        for rep in range(reps):
            k = rep % len(tools)
            order = tools[k:] + tools[:k]
            for t in order:
                if t in stopped:
                    continue
                r = self.run_tool(t, name, info, cache, f"rep {rep + 1}")
                res["runs"][t].append(r)
                log(f"{name}: rep {rep + 1}/{reps} {t:9s} {r['status']:8s} {r['wall_s']:7.2f} s "
                    f"{r.get('rss_mib', 0):6.0f} MiB (load {r['load1']:.2f})")
                if r["status"] != "ok":
                    stopped[t] = r["status"]
                elif not t.startswith("fdmsurf") and rep == 0 and r["wall_s"] > self.a.long:
                    stopped[t] = f"one run (over {self.a.long:g} s)"
        res["stopped"] = stopped
        # mesh sizes (welded, as `fdmsurf compare` cleans them) and accuracy of the last mesh
        ref = os.path.join(self.refdir, spec["ref"]) if spec["ref"] else None
        res["mesh"] = {}
        for t in tools:
            ok = [r for r in res["runs"][t] if r["status"] == "ok"]
            if not ok:
                continue
            mesh = ok[-1]["mesh"]
            if t.startswith("pymol"):
                off = mesh[:-4] + ".off"
                pymol_obj_to_off(mesh, off)
                mesh = off
            elif t == "edtsurf":
                off = mesh[:-4] + ".off"
                ply_ascii_to_off(mesh, off, self.frames.get(name))
                mesh = off
            row = {}
            try:
                st = fdm_compare(self.fdm, self.probe, mesh)
                row.update(vertices=st["test_vertices"], triangles=st["test_triangles"],
                           area=st["test_area"], volume=st["test_volume"])
                if ref:
                    log(f"{name}: fdmsurf compare {os.path.basename(ref)} {os.path.basename(mesh)}")
                    c = fdm_compare(self.fdm, ref, mesh)
                    row.update({k: c[k] for k in ("rmsd", "pct_area_beyond_spacing", "area_rel_err",
                                                  "volume_rel_err", "hausdorff", "mean_signed")})
                else:
                    row["area_rel_err"] = row["area"] / spec["ns"][0] - 1.0
                    row["volume_rel_err"] = row["volume"] / spec["ns"][1] - 1.0
                    row["vs_published"] = True
            except (RuntimeError, subprocess.SubprocessError, ValueError) as e:
                row["error"] = str(e)
                log(f"{name}: measuring {t}'s mesh failed: {e}")
            res["mesh"][t] = row
        if any(t.startswith("pymol") for t in tools) and os.path.exists(os.path.join(info["dir"], "radii_pymol_used.xyzr")):
            a = read_xyzr(info["xyzr"])
            b = read_xyzr(os.path.join(info["dir"], "radii_pymol_used.xyzr"))
            if len(a) == len(b):
                dmax = max(max(abs(p[i] - q[i]) for i in range(3)) for p, q in zip(a, b))
                rmax = max(abs(p[3] - q[3]) for p, q in zip(a, b))
                res["notes"].append(f"PyMOL's atoms = reference .xyzr: {len(a)} atoms, max coordinate "
                                    f"difference {dmax:.3f} Å, max radius difference {rmax:.2f} Å")
            else:
                res["notes"].append(f"PyMOL used {len(b)} atoms, the reference .xyzr has {len(a)}")

    # ---------------------------------------------------------------- scaling
    def scaling(self):
        sd = os.path.join(self.out, "scaling")
        os.makedirs(sd, exist_ok=True)
        cases = []
        h4 = os.path.join(self.refdir, "4hhb.xyzr")
        for h in [float(x) for x in self.a.scaling_spacings.split(",") if x]:
            cases.append((f"4HHB, {h:g} Å", h4, h, 4384))
        for n in [int(x) for x in self.a.synthetic_atoms.split(",") if x]:
            path = os.path.join(sd, f"random_{n}.xyzr")
            if not os.path.exists(path):
                log(f"scaling: generating {n} random atoms in an 80 Å box")
                synth_xyzr(path, n)
            cases.append((f"random {n // 1000}k atoms, 80 Å box, 0.5 Å", path, 0.5, n))
        for label, xyzr, h, n in cases:
            cache = os.path.join(self.out, "cache", "scaling-" + re.sub(r"[^a-z0-9]+", "_", label.lower()))
            shutil.rmtree(cache, ignore_errors=True)
            os.makedirs(cache)   # Mesa creates only the last component of its cache directory
            env = dict(os.environ, MESA_SHADER_CACHE_DIR=os.path.join(cache, "mesa"),
                       FDMSURF_CACHE_DIR=os.path.join(cache, "fdmsurf"))
            runs = []
            for i in range(self.a.scaling_reps + 1):        # the first run fills the caches
                r = timed([self.fdm, xyzr, "-o", os.path.join(sd, "mesh.ply"), "--spacing", str(h),
                           "--stats", "json", "--quiet"], sd, self.a.timeout, env, f"scaling {label} {i}")
                js = json_line(r["stdout"]) if r["status"] == "ok" else None
                if not js:
                    log(f"scaling: {label} failed: {r['status']}")
                    break
                r.update(times=js["times"], total_ms=js["total_ms"], grid=js["grid"]["dims"],
                         triangles=js["triangles"], atoms=js["atoms_used"])
                for k in ("stdout", "stderr"):
                    r[k] = r[k][-500:]
                if i > 0:
                    runs.append(r)
                log(f"scaling: {label} run {i} {r['wall_s']:.2f} s")
            if runs:
                self.results["scaling"].append({"label": label, "atoms": runs[0]["atoms"], "spacing": h,
                                                "grid": runs[0]["grid"], "runs": runs})

    # ---------------------------------------------------------------- report
    def report(self, tools):
        R, md = self.results, []
        m = R["meta"]
        md.append("## Machine\n")
        md.append(f"- date: {m['date_utc']}; command: `{m['command']}`")
        md.append(f"- CPU: {m['cpu']}, {m['nproc']} logical CPUs (nproc), {m['memory']} memory, {m['kernel']}")
        dev = m["devices"].splitlines()
        md.append(f"- Vulkan: {dev[0] if dev else '?'}" + (f"; {dev[2].strip()}" if len(dev) > 2 else ""))
        md.append(f"- fdmsurf: {m['fdmsurf_version']} (git {m['git']}; binary built {m['fdmsurf_built']} UTC, run from a copy)")
        md.append(f"- peers: Mol* {m['molstar'] or '–'} (node {m['node'] or '–'}); "
                  + "; ".join(m["packages"].splitlines()))
        md.append(f"- load at start: `{m['uptime_start']}`")
        md.append(f"- load at end: `{m.get('uptime_end', '')}`")
        loads = [r["load1"] for s in R["structures"].values() for rs in s["runs"].values() for r in rs]
        if loads:
            md.append(f"- 1-minute load average before each timed run: min {min(loads):.2f}, "
                      f"median {statistics.median(loads):.2f}, max {max(loads):.2f}")
        md.append(f"- wall time of the whole benchmark: {m.get('bench_wall_s', 0) / 60:.1f} min")
        for n in self.notes:
            md.append(f"- note: {n}")

        md.append("\n## Headline: fdmsurf's warm wall time against the peers in the same run\n")
        md.append("Median wall times (s). Mol* is the one peer whose RMSD to the analytical SES is at or "
                  "below fdmsurf's (1CRN, 4HHB); the faster peers are less accurate (table below). "
                  "NanoShaper: the figures of ../shared/reference/ses/README.md (same kind of machine, "
                  "another day), not measured here.\n")
        rows = []
        for name, s in R["structures"].items():
            meds = {t: med([r["wall_s"] for r in s["runs"][t] if r["status"] == "ok"]) for t in tools}
            fd = meds.get("fdmsurf")
            peers = {t: w for t, w in meds.items() if not t.startswith("fdmsurf") and w is not None}
            if fd is None or not peers:
                continue
            fastest = min(peers, key=peers.get)
            ms = meds.get("molstar")
            ns = NANOSHAPER_S.get(name)
            ed = meds.get("fdmsurf-edt")
            rows.append([name.upper(), f"{s['atoms']:,}", fmt(fd), fmt(s.get("cold", {}).get("wall_s")),
                         f"{LABEL[fastest]}: {peers[fastest]:.2f}", f"**{fd / peers[fastest]:.2f}**",
                         fmt(ms), fmt(fd / ms if ms else None), fmt(ed), fmt(ed / ms if ed and ms else None),
                         fmt(ns, "{:g}"), fmt(fd / ns if ns else None, "{:.1f}")])
        md.append(table(["structure", "atoms", "fdmsurf warm", "fdmsurf cold", "fastest peer", "fdmsurf ÷ fastest",
                         "Mol*", "fdmsurf ÷ Mol*", "fdmsurf edt warm", "edt ÷ Mol*",
                         "NanoShaper (published)", "fdmsurf ÷ NanoShaper"], rows))

        md.append("\n## Side by side: SES, probe 1.4 Å, 0.5 Å grid\n")
        md.append("Median wall time over the runs (GNU time, whole process), largest peak RSS, median "
                  "CPU time (user + system). fdmsurf's row is warm (Mesa shader cache and fdmsurf's "
                  "plan cache filled by the cold run). × fastest peer: the tool's median wall time "
                  "over the fastest peer's on that structure. Mesh size after welding duplicate "
                  "vertices (PyMOL writes three per triangle). RMSD (Å), share of reference area "
                  "beyond 0.5 Å, dA, dV: `fdmsurf compare` against NanoShaper's analytical SES "
                  "(1CRN, 4HHB); dA and dV marked † are against NanoShaper's published area and "
                  "volume (4YVS, 1AON: no reference mesh).\n")
        rows = []
        for name, s in R["structures"].items():
            meds = {t: med([r["wall_s"] for r in s["runs"][t] if r["status"] == "ok"]) for t in tools}
            peers_ok = [meds[t] for t in tools if not t.startswith("fdmsurf") and meds[t] is not None]
            fastest = min(peers_ok) if peers_ok else None
            for t in tools:
                runs = s["runs"][t]
                okr = [r for r in runs if r["status"] == "ok"]
                mesh = s["mesh"].get(t, {})
                stop = s["stopped"].get(t)
                if not okr:
                    why = stop or "not run"
                    if why == "timeout":
                        why = f"timeout (> {self.a.timeout} s)"
                    rows.append([LABEL[t], name.upper(), len(runs), why] + ["–"] * 10)
                    continue
                w = meds[t]
                ratio = fmt(w / fastest, "{:.2f}") if fastest else "–"
                dag = "†" if mesh.get("vs_published") else ""
                rows.append([
                    LABEL[t], name.upper(), len(okr) if len(okr) == len(runs) else f"{len(okr)}/{len(runs)}",
                    fmt(w), ratio, fmt(max(r.get("rss_mib", 0) for r in okr), "{:.0f}"),
                    fmt(med([r.get("cpu_s") for r in okr])),
                    fmt(mesh.get("vertices"), "{:,}"), fmt(mesh.get("triangles"), "{:,}"),
                    fmt(mesh.get("rmsd"), "{:.3f}"), fmt(mesh.get("pct_area_beyond_spacing"), "{:.2f}%"),
                    fmt(mesh.get("area_rel_err"), "{:+.1%}") + dag, fmt(mesh.get("volume_rel_err"), "{:+.1%}") + dag,
                    (stop or "") + (" " if stop else "") + (f"scale {okr[-1]['edt_scale']:g}" if "edt_scale" in okr[-1] else "")
                    + (f"gen {med([r.get('gen_s') for r in okr]):.2f} s" if okr[-1].get("gen_s") is not None else ""),
                ])
        md.append(table(["tool", "structure", "runs", "median wall (s)", "× fastest peer", "peak RSS (MiB)",
                         "CPU (s)", "vertices", "triangles", "RMSD (Å)", "> 0.5 Å", "dA", "dV", "notes"], rows))
        for name, s in R["structures"].items():
            for n in s["notes"]:
                md.append(f"\n{name.upper()}: {n}")

        md.append("\n## fdmsurf: cold and warm, stage by stage\n")
        md.append("Cold: the first run with an empty `MESA_SHADER_CACHE_DIR` and `FDMSURF_CACHE_DIR` "
                  "(fresh directories). Warm: median of the timed runs, same directories. Stage times "
                  "(ms) from `--stats json` (`times`; GPU timestamps for GPU stages); 'unstaged' is fdmsurf's "
                  "total minus the stages (plan and pipeline set-up, buffer allocation, host work between "
                  "submissions; cold, mostly compilation); 'outside' is the "
                  "process wall time minus fdmsurf's own total (process start-up, Vulkan instance and "
                  "device teardown, exit).\n")
        stages = []
        for s in R["structures"].values():
            for r in [s.get("cold")] + s["runs"].get("fdmsurf", []):
                for k in (r or {}).get("times", {}):
                    if k not in stages:
                        stages.append(k)
        stages.sort(key=lambda k: STAGE_ORDER.index(k) if k in STAGE_ORDER else 99)
        rows = []
        for name, s in R["structures"].items():
            if "fdmsurf" not in s["runs"]:
                continue
            warm = [r for r in s["runs"]["fdmsurf"] if r.get("times")]
            cold = s.get("cold") if s.get("cold", {}).get("times") else None
            grid = (warm or [cold])[0].get("grid") if (warm or cold) else None
            gtxt = "×".join(str(g) for g in grid) if grid else "?"
            for label, rs in (("cold", [cold] if cold else []), ("warm", warm)):
                if not rs:
                    continue
                wall = med([r["wall_s"] for r in rs])
                total = med([r["total_ms"] for r in rs])
                medians = [med([r["times"].get(k) for r in rs]) for k in stages]
                other = total - sum(m for m in medians if m is not None)
                rows.append([name.upper(), f"{s['atoms']:,}", gtxt, label, fmt(wall)]
                            + [fmt(m, "{:.0f}") for m in medians]
                            + [fmt(other, "{:.0f}"), fmt(total, "{:.0f}"), fmt(wall * 1000 - total, "{:.0f}")])
        md.append(table(["structure", "atoms", "grid", "run", "wall (s)"] + stages
                        + ["unstaged (ms)", "total (ms)", "outside (ms)"], rows))

        if R["scaling"]:
            md.append("\n## Scaling: fdmsurf's stage times against voxels and atoms\n")
            md.append(f"Warm runs (median of {self.a.scaling_reps} after one run that fills the caches). "
                      "Rows marked * come from the side-by-side runs above. ns/voxel: stage time over "
                      "grid points; density µs/atom: density time over atoms.\n")
            rows, fit_rows, fit_y = [], [], []
            entries = [(e["label"], e["atoms"], e["grid"], e["runs"], "") for e in R["scaling"]]
            for name, s in R["structures"].items():
                warm = [r for r in s["runs"].get("fdmsurf", []) if r.get("times")]
                if warm:
                    entries.append((f"{name.upper()}, 0.5 Å", s["atoms"], warm[0]["grid"], warm, "*"))
            for label, atoms, grid, runs, mark in entries:
                vox = grid[0] * grid[1] * grid[2]
                t = {k: med([r["times"].get(k) for r in runs]) for k in runs[0]["times"]}
                d = (t.get("density") or 0.0) + (t.get("density-host") or 0.0)
                # The filter's transforms, or (on a CPU device) its convolution on the host.
                fft = (t.get("fft-forward") or 0) + (t.get("fft-inverse") or 0) + (t.get("filter-host") or 0)
                # Marching cubes up to the sizes (occupancy words and counts), then the output.
                mc = (t.get("mc-occupancy") or 0) + (t.get("mc-count") or 0)
                emit = ((t.get("mc-emit") or 0) + (t.get("mc-vertices") or 0) + (t.get("mc-triangles") or 0)
                        + (t.get("mc-host") or 0))
                tri = med([r.get("triangles") for r in runs])
                rows.append([label + mark, f"{atoms:,}", "×".join(map(str, grid)), f"{vox / 1e6:.2f}",
                             f"{d:.0f}", f"{d * 1e6 / vox:.0f}", f"{d * 1e3 / atoms:.1f}",
                             f"{fft:.0f}", f"{fft * 1e6 / vox:.0f}", f"{t.get('mask') or 0:.0f}",
                             f"{mc:.0f}", f"{mc * 1e6 / vox:.0f}", f"{emit:.0f}", fmt(tri, "{:,.0f}"),
                             f"{med([r['total_ms'] for r in runs]):.0f}", fmt(med([r['wall_s'] for r in runs]))])
                if not grid or len(runs) == 0:
                    continue
                slabs = runs[0].get("slabs")
                if d and (slabs in (None, 1)):
                    fit_rows.append((vox / 1e6, atoms / 1e3))
                    fit_y.append(d)
            md.append(table(["case", "atoms", "grid", "Mvoxels", "density (ms)", "density ns/voxel",
                             "density µs/atom", "filter: FFT fwd+inv or host (ms)", "filter ns/voxel",
                             "mask (ms)", "mc occupancy+count (ms)", "mc occupancy+count ns/voxel",
                             "mc vertices+triangles or mc-host (ms)", "triangles",
                             "total (ms)", "wall (s)"], rows))
            if len(fit_rows) >= 4:
                md.append(f"\nLeast-squares fits of the density time over the {len(fit_y)} single-slab rows "
                          f"(V in millions of voxels, A in thousands of atoms):\n")
                fits = {}
                for key, terms, text in (
                        ("additive", lambda v, a: (1.0, v, a), "{0:.0f} ms + {1:.1f} ms·V + {2:.2f} ms·A"),
                        ("product", lambda v, a: (1.0, v * a), "{0:.0f} ms + {1:.3f} ms·V·A"),
                        ("both", lambda v, a: (1.0, v, a, v * a),
                         "{0:.0f} ms + {1:.1f} ms·V + {2:.2f} ms·A + {3:.4f} ms·V·A")):
                    coef, r2, pred = lstsq([terms(v, a) for v, a in fit_rows], fit_y)
                    if coef is None:
                        continue
                    worst = max(abs(p - y) / y for p, y in zip(pred, fit_y))
                    md.append(f"- {key}: density ≈ " + text.format(*coef)
                              + f", R² = {r2:.3f}, worst relative residual {worst:.0%}")
                    fits[key] = {"coef": coef, "r2": r2}
                R["fits"] = fits
        return "\n".join(md) + "\n"

    def main(self):
        if self.a.report_only:            # re-render OUT/report.md from OUT/results.json
            with open(os.path.join(self.out, "results.json")) as fh:
                self.results = json.load(fh)
            md = self.report(self.results["meta"]["tools"])
            with open(os.path.join(self.out, "report.md"), "w") as fh:
                fh.write(md)
            print(md)
            return
        os.makedirs(self.out, exist_ok=True)
        # Run a private copy: colleagues may rebuild build/fdmsurf while the benchmark runs.
        os.makedirs(os.path.join(self.out, "bin"), exist_ok=True)
        copy = os.path.join(self.out, "bin", "fdmsurf")
        shutil.copy2(self.fdm, copy)
        self.fdm_src, self.fdm = self.fdm, copy
        global LOG
        LOG = os.path.join(self.out, "bench.log")
        t0 = time.perf_counter()
        write_probe_mesh(self.probe)
        self.results["meta"] = self.machine()
        log(f"load at start: {self.results['meta']['uptime_start']}")
        tools = self.available()
        self.results["meta"]["tools"] = tools
        log(f"tools: {', '.join(tools)}; structures: {self.a.structures}; reps {self.a.reps} "
            f"({self.a.reps_large} for 1AON)")
        for n in self.notes:
            log("note: " + n)
        for name in [s for s in self.a.structures.split(",") if s]:
            if name not in STRUCTURES:
                raise SystemExit(f"unknown structure {name}; known: {list(STRUCTURES)}")
            self.structure(name, tools)
            self.save()
        if not self.a.no_scaling:
            self.scaling()
        self.results["meta"]["uptime_end"] = sh(["uptime"])
        self.results["meta"]["bench_wall_s"] = time.perf_counter() - t0
        log(f"load at end: {self.results['meta']['uptime_end']}")
        md = self.report(tools)
        self.save()
        with open(os.path.join(self.out, "report.md"), "w") as fh:
            fh.write(md)
        print(md)
        log(f"wrote {self.out}/report.md and results.json")

    def save(self):
        with open(os.path.join(self.out, "results.json"), "w") as fh:
            json.dump(self.results, fh, indent=1)


def main(argv=None):
    ap = argparse.ArgumentParser(description="fdmsurf vs Mol*, PyMOL and EDTSurf, side by side "
                                             "(see docs/performance.md)")
    ap.add_argument("--reps", type=int, default=3, help="timed runs per tool and structure (default 3)")
    ap.add_argument("--reps-large", type=int, default=2, help="timed runs for 1AON (default 2)")
    ap.add_argument("--structures", default="1crn,4hhb,4yvs,1aon")
    ap.add_argument("--tools", default=",".join(ALL_TOOLS), help=f"default {','.join(ALL_TOOLS)}")
    ap.add_argument("--skip", default="1aon:pymol-q1",
                    help="STRUCTURE:TOOL pairs not run (default 1aon:pymol-q1; '' runs everything)")
    ap.add_argument("--timeout", type=int, default=300, help="seconds before a run is killed (default 300)")
    ap.add_argument("--long", type=float, default=60.0,
                    help="a peer whose first run takes longer than this is run once (default 60 s)")
    ap.add_argument("--no-scaling", action="store_true", help="skip the scaling table")
    ap.add_argument("--scaling-spacings", default="1.0,0.7,0.5")
    ap.add_argument("--synthetic-atoms", default="2000,8000,32000")
    ap.add_argument("--scaling-reps", type=int, default=2)
    ap.add_argument("--fdmsurf", default=os.path.join(ROOT, "build", "fdmsurf"))
    ap.add_argument("--shared", default=os.path.normpath(os.path.join(ROOT, "..", "shared")))
    ap.add_argument("--molstar", default=os.path.join(BENCH, ".cache", "molstar"),
                    help="folder with ms_surface.js and its node_modules (bench/run.sh installs it)")
    ap.add_argument("--out", default=os.path.join(BENCH, "out"))
    ap.add_argument("--report-only", action="store_true",
                    help="only print the tables again from OUT/results.json")
    a = ap.parse_args(argv)
    Bench(a).main()
    return 0


if __name__ == "__main__":
    sys.exit(main())
