#!/usr/bin/env bash
# Sets up and builds fdmsurf (scripts/setup-debian.sh), checks that no two src/ folders include
# each other (scripts/include-graph.py), then runs every test with ctest.
#
# GPU tests run on whatever Vulkan device there is (lavapipe on a machine without a GPU).
# FDMSURF_REQUIRE_DEVICE=1 makes a GPU test fail instead of skipping when no device is found
# (FDMSURF_REQUIRE_TOOLS=1 likewise for tests that need ../shared/tools and python3-scipy), and
# this script also fails if ctest reports any skipped test: a green run means every test ran and
# passed (one exception: GltfValidator when npm's gltf-validator cannot be installed, e.g. with no
# route to the npm registry; a warning says so). Extra arguments go to ctest (e.g. -R Density, or -j4 to override -j2).
# After ctest, scripts/embed-example.sh installs the build into a temporary prefix and builds and
# runs examples/embed against it.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
build_dir=${FDMSURF_BUILD_DIR:-build}

./scripts/setup-debian.sh

# No two folders under src/ include each other (CONTRIBUTING.md): the include arrows between
# them, and a failure on a cycle.
if ! ./scripts/include-graph.py >"$build_dir/include-graph.txt"; then
    echo "test.sh: src/ folders include each other (scripts/include-graph.py above)" >&2
    exit 1
fi

# The Khronos glTF validator for the GltfValidator test (tests/tools/gltf_validator.sh), from
# npm into the build folder. Without the npm registry the test skips, and only that skip is
# let through below, with a warning.
validator_dir="$build_dir/tools/gltf-validator"
validator_version=2.0.0-dev.3.10
validator_missing=0
if [[ ! -f $validator_dir/node_modules/gltf-validator/package.json ]] ||
   ! grep -q "\"version\": \"$validator_version\"" "$validator_dir/node_modules/gltf-validator/package.json"; then
    mkdir -p "$validator_dir"
    if ! command -v npm >/dev/null 2>&1 ||
       ! npm install --prefix "$validator_dir" --no-audit --no-fund --no-save \
             "gltf-validator@$validator_version" >"$validator_dir/npm.log" 2>&1; then
        echo "test.sh: warning: could not install npm's gltf-validator $validator_version" \
             "(no npm, or no registry: see $validator_dir/npm.log); GltfValidator will be skipped" >&2
        validator_missing=1
    fi
fi

# ctest counts a skipped test (GTEST_SKIP) as passed; here it is a failure.
source scripts/lib/ctest_no_skips.sh
status=0
ctest_no_skips "$build_dir" "$validator_missing" test.sh "$@" || status=$?
# fdmsurf's reading of tests/data against gemmi's, Biopython's and MDAnalysis's (those that are
# installed; the others are skipped with a note): docs/structure.md, "Other readers".
if ! FDMSURF_BUILD_DIR="$build_dir" /usr/bin/python3 scripts/cross-check-readers.py tests/data; then
    echo "test.sh: fdmsurf reads a file of tests/data differently from another reader (above)" >&2
    ((status != 0)) || status=1
fi
# The embedding example built against the installed package (cmake --install into a
# temporary prefix, examples/embed configured with find_package(fdmsurf), run with the
# validation layer): what an application that embeds fdmsurf sees.
if ! ./scripts/embed-example.sh; then
    echo "test.sh: the embedding example (scripts/embed-example.sh) failed" >&2
    ((status != 0)) || status=1
fi

if ((status != 0)); then
    echo "test.sh: FAILED (ctest exit status, skipped tests or the embedding example above)" >&2
else
    if ((validator_missing)); then
        echo "test.sh: every test ran and passed, but GltfValidator, skipped: npm's" \
             "gltf-validator could not be installed (see $validator_dir/npm.log)"
    else
        echo "test.sh: every test ran and passed, and the embedding example too"
    fi
fi
exit "$status"
