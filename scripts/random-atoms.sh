#!/usr/bin/env bash
# Longer runs of the randomized property test (tests/engine/test_random_atoms.cpp): SEEDS seeds
# (default 5) of CASES random atom sets each (default 25), every surface kind and method, with
# the test's checks (closed manifolds, byte-identical reruns, slabs, vdw/sas against Monte Carlo
# and Shrake-Rupley). CI runs the fixed seed with 5 sets.
#
#   scripts/random-atoms.sh [SEEDS] [CASES]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
seeds=${1:-5}
cases=${2:-25}
failed=0
for seed in $(seq 1 "$seeds"); do
    FDMSURF_REQUIRE_DEVICE=1 FDMSURF_TEST_SEED=$seed FDMSURF_TEST_CASES=$cases \
        build/tests/fdmsurf_tests --gtest_filter='RandomAtoms.*' >"${TMPDIR:-/tmp}/random-atoms-$seed.log" 2>&1 ||
        failed=$((failed + 1))
    grep -E "random sets|Failure|trace:|evaluates|OK \]|FAILED  \] R" "${TMPDIR:-/tmp}/random-atoms-$seed.log" || true
done
echo "random-atoms.sh: $seeds seeds x $cases sets, $failed seed(s) with failures"
((failed == 0))
