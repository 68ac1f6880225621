"""packaging/fdmsurf.bash against the program: every option of `fdmsurf --help` (and of compare,
prepare and msms) is completed, every completed option is one, and each listed option value is
exactly the list the program's own message gives for a value it does not know, so that the
completion cannot drift from the parser. Run by ctest (packaging.completion) with FDMSURF_CLI."""

import os
import re
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
COMPLETION = REPO / "packaging" / "fdmsurf.bash"
FDMSURF = os.environ.get("FDMSURF_CLI") or str(REPO / "build" / "fdmsurf")


def complete(*words, cwd=None):
    """COMPREPLY for the command line WORDS, the last one being completed."""
    script = (f'source "{COMPLETION}"\nCOMP_WORDS=("$@"); COMP_CWORD=$(($# - 1))\n'
              '_fdmsurf; printf "%s\\n" "${COMPREPLY[@]}"')
    done = subprocess.run(["bash", "-c", script, "bash", *words], capture_output=True,
                          encoding="utf-8", cwd=cwd, check=True)
    assert done.stderr == "", done.stderr
    return sorted(line for line in done.stdout.splitlines() if line)


def run(*args):
    return subprocess.run([FDMSURF, *args], capture_output=True, encoding="utf-8",
                          env=dict(os.environ, FDMSURF_HUGE_PAGES="0"))


def defined_options(help_text):
    """The options a help text defines: its lines that start (indented) with one."""
    options = set()
    for line in help_text.splitlines():
        found = re.match(r"^  (-\w)?(?:, )?(--?[A-Za-z][\w-]*)?", line)
        if found:
            options.update(o for o in found.groups() if o)
    # `--view V[,V...] ... (also --views)`: an alias that the text names.
    options.update(re.findall(r"\(also (--[\w-]+)\)", help_text))
    return options


@pytest.fixture(scope="module")
def help_text():
    done = run("--help")
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_every_option_of_the_help_is_completed(help_text):
    offered = set(complete("fdmsurf", "-"))
    defined = defined_options(help_text)
    assert "--surface" in defined and "-o" in defined and "--views" in defined
    assert defined == offered, (defined - offered, offered - defined)


@pytest.mark.parametrize("command", ["compare", "prepare", "msms"])
def test_every_option_of_each_subcommand_is_completed(command):
    done = run(command, "--help")
    assert done.returncode == 0, done.stderr
    text = done.stdout
    if command == "prepare":  # its options are in its usage line
        defined = set(re.findall(r"\[(--[\w-]+)", text.splitlines()[0])) | {"-h", "--help"}
    elif command == "msms":  # MSMS's single-dash options, in the usage lines
        usage = text.split("\n\n")[0]
        defined = set(re.findall(r"(?<![\w-])(-[a-z][a-z_]*)", usage)) | {"-h", "-help"}
    else:
        defined = defined_options(text)
    offered = set(complete("fdmsurf", command, "-"))
    assert defined == offered, (defined - offered, offered - defined)
    if command == "msms":  # and as the program msms
        assert set(complete("msms", "-")) == offered


def expected_values(option, command=()):
    """The values the program lists when OPTION gets one it does not know."""
    done = run(*command, option, "no-such-value", "--help")
    assert done.returncode == 2, (option, done.stdout, done.stderr)
    listed = re.search(r"\(expected (?:a comma-separated list of )?([^;)]*)", done.stderr)
    assert listed, done.stderr
    values = re.split(r", | or ", listed.group(1).strip())
    return {v for v in values if v and not v.startswith("#") and " " not in v}


@pytest.mark.parametrize("option", [
    "--surface", "--method", "--filter", "--format", "--models", "--color", "--properties",
    "--simplifier", "--host-filter", "--host-density", "--host-mc", "--host-atoms", "--host-ses",
    "--output-format", "--stats", "--relative", "--view", "--views", "--background"])
def test_option_values_are_the_programs(option):
    offered = set(complete("fdmsurf", option, ""))
    assert offered == expected_values(option), option
    # --name=value: bash splits the word at '='.
    first = sorted(offered)[0]
    assert complete("fdmsurf", option, "=", first[:1]) == \
        sorted(v for v in offered if v.startswith(first[:1]))


def test_value_lists_the_help_gives_agree(help_text):
    # Options written `--name a|b|c` in the help: the same values.
    for option, values in re.findall(r"^  (--[\w-]+) ([a-z0-9]+(?:\|[a-z0-9]+)+)\b", help_text,
                                      re.M):
        assert set(complete("fdmsurf", option, "")) == set(values.split("|")), option


def test_msms_values():
    assert complete("msms", "-surface", "") == ["ases", "ses", "tses"]
    assert complete("fdmsurf", "msms", "-method", "") == ["edt", "fdm"]
    assert complete("msms", "-host_mc", "o") == ["off", "on"]
    assert complete("fdmsurf", "compare", "a.ply", "b.ply", "--stats", "") == ["json"]


def test_comma_separated_lists_complete_the_last_item():
    assert complete("fdmsurf", "--properties", "coulombic,shape") == ["coulombic,shape_index"]
    assert complete("fdmsurf", "--view", "front,le") == ["front,left"]


def test_file_names(tmp_path):
    for name in ["a.pdb", "b.cif.gz", "c.xyzrn", "notes.txt", "m.ply", "m.csv"]:
        (tmp_path / name).write_text("")
    (tmp_path / "sub").mkdir()
    first = complete("fdmsurf", "", cwd=tmp_path)
    assert first == ["a.pdb", "b.cif.gz", "c.xyzrn", "compare", "msms", "prepare", "sub"]
    assert complete("fdmsurf", "a.pdb", "", cwd=tmp_path) == ["a.pdb", "b.cif.gz", "c.xyzrn",
                                                              "sub"]
    assert complete("fdmsurf", "a.pdb", "-o", "", cwd=tmp_path) == sorted(
        ["a.pdb", "b.cif.gz", "c.xyzrn", "notes.txt", "m.ply", "m.csv", "sub"])
    assert complete("fdmsurf", "a.pdb", "--areas", "", cwd=tmp_path) == ["m.csv", "sub"]
    assert complete("fdmsurf", "compare", "", cwd=tmp_path) == ["m.ply", "sub"]
    assert complete("msms", "-if", "", cwd=tmp_path) == ["c.xyzrn", "sub"]
    # Options that take a number or a selection offer nothing.
    assert complete("fdmsurf", "a.pdb", "--spacing", "", cwd=tmp_path) == []
