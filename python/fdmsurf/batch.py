"""Surfaces of many structures on a Dask cluster: ``python3 -m fdmsurf.batch``.

    python3 -m fdmsurf.batch INPUTS... -o OUTDIR [--scheduler ADDRESS] [--workers N]
                             [surface and selection options of fdmsurf]

INPUTS are structure files, folders (searched recursively for .pdb, .ent, .cif, .mmcif, .pqr,
.xyzr and .xyzrn files, gzipped or not) and list files (@FILE, or a .txt/.list/.lst file: one
path per line, relative to the list file's folder, '#' comments). Without --scheduler a
LocalCluster starts on this machine with one worker process per GPU (or per core when the only
device is a CPU one, lavapipe); with --scheduler the run joins that cluster, whose workers must
be able to import fdmsurf and read the inputs and OUTDIR at the same paths.

Each worker process makes one Engine when it starts (a WorkerPlugin) and keeps it for every
structure it is given; each structure is one task (with --models all, every model of the file
in that one task, on one grid). Meshes are written under a temporary name and renamed
(OUTDIR/NAME.ply, or NAME-mK.ply per model). The client appends one JSON line per structure to
OUTDIR/manifest.jsonl as each one finishes: input, output, atoms, vertices, triangles, area,
volume, pieces, closed, times (ms per stage), warnings, status ('ok' or 'failed'), error and
error_class, and options_hash, a hash of every setting that changes the meshes. A structure that
fails is recorded and the rest go on. A re-run with the same options skips every structure
whose row says ok (its files still there) or failed for a reason that would fail again (an
unreadable file, a bad selection; --retry-failed retries those too): an interrupted run picks up
where it stopped. Exit status: 0 when every structure has a mesh, 1 when any failed, 2 for a
usage error.
"""

import argparse
import contextlib
import datetime
import hashlib
import json
import math
import os
import re
import sys
import time

import fdmsurf
from fdmsurf import _options

STRUCTURE_SUFFIXES = (".pdb", ".ent", ".cif", ".mmcif", ".pqr", ".xyzr", ".xyzrn")
LIST_SUFFIXES = (".txt", ".list", ".lst")
MANIFEST = "manifest.jsonl"
PLUGIN = "fdmsurf-engine"
# Failures that a re-run would repeat: skipped by a re-run unless --retry-failed. Others (a
# worker that died, a device failure) are retried.
REPEATABLE = frozenset({"InvalidArgumentError", "FileError", "FormatError",
                        "EmptySelectionError", "DeviceLimitError"})


# --- inputs and outputs ---------------------------------------------------------------------

def _strip_gz(name):
    return name[:-3] if name.lower().endswith(".gz") else name


def is_structure_file(name):
    return _strip_gz(name).lower().endswith(STRUCTURE_SUFFIXES)


def find_inputs(inputs):
    """The structure files that INPUTS name, in order, each once (by absolute path). A path
    that does not exist is kept: it becomes one failed row. One path (str, bytes or
    os.PathLike) is one input."""
    if isinstance(inputs, (str, bytes, os.PathLike)):  # not its characters
        inputs = [inputs]
    found, seen = [], set()

    def add(path):
        key = os.path.abspath(path)
        if key not in seen:
            seen.add(key)
            found.append(path)

    for item in inputs:
        item = os.fsdecode(item)  # str, bytes or os.PathLike
        if item.startswith("@") or (os.path.isfile(item) and item.endswith(LIST_SUFFIXES)):
            list_path = item[1:] if item.startswith("@") else item
            folder = os.path.dirname(list_path)
            with open(list_path, encoding="utf-8") as lines:
                for line in lines:
                    line = line.strip()
                    if line and not line.startswith("#"):
                        add(os.path.join(folder, line))
        elif os.path.isdir(item):
            for root, dirs, files in os.walk(item):
                dirs.sort()
                for name in sorted(files):
                    if is_structure_file(name):
                        add(os.path.join(root, name))
        else:
            add(item)
    return found


