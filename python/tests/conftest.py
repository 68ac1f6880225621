"""Fixtures of the Python module's tests (run by ctest with PYTHONPATH=build/python): the test
data, the CLI to compare against, and one Engine for the session."""

import os
import pathlib
import subprocess

import pytest

import fdmsurf

REPO = pathlib.Path(__file__).resolve().parents[2]


def pytest_sessionfinish(session, exitstatus):
    """Exit code 77 when every test was skipped, which ctest reports as a skip (and
    scripts/test.sh as a failure): a green ctest run means these tests ran."""
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is None or exitstatus != 0:
        return
    if reporter.stats.get("skipped") and not reporter.stats.get("passed"):
        session.exitstatus = 77


@pytest.fixture(scope="session")
def data():
    return pathlib.Path(os.environ.get("FDMSURF_TEST_DATA_DIR", REPO / "tests" / "data"))


@pytest.fixture(scope="session")
def engine():
    """One engine for the session; without a Vulkan device the test is skipped, or fails with
    FDMSURF_REQUIRE_DEVICE=1 (scripts/test.sh)."""
    try:
        with fdmsurf.Engine() as e:
            yield e
    except fdmsurf.NoDeviceError as error:
        if os.environ.get("FDMSURF_REQUIRE_DEVICE") == "1":
            pytest.fail(f"no Vulkan device and FDMSURF_REQUIRE_DEVICE=1: {error}")
        pytest.skip(f"no Vulkan device: {error}")


@pytest.fixture(scope="session")
def cli():
    """A function running the fdmsurf program; returns the CompletedProcess."""
    path = os.environ.get("FDMSURF_CLI") or str(REPO / "build" / "fdmsurf")
    if not os.path.exists(path):
        pytest.skip(f"the fdmsurf program is not built ({path})")

    def run(*args, check=True):
        done = subprocess.run([path, *map(str, args)], capture_output=True, encoding="utf-8")
        if check and done.returncode != 0:
            raise AssertionError(f"fdmsurf {' '.join(map(str, args))} failed "
                                 f"({done.returncode}): {done.stderr}")
        return done

    return run
