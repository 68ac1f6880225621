"""fdmsurf's PEP 517 build backend: `pip install .`, `pip wheel .` and `pip install -e .` through
CMake, with the standard library alone.

pip builds in an isolated environment into which it installs the backend's requirements from an
index; pyproject.toml declares none (`requires = []`) and names this file (`backend-path`), so a
machine without PyPI builds as well as one with it. Debian 12 packages no CMake-based backend
(no scikit-build-core), and the project is a CMake build already: this backend configures it for
the interpreter that runs pip (sys.executable), builds the program and the module, installs the
cli and python components into a staging folder, and packs that as the wheel (docs/install.md):

    fdmsurf/                        the package: _fdmsurf.*.so, .py files, __init__.pyi, py.typed
    fdmsurf-V.data/scripts/fdmsurf  the program, into the environment's bin/
    fdmsurf-V.data/scripts/msms     a shell script: fdmsurf msms "$@"
    fdmsurf-V.dist-info/            METADATA (pyproject.toml's; CMake's version), WHEEL, RECORD

The build folder is build-pip/TAG (TAG: cp311-cp311-linux_x86_64) in the source tree, kept, so
that the next `pip install .` rebuilds only what changed; `--config-settings build-dir=DIR`
moves it, `build-type=Debug` and `cmake-args="-DX=Y ..."` are passed on. Before CMake runs, the
Debian packages the build needs are looked for; a missing one stops the build with one line that
names every missing package.
"""

import base64
import csv
import hashlib
import io
import os
import re
import shlex
import shutil
import stat
import subprocess
import sys
import sysconfig
import tarfile
import tempfile
import time
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
NAME = "fdmsurf"

# What the build needs, by Debian package: a program on PATH, a header in an include folder, a
# library in a library folder. scripts/setup-debian.sh installs these and the test tools.
PROGRAMS = [("cmake", ["cmake"]), ("g++", ["c++", "g++"]), ("pkg-config", ["pkg-config"]),
            ("glslang-tools", ["glslangValidator"]), ("ninja-build", ["ninja", "make"])]
HEADERS = [("libvulkan-dev", "vulkan/vulkan.h"), ("glslang-dev", "glslang/Public/ShaderLang.h"),
           ("libvkfft-dev", "vkFFT.h"), ("gemmi-dev", "gemmi/mmread.hpp"),
           ("tao-pegtl-dev", "tao/pegtl.hpp"), ("zlib1g-dev", "zlib.h"),
           ("libtinygltf-dev", "tiny_gltf.h"), ("libmeshoptimizer-dev", "meshoptimizer.h"),
           ("libpng-dev", "png.h"), ("libglm-dev", "glm/glm.hpp"),
           ("pybind11-dev", "pybind11/pybind11.h")]
LIBRARIES = [("spirv-tools", "SPIRV-Tools-opt"), ("libvulkan-dev", "vulkan")]


class BuildError(Exception):
    """A build that cannot go on, with the one line that says why."""


def _fail(message):
    # One line on stderr and exit status 1: pip shows the line as the hook's whole output.
    print(f"fdmsurf: {message}", file=sys.stderr, flush=True)
    raise SystemExit(1)


# ---- what the build needs ----------------------------------------------------------------

def _env_dirs(*names):
    return [Path(d) for name in names for d in os.environ.get(name, "").split(os.pathsep) if d]


def search_dirs():
    """The include and library folders searched for the build's dependencies."""
    arch = sysconfig.get_config_var("MULTIARCH") or ""
    prefixes = _env_dirs("CMAKE_PREFIX_PATH") + [Path("/usr/local"), Path("/usr")]
    include = _env_dirs("CPATH", "CPLUS_INCLUDE_PATH") + [p / "include" for p in prefixes]
    include += [Path("/usr/include") / arch] if arch else []
    lib = _env_dirs("LIBRARY_PATH") + [p / "lib" for p in prefixes]
    lib += [Path("/usr/lib") / arch, Path("/usr/local/lib") / arch] if arch else []
    lib += [Path("/usr/lib64")]
    return include, lib


