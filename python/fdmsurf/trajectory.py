"""Surfaces and areas of every frame of a trajectory (docs/trajectories.md): Engine.trajectory.

The atoms are selected once (the read keywords, applied by fdmsurf's reader to the topology);
each frame then only moves them: its coordinates are copied into the one Structure, whose surface
(on one grid size for the whole run, so the engine's FFT plan and pipelines are made once) and
exact sphere-patch areas make the frame's row. Frames are read as they are processed, one at a
time, and nothing of a frame is kept once its row has been handed out: memory stays flat over
any number of frames.
"""

import math
import os
import sys
import time

import numpy as np

from . import _fdmsurf, _objects, _options

SOURCES = ("an MDAnalysis Universe or AtomGroup, an mdtraj Trajectory, or coordinates (frames, "
           "atoms, 3) in Å (a numpy array, memmap, or an iterable of (atoms, 3) arrays) with "
           "radii=(atoms,) or topology=")


class Frame:
    """One frame's row. frame: its index in the source; time: the source's time (ps) or None;
    ok: False when the frame could not be computed (error says why; the numbers are NaN).
    area (Å²), volume (Å³), pieces, cavities (count) and cavity_volume (Å³, positive) describe
    the surface; sasa is the total solvent-accessible area (Å², exact sphere patches);
    atom_sasa / residue_sasa and atom_area / residue_area (the surface's area by atom) are
    arrays over Trajectory.atoms / Trajectory.residues, None when not asked for; ms is the
    frame's wall time; mesh: the SurfaceResult when keep_mesh=True, else None."""

    __slots__ = ("frame", "time", "ok", "error", "area", "volume", "pieces", "cavities",
                 "cavity_volume", "sasa", "atom_sasa", "residue_sasa", "atom_area",
                 "residue_area", "mesh", "path", "ms")

    def __init__(self, frame, time_ps):
        self.frame = frame
        self.time = time_ps
        self.ok = True
        self.error = None
        self.area = self.volume = self.cavity_volume = self.sasa = math.nan
        self.pieces = self.cavities = 0
        self.atom_sasa = self.residue_sasa = self.atom_area = self.residue_area = None
        self.mesh = None
        self.path = None
        self.ms = 0.0

    def row(self):
        """The frame's scalars as a dict (one row of a table: CSV, JSON lines, a DataFrame)."""
        return {name: getattr(self, name) for name in (
            "frame", "time", "ok", "error", "area", "volume", "pieces", "cavities",
            "cavity_volume", "sasa", "path", "ms")}

    def __repr__(self):
        if not self.ok:
            return f"<fdmsurf.Frame {self.frame}: failed: {self.error}>"
        return (f"<fdmsurf.Frame {self.frame}: area {self.area:.1f} Å², volume "
                f"{self.volume:.1f} Å³, {self.cavities} cavities, SASA {self.sasa:.1f} Å²>")


class _Source:
    """Frames of one source: count(), and frames() -> (index, time, xyz of the object's atoms)."""

    def __init__(self, name, n_atoms, count, frames):
        self.name = name
        self.n_atoms = n_atoms
        self._count = count
        self._frames = frames

    def count(self):
        return self._count

    def frames(self):
        return self._frames()


def _range(n, start, stop, stride):
    if stride is None:
        stride = 1
    if isinstance(stride, bool) or not isinstance(stride, int) or stride < 1:
        raise _fdmsurf.InvalidArgumentError(f"stride must be an integer >= 1, not {stride!r}")
    for name, value in (("start", start), ("stop", stop)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int)):
            raise TypeError(f"{name} must be an integer or None, not {type(value).__name__}")
    return range(n)[slice(start, stop, stride)] if n is not None else None


def _mdanalysis_source(obj, start, stop, stride):
    group = obj.atoms if type(obj).__name__ == "Universe" else obj
    universe = group.universe
    trajectory = universe.trajectory
    frames = _range(len(trajectory), start, stop, stride)

    def read():
        for ts in trajectory[frames.start:frames.stop:frames.step]:
            if ts.n_atoms != len(universe.atoms):
                yield ts.frame, ts.time, _BadFrame(
                    f"frame {ts.frame} has {ts.n_atoms} atoms, the topology "
                    f"{len(universe.atoms)}")
                continue
            yield ts.frame, float(ts.time), group.positions

    return _Source(f"MDAnalysis {type(obj).__name__}", len(group), len(frames), read)


def _mdtraj_source(obj, start, stop, stride):
    frames = _range(obj.n_frames, start, stop, stride)
    times = getattr(obj, "time", None)

    def read():
        for i in frames:
            t = float(times[i]) if times is not None and len(times) > i else None
            yield i, t, obj.xyz[i] * np.float32(10.0)  # nm -> Å

    return _Source("mdtraj Trajectory", obj.n_atoms, len(frames), read)


