"""The keywords of Engine.surface and read_structure: one table of names, defaults and CLI
options, and the conversion of the keywords a call gives into the CLI's options, which the
compiled module parses with the CLI's own parser (python/src/options.cpp): same names, same
defaults, same checks and messages as ``fdmsurf --help``."""

import difflib
import functools
import inspect
import numbers
import re
import textwrap
from typing import Any, NamedTuple, Optional

from . import _fdmsurf


class Keyword(NamedTuple):
    name: str           # the Python keyword: the CLI option's name with '_' for '-'
    default: Any        # None: the CLI's default when the option is not given
    kind: str           # how a value becomes an option (see _option_args)
    cli: Optional[str]  # the CLI option; None for the library-only settings
    doc: str


# In the order of `fdmsurf --help`.
SURFACE = (
    Keyword("surface", "ses", "choice", "--surface",
            "'ses' (solvent excluded), 'vdw' (van der Waals) or 'sas' (solvent accessible)"),
    Keyword("method", "fdm", "choice", "--method",
            "how the ses surface is computed: 'fdm', the filtered density map (smooth, about "
            "0.15-0.2 Å from the exact SES), or 'edt', the exact SES (no filter; cutoff, sigma, "
            "level, filter and paper are refused with it)"),
    Keyword("spacing", 0.5, "float", "--spacing", "grid spacing, Å (> 0)"),
    Keyword("probe", 1.4, "float", "--probe", "solvent probe radius, Å (>= 0)"),
    Keyword("cutoff", 0.0, "float", "--cutoff",
            "filter cut-off, 1/Å (>= 0; 0: 1.3/(4 probe) for the Gaussian filter, 1/(4 probe) "
            "for the ideal one); ses with fdm only"),
    Keyword("sigma", 3.0, "float", "--sigma", "Gaussian width of each atom's density, Å (> 0)"),
    Keyword("level", None, "float", "--level",
            "iso-level in units of T, the density on each van der Waals sphere (> 0; None: 0.9 "
            "for ses with the Gaussian filter, 1 otherwise)"),
    Keyword("filter", "gaussian", "choice", "--filter",
            "filter shape: 'gaussian' 2^-(|f|/cutoff)^2 or the paper's 'ideal' spherical mask"),
    Keyword("paper", False, "flag", "--paper",
            "the paper's settings: ideal filter at 1/(4 probe), level 1, every cavity kept "
            "(filter, level and cavity keywords given explicitly still apply)"),
    Keyword("no_cavities", False, "flag", "--no-cavities",
            "keep only outer surfaces: remove every cavity"),
    Keyword("min_cavity_volume", None, "float", "--min-cavity-volume",
            "remove cavities enclosing less than this many Å³ (>= 0; None: for fdm remove the "
            "cavities no probe sphere fits in, for edt, vdw and sas keep all)"),
    Keyword("padding", None, "float", "--padding",
            "empty space around the atoms, Å (>= 0; None: one filter wavelength for ses, 1 Å "
            "for vdw and sas)"),
    Keyword("refine", 0, "int", "--refine",
            "refinement levels, 0 to 4: each splits every triangle into four (modified "
            "butterfly) and moves the new vertices onto the surface"),
    Keyword("snap", True, "negflag", "--no-snap",
            "place the mesh on the exact surface after marching cubes: for vdw and sas every "
            "vertex on its ball, with vertices on the creases where spheres meet and chords "
            "split to chord_tolerance; for edt every vertex projected onto the exact SES; fdm "
            "is not snapped (False: the CLI's --no-snap, marching cubes' vertices as they are)"),
    Keyword("canonical_grid", True, "negflag", "--natural-grid",
            "fdm with the Gaussian filter: round a small grid up to a cube of 64 to 160 points "
            "whose FFT plan `fdmsurf prepare` builds ahead, for a fast first run (False: the "
            "CLI's --natural-grid, the smallest FFT-friendly grid)"),
    Keyword("chord_tolerance", None, "float", "--chord-tolerance",
            "vdw and sas with snap: split edges whose arc lies more than this from them, Å (>= "
            "0; 0: creases only; None: spacing / 50)"),
    Keyword("color", None, "color", "--color",
            "vertex colours: 'chain', 'element', 'residue', 'hydrophobicity', 'bfactor', "
            "'coulombic', '#RRGGBB' or an (r, g, b) tuple of 0-255; None: uncoloured"),
    Keyword("properties", None, "list", "--properties",
            "per-vertex scalars, a list (or comma-separated str) of 'coulombic', "
            "'hydrophobicity', 'bfactor', 'mean_curvature', 'gaussian_curvature', "
            "'shape_index': SurfaceResult.properties"),
    Keyword("patch", None, "str", "--patch",
            "compute the surface of every atom, then keep only the triangles whose three "
            "vertices belong to atoms this gemmi selection matches: an open patch"),
    Keyword("simplify", None, "float", "--simplify",
            "keep about this fraction of the triangles, in (0, 1], by edge collapses in "
            "quadric-error order, after patch; the mesh keeps its topology (closed, the same "
            "pieces and holes) and every vertex keeps its atom, colour and properties; "
            "SurfaceResult.simplify reports the result (None: no simplification)"),
    Keyword("max_triangles", None, "int", "--max-triangles",
            "simplify to at most about this many triangles (>= 1); with simplify too, the "
            "smaller of the two targets (None: no cap)"),
    Keyword("simplifier", "collapse", "choice", "--simplifier",
            "'collapse' (fdmsurf's collapses, each tested so that it keeps the topology) or "
            "'meshopt' (meshoptimizer's, behind a guard that redoes the regions it breaks); with "
            "simplify or max_triangles only"),
    Keyword("optimize", False, "flag", "--optimize",
            "reorder triangles and vertices for the GPU's vertex cache and fetch (the same "
            "triangles), after simplification"),
    Keyword("density_cut", 0.01, "fraction", None,
            "(library only) an atom's Gaussian is taken as 0 below this fraction of T, in (0, 1)"),
    Keyword("min_grid", None, "grid", None,
            "(library only) grid points per axis at least, (nx, ny, nz): structures given one "
            "grid share one FFT plan"),
)