def missing_packages(include_dirs=None, library_dirs=None, path=None, python_include=None):
    """The Debian packages whose files the build needs and does not find, in order."""
    if include_dirs is None or library_dirs is None:
        include, lib = search_dirs()
        include_dirs = include if include_dirs is None else include_dirs
        library_dirs = lib if library_dirs is None else library_dirs
    missing = []
    for package, programs in PROGRAMS:
        if not any(shutil.which(p, path=path) for p in programs):
            missing.append(package)
    for package, header in HEADERS:
        if not any((Path(d) / header).is_file() for d in include_dirs):
            missing.append(package)
    for package, library in LIBRARIES:
        if not any((Path(d) / f"lib{library}{ext}").exists()
                   for d in library_dirs for ext in (".so", ".a")):
            missing.append(package)
    if python_include is None:
        python_include = sysconfig.get_paths()["include"]
    if not (Path(python_include) / "Python.h").is_file():
        version = f"{sys.version_info.major}.{sys.version_info.minor}"
        missing.append("python3-dev" if python_include.startswith("/usr/include/")
                       else f"the headers of Python {version} ({python_include}/Python.h)")
    return list(dict.fromkeys(missing))


def _check_prerequisites():
    missing = missing_packages()
    if missing:
        debian = [p for p in missing if " " not in p]
        hint = f" (as root: apt-get install {' '.join(debian)})" if debian else ""
        _fail(f"cannot build: missing Debian packages: {', '.join(missing)}{hint}")


# ---- metadata ----------------------------------------------------------------------------

def version():
    """The version the CMake project declares: project(fdmsurf VERSION X.Y.Z)."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    found = re.search(r"^project\(\s*fdmsurf\s+VERSION\s+([0-9][0-9.]*)", text, re.M)
    if not found:
        raise BuildError("CMakeLists.txt declares no project(fdmsurf VERSION ...)")
    return found.group(1)


def _project():
    try:
        import tomllib
    except ImportError:
        _fail(f"building fdmsurf needs Python >= 3.11 (tomllib); this is {sys.version.split()[0]}")
    with open(ROOT / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["project"]


def metadata():
    """The METADATA file's text (core metadata 2.1)."""
    project = _project()
    lines = [("Metadata-Version", "2.1"), ("Name", project["name"]), ("Version", version()),
             ("Summary", project["description"])]
    if "license" in project:
        lines.append(("License", project["license"]["text"]))
    lines += [("Classifier", c) for c in project.get("classifiers", [])]
    lines.append(("Requires-Python", project["requires-python"]))
    lines += [("Requires-Dist", d) for d in project.get("dependencies", [])]
    for extra, requirements in project.get("optional-dependencies", {}).items():
        lines.append(("Provides-Extra", extra))
        lines += [("Requires-Dist", f'{r}; extra == "{extra}"') for r in requirements]
    readme = project.get("readme")
    body = ""
    if readme:
        lines.append(("Description-Content-Type", "text/markdown"))
        body = "\n" + (ROOT / readme).read_text(encoding="utf-8")
    return "".join(f"{k}: {v}\n" for k, v in lines) + body


def wheel_tag():
    """The interpreter, ABI and platform tags of the wheel: cp311-cp311-linux_x86_64."""
    if sys.implementation.name != "cpython":
        _fail(f"the module is built for CPython only, not {sys.implementation.name}")
    interpreter = f"cp{sys.version_info.major}{sys.version_info.minor}"
    abi = interpreter + ("d" if hasattr(sys, "gettotalrefcount") else "")
    abi += "t" if sysconfig.get_config_var("Py_GIL_DISABLED") else ""
    platform = re.sub(r"[^A-Za-z0-9_]", "_", sysconfig.get_platform())
    return f"{interpreter}-{abi}-{platform}"


def _dist_info_name():
    return f"{NAME}-{version()}.dist-info"


def _wheel_file(tag):
    return (f"Wheel-Version: 1.0\nGenerator: fdmsurf_build (python/build_backend)\n"
            f"Root-Is-Purelib: false\nTag: {tag}\n")


# ---- the CMake build ---------------------------------------------------------------------

def _settings(config_settings):
    settings = dict(config_settings or {})
    unknown = set(settings) - {"build-dir", "build-type", "cmake-args"}
    if unknown:
        _fail(f"unknown --config-settings {', '.join(sorted(unknown))} "
              "(known: build-dir, build-type, cmake-args)")
    build_dir = settings.get("build-dir") or ROOT / "build-pip" / wheel_tag()
    return Path(build_dir).resolve(), settings.get("build-type", "Release"), \
        shlex.split(settings.get("cmake-args", ""))


def _run(command, what):
    print(f"fdmsurf: {what}: {shlex.join(str(c) for c in command)}", flush=True)
    status = subprocess.call([str(c) for c in command], stdout=sys.stdout, stderr=sys.stderr)
    if status != 0:
        _fail(f"{what} failed (exit status {status}; its output is above)")