class _BadFrame:
    """A frame that cannot be used, with why (its row says so, or the run stops)."""

    def __init__(self, message):
        self.message = message


def _array_source(coordinates, n_atoms, start, stop, stride):
    if isinstance(coordinates, np.ndarray) or hasattr(coordinates, "__array_interface__"):
        array = np.asarray(coordinates) if not isinstance(coordinates, np.ndarray) else coordinates
        if array.ndim != 3 or array.shape[2] != 3:
            raise _fdmsurf.InvalidArgumentError(
                f"coordinates must have shape (frames, atoms, 3), not {array.shape}")
        if array.dtype.kind not in "fiu":
            raise TypeError(f"coordinates must hold real numbers, not dtype {array.dtype}")
        if array.shape[1] != n_atoms:
            raise _fdmsurf.InvalidArgumentError(
                f"the frames have {array.shape[1]} atoms, the topology {n_atoms}: they must be "
                "the same atoms")
        frames = _range(array.shape[0], start, stop, stride)

        def read():
            for i in frames:  # a memmap reads each frame from disk here, not before
                yield i, None, array[i]

        return _Source("coordinates", n_atoms, len(frames), read)
    if isinstance(coordinates, (str, bytes)) or not hasattr(coordinates, "__iter__"):
        raise TypeError(f"Engine.trajectory takes {SOURCES}; not a {type(coordinates).__name__}")
    _range(None, start, stop, stride)
    step = stride or 1
    first = start or 0

    def read():
        for i, xyz in enumerate(coordinates):
            if i < first or (stop is not None and i >= stop) or (i - first) % step:
                continue
            array = np.asarray(xyz)
            if array.shape != (n_atoms, 3):
                yield i, None, _BadFrame(f"frame {i} has shape {array.shape}, the topology "
                                         f"needs ({n_atoms}, 3)")
                continue
            yield i, None, array

    return _Source("coordinates", n_atoms, None, read)


def _residue_index(structure):
    """Per atom the index of its residue (chain, number, insertion code, name; in order of first
    appearance) and the residues as (chain, number, insertion_code, name); None without
    metadata."""
    if structure.chain is None:
        return None, None
    keys = list(zip(structure.chain.tolist(), structure.residue_number.tolist(),
                    structure.insertion_code.tolist(), structure.residue_name.tolist()))
    seen = {}
    index = np.empty(len(keys), dtype=np.int64)
    for i, key in enumerate(keys):
        index[i] = seen.setdefault(key, len(seen))
    return index, list(seen)


