# Sourced by scripts/test.sh and scripts/sanitize.sh: runs the whole ctest suite of a build
# folder with FDMSURF_REQUIRE_DEVICE=1 and FDMSURF_REQUIRE_TOOLS=1, and counts a skipped test
# (ctest counts GTEST_SKIP as passed) as a failure.
#
#   ctest_no_skips BUILD_DIR ALLOW_GLTF_SKIP NAME [ctest arguments...]
#
# ALLOW_GLTF_SKIP 1: the GltfValidator test may skip (npm's validator could not be installed).
# NAME prefixes the messages. Returns 0 when every test ran and passed.
ctest_no_skips() {
    local build_dir=$1 allow_gltf_skip=$2 name=$3
    shift 3
    local log status=0 skipped
    log=$(mktemp)
    FDMSURF_REQUIRE_DEVICE=1 FDMSURF_REQUIRE_TOOLS=1 \
        ctest --test-dir "$build_dir" --output-on-failure --no-tests=error -j2 "$@" 2>&1 | tee "$log" \
        || status=$?
    skipped=$(grep -E '^[[:space:]]*[0-9]+ - .* \(Skipped\)$' "$log" || true)
    rm -f "$log"
    if ((allow_gltf_skip)); then
        skipped=$(grep -v ' - GltfValidator\.' <<<"$skipped" || true)
    fi
    if [[ -n $skipped ]]; then
        echo "$name: these tests were skipped, so not every test ran:" >&2
        echo "$skipped" >&2
        ((status != 0)) || status=1
    fi
    return $status
}
