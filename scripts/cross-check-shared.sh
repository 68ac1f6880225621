#!/usr/bin/env bash
# Cross-checks against the development checkout's ../shared (not part of this repository):
# fdmsurf's mesh readers and statistics against ../shared/tools/meshstat.py (the tests named
# *Meshstat* in build/tests/fdmsurf_tests, which ctest leaves out so that the suite runs from the
# repository alone). Says so and exits 0 when ../shared is absent; fails if a check fails.
#
#   scripts/cross-check-shared.sh        # after scripts/setup-debian.sh (or cmake --build build)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
shared=${FDMSURF_SHARED:-../shared}
tests=${FDMSURF_BUILD_DIR:-build}/tests/fdmsurf_tests
if [[ ! -f $shared/tools/meshstat.py ]]; then
    echo "cross-check-shared.sh: $shared/tools/meshstat.py is absent (../shared is the development" \
         "checkout's folder of tools and data, not part of this repository): nothing checked"
    exit 0
fi
[[ -x $tests ]] || { echo "cross-check-shared.sh: $tests is missing: scripts/setup-debian.sh" >&2; exit 1; }
if ! /usr/bin/python3 -c 'import numpy, scipy' 2>/dev/null; then
    if [[ $(id -u) == 0 ]]; then
        apt-get install -y python3-numpy python3-scipy >/dev/null
    else
        echo "cross-check-shared.sh: meshstat.py needs python3-numpy and python3-scipy" >&2
        exit 1
    fi
fi
FDMSURF_REQUIRE_DEVICE=1 FDMSURF_REQUIRE_TOOLS=1 "$tests" --gtest_filter='*Meshstat*'
echo "cross-check-shared.sh: fdmsurf agrees with $shared/tools/meshstat.py"
