"""The man page the build makes (cmake/FdmsurfManPage.cmake) against the program: every option of
`fdmsurf --help` and of its subcommands is in it, with the exit codes; every example of
packaging/fdmsurf.h2m is a command line the program accepts; groff renders it without a warning.
Run by ctest (packaging.man_page) with FDMSURF_CLI and FDMSURF_MAN_PAGE (build/man/fdmsurf.1)."""

import os
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
FDMSURF = os.environ.get("FDMSURF_CLI") or str(REPO / "build" / "fdmsurf")
MAN_PAGE = Path(os.environ.get("FDMSURF_MAN_PAGE") or REPO / "build" / "man" / "fdmsurf.1")


def run(*args):
    return subprocess.run([FDMSURF, *args], capture_output=True, encoding="utf-8",
                          env=dict(os.environ, FDMSURF_HUGE_PAGES="0"))


def unroff(text):
    """The page's text with roff's escapes of '-' and fonts undone."""
    text = text.replace("\\-", "-").replace("\\(oA", "Å").replace("\\&", "")
    text = text.replace("\\e", "\\")
    return re.sub(r"\\f[BIRP]", "", text)


@pytest.fixture(scope="module")
def page():
    assert MAN_PAGE.is_file(), f"no man page at {MAN_PAGE} (FDMSURF_MAN=ON builds it)"
    return unroff(MAN_PAGE.read_text(encoding="utf-8"))


def options_in(text):
    return set(re.findall(r"(?<![\w-])(--[a-z][\w-]*|-[a-z](?![\w-]))", text))


def test_every_option_and_exit_code_is_in_the_page(page):
    help_text = run("--help").stdout
    options = options_in(help_text)
    assert {"--surface", "--list-devices", "-o", "--version"} <= options
    missing = {o for o in options if not re.search(rf"(?<![\w-]){re.escape(o)}(?![\w-])", page)}
    assert not missing, missing
    assert ".SH SYNOPSIS" in page and ".SH EXAMPLES" in page and ".SH COMMANDS" in page
    for code in range(8):  # the exit codes' table of the help
        assert re.search(rf"^\s*{code}\s+\S", page, re.M), code
    assert "Exit codes" in page


@pytest.mark.parametrize("command", ["compare", "msms", "prepare"])
def test_each_subcommand_has_its_help_in_the_page(page, command):
    assert f'.SS "fdmsurf {command}"' in page
    help_text = run(command, "--help").stdout
    section = page.split(f'.SS "fdmsurf {command}"')[1].split(".SS")[0].split(".SH")[0]
    for line in help_text.splitlines():
        line = line.strip()
        if line:
            assert line in section, (command, line)


def test_examples_are_command_lines_the_program_takes(page):
    examples = page.split(".SH EXAMPLES")[1].split(".SH")[0]
    commands = re.findall(r"^\.B (.*)$", examples, re.M)
    assert len(commands) >= 8, commands
    for command in commands:
        words = shlex.split(command)
        if words[0] == "msms" or words[1:2] == ["msms"]:
            msms_help = run("msms", "--help").stdout
            for option in (w for w in words if w.startswith("-")):
                assert re.search(rf"(?<![\w-]){option}(?![\w-])", msms_help), (command, option)
        elif words[1:2] == ["compare"]:
            compare_help = run("compare", "--help").stdout
            for option in (w for w in words if w.startswith("--")):
                assert option in compare_help, (command, option)
        else:
            # The parser checks every option and value before --help prints: a renamed option
            # or a value the program no longer takes fails here.
            done = run(*words[1:], "--help")
            assert done.returncode == 0, (command, done.stderr)


def test_groff_renders_it_without_warnings():
    if shutil.which("groff") is None:
        pytest.fail("groff is missing (Debian: groff-base, which man-db needs)")
    done = subprocess.run(["groff", "-k", "-man", "-Tutf8", "-ww", "-z", str(MAN_PAGE)],
                          capture_output=True, encoding="utf-8")
    assert done.returncode == 0 and done.stderr == "", done.stderr