# Selection rules when the source is a path (PDB and mmCIF; PQR and XYZR are taken whole).
READ = (
    Keyword("format", None, "choice", "--format",
            "'pdb', 'cif', 'pqr', 'xyzr' or 'xyzrn'; None: from the extension, then the content"),
    Keyword("model", 1, "int", "--model", "the model to read, 1-based"),
    Keyword("assembly", 0, "int", "--assembly",
            "biological assembly N (the n-th the file lists), built before selection; 0: the "
            "model as deposited"),
    Keyword("chains", None, "list", "--chains",
            "keep only these chains (author ids, case-sensitive): a list or 'A,B'"),
    Keyword("select", None, "str", "--select",
            "keep only the atoms gemmi's selection matches ('A/10-50', '(HEM)', '[S]', ';b>20')"),
    Keyword("waters", False, "flag", "--waters", "keep water molecules"),
    Keyword("hydrogens", False, "flag", "--hydrogens", "keep hydrogen atoms"),
    Keyword("ligands", True, "negflag", "--no-ligands",
            "keep HETATM residues other than water (False: the CLI's --no-ligands)"),
)

# What the CLI's negated flags do (--no-ligands is ligands=False): fdmsurf.batch's help.
NEGATED_HELP = {
    "snap": "keep marching cubes' vertices where they are (snap=False)",
    "canonical_grid": "fdm: the smallest FFT-friendly grid, not a prepared cube (canonical_grid=False)",
    "ligands": "leave out HETATM residues other than water (ligands=False)",
}

KEYWORDS = {k.name: k for k in SURFACE + READ}
READ_NAMES = frozenset(k.name for k in READ)

# CLI option -> keyword, to word the parser's messages for Python callers.
_BY_OPTION = {k.cli: k for k in SURFACE + READ if k.cli}
_BY_OPTION["--colour"] = KEYWORDS["color"]


