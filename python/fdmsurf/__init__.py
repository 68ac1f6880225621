"""fdmsurf: molecular surface meshes (solvent excluded, van der Waals, solvent accessible) from a
structure, computed with Vulkan compute, as numpy arrays.

    >>> import fdmsurf
    >>> result = fdmsurf.surface("tests/data/1crn.pdb")            # default engine, SES, 0.5 Å
    >>> result.vertices.shape, result.faces.dtype, round(result.area)
    ((13304, 3), dtype('uint32'), 2213)

Engine is the reusable device context (make one per process or thread and keep it);
read_structure gives the atoms as numpy arrays with their metadata; compare measures a mesh
against a reference; fdmsurf.batch runs whole archives on a Dask cluster. Every surface option
of the command-line program is a keyword of Engine.surface with the same name ('-' as '_') and
default. Errors are fdmsurf.Error subclasses carrying the CLI's messages. docs/python.md has
examples.
"""

import os
import threading

try:
    from . import _fdmsurf
except ImportError as error:
    # The compiled module links the Vulkan loader: say what to install, in one line.
    missing = str(error).split(":")[0] if "cannot open shared object" in str(error) else ""
    if missing.startswith("libvulkan"):
        raise ImportError(
            f"fdmsurf needs the Vulkan loader {missing}, which is not installed: apt-get install "
            "libvulkan1, and a Vulkan driver (mesa-vulkan-drivers, or your GPU's; "
            "docs/install.md)") from None
    if missing:
        raise ImportError(f"fdmsurf's compiled module needs {missing}, which is not installed "
                          "(docs/install.md lists what the module needs at run time)") from None
    raise
from . import _objects, _options
from ._fdmsurf import (
    DeviceError,
    DeviceLimitError,
    EmptySelectionError,
    Error,
    FftError,
    FileError,
    FormatError,
    InputError,
    InternalError,
    InvalidArgumentError,
    Mesh,
    NoDeviceError,
    Structure,
    SurfaceResult,
    VulkanError,
    compare,
    list_devices,
    read_mesh,
)
from ._options import READ, SURFACE, with_keywords
from .trajectory import Frame, Trajectory

__version__ = _fdmsurf.__version__

__all__ = [
    "Engine", "surface", "default_engine", "read_structure", "read_models", "parse_structure",
    "plan_grid", "compare", "read_mesh", "list_devices", "sas_areas", "exact_areas",
    "as_structure", "trajectory", "Frame", "Trajectory", "Structure", "Mesh",
    "SurfaceResult", "Error", "InvalidArgumentError", "InputError", "FileError", "FormatError",
    "EmptySelectionError", "DeviceError", "NoDeviceError", "DeviceLimitError", "VulkanError",
    "FftError", "InternalError", "__version__",
]

def _structure_of(source, radii, given):
    """The Structure and the parsed options of a call's source and keywords."""
    options = _options.parse(given)
    if isinstance(source, (str, bytes, os.PathLike)):
        if radii is not None:
            raise TypeError("radii goes with an xyz array, not with a path")
        return _fdmsurf._read_structure(source, options), options
    read = sorted(name for name, value in given.items()
                  if name in _options.READ_NAMES and value is not None
                  and value != _options.KEYWORDS[name].default)
    if _objects.library_of(source) is not None:
        if radii is not None:
            raise TypeError(f"radii goes with an xyz array, not with a {type(source).__name__}: "
                            "radii come from the elements")
        return _object_structure(source, given, read), options
    if read:
        raise InvalidArgumentError(
            f"{', '.join(read)} select atoms while reading a file; atoms given as a Structure "
            "or arrays are taken whole (use Structure.select or Structure.subset)")
    if isinstance(source, Structure):
        if radii is not None:
            raise TypeError("radii goes with an xyz array, not with a Structure")
        return source, options
    if radii is None:
        if isinstance(source, tuple) and len(source) == 2:
            source, radii = source
        else:
            raise TypeError(f"source must be {_objects.SUPPORTED}; got "
                            f"{type(source).__name__} and no radii")
    return Structure(source, radii), options