def is_temporary_of(name, stem, mesh_format):
    """Whether NAME is the temporary file of a mesh named STEM[-mN].FORMAT: that name followed
    by .tmp. and 12 hex digits, or, where both would pass 255 bytes, the name cut short in front
    of the suffix, as the library's atomic writer makes it."""
    m = re.fullmatch(r"(.*)\.tmp\.[0-9a-f]{12}", name, re.S)
    if not m:
        return False
    head = m.group(1)
    if re.fullmatch(re.escape(stem) + r"(-m[0-9]+)?\." + re.escape(mesh_format), head, re.S):
        return True
    if len(os.fsencode(name)) != 255:
        return False
    # Cut short: HEAD is the start of such a name.
    if stem.startswith(head):
        return True
    if not head.startswith(stem):
        return False
    rest = re.fullmatch(r"(?:\.|-m[0-9]+\.)(.*)|-(?:m[0-9]*)?", head[len(stem):], re.S)
    return rest is not None and mesh_format.startswith(rest.group(1) or "")


def remove_stale_temporaries(outdir, stems, mesh_format):
    """Removes the temporary files that the meshes STEMS (.FORMAT) of OUTDIR left."""
    names = os.listdir(outdir) if os.path.isdir(outdir) else []
    for stem in stems:
        for name in names:
            if ".tmp." in name and is_temporary_of(name, stem, mesh_format):
                try:
                    os.remove(os.path.join(outdir, name))
                except FileNotFoundError:
                    pass


def stem_of(path):
    """1abc.cif.gz -> 1abc: the name its meshes get."""
    return os.path.splitext(_strip_gz(os.path.basename(path)))[0]


# The formats of SurfaceResult.write (fdmsurf's --output-format).
MESH_FORMATS = ("ply", "obj", "glb", "stl", "off")