def cmake_build(config_settings):
    """Configures and builds the program and the module for this interpreter; the build folder."""
    _check_prerequisites()
    build_dir, build_type, cmake_args = _settings(config_settings)
    generator = "Ninja" if shutil.which("ninja") else "Unix Makefiles"
    cache = build_dir / "CMakeCache.txt"
    if cache.is_file():
        made_by = re.search(r"^CMAKE_GENERATOR:INTERNAL=(.*)$", cache.read_text(), re.M)
        if made_by and made_by.group(1) != generator:
            _fail(f"{build_dir} was configured with {made_by.group(1)}, not {generator}: "
                  "remove it, or give another --config-settings build-dir=")
    _run(["cmake", "-S", ROOT, "-B", build_dir, "-G", generator,
          f"-DCMAKE_BUILD_TYPE={build_type}", f"-DPython3_EXECUTABLE={sys.executable}",
          "-DFDMSURF_PYTHON=ON", "-DFDMSURF_BUILD_CLI=ON", "-DFDMSURF_BUILD_TESTS=OFF",
          "-DFDMSURF_BUILD_BENCH=OFF", "-DFDMSURF_PYTHON_INSTALL_DIR=site-packages",
          *cmake_args], "configuring")
    _run(["cmake", "--build", build_dir], "building")
    return build_dir


# ---- wheels ------------------------------------------------------------------------------

class _Wheel:
    """A wheel being written: deterministic entries (the time of SOURCE_DATE_EPOCH, else 1980),
    each file's mode, and the RECORD of what was written."""

    def __init__(self, path):
        self.zip = zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED)
        epoch = int(os.environ.get("SOURCE_DATE_EPOCH", 315532800))
        self.when = time.gmtime(max(epoch, 315532800))[:6]
        self.records = []

    def add(self, name, data, executable=False):
        info = zipfile.ZipInfo(name, date_time=self.when)
        info.external_attr = (stat.S_IFREG | (0o755 if executable else 0o644)) << 16
        info.compress_type = zipfile.ZIP_DEFLATED
        self.zip.writestr(info, data)
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        self.records.append((name, f"sha256={digest}", str(len(data))))

    def add_file(self, name, path):
        path = Path(path)
        self.add(name, path.read_bytes(), executable=bool(path.stat().st_mode & 0o111))

    def close(self, dist_info):
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerows(self.records)
        writer.writerow((f"{dist_info}/RECORD", "", ""))
        info = zipfile.ZipInfo(f"{dist_info}/RECORD", date_time=self.when)
        info.external_attr = (stat.S_IFREG | 0o644) << 16
        info.compress_type = zipfile.ZIP_DEFLATED
        self.zip.writestr(info, out.getvalue())
        self.zip.close()


def _msms_script(fdmsurf):
    # A wheel holds no symlinks: msms is a script that runs the program's msms command.
    return (f"#!/bin/sh\n# msms: fdmsurf with MSMS's command line (docs/formats.md).\n"
            f"exec {fdmsurf} msms \"$@\"\n").encode()


def _write_wheel(wheel_directory, add_contents):
    tag = wheel_tag()
    dist_info = _dist_info_name()
    filename = f"{NAME}-{version()}-{tag}.whl"
    wheel = _Wheel(Path(wheel_directory) / filename)
    try:
        add_contents(wheel, f"{NAME}-{version()}.data")
        wheel.add(f"{dist_info}/METADATA", metadata().encode())
        wheel.add(f"{dist_info}/WHEEL", _wheel_file(tag).encode())
        wheel.add(f"{dist_info}/top_level.txt", f"{NAME}\n".encode())
        wheel.close(dist_info)
    except BaseException:
        wheel.zip.close()
        (Path(wheel_directory) / filename).unlink(missing_ok=True)
        raise
    return filename


def _staged(build_dir, staging):
    """The cli and python components installed (stripped) into staging."""
    for component in ("cli", "python"):
        _run(["cmake", "--install", build_dir, "--prefix", staging, "--component", component,
              "--strip"], f"installing the {component} component")


# ---- the PEP 517 and PEP 660 hooks -------------------------------------------------------