def _real(name, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, not {type(value).__name__}")
    return repr(float(value))


def _integer(name, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be a whole number, not {type(value).__name__}")
    return str(int(value))


def _text(name, value):
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a str, not {type(value).__name__}")
    return value


def _items(name, value):
    if isinstance(value, str):
        return value
    try:
        items = list(value)
    except TypeError:
        raise TypeError(f"{name} must be a list of str or a comma-separated str, "
                        f"not {type(value).__name__}") from None
    for item in items:
        _text(f"each item of {name}", item)
    return ",".join(items)


def _color(name, value):
    if isinstance(value, str):
        return value
    try:
        rgb = [int(c) for c in value]
        if len(rgb) == 3 and all(0 <= c <= 255 and c == v for c, v in zip(rgb, value)):
            return "#%02x%02x%02x" % tuple(rgb)
    except (TypeError, ValueError):
        pass
    raise TypeError(f"{name} must be a scheme name, '#RRGGBB' or an (r, g, b) tuple of whole "
                    f"numbers 0-255, not {value!r}")


def _flag(name, value):
    numpy_bool = getattr(getattr(value, "dtype", None), "kind", None) == "b" and \
        getattr(value, "ndim", None) == 0  # np.True_, np.bool_(x)
    if not numpy_bool and not (isinstance(value, numbers.Integral) and value in (0, 1)):
        raise TypeError(f"{name} must be True or False, not {value!r}")
    return bool(value)


def _fraction(name, value):
    _real(name, value)
    return float(value)


def _grid(name, value):
    grid = tuple(value)
    if len(grid) != 3:
        raise TypeError(f"{name} must be three whole numbers (nx, ny, nz)")
    grid = tuple(int(_integer(name, n)) for n in grid)
    if min(grid) < 0:
        raise _fdmsurf.InvalidArgumentError(f"{name} must be >= 0 on every axis")
    if max(grid) >= 2**32:
        raise _fdmsurf.InvalidArgumentError(f"{name} must be below 2**32 points on every axis "
                                            f"(got {max(grid)})")
    return grid


# Keyword.kind -> how a value becomes the text of `--option=TEXT` (None: no option).
_OPTION_TEXT = {
    "float": _real,
    "int": _integer,
    "choice": _text,
    "str": _text,
    "list": lambda name, value: _items(name, value) or None,  # []: every chain, no property
    "color": _color,
}
# Flags: the value that gives the bare option (--no-cavities; --no-snap for snap=False).
_FLAG_VALUE = {"flag": True, "negflag": False}
# Library-only settings: the value set on _Options.
_LIBRARY_VALUE = {"fraction": _fraction, "grid": _grid}


# Settings of the FDM method that the exact SES refuses (as the CLI refuses --sigma with
# --method edt); given at their defaults alongside method="edt", they are taken as not given, so
# that a dict of every keyword at its default works with either method.
_FDM_ONLY = ("cutoff", "sigma", "level", "filter")


def _option_args(given):
    """The CLI arguments of the keywords in `given` (name -> value), and the library-only
    settings. A keyword given as None is left at its default."""
    args, library = [], {}
    edt = isinstance(given.get("method"), str) and given["method"].lower() == "edt"
    for name, value in given.items():
        k = KEYWORDS[name]
        if value is None:
            continue
        if edt and name in _FDM_ONLY and isinstance(value, (str, numbers.Real)) and \
                not isinstance(value, bool) and value == k.default:
            continue
        if k.kind in _OPTION_TEXT:
            text = _OPTION_TEXT[k.kind](name, value)
            if text is not None:
                args.append(f"{k.cli}={text}")
        elif k.kind in _FLAG_VALUE:
            if _flag(name, value) == _FLAG_VALUE[k.kind]:
                args.append(k.cli)
        else:
            library[name] = _LIBRARY_VALUE[k.kind](name, value)
    return args, library


def _python_words(message):
    """The CLI parser's message with keyword names for option names."""
    def keyword(match):
        k = _BY_OPTION.get(match.group(2))
        if k is None:
            return match.group(0)
        return f"{k.name}=False" if k.kind == "negflag" else k.name
    return re.sub(r"(option )?(--[a-z][a-z-]*)", keyword, message)


def parse(given, extra_args=()):
    """The parsed options (_fdmsurf._Options) of the keywords in `given`."""
    args, library = _option_args(given)
    try:
        options = _fdmsurf._Options(args + list(extra_args))
        for name, value in library.items():
            setattr(options, name, value)
    except _fdmsurf.InvalidArgumentError as e:
        raise _fdmsurf.InvalidArgumentError(_python_words(str(e))) from None
    return options


def check_names(function_name, given, allowed):
    """TypeError for a keyword `function_name` does not take, with the nearest one."""
    for name in given:
        if name not in allowed:
            close = difflib.get_close_matches(name, allowed, n=1)
            hint = f" (did you mean {close[0]}?)" if close else ""
            raise TypeError(f"{function_name}() got an unknown keyword '{name}'{hint}")


def with_keywords(*groups, exclude=()):
    """Decorator for `f(*args, **keywords)`: gives f the signature and the docstring section of
    the keywords of `groups`, and refuses other keywords with the nearest name."""
    table = [k for group in groups for k in group if k.name not in exclude]
    names = [k.name for k in table]

    def decorate(function):
        signature = inspect.signature(function)
        positional = [p for p in signature.parameters.values()
                      if p.kind is not inspect.Parameter.VAR_KEYWORD]
        keywords = [inspect.Parameter(k.name, inspect.Parameter.KEYWORD_ONLY, default=k.default)
                    for k in table]
        lines = []
        for k in table:
            option = f" [{k.cli}]" if k.cli else ""
            lines.append(f"    {k.name}={k.default!r}{option}")
            lines.append(textwrap.fill(f"{k.doc}.", width=92, initial_indent=" " * 8,
                                       subsequent_indent=" " * 8))
        doc = inspect.cleandoc(function.__doc__ or "")
        doc = doc.replace("{keywords}", "\n".join(lines))

        allowed = names + [p.name for p in positional]

        @functools.wraps(function)
        def wrapper(*args, **given):
            check_names(function.__qualname__, given, allowed)
            return function(*args, **given)

        wrapper.__signature__ = signature.replace(parameters=positional + keywords)
        wrapper.__doc__ = doc
        return wrapper

    return decorate