class Trajectory:
    """The frames of a run of Engine.trajectory: iterate it for one Frame per frame, in frame
    order. atoms: the Structure of the selected atoms (its xyz is the frame being computed);
    index: each selected atom's index in the source's atoms; residues: (chain, number,
    insertion code, name) per residue, the order of residue_sasa and residue_area; grid: the
    grid dims used for every frame; frames: the number of frames (None for an iterable)."""

    def __init__(self, engine, source, radii, topology, keywords, sasa, ses, atom_areas, write,
                 callback, keep_mesh, start, stop, stride, grid, on_error, progress):
        if on_error not in ("stop", "skip"):
            raise ValueError(f"on_error must be 'stop' or 'skip', not {on_error!r}")
        if write is not None and not isinstance(write, (str, os.PathLike)):
            raise TypeError("write must be a path pattern such as 'out/frame-{frame:05d}.ply'")
        if write is not None:
            write = os.fspath(write)
            try:
                write.format(frame=0, time=0.0)
            except (KeyError, IndexError, ValueError) as e:
                raise ValueError(f"write pattern {write!r} takes {{frame}} and {{time}} only "
                                 f"({e})") from None
            extension = os.path.splitext(write.format(frame=0, time=0.0))[1].lower()
            if extension not in (".ply", ".obj", ".glb", ".stl", ".off"):
                raise _fdmsurf.InvalidArgumentError(
                    f"write pattern {write!r}: the extension must be .ply, .obj, .glb, .stl or "
                    f".off, not {extension or 'none'!r}")
            if write.format(frame=0, time=0.0) == write.format(frame=1, time=1.0):
                raise ValueError(f"write pattern {write!r} names every frame's file the same: "
                                 "put {frame} in it, e.g. 'out/frame-{frame:05d}.ply'")
        if callback is not None and not callable(callback):
            raise TypeError("callback must be callable: callback(frame, result)")
        if (write or callback or keep_mesh) and not ses:
            raise ValueError("write, callback and keep_mesh need the surface (ses=True)")
        if not (sasa or ses):
            raise ValueError("nothing to compute: sasa and ses are both False")
        self._engine = engine
        self._sasa, self._ses, self._atom_areas = bool(sasa), bool(ses), bool(atom_areas)
        self._write, self._callback, self._keep_mesh = write, callback, bool(keep_mesh)
        self._on_error = on_error
        self._progress = progress
        read = {k: v for k, v in keywords.items() if k in _options.READ_NAMES}
        self._surface_keywords = {k: v for k, v in keywords.items()
                                  if k not in _options.READ_NAMES}
        if self._surface_keywords.get("min_grid") is not None:
            raise _fdmsurf.InvalidArgumentError("trajectory sets min_grid itself: use grid=")
        self._options = _options.parse(self._surface_keywords)
        self._setup(source, radii, topology, read, start, stop, stride)
        self._grid_mode = grid
        self.grid = None

    # -- the atoms, selected once ---------------------------------------------------------------

    def _setup(self, source, radii, topology, read, start, stop, stride):
        library = _objects.library_of(source)
        kind = type(source).__name__
        if library == "MDAnalysis" and kind in ("Universe", "AtomGroup", "UpdatingAtomGroup"):
            if topology is not None or radii is not None:
                raise TypeError("an MDAnalysis source is its own topology: no radii= or topology=")
            selected = self._select(source, read)
            self._source = _mdanalysis_source(source, start, stop, stride)
        elif library == "mdtraj" and kind == "Trajectory":
            if topology is not None or radii is not None:
                raise TypeError("an mdtraj Trajectory is its own topology: no radii= or topology=")
            selected = self._select(source[0] if source.n_frames else source, read)
            self._source = _mdtraj_source(source, start, stop, stride)
        elif library is not None or isinstance(source, (str, bytes, os.PathLike,
                                                        _fdmsurf.Structure)):
            raise TypeError(f"Engine.trajectory takes {SOURCES}; not a "
                            f"{type(source).__module__}.{kind}")
        else:
            if (radii is None) == (topology is None):
                raise TypeError("coordinates need radii=(atoms,) or topology= (a Structure, a "
                                "path or a gemmi/Biopython/MDAnalysis/mdtraj object), one of them")
            if radii is not None:
                if any(v is not None and v != _options.KEYWORDS[k].default
                       for k, v in read.items()):
                    raise _fdmsurf.InvalidArgumentError(
                        "the read keywords select atoms of a topology; with radii= every atom "
                        "is taken (slice the coordinates instead)")
                radii = np.asarray(radii)
                if radii.ndim != 1:
                    raise _fdmsurf.InvalidArgumentError(
                        f"radii must have shape (atoms,), not {radii.shape}")
                structure = _fdmsurf.Structure(np.zeros((len(radii), 3), np.float32), radii)
                selected = _objects.Selected(structure, np.arange(len(radii)))
                n_atoms = len(radii)
            else:
                selected, n_atoms = self._topology(topology, read)
            self._source = _array_source(source, n_atoms, start, stop, stride)
        self.atoms = selected.structure
        self.index = selected.index
        self._residue_of, self.residues = _residue_index(self.atoms)
        self.frames = self._source.count()

    def _select(self, obj, read):
        given = {k: v for k, v in read.items() if k not in ("format", "assembly", "model")}
        for k in ("format", "assembly"):
            if read.get(k) not in (None, _options.KEYWORDS[k].default):
                raise _fdmsurf.InvalidArgumentError(f"{k} applies to files, not to a "
                                                    f"{type(obj).__name__}")
        return _objects.structure_of_object(obj, _options.parse(given),
                                            model=read.get("model") or 1)

    def _topology(self, topology, read):
        """The selected atoms of a topology= and its atom count (the frames' atom count). A path
        is read with the read keywords and the frames hold the atoms read; a Structure is taken
        whole; an object of another library is selected by the reader and the frames hold all
        of its atoms."""
        if isinstance(topology, (str, bytes, os.PathLike)):
            from . import read_structure
            topology = read_structure(topology, **read)
        elif isinstance(topology, _fdmsurf.Structure):
            given = sorted(k for k, v in read.items()
                           if v is not None and v != _options.KEYWORDS[k].default)
            if given:
                raise _fdmsurf.InvalidArgumentError(
                    f"{', '.join(given)} select atoms while reading; a Structure topology is "
                    "taken whole (select it first and give the frames of the atoms kept)")
        if isinstance(topology, _fdmsurf.Structure):
            whole = topology.subset(np.ones(len(topology), bool))
            return _objects.Selected(whole, np.arange(len(topology))), len(topology)
        if _objects.library_of(topology) is None:
            raise TypeError(f"topology must be a path, a Structure or {_objects.SUPPORTED}; not "
                            f"a {type(topology).__name__}")
        selected = self._select(topology, read)
        counted = _objects.topology_of(topology, read.get("model") or 1)
        return selected, len(counted)

    # -- the grid, one size for the run ---------------------------------------------------------

    def _plan(self, xyz):
        self.atoms.xyz[:] = xyz
        return tuple(_fdmsurf._plan_grid(self.atoms, self._options)["dims"])

    def _fix_grid(self):
        mode = self._grid_mode
        if not self._ses:
            return None
        if isinstance(mode, (tuple, list)):
            if len(mode) != 3 or not all(isinstance(d, int) and d > 0 for d in mode):
                raise ValueError(f"grid must be 'all', 'grow' or (nx, ny, nz), not {mode!r}")
            return tuple(mode)
        if mode == "grow" or (mode == "all" and self.frames is None):
            return None  # set from each frame, the largest so far
        if mode != "all":
            raise ValueError(f"grid must be 'all', 'grow' or (nx, ny, nz), not {mode!r}")
        dims = None
        for i, _t, xyz in self._source.frames():
            if isinstance(xyz, _BadFrame):
                continue
            xyz = np.asarray(xyz)[self.index]
            if not np.isfinite(xyz).all():
                continue
            d = self._plan(xyz)
            dims = d if dims is None else tuple(max(a, b) for a, b in zip(dims, d))
        return dims

    # -- the frames -----------------------------------------------------------------------------

    def __iter__(self):
        fixed = self._fix_grid()
        self.grid = fixed
        grow = fixed is None and self._ses
        total = self.frames
        show = self._progress if self._progress is not None else sys.stderr.isatty()
        started = time.perf_counter()
        done = 0
        for i, t, xyz in self._source.frames():
            row = Frame(i, t)
            tick = time.perf_counter()
            if isinstance(xyz, _BadFrame):
                self._fail(row, xyz.message)
            else:
                coordinates = np.asarray(xyz)[self.index]
                bad = ~np.isfinite(coordinates).all(axis=1)
                if bad.any():
                    atom = int(self.index[np.flatnonzero(bad)[0]])
                    self._fail(row, f"frame {i}: NaN or infinite coordinates ({int(bad.sum())} "
                                    f"atom(s), the first atom {atom} of the source)")
                else:
                    self.atoms.xyz[:] = coordinates
                    if grow:
                        d = self._plan(coordinates)
                        self.grid = d if self.grid is None else tuple(
                            max(a, b) for a, b in zip(self.grid, d))
                    self._compute(row)
            row.ms = (time.perf_counter() - tick) * 1000.0
            done += 1
            if show:
                _progress_line(done, total, time.perf_counter() - started)
            yield row
        if show:
            sys.stderr.write("\n")

    def _fail(self, row, message):
        if self._on_error == "stop":
            raise _fdmsurf.InvalidArgumentError(message)
        row.ok = False
        row.error = message

    def _compute(self, row):
        if self._sasa:
            areas = _fdmsurf.exact_areas(self.atoms, self._probe_value())
            row.sasa = float(areas.sum())
            if self._atom_areas:
                row.atom_sasa = areas
                if self._residue_of is not None:
                    row.residue_sasa = np.bincount(self._residue_of, weights=areas,
                                                   minlength=len(self.residues))
        if not self._ses:
            return
        self._options.min_grid = self.grid if self.grid is not None else (0, 0, 0)
        result = self._engine._engine.surface(self.atoms, self._options)
        row.area = result.area
        row.volume = result.volume
        pieces = result.piece_stats()
        row.pieces = len(pieces)
        cavities = [p["volume"] for p in pieces if p["volume"] < 0]
        row.cavities = len(cavities)
        row.cavity_volume = -float(sum(cavities))
        if self._atom_areas:
            row.atom_area = result.atom_areas()
            if self._residue_of is not None:
                row.residue_area = np.bincount(self._residue_of, weights=row.atom_area,
                                               minlength=len(self.residues))
        if self._write:
            path = self._write.format(frame=row.frame, time=row.time or 0.0)
            folder = os.path.dirname(path)
            if folder:
                os.makedirs(folder, exist_ok=True)
            result.write(path)
            row.path = path
        if self._callback is not None:
            self._callback(row, result)
        if self._keep_mesh:
            row.mesh = result

    def _probe_value(self):
        probe = self._surface_keywords.get("probe")
        return 1.4 if probe is None else float(probe)

    def table(self):
        """Every frame's row (Frame.row()), as a list in frame order (runs the frames)."""
        return [frame.row() for frame in self]


def _progress_line(done, total, seconds):
    rate = done / seconds if seconds > 0 else 0.0
    if total:
        eta = (total - done) / rate if rate > 0 else 0.0
        width = 30
        filled = int(width * done / total)
        text = (f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} frames, "
                f"{rate:.2f}/s, ETA {eta:.0f} s ")
    else:
        text = f"\r{done} frames, {rate:.2f}/s "
    sys.stderr.write(text)
    sys.stderr.flush()
