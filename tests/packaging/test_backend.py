"""The PEP 517 backend (python/build_backend/fdmsurf_build.py) without building: its metadata and
wheel tag, its one line naming the missing Debian packages, the source archive, and what
`fdmsurf --version` says of a tree without git. The builds themselves (pip install ., pip
wheel ., pip install -e .) are scripts/pip-test.sh's. Run by ctest (packaging.backend) with
FDMSURF_VERSION, CMake's project version."""

import os
import subprocess
import sys
import sysconfig
import tarfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python" / "build_backend"))
import fdmsurf_build  # noqa: E402


def test_the_version_is_the_cmake_projects():
    assert fdmsurf_build.version() == os.environ.get("FDMSURF_VERSION", fdmsurf_build.version())
    assert fdmsurf_build.version().count(".") == 2


def test_metadata():
    lines = fdmsurf_build.metadata().split("\n\n")[0].splitlines()
    fields = [tuple(line.split(": ", 1)) for line in lines]
    assert ("Name", "fdmsurf") in fields
    assert ("Version", fdmsurf_build.version()) in fields
    assert ("Requires-Python", ">=3.11") in fields
    assert ("Requires-Dist", "numpy") in fields
    assert ("Provides-Extra", "batch") in fields
    assert ("Requires-Dist", 'distributed; extra == "batch"') in fields
    assert any(k == "License" for k, _ in fields) and any(k == "Summary" for k, _ in fields)


def test_wheel_tag_is_this_interpreters():
    tag = fdmsurf_build.wheel_tag()
    python = f"cp{sys.version_info.major}{sys.version_info.minor}"
    assert tag.startswith(f"{python}-{python}")
    assert tag.endswith(sysconfig.get_platform().replace("-", "_").replace(".", "_"))
    # The module built for this interpreter carries the same ABI in its name.
    assert sysconfig.get_config_var("EXT_SUFFIX").startswith(
        f".cpython-{sys.version_info.major}{sys.version_info.minor}")


def test_missing_packages_are_named(tmp_path):
    missing = fdmsurf_build.missing_packages(include_dirs=[tmp_path], library_dirs=[tmp_path],
                                             path=str(tmp_path), python_include="/usr/include/x")
    assert missing == ["cmake", "g++", "pkg-config", "glslang-tools", "ninja-build",
                       "libvulkan-dev", "glslang-dev", "libvkfft-dev", "gemmi-dev",
                       "tao-pegtl-dev", "zlib1g-dev", "libtinygltf-dev", "libmeshoptimizer-dev",
                       "libpng-dev", "libglm-dev", "pybind11-dev", "spirv-tools", "python3-dev"]
    (tmp_path / "vulkan").mkdir()
    (tmp_path / "vulkan" / "vulkan.h").write_text("")
    (tmp_path / "libvulkan.so").write_text("")
    assert "libvulkan-dev" not in fdmsurf_build.missing_packages(
        include_dirs=[tmp_path], library_dirs=[tmp_path], path=str(tmp_path))


def test_a_build_without_the_tools_stops_with_one_line(tmp_path):
    # No cmake, compiler or glslangValidator on PATH: one line, exit status 1, no wheel.
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import fdmsurf_build; "
            "fdmsurf_build.build_wheel(sys.argv[2])")
    done = subprocess.run([sys.executable, "-c", code, str(REPO / "python" / "build_backend"),
                           str(tmp_path)], capture_output=True, encoding="utf-8",
                          env=dict(os.environ, PATH=str(tmp_path)), cwd=tmp_path)
    assert done.returncode == 1
    assert done.stdout == ""
    assert done.stderr == ("fdmsurf: cannot build: missing Debian packages: cmake, g++, "
                           "pkg-config, glslang-tools, ninja-build (as root: apt-get install "
                           "cmake g++ pkg-config glslang-tools ninja-build)\n"), done.stderr
    assert list(tmp_path.iterdir()) == []


def test_source_archive(tmp_path):
    if not (REPO / ".git").exists():
        with pytest.raises(SystemExit):
            fdmsurf_build.build_sdist(str(tmp_path))
        return
    name = fdmsurf_build.build_sdist(str(tmp_path))
    assert name == f"fdmsurf-{fdmsurf_build.version()}.tar.gz"
    with tarfile.open(tmp_path / name) as tar:
        names = tar.getnames()
        info = tar.extractfile(f"fdmsurf-{fdmsurf_build.version()}/fdmsurf-source-info.txt")
        info = info.read().decode()
    base = f"fdmsurf-{fdmsurf_build.version()}/"
    for needed in ["CMakeLists.txt", "pyproject.toml", "python/build_backend/fdmsurf_build.py",
                   "PKG-INFO", "tests/data/1crn.pdb", "packaging/fdmsurf.bash"]:
        assert base + needed in names, needed
    assert not any("/build/" in n or "/build-pip/" in n for n in names)
    assert info.startswith("commit=") and "release=" in info


@pytest.mark.parametrize("info, line", [
    ("commit=0123456789abcdef0123\nchanged=no\nrelease=yes\n",
     "git commit 0123456789ab, tag v{v}: a release"),
    ("commit=0123456789abcdef0123\nchanged=yes\nrelease=no\n",
     "git commit 0123456789ab with local changes: a development build, not a release"),
    (None, "git commit unknown (not built from a git checkout): not a release"),
])
def test_version_line_of_a_tree_without_git(tmp_path, info, line):
    # cmake/FdmsurfBuildInfo.cmake in script mode, on a folder that is not a git checkout.
    source = tmp_path / "source"
    source.mkdir()
    if info is not None:
        (source / "fdmsurf-source-info.txt").write_text(info)
    out = tmp_path / "build_info.cpp"
    subprocess.run(["cmake", f"-DSOURCE_DIR={source}", "-DVERSION=9.8.7",
                    f"-DTEMPLATE={REPO / 'src' / 'cli' / 'version.cpp.in'}", f"-DOUTPUT={out}",
                    "-P", str(REPO / "cmake" / "FdmsurfBuildInfo.cmake")], check=True)
    assert f'"{line.format(v="9.8.7")}"' in out.read_text()