def _object_structure(source, given, read):
    """The Structure of a gemmi, Biopython, MDAnalysis or mdtraj object (fdmsurf/_objects.py),
    selected by the read keywords as fdmsurf's reader selects a file's atoms."""
    unusable = [name for name in read if name in ("format", "assembly")]
    if unusable:
        raise InvalidArgumentError(f"{', '.join(unusable)} apply to files; a "
                                   f"{type(source).__name__} object is read as it is")
    model = given.get("model") or 1
    selection = {name: value for name, value in given.items()
                 if name in _options.READ_NAMES and name not in ("format", "assembly", "model")}
    return _objects.structure_of_object(source, _options.parse(selection), model=model).structure


@with_keywords(READ)
def as_structure(source, **keywords):
    """The fdmsurf Structure of an object of another library (a gemmi Structure or Model, a
    Biopython Structure, Model or Chain, an MDAnalysis Universe or AtomGroup at its current
    frame, an mdtraj Trajectory: frame model - 1), with the selection keywords of
    read_structure (model, chains, select, waters, hydrogens, ligands) applied by fdmsurf's
    own PDB reader, so that a file read by that library gives the atoms, radii and metadata that
    read_structure gives for the file. Structure.serial is each atom's 1-based position in the
    object. A path or a Structure is returned as read_structure(path) or as it is.

    {keywords}
    """
    if isinstance(source, Structure):
        return source
    if isinstance(source, (str, bytes, os.PathLike)):
        return read_structure(source, **keywords)
    if _objects.library_of(source) is None:
        raise TypeError(f"fdmsurf takes {_objects.SUPPORTED}; not a {type(source).__name__}")
    read = sorted(name for name, value in keywords.items()
                  if value is not None and value != _options.KEYWORDS[name].default)
    return _object_structure(source, keywords, read)


def sas_areas(structure, probe=1.4, points=1000, **keywords):
    """The solvent-accessible area of every atom (Å², (N,) float64) by Shrake & Rupley's test
    points (`points` per atom; probe 0: the van der Waals area), on every thread. structure: a
    Structure, a path, or a gemmi / Biopython / MDAnalysis / mdtraj object (as_structure, with
    its read keywords)."""
    return _fdmsurf.sas_areas(as_structure(structure, **keywords), probe, points)


def exact_areas(structure, probe=1.4, **keywords):
    """The solvent-accessible area of every atom (Å², (N,) float64) exactly: each atom's patch
    of the union of the balls of radius r + probe, by the Gauss-Bonnet theorem on the arcs where
    the spheres meet (no sampling; probe 0: the van der Waals area), on every thread. structure
    as for sas_areas."""
    return _fdmsurf.exact_areas(as_structure(structure, **keywords), probe)


