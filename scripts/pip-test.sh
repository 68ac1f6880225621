#!/usr/bin/env bash
# The pip installs as a user makes them, with no package index (PIP_NO_INDEX): into virtual
# environments made with `python3 -m venv --system-site-packages` (Debian's numpy and distributed
# seen from them), through the in-tree build backend (pyproject.toml,
# python/build_backend/fdmsurf_build.py; docs/install.md):
#   1. pip install . : the package, its stubs, bin/fdmsurf and bin/msms work from the venv;
#      pip uninstall fdmsurf leaves the venv as it was;
#   2. pip wheel . : the wheel's name, tag, metadata and RECORD; installed into a second, fresh
#      venv (with the [batch] extra) it works; with the Vulkan loader hidden (a mount namespace
#      where libvulkan.so.1 is deleted from an overlay), import fdmsurf says in one line what to
#      install;
#   3. pip install -e . : the build folder's package and program; cmake --build is the rebuild;
#   4. pip install . without the build tools on PATH: one line naming the missing packages.
#
# Run after scripts/setup-debian.sh (scripts/test.sh), from anywhere: ./scripts/pip-test.sh.
# Builds in build-pip/TAG (kept: a second run rebuilds nothing); needs a Vulkan device
# (lavapipe will do). Environment: FDMSURF_PIP_PYTHON (default /usr/bin/python3).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
repo=$(pwd)
python=${FDMSURF_PIP_PYTHON:-/usr/bin/python3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_NO_CACHE_DIR=1 PIP_NO_INPUT=1
version=$(sed -n 's/^project(fdmsurf VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
tag=$("$python" -c 'import sys; sys.path.insert(0, "python/build_backend")
import fdmsurf_build; print(fdmsurf_build.wheel_tag())')

script=pip-test.sh
source scripts/lib/steps.sh  # fail, step

new_venv() {  # new_venv DIR: a venv that sees Debian's packages, and the list of its files
    "$python" -m venv --system-site-packages "$1"
    "$1/bin/python" -m pip --version >/dev/null  # pip's own first-run files, before the list
    listing "$1" >"$1.files"
}

listing() {  # every path in a venv but bytecode
    (cd "$1" && find . -not -path '*/__pycache__*' | sort)
}

uninstalled_cleanly() {  # VENV: pip uninstall fdmsurf leaves the files the venv had before
    step "uninstall-$(basename "$1")" "$1/bin/python" -m pip uninstall -y fdmsurf
    if ! diff <(cat "$1.files") <(listing "$1") >"$work/left.diff"; then
        cat "$work/left.diff" >&2
        fail "pip uninstall fdmsurf left these files in $1 (> lines) or took others (<)"
    fi
    [[ -z $(find "$1" -name '*fdmsurf*' -o -name msms) ]] ||
        fail "pip uninstall fdmsurf left $(find "$1" -name '*fdmsurf*' -o -name msms | head -3)"
}

check_venv() {  # VENV LABEL WHERE: the program, msms, the batch driver, the module from WHERE
    local venv=$1 label=$2
    [[ $("$venv/bin/fdmsurf" --version | head -1) == "fdmsurf $version" ]] ||
        fail "$label: $venv/bin/fdmsurf --version says '$("$venv/bin/fdmsurf" --version)'"
    "$venv/bin/fdmsurf" --version
    (cd "$work" && "$venv/bin/fdmsurf" "$repo/tests/data/1crn.pdb" -o "$work/$label.ply" --quiet) ||
        fail "$label: $venv/bin/fdmsurf tests/data/1crn.pdb failed"
    [[ $(head -c 3 "$work/$label.ply") == ply ]] || fail "$label: no PLY written"
    (cd "$work" && "$venv/bin/msms" -if "$repo/tests/data/1crn.xyzrn" -of "$work/$label-msms" \
        -probe_radius 1.5 >/dev/null) || fail "$label: $venv/bin/msms failed"
    [[ -s $work/$label-msms.vert && -s $work/$label-msms.face ]] ||
        fail "$label: msms wrote no files"
    (cd "$work" && "$venv/bin/python" -m fdmsurf.batch --help >/dev/null) ||
        fail "$label: python -m fdmsurf.batch --help failed"
    # From outside the clone, so that nothing but the installed package can be imported.
    (cd "$work" && "$venv/bin/python" - "$repo/tests/data/1crn.pdb" "$version" "$3" <<'EOF'
import os, sys
import fdmsurf
path, version, where = sys.argv[1:]
assert fdmsurf.__version__ == version, fdmsurf.__version__
assert os.path.dirname(fdmsurf.__file__).startswith(where), (fdmsurf.__file__, where)
for name in ("__init__.pyi", "py.typed"):
    assert os.path.isfile(os.path.join(os.path.dirname(fdmsurf.__file__), name)), name
r = fdmsurf.surface(path, spacing=1.0)
assert r.closed_manifold and len(r.faces) > 1000, r
print(f"  import fdmsurf: {fdmsurf.__file__}: {r}")
EOF
    ) || fail "$label: the module does not work from $venv"
}

# 1. pip install . into a venv.
new_venv "$work/venv"
step "pip-install" "$work/venv/bin/python" -m pip install .
site=$("$work/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_path("platlib"))')
check_venv "$work/venv" install "$site/fdmsurf"
record=$site/fdmsurf-$version.dist-info/RECORD
for file in ../../../bin/fdmsurf ../../../bin/msms; do
    grep -q "^$file," "$record" || fail "pip install .: $file is not in $record"
done
uninstalled_cleanly "$work/venv"

# 2. pip wheel ., installed into a second, fresh venv.
step "pip-wheel" "$work/venv/bin/python" -m pip wheel --no-deps -w "$work/wheels" .
wheel=$work/wheels/fdmsurf-$version-$tag.whl
[[ -f $wheel ]] || fail "pip wheel . made $(ls "$work/wheels"), not $(basename "$wheel")"
"$python" - "$wheel" "$version" <<'EOF' || fail "the wheel's contents are not right (above)"
import base64, csv, hashlib, io, sys, zipfile
path, version = sys.argv[1:]
wheel = zipfile.ZipFile(path)
names = set(wheel.namelist())
info = f"fdmsurf-{version}.dist-info"
data = f"fdmsurf-{version}.data"
metadata = wheel.read(f"{info}/METADATA").decode().split("\n\n")[0].splitlines()
for line in ["Name: fdmsurf", f"Version: {version}", "Requires-Python: >=3.11",
             "Requires-Dist: numpy", "Provides-Extra: batch",
             'Requires-Dist: distributed; extra == "batch"']:
    assert line in metadata, (line, metadata)
for field in ("Summary: ", "License: "):
    assert any(line.startswith(field) for line in metadata), field
assert "Root-Is-Purelib: false" in wheel.read(f"{info}/WHEEL").decode()
records = {row[0]: row for row in csv.reader(io.StringIO(wheel.read(f"{info}/RECORD").decode()))}
assert set(records) == names, names ^ set(records)
for name, digest, size in records.values():
    if name.endswith("RECORD"):
        continue
    body = wheel.read(name)
    hashed = base64.urlsafe_b64encode(hashlib.sha256(body).digest()).rstrip(b"=").decode()
    expected = f"sha256={hashed}"
    assert digest == expected and int(size) == len(body), name
needed = ["fdmsurf/__init__.py", "fdmsurf/__init__.pyi", "fdmsurf/py.typed", "fdmsurf/batch.py",
          "fdmsurf/trajectory.py", "fdmsurf/_objects.py",
          f"{data}/scripts/fdmsurf", f"{data}/scripts/msms"]
assert all(n in names for n in needed), [n for n in needed if n not in names]
assert any(n.startswith("fdmsurf/_fdmsurf.cpython-") and n.endswith(".so") for n in names)
for script in ("fdmsurf", "msms"):
    assert wheel.getinfo(f"{data}/scripts/{script}").external_attr >> 16 & 0o111, script
sizes = {n: wheel.getinfo(n).compress_size for n in names}
print(f"  {path.rsplit('/', 1)[1]}: {len(names)} files, "
      f"{sum(sizes.values()) / 2**20:.1f} MiB compressed "
      f"(program {sizes[f'{data}/scripts/fdmsurf'] / 2**20:.1f} MiB)")
EOF
new_venv "$work/venv2"
step "wheel-install" "$work/venv2/bin/python" -m pip install "$wheel[batch]"
site2=$("$work/venv2/bin/python" -c 'import sysconfig; print(sysconfig.get_path("platlib"))')
check_venv "$work/venv2" wheel "$site2/fdmsurf"
# The Vulkan loader hidden: libvulkan.so.1 deleted from an overlay of the library folder, in a
# mount namespace of this command alone.
loader=$(ldconfig -p | sed -n 's/.*libvulkan\.so\.1 .*=> //p' | head -1)
libdir=$(dirname "$(readlink -f "$loader")")
mkdir -p "$work/overlay/upper" "$work/overlay/work"
if unshare -m true 2>/dev/null; then
    message=$(unshare -m sh -c '
        mount -t overlay overlay -o "lowerdir=$1,upperdir=$2/upper,workdir=$2/work" "$1" &&
        rm -f "$1"/libvulkan.so* && cd "$2" && "$3" -c "import fdmsurf" 2>&1 | tail -1' \
        sh "$libdir" "$work/overlay" "$work/venv2/bin/python") || true
    expected="ImportError: fdmsurf needs the Vulkan loader libvulkan.so.1, which is not installed:"
    [[ $message == "$expected"* ]] ||
        fail "import fdmsurf without libvulkan.so.1 says '$message', not '$expected ...'"
    echo "pip-test.sh: without the Vulkan loader: $message"
else
    echo "pip-test.sh: warning: no mount namespace here (unshare -m); the import without" \
         "libvulkan.so.1 was not tried (tests/packaging/test_import_error.py checks the" \
         "message)" >&2
fi
uninstalled_cleanly "$work/venv2"

# 3. pip install -e . : the package and program of the build folder.
build_dir=$repo/build-pip/$tag
new_venv "$work/venv3"
step "pip-install-editable" "$work/venv3/bin/python" -m pip install -e .
check_venv "$work/venv3" editable "$build_dir/python/fdmsurf"
step "rebuild" cmake --build "$build_dir"
uninstalled_cleanly "$work/venv3"

# 4. Without the build tools: one line naming the missing Debian packages, no CMake trace.
new_venv "$work/venv4"
if env PATH="$work/venv4/bin" "$work/venv4/bin/python" -m pip install . \
    >"$work/no-tools.log" 2>&1; then
    fail "pip install . without cmake and a compiler on PATH succeeded"
fi
line=$(grep '^ *fdmsurf: ' "$work/no-tools.log" | sed 's/^ *//')
tools="cmake, g++, pkg-config, glslang-tools, ninja-build"
expected="fdmsurf: cannot build: missing Debian packages: $tools"
[[ $line == "$expected (as root: apt-get install ${tools//,/})" ]] || {
    cat "$work/no-tools.log" >&2
    fail "pip install . without the tools did not name them in one line"
}
! grep -qi 'cmake error\|traceback' "$work/no-tools.log" ||
    { cat "$work/no-tools.log" >&2; fail "pip install . without the tools printed a trace"; }
echo "pip-test.sh: without the build tools, pip install . says: $line"

echo "pip-test.sh: pip install ., pip wheel . ($(basename "$wheel")), pip install -e . and" \
     "pip uninstall all work in venvs with no index"