def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_editable(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def _prepare_metadata(metadata_directory):
    dist_info = Path(metadata_directory) / _dist_info_name()
    dist_info.mkdir(parents=True, exist_ok=True)
    (dist_info / "METADATA").write_text(metadata(), encoding="utf-8")
    (dist_info / "WHEEL").write_text(_wheel_file(wheel_tag()), encoding="utf-8")
    return dist_info.name


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    return _prepare_metadata(metadata_directory)


def prepare_metadata_for_build_editable(metadata_directory, config_settings=None):
    return _prepare_metadata(metadata_directory)


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    build_dir = cmake_build(config_settings)
    with tempfile.TemporaryDirectory(prefix="fdmsurf-wheel-") as staging:
        _staged(build_dir, staging)
        staging = Path(staging)

        def contents(wheel, data):
            package = staging / "site-packages"
            for path in sorted(package.rglob("*")):
                if path.is_file() and "__pycache__" not in path.parts:
                    wheel.add_file(path.relative_to(package).as_posix(), path)
            wheel.add_file(f"{data}/scripts/fdmsurf", staging / "bin" / "fdmsurf")
            wheel.add(f"{data}/scripts/msms", _msms_script('"$(dirname -- "$0")/fdmsurf"'),
                      executable=True)
            # Not the man page and completion (share/): pip uninstall would leave the folders
            # share/man and share/bash-completion behind, empty.

        return _write_wheel(wheel_directory, contents)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    """An editable install: a .pth file that puts the build folder's python/ (the package as the
    build assembles it: the module and copies of the .py files) on sys.path, and fdmsurf and
    msms scripts that run the build folder's program. After an edit, `cmake --build BUILD_DIR`
    (the folder the install printed) is the whole rebuild: no reinstall."""
    build_dir = cmake_build(config_settings)
    program = shlex.quote(str(build_dir / "fdmsurf"))

    def contents(wheel, data):
        wheel.add(f"__editable__.{NAME}.pth", f"{build_dir / 'python'}\n".encode())
        wheel.add(f"{data}/scripts/fdmsurf",
                  f"#!/bin/sh\n# fdmsurf, editable install: the program of the build folder.\n"
                  f"exec {program} \"$@\"\n".encode(), executable=True)
        wheel.add(f"{data}/scripts/msms", _msms_script(program), executable=True)

    print(f"fdmsurf: editable install of {build_dir}: after an edit, "
          f"cmake --build {shlex.quote(str(build_dir))} rebuilds it", flush=True)
    return _write_wheel(wheel_directory, contents)


def build_sdist(sdist_directory, config_settings=None):
    """The tracked files of the git checkout, with fdmsurf-source-info.txt (the commit, for
    `fdmsurf --version`; cmake/FdmsurfBuildInfo.cmake) and PKG-INFO."""
    git = ["git", "-c", "safe.directory=*", "-C", str(ROOT)]
    try:
        files = subprocess.run(git + ["ls-files", "-z"], check=True, capture_output=True)
        commit = subprocess.run(git + ["rev-parse", "HEAD"], check=True, capture_output=True)
        changes = subprocess.run(git + ["status", "--porcelain", "--untracked-files=no"],
                                 check=True, capture_output=True)
        tags = subprocess.run(git + ["tag", "--points-at", "HEAD"], check=True,
                              capture_output=True)
    except (OSError, subprocess.CalledProcessError):
        _fail("a source archive is made from a git checkout (git ls-files), and this is not one")
    changed = bool(changes.stdout.strip())
    release = f"v{version()}" in tags.stdout.decode().split() and not changed
    info = (f"commit={commit.stdout.decode().strip()}\nchanged={'yes' if changed else 'no'}\n"
            f"release={'yes' if release else 'no'}\n")
    base = f"{NAME}-{version()}"
    filename = f"{base}.tar.gz"
    epoch = int(os.environ.get("SOURCE_DATE_EPOCH", 315532800))

    def add_bytes(tar, name, data):
        member = tarfile.TarInfo(f"{base}/{name}")
        member.size, member.mtime, member.mode = len(data), epoch, 0o644
        tar.addfile(member, io.BytesIO(data))

    with tarfile.open(Path(sdist_directory) / filename, "w:gz", format=tarfile.PAX_FORMAT) as tar:
        for name in sorted(f for f in files.stdout.decode().split("\0") if f):
            if (ROOT / name).exists():  # a file deleted but not yet committed is left out
                tar.add(ROOT / name, arcname=f"{base}/{name}", recursive=False)
        add_bytes(tar, "fdmsurf-source-info.txt", info.encode())
        add_bytes(tar, "PKG-INFO", metadata().encode())
    return filename