class Engine:
    """A Vulkan device with fdmsurf's pipelines and FFT plans, reused for many surfaces.

    device: None for the first usable device (discrete GPU first), an index from
    list_devices(), or part of a device's name ('llvmpipe'). validation=True enables the Vulkan
    validation layer; its messages are added to each result's warnings.

    Making an Engine takes from a fraction of a second (a GPU) to about a second (lavapipe,
    which compiles its pipelines on first use): keep one and reuse it. Threads: Engine.surface
    releases the GIL while it computes, so surfaces on two engines in two threads run at the
    same time; calls on one engine from several threads are safe and take turns (an internal
    lock). close() (or a `with` block) frees the device early. Raises NoDeviceError when no
    usable Vulkan device exists (install mesa-vulkan-drivers for lavapipe, the CPU device).

    host_filter, host_mc, host_atoms, host_ses, host_density: "auto" (default), "on" or "off",
    as the CLI's --host-filter, --host-mc, --host-atoms, --host-ses and --host-density: whether
    the Gaussian filter, marching cubes, each vertex's atom, the exact SES's field and the
    density run on the host's threads instead of the device's passes; "auto" does so on a CPU
    device (lavapipe).
    """

    _PLACES = {"auto": 0, "off": 1, "on": 2}

    def __init__(self, device=None, validation=False, host_filter="auto", host_mc="auto",
                 host_atoms="auto", host_ses="auto", host_density="auto"):
        if isinstance(device, bool) or not (device is None or isinstance(device, (int, str))):
            raise TypeError(f"device must be None, an index or a name, not {device!r}")
        places = []
        for name, value in (("host_filter", host_filter), ("host_mc", host_mc),
                            ("host_atoms", host_atoms), ("host_ses", host_ses),
                            ("host_density", host_density)):
            if not isinstance(value, str) or value.lower() not in self._PLACES:
                raise ValueError(f"{name} must be 'auto', 'on' or 'off', not {value!r}")
            places.append(self._PLACES[value.lower()])
        self._engine = _fdmsurf._Engine("" if device is None else str(device), bool(validation),
                                        places)

    @with_keywords(SURFACE, READ)
    def surface(self, source, radii=None, **keywords):
        """Computes the molecular surface of `source`; returns a SurfaceResult.

        source: a path (str or os.PathLike) of a PDB, mmCIF, PQR, XYZR or XYZRN file, gzipped
        or not, read with the selection keywords (format ... ligands); a Structure; or numpy
        arrays, xyz of shape (N, 3) with radii=(N,) or the tuple (xyz, radii), Å, any real
        dtype.

        The result's vertices (V, 3) float32, normals (V, 3) float32, faces (F, 3) uint32,
        atoms (V,) uint32 (indices into result.structure), colors (V, 3) uint8 and
        properties {name: (V,) float32} are numpy arrays over the mesh's own memory; area,
        volume, pieces, closed_manifold, grid, times and warnings describe it, and
        write(path) writes it as the CLI would.

        Keywords: the command-line options of `fdmsurf --help`, named without the dashes
        and with '_' for '-' (shown in brackets); a keyword given as None keeps its default.

        {keywords}

        Raises InvalidArgumentError (a ValueError) for an option out of range or bad arrays
        (wrong shape, NaN coordinates, radii <= 0), TypeError for an unknown keyword or a
        value of the wrong type, InputError (FileError, FormatError, EmptySelectionError) for
        a file that cannot be read or a selection that keeps no atom, DeviceError for device
        failures. The GIL is released while the surface is computed.
        """
        structure, options = _structure_of(source, radii, keywords)
        return self._engine.surface(structure, options)

    @with_keywords(SURFACE, READ, exclude=("model",))
    def surface_models(self, path, **keywords):
        """Every model of the file at `path`, one SurfaceResult each (in model order): the
        CLI's ``--models all``. The file is read once, and every model gets the largest of
        their grids so that one FFT plan serves them all. Keywords as for surface():

        {keywords}
        """
        options = _options.parse(keywords, ["--models=all"])
        structures = _fdmsurf._read_models(path, options)
        grid = list(options.min_grid)
        if len(structures) > 1:
            for structure in structures:
                try:
                    dims = _fdmsurf._plan_grid(structure, options)["dims"]
                except Error:
                    continue  # raised again by its own surface below
                grid = [max(a, b) for a, b in zip(grid, dims)]
        options.min_grid = tuple(grid)
        return [self._engine.surface(structure, options) for structure in structures]

    @with_keywords(SURFACE, READ)
    def trajectory(self, source, radii=None, *, topology=None, sasa=True, ses=True,
                   atom_areas=True, write=None, callback=None, keep_mesh=False, start=None,
                   stop=None, stride=1, grid="all", on_error="stop", progress=None, **keywords):
        """The surface and areas of every frame of `source`: a Trajectory to iterate, one
        fdmsurf.trajectory.Frame per frame in frame order (docs/trajectories.md).

        source: an MDAnalysis Universe or AtomGroup, an mdtraj Trajectory, or coordinates in Å
        (frames, atoms, 3) (a numpy array or memmap, or an iterable of (atoms, 3) arrays) with
        radii=(atoms,) or topology= (a path, a Structure, or a gemmi / Biopython / MDAnalysis /
        mdtraj object whose atoms the frames hold). The read keywords (chains, select, waters,
        hydrogens, ligands) select the atoms once, by fdmsurf's reader; the surface keywords
        shape each frame's surface.

        sasa: each frame's exact solvent-accessible area (sphere patches of radius r + probe)
        per atom, per residue and in total. ses: each frame's surface (kind, spacing... from the
        keywords): area, volume, pieces, cavities, and its area per atom and per residue
        (atom_areas=False leaves the per-atom arrays out). write: a path pattern with {frame}
        (and {time}), e.g. 'out/frame-{frame:05d}.ply': each frame's mesh written there;
        callback(frame, result): called with each frame's SurfaceResult; keep_mesh: the result
        kept in Frame.mesh. start, stop, stride: the frames taken, as a slice. grid: 'all' (the
        grid dims that hold every frame, found by a first pass over the frames' coordinates),
        'grow' (the largest so far: no first pass) or (nx, ny, nz) fixed: one FFT plan and one
        set of pipelines for the whole run. on_error: 'stop' (InvalidArgumentError naming the
        frame) or 'skip' (the frame's row has ok=False and the error) for frames with NaN
        coordinates or the wrong atom count. progress: a progress line on stderr (None: when
        stderr is a terminal).

        Keywords as Engine.surface:

        {keywords}
        """
        return Trajectory(self, source, radii, topology, keywords, sasa, ses, atom_areas, write,
                          callback, keep_mesh, start, stop, stride, grid, on_error, progress)

    @property
    def device(self):
        """The device in use, a dict as list_devices() gives."""
        return self._engine.device

    def take_validation_messages(self):
        """The validation layer's messages not yet taken (Engine(validation=True))."""
        return self._engine.take_validation_messages()

    def close(self):
        """Frees the device now; the engine cannot be used afterwards."""
        self._engine.close()

    @property
    def closed(self):
        return self._engine.closed

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        state = "closed" if self.closed else f"on {self.device['name']}"
        return f"<fdmsurf.Engine {state}>"


