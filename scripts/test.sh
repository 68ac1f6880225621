#!/usr/bin/env bash
# Sets up and builds fdmsurf (scripts/setup-debian.sh), then runs every test with ctest.
#
# GPU tests run on whatever Vulkan device there is (lavapipe on a machine without a GPU).
# FDMSURF_REQUIRE_DEVICE=1 makes a GPU test fail instead of skipping when no device is found
# (FDMSURF_REQUIRE_TOOLS=1 likewise for tests that need ../shared/tools and python3-scipy), and
# this script also fails if ctest reports any skipped test: a green run means every test ran and
# passed. Extra arguments go to ctest (e.g. -R Density, or -j4 to override -j2).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
build_dir=${FDMSURF_BUILD_DIR:-build}

./scripts/setup-debian.sh

log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=0
FDMSURF_REQUIRE_DEVICE=1 FDMSURF_REQUIRE_TOOLS=1 \
    ctest --test-dir "$build_dir" --output-on-failure --no-tests=error -j2 "$@" 2>&1 | tee "$log" \
    || status=$?

# ctest counts a skipped test (GTEST_SKIP) as passed; here it is a failure.
skipped=$(grep -E '^[[:space:]]*[0-9]+ - .* \(Skipped\)$' "$log" || true)
if [[ -n $skipped ]]; then
    echo "test.sh: these tests were skipped, so not every test ran:" >&2
    echo "$skipped" >&2
    ((status != 0)) || status=1
fi
if ((status != 0)); then
    echo "test.sh: FAILED (ctest exit status or skipped tests above)" >&2
else
    echo "test.sh: every test ran and passed"
fi
exit "$status"
