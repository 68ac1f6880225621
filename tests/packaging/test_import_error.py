"""`import fdmsurf` where the compiled module cannot load a shared library it links: one line
that says what to install (the Vulkan loader above all). The package's .py files are used with a
stand-in _fdmsurf that fails as the real one does when the library is missing; scripts/pip-test.sh
checks the real module with libvulkan.so.1 hidden. Run by ctest (packaging.import_error)."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def import_error(tmp_path, message):
    package = tmp_path / "fdmsurf"
    shutil.copytree(REPO / "python" / "fdmsurf", package)
    (package / "_fdmsurf.py").write_text(f"raise ImportError({message!r})\n")
    done = subprocess.run([sys.executable, "-c", "import fdmsurf"], capture_output=True,
                          encoding="utf-8", cwd=tmp_path)
    assert done.returncode == 1
    return done.stderr.strip().splitlines()[-1]


@pytest.mark.parametrize("library", ["libvulkan.so.1", "libvulkan.so"])
def test_missing_vulkan_loader(tmp_path, library):
    line = import_error(tmp_path, f"{library}: cannot open shared object file: No such file or "
                                  "directory")
    assert line == (f"ImportError: fdmsurf needs the Vulkan loader {library}, which is not "
                    "installed: apt-get install libvulkan1, and a Vulkan driver "
                    "(mesa-vulkan-drivers, or your GPU's; docs/install.md)")


def test_other_missing_library(tmp_path):
    line = import_error(tmp_path, "libpng16.so.16: cannot open shared object file: No such file "
                                  "or directory")
    assert line == ("ImportError: fdmsurf's compiled module needs libpng16.so.16, which is not "
                    "installed (docs/install.md lists what the module needs at run time)")


def test_other_import_errors_pass_through(tmp_path):
    line = import_error(tmp_path, "undefined symbol: PyFoo")
    assert line == "ImportError: undefined symbol: PyFoo"