_default_engine = None
_default_lock = threading.Lock()


def default_engine():
    """The Engine that fdmsurf.surface uses, made on first use (on the default device)."""
    global _default_engine
    with _default_lock:
        if _default_engine is None or _default_engine.closed:
            _default_engine = Engine()
        return _default_engine


@with_keywords(SURFACE, READ)
def surface(source, radii=None, **keywords):
    """Engine.surface on default_engine(): the surface of `source` in one call.

    source: a path, a Structure, or xyz (N, 3) with radii=(N,). Keywords as
    Engine.surface (see help(fdmsurf.Engine.surface)):

    {keywords}
    """
    return default_engine().surface(source, radii, **keywords)


def trajectory(source, radii=None, **keywords):
    """Engine.trajectory on default_engine(); see help(fdmsurf.Engine.trajectory)."""
    return default_engine().trajectory(source, radii, **keywords)


@with_keywords(READ)
def read_structure(path, **keywords):
    """Reads a structure file (PDB, mmCIF, PQR, XYZR or XYZRN; .gz too) as the CLI does; returns
    a Structure: xyz (N, 3) and radii (N,) float32 arrays, and per-atom metadata (chain,
    residue_name, residue_number, name, element, b_factor, ...) in file order.

    {keywords}

    Raises FileError, FormatError or EmptySelectionError with a message that names the file
    and, where it can, the line.
    """
    return _fdmsurf._read_structure(path, _options.parse(keywords))


@with_keywords(READ, exclude=("model",))
def read_models(path, **keywords):
    """Every model of a structure file, one Structure each (model i+1 at index i), the file read
    and parsed once. PQR and XYZR files give one.

    {keywords}
    """
    return _fdmsurf._read_models(path, _options.parse(keywords, ["--models=all"]))


@with_keywords(READ)
def parse_structure(text, name="structure.pdb", **keywords):
    """A Structure from the text of a structure file (not gzipped). `name` stands for the file
    in messages and, without format=, gives the format by its extension.

    {keywords}
    """
    return _fdmsurf._parse_structure(text, name, _options.parse(keywords))


@with_keywords(SURFACE, READ)
def plan_grid(source, radii=None, **keywords):
    """The grid Engine.surface would use for `source` (no device work): a dict of dims,
    spacing, origin and cutoff (slabs and the stages' places are the engine's choice when it
    runs: result.grid). Useful to estimate the work and memory of a batch.
    Keywords as Engine.surface:

    {keywords}
    """
    structure, options = _structure_of(source, radii, keywords)
    return _fdmsurf._plan_grid(structure, options)


# The compiled classes appear as fdmsurf.X in help() and tracebacks.
for _cls in (Structure, Mesh, SurfaceResult):
    _cls.__module__ = __name__
del _cls