def options_hash(keywords, mesh_format, all_models):
    """A hash of every setting that changes the meshes: the options as the library resolves
    them (so spacing=0.5 and no spacing hash alike), the mesh format and --models all."""
    described = _options.parse(keywords, ["--models=all"] if all_models else []).describe()
    blob = json.dumps({"options": described, "format": mesh_format}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def read_manifest(path):
    """The last row of each input (by absolute path) in a manifest; a torn last line (a run
    killed while writing it) is ignored."""
    rows = {}
    if os.path.exists(path):
        with open(path, encoding="utf-8") as lines:
            for line in lines:
                try:
                    row = json.loads(line)
                    rows[row["key"]] = row
                except (ValueError, KeyError, TypeError):
                    continue
    return rows


def _outputs(row):
    output = row.get("output")
    return output if isinstance(output, list) else [output] if output else []


def is_done(row, digest, retry_failed=False):
    """Whether a manifest row makes its structure's task unnecessary under options `digest`."""
    if row is None or row.get("options_hash") != digest:
        return False
    if row.get("status") == "ok":
        return all(os.path.exists(path) for path in _outputs(row))
    return not retry_failed and row.get("error_class") in REPEATABLE


# --- on the workers -------------------------------------------------------------------------

try:
    from distributed.diagnostics.plugin import WorkerPlugin
except ImportError:  # fdmsurf.batch's helpers stay importable without Dask
    WorkerPlugin = object


class EnginePlugin(WorkerPlugin):
    """Makes one fdmsurf.Engine per worker process, when the worker starts, for every task it
    runs. device: as Engine's; None gives each worker on a several-GPU machine its own GPU when
    the worker's name ends in a number i (a LocalCluster's 0, 1, ...; `dask-worker --nworkers
    N --name NODE` gives NODE-0 ... NODE-(N-1)): GPU i mod their count; else the default
    device."""

    name = PLUGIN

    def __init__(self, device=None, validation=False):
        self.device = device
        self.validation = validation
        self.engine = None
        self.error = None
        self.device_in_use = device

    def setup(self, worker):
        _undo_malloc_trimming()
        try:
            device = self.device
            if device is None:
                gpus = [d["index"] for d in fdmsurf.list_devices()
                        if d["usable"] and d["type"] != "CPU"]
                number = re.search(r"([0-9]+)$", str(worker.name))
                if len(gpus) > 1 and number:
                    device = gpus[int(number.group(1)) % len(gpus)]
            self.device_in_use = device
            self.engine = fdmsurf.Engine(device=device, validation=self.validation)
        except fdmsurf.Error as e:
            self.error = e  # each task reports it as its failure
            raise

    def teardown(self, worker):
        if self.engine is not None:
            self.engine.close()


def _undo_malloc_trimming():
    """Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536, which also fixes glibc's
    mmap threshold at 128 KiB: every large allocation is then a fresh mmap, faulted in page by
    page. Lavapipe allocates its working memory as it computes, and its FFTs ran 5 times slower
    so (docs/python.md, Throughput). Restore the thresholds glibc would have grown to."""
    if "MALLOC_TRIM_THRESHOLD_" not in os.environ:
        return
    try:
        import ctypes
        libc = ctypes.CDLL("libc.so.6")
    except OSError:  # not glibc
        return
    m_trim_threshold, m_mmap_threshold = -1, -3  # <malloc.h>
    libc.mallopt(m_mmap_threshold, 32 << 20)  # glibc's largest dynamic mmap threshold
    libc.mallopt(m_trim_threshold, 64 << 20)  # twice that, as glibc's dynamic rule keeps it


def _worker_engine():
    from distributed import get_worker
    plugin = get_worker().plugins.get(PLUGIN)
    if plugin is None or plugin.engine is None:
        if plugin is not None and plugin.error is not None:
            raise plugin.error
        raise fdmsurf.DeviceError("this worker has no fdmsurf engine (plugin not set up)")
    return plugin.engine


def _renew_worker_engine():
    """A new engine for this worker after a Vulkan failure; if that fails too, the worker's
    later tasks report why."""
    try:
        from distributed import get_worker
        plugin = get_worker().plugins.get(PLUGIN)
    except (ImportError, ValueError):
        return
    if plugin is None or plugin.engine is None:
        return
    plugin.engine.close()
    plugin.engine = None
    try:
        plugin.engine = fdmsurf.Engine(device=plugin.device_in_use, validation=plugin.validation)
    except fdmsurf.Error as e:
        plugin.error = e


def _worker_address():
    try:
        from distributed import get_worker
        return get_worker().address
    except (ImportError, ValueError):  # not on a Dask worker (compute called directly)
        return None


def _ms(start):
    return round((time.perf_counter() - start) * 1000.0, 3)


def compute(path, outdir, keywords, mesh_format, all_models, digest, engine=None):
    """One task: the surface(s) of the structure file at `path`, written to OUTDIR; returns its
    manifest row. Every failure becomes a failed row (the worker stays up)."""
    start = time.perf_counter()
    stem = stem_of(path)
    row = {"input": path, "key": os.path.abspath(path), "options_hash": digest,
           "version": fdmsurf.__version__}
    read = {k: v for k, v in keywords.items() if k in _options.READ_NAMES}
    surface = {k: v for k, v in keywords.items() if k not in _options.READ_NAMES}
    try:
        engine = engine or _worker_engine()
        t = time.perf_counter()
        if all_models:
            structures = fdmsurf.read_models(path, **read)
        else:
            structures = [fdmsurf.read_structure(path, **read)]
        read_ms = _ms(t)
        if all_models and len(structures) > 1:
            grid = [0, 0, 0]
            for s in structures:
                grid = [max(a, b) for a, b in zip(grid, fdmsurf.plan_grid(s, **surface)["dims"])]
            surface["min_grid"] = tuple(grid)
        models = []
        for structure in structures:
            model = structure.info["model"]
            name = f"{stem}-m{model}" if all_models else stem
            output = os.path.join(outdir, f"{name}.{mesh_format}")
            result = engine.surface(structure, **surface)
            t = time.perf_counter()
            result.write(output, format=mesh_format)
            times = {"read": read_ms, **{k: round(v, 3) for k, v in result.times.items()},
                     "write": _ms(t)}
            read_ms = 0.0
            models.append({"output": output, "model": model, "atoms": len(structure),
                           "vertices": result.vertex_count, "triangles": result.triangle_count,
                           "area": result.area, "volume": result.volume,
                           "pieces": result.pieces, "closed": result.closed_manifold,
                           "grid": list(result.grid["dims"]), "times": times,
                           "warnings": structure.info["warnings"] + result.warnings})
            del result
        fields = models[0].keys()
        if all_models:  # every field a list, one entry per model
            row.update({f: [m[f] for m in models] for f in fields})
        else:
            row.update(models[0])
        row.update(status="ok", error=None, error_class=None, device=engine.device["name"])
        row["worker"] = _worker_address()
    except Exception as e:  # noqa: BLE001 - any failure is this structure's row
        row.update(status="failed", error=str(e) or repr(e), error_class=type(e).__name__)
        if isinstance(e, fdmsurf.VulkanError):
            _renew_worker_engine()  # a failed device (lost, out of memory) fails every later task
    row["elapsed_ms"] = _ms(start)
    return row


def _finite_or_none(value):
    """VALUE with every float that is not finite replaced by None (strict JSON has no NaN)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite_or_none(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_finite_or_none(v) for v in value]
    return value


def _printable(name):
    """NAME with the bytes of a file name that are not UTF-8 as U+FFFD (for Dask's keys)."""
    return os.fsencode(name).decode("utf-8", "replace")


def _row_text(row):
    """A manifest row as one line of strict JSON. File names that are not UTF-8 (str with
    surrogate escapes, as os.fsdecode gives them) are written as \\udcXX escapes, which read
    back to the same str."""
    return json.dumps(_finite_or_none(row), allow_nan=False)


def _compute_text(*args):
    """compute() for a Dask task: its row as JSON text, which Dask's transport carries whatever
    the file names hold (it refuses str that are not valid UTF-8)."""
    return _row_text(compute(*args))


# --- on the client --------------------------------------------------------------------------

def default_workers():
    """One worker per usable GPU, or per core when the usable devices are all CPU ones."""
    devices = [d for d in fdmsurf.list_devices() if d["usable"]]
    if not devices:
        raise fdmsurf.NoDeviceError("no usable Vulkan device (install mesa-vulkan-drivers for "
                                    "lavapipe on a machine without a GPU)")
    gpus = [d for d in devices if d["type"] != "CPU"]
    return len(gpus) if gpus else (os.cpu_count() or 1)


class _Progress:
    def __init__(self, stream, total):
        self.stream, self.total, self.done = stream, total, 0
        self.start = time.perf_counter()

    def __call__(self, row):
        self.done += 1
        if self.stream is None:
            return
        elapsed = time.perf_counter() - self.start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else 0.0
        status = "ok" if row["status"] == "ok" else "FAILED"
        width = len(str(self.total))
        line = (f"[{self.done:{width}}/{self.total}] {status:6} {stem_of(row['input'])} "
                f"{row.get('elapsed_ms', 0) / 1000:.2f} s ({rate:.2f}/s, ETA {eta:.0f} s)")
        if row["status"] != "ok":
            line += f": {row['error_class']}: {row['error']}"
        print(line, file=self.stream, flush=True)


@contextlib.contextmanager
def _dask_client(client, scheduler, workers, memory_limit="auto"):
    """(client, cluster) for a run: `client` as given (cluster None, left open), else a client
    of `scheduler`, else of a LocalCluster of `workers` single-threaded processes (default:
    default_workers()); those two are closed when the run ends."""
    from distributed import Client, LocalCluster

    if client is not None:
        yield client, None
        return
    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        import logging
        # dashboard_address=None still binds the scheduler's HTTP server to port 8787, and a
        # second cluster on the machine then warns on stderr that the port is taken: ":0" takes
        # a free port.
        cluster = LocalCluster(n_workers=workers or default_workers(), threads_per_worker=1,
                               processes=True, dashboard_address=":0", memory_limit=memory_limit,
                               silence_logs=logging.ERROR)
        client = Client(cluster)
    try:
        yield client, cluster
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _check_memory_limit(limit):
    """InvalidArgumentError unless LIMIT is one that LocalCluster takes: 'auto', None or 0 (no
    limit), a number of bytes, a fraction of the memory (a number up to 1, as '0.5'), or a size
    such as '4GB' ('0GB': no limit)."""
    if limit is None or limit == "auto":
        return
    if isinstance(limit, str):
        try:
            limit = float(limit)
        except ValueError:
            from dask.utils import parse_bytes
            try:
                if parse_bytes(limit) >= 0:
                    return
            except (ValueError, TypeError):
                pass
    if isinstance(limit, (int, float)) and not isinstance(limit, bool):
        if limit >= 0 and math.isfinite(limit):
            return
    raise fdmsurf.InvalidArgumentError(
        f"memory limit must be 'auto', 0 (none), a fraction of the memory (0.5), a number of "
        f"bytes or a size such as '4GB', not {limit!r}")


def run(inputs, outdir, *, scheduler=None, workers=None, client=None, device=None,
        validation=False, mesh_format="ply", all_models=False, retry_failed=False,
        memory_limit="auto", progress=sys.stderr, **keywords):
    """Computes the surfaces of INPUTS into OUTDIR on a Dask cluster (see the module's help);
    returns a summary dict: inputs, skipped (done before), computed, failed, failed_before
    (skipped because they failed before), seconds, startup_seconds (cluster start and engine
    creation), workers, manifest, rows (the rows written by this run). client: an existing
    distributed.Client to use (its cluster is left running); else scheduler: an address to
    join; else a LocalCluster of `workers` processes (default_workers()). keywords: those of
    fdmsurf.Engine.surface. From a script, call it under `if __name__ == "__main__":` (Dask
    spawns the worker processes, which import the script)."""
    _options.check_names("run", keywords, list(_options.KEYWORDS))
    if mesh_format not in MESH_FORMATS:
        raise fdmsurf.InvalidArgumentError(
            f"mesh format must be {', '.join(MESH_FORMATS[:-1])} or {MESH_FORMATS[-1]}, "
            f"not {mesh_format!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 1):
        raise fdmsurf.InvalidArgumentError(f"workers must be a whole number >= 1, not {workers!r}")
    _check_memory_limit(memory_limit)
    digest = options_hash(keywords, mesh_format, all_models)  # bad options fail here, early
    paths = find_inputs(inputs)
    by_stem = {}
    for path in paths:
        other = by_stem.setdefault(stem_of(path), path)
        if other != path:
            raise fdmsurf.InvalidArgumentError(
                f"inputs '{other}' and '{path}' would both write {stem_of(path)}.{mesh_format}")
    os.makedirs(outdir, exist_ok=True)
    manifest = os.path.join(outdir, MANIFEST)
    previous = read_manifest(manifest)
    todo = [p for p in paths if not is_done(previous.get(os.path.abspath(p)), digest,
                                            retry_failed)]
    # Largest files first: the long tasks start early and do not trail at the end.
    todo.sort(key=lambda p: -os.path.getsize(p) if os.path.exists(p) else 0)
    # Structures skipped because they failed before, for a reason that would repeat.
    failed_before = sum(1 for p in paths if p not in todo and
                        previous[os.path.abspath(p)].get("status") != "ok")
    summary = {"inputs": len(paths), "skipped": len(paths) - len(todo), "computed": 0,
               "failed": 0, "failed_before": failed_before, "seconds": 0.0,
               "startup_seconds": 0.0, "workers": 0,
               "manifest": manifest, "rows": []}
    if progress is not None:
        note = (f" ({failed_before} of them failed: --retry-failed retries them)"
                if failed_before else "")
        print(f"fdmsurf.batch: {len(paths)} structure(s), {summary['skipped']} done "
              f"already{note}, {len(todo)} to compute", file=progress, flush=True)
    if not todo:
        return summary

    from distributed import as_completed

    start = time.perf_counter()
    with _dask_client(client, scheduler, workers, memory_limit) as (client, cluster):
        responses = client.register_worker_plugin(EnginePlugin(device, validation), name=PLUGIN)
        broken = {w: r for w, r in responses.items() if r.get("status") != "OK"}
        if responses and len(broken) == len(responses):
            first = next(iter(broken.values()))
            raise fdmsurf.DeviceError("no worker could make an fdmsurf engine: "
                                      f"{first.get('exception_text') or first}")
        summary["workers"] = len(responses)
        summary["startup_seconds"] = time.perf_counter() - start  # cluster, engines
        if progress is not None:
            where = scheduler or ("LocalCluster" if cluster else client.scheduler.address)
            print(f"fdmsurf.batch: {len(responses)} worker(s) on {where}", file=progress,
                  flush=True)
        futures = {client.submit(_compute_text, path, outdir, keywords, mesh_format, all_models,
                                 digest, pure=False,
                                 key=f"fdmsurf-{_printable(stem_of(path))}-{digest}-"
                                 f"{os.urandom(4).hex()}"): path
                   for path in todo}
        report = _Progress(progress, len(todo))
        with open(manifest, "a", encoding="utf-8") as out:
            for future in as_completed(futures):
                path = futures[future]
                if future.status == "finished":
                    row = json.loads(future.result())
                else:  # the task itself could not run: a worker died on it, repeatedly
                    error = future.exception()
                    row = {"input": path, "key": os.path.abspath(path), "options_hash": digest,
                           "version": fdmsurf.__version__, "status": "failed",
                           "error": str(error) or repr(error),
                           "error_class": type(error).__name__}
                future.release()
                row["finished"] = datetime.datetime.now(datetime.timezone.utc).isoformat(
                    timespec="seconds")
                out.write(_row_text(row) + "\n")
                out.flush()
                os.fsync(out.fileno())
                summary["rows"].append(row)
                summary["computed" if row["status"] == "ok" else "failed"] += 1
                report(row)
    # A worker killed while writing leaves its temporary file: remove those of this run's
    # meshes (every task has ended, so none is being written).
    remove_stale_temporaries(outdir, [stem_of(path) for path in todo], mesh_format)
    summary["seconds"] = time.perf_counter() - start
    if progress is not None:
        rate = len(todo) / summary["seconds"] if summary["seconds"] > 0 else 0.0
        print(f"fdmsurf.batch: {summary['computed']} computed, {summary['failed']} failed, "
              f"{summary['skipped']} skipped in {summary['seconds']:.1f} s ({rate:.2f} "
              f"structures/s); manifest {manifest}", file=progress, flush=True)
    return summary


def _argument_parser():
    parser = argparse.ArgumentParser(
        prog="python3 -m fdmsurf.batch",
        description="Surfaces of many structures on a Dask cluster (docs/python.md).",
        epilog="Surface and selection options are those of fdmsurf --help, with the same "
               "names and defaults. Exit status: 0 all done, 1 some failed, 2 usage error.")
    parser.add_argument("inputs", nargs="+", metavar="INPUT",
                        help="structure files, folders, list files (@FILE or .txt/.list/.lst)")
    parser.add_argument("-o", "--output", required=True, metavar="OUTDIR",
                        help="folder for the meshes and manifest.jsonl (created)")
    run_group = parser.add_argument_group("cluster")
    run_group.add_argument("--scheduler", metavar="ADDRESS",
                           help="join this Dask scheduler (tcp://host:8786) instead of starting "
                                "a LocalCluster")
    run_group.add_argument("--workers", type=int, metavar="N",
                           help="LocalCluster worker processes (default: one per GPU, or per "
                                "core on a CPU device)")
    run_group.add_argument("--memory-limit", default="auto", metavar="LIMIT",
                           help="LocalCluster memory limit per worker ('4GB', 0 for none; "
                                "default auto: the machine's memory shared out)")
    run_group.add_argument("--device", help="Vulkan device of every worker (index or name)")
    run_group.add_argument("--validation", action="store_true",
                           help="Vulkan validation layer (its messages go to the warnings)")
    run_group.add_argument("--mesh-format", choices=MESH_FORMATS, default="ply",
                           help="mesh files: binary PLY (default), OBJ, GLB, binary STL or "
                                "OFF (as fdmsurf --output-format)")
    run_group.add_argument("--models", choices=("all",),
                           help="every model of each file, one mesh each (NAME-mK.ply), in "
                                "one task")
    run_group.add_argument("--retry-failed", action="store_true",
                           help="recompute structures that failed before for reasons that "
                                "would repeat (unreadable file, bad selection)")
    run_group.add_argument("--quiet", action="store_true", help="no progress lines")
    surface = parser.add_argument_group("surface and selection (as fdmsurf)")
    types = {"float": float, "int": int}
    for k in _options.SURFACE + _options.READ:
        if k.cli is None:
            continue
        help_text = f"{k.doc} (default {k.default!r})"
        if k.kind == "flag":
            surface.add_argument(k.cli, dest=k.name, action="store_true", default=None,
                                 help=k.doc)
        elif k.kind == "negflag":
            surface.add_argument(k.cli, dest=k.name, action="store_false", default=None,
                                 help=_options.NEGATED_HELP[k.name])
        else:
            names = [k.cli, "--colour"] if k.name == "color" else [k.cli]
            surface.add_argument(*names, dest=k.name, type=types.get(k.kind, str),
                                 default=None, metavar=k.name.upper(),
                                 help=help_text.replace("%", "%%"))
    return parser


def main(argv=None):
    args = _argument_parser().parse_args(argv)
    keywords = {k: getattr(args, k) for k in _options.KEYWORDS
                if getattr(args, k, None) is not None}
    try:
        summary = run(args.inputs, args.output, scheduler=args.scheduler, workers=args.workers,
                      device=args.device, validation=args.validation,
                      mesh_format=args.mesh_format, all_models=args.models == "all",
                      retry_failed=args.retry_failed, memory_limit=args.memory_limit,
                      progress=None if args.quiet else sys.stderr, **keywords)
    except (fdmsurf.InvalidArgumentError, TypeError) as e:
        print(f"fdmsurf.batch: error: {e}", file=sys.stderr)
        return 2
    except (fdmsurf.Error, OSError) as e:
        print(f"fdmsurf.batch: error: {e}", file=sys.stderr)
        return 1
    return 1 if summary["failed"] or summary["failed_before"] else 0


if __name__ == "__main__":
    sys.exit(main())


# --- one trajectory over many workers ---------------------------------------------------------

def _open(source):
    return source() if callable(source) else source


def _frame_count(source):
    kind = type(source).__name__
    library = fdmsurf._objects.library_of(source)
    if library == "MDAnalysis":
        return len(source.universe.trajectory)
    if library == "mdtraj" and kind == "Trajectory":
        return source.n_frames
    if hasattr(source, "shape") and len(source.shape) == 3:
        return source.shape[0]
    raise TypeError("batch.trajectory takes an MDAnalysis Universe or AtomGroup, an mdtraj "
                    "Trajectory or a (frames, atoms, 3) array, or a picklable callable that "
                    f"returns one; not a {kind}")


def _chunk_grid(source, start, stop, keywords):
    from .trajectory import Trajectory
    run = Trajectory(None, _open(source), keywords.pop("radii", None),
                     keywords.pop("topology", None), keywords, sasa=True, ses=True,
                     atom_areas=False, write=None, callback=None, keep_mesh=False, start=start,
                     stop=stop, stride=1, grid="all", on_error="skip", progress=False)
    return run._fix_grid()


def _chunk_rows(source, start, stop, grid, sasa, ses, atom_areas, write, on_error, keywords):
    _undo_malloc_trimming()
    engine = _worker_engine()
    run = engine.trajectory(_open(source), keywords.pop("radii", None),
                            topology=keywords.pop("topology", None), sasa=sasa, ses=ses,
                            atom_areas=atom_areas, write=write, start=start, stop=stop,
                            grid=grid if grid is not None else "all", on_error=on_error,
                            progress=False, **keywords)
    return list(run)


def trajectory(source, *, chunk=100, start=0, stop=None, client=None, scheduler=None,
               workers=None, device=None, sasa=True, ses=True, atom_areas=True, write=None,
               grid=None, on_error="stop", progress=sys.stderr, **keywords):
    """Engine.trajectory over a Dask cluster: the frames start..stop split into ranges of
    `chunk` frames, one task each, and the rows (fdmsurf.trajectory.Frame) gathered in frame
    order into one list.

    source: what Engine.trajectory takes (an MDAnalysis Universe, an mdtraj Trajectory, an
    array), or better a picklable callable that returns it (functools.partial(
    MDAnalysis.Universe, topology, trajectory), or np.load with mmap_mode='r'): each task then
    opens the files on its worker and reads only its frames. keywords: Engine.trajectory's
    (radii=, topology=, selection and surface keywords). grid: None finds the grid dims that
    hold every frame by a first round of tasks (each its range's largest), so every worker
    uses the same grid and the series is the one Engine.trajectory gives in one process; or
    fixed (nx, ny, nz). client / scheduler / workers / device as batch.run: an existing
    Client, a scheduler's address, or a LocalCluster of `workers` processes, one Engine each.
    Call it under `if __name__ == "__main__":` (the worker processes import the script)."""
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise fdmsurf.InvalidArgumentError(f"chunk must be a whole number >= 1, not {chunk!r}")
    for name in ("callback", "keep_mesh", "stride"):
        if name in keywords:
            raise TypeError(f"batch.trajectory runs on the workers: no {name}= (meshes stay "
                            "there; write= writes them)")
    total = _frame_count(_open(source))
    first, last, _ = slice(start, stop).indices(total)
    ranges = [(a, min(a + chunk, last)) for a in range(first, last, chunk)]
    if not ranges:
        return []

    with _dask_client(client, scheduler, workers) as (client, _):
        client.register_worker_plugin(EnginePlugin(device, False), name=PLUGIN)
        if ses and grid is None:
            dims = client.gather([client.submit(_chunk_grid, source, a, b, dict(keywords),
                                                pure=False) for a, b in ranges])
            dims = [d for d in dims if d is not None]
            grid = tuple(int(max(d[k] for d in dims)) for k in range(3)) if dims else None
        futures = [client.submit(_chunk_rows, source, a, b, grid, sasa, ses, atom_areas, write,
                                 on_error, dict(keywords), pure=False) for a, b in ranges]
        rows = []
        started = time.perf_counter()
        for i, future in enumerate(futures):    # in frame order, as each range is done
            rows.extend(future.result())
            if progress is not None:
                print(f"fdmsurf.batch.trajectory: frames {ranges[i][0]}-{ranges[i][1] - 1} "
                      f"({i + 1}/{len(ranges)}, {time.perf_counter() - started:.1f} s)",
                      file=progress, flush=True)
        return rows
