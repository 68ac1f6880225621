#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (clang, build-san),
# lavapipe and the validation layer included, then every libFuzzer harness for a bounded time
# (scripts/fuzz.sh). .ci/run runs it after scripts/test.sh; docs/reliability.md has the figures.
#
#   scripts/sanitize.sh                 # set up, build build-san, ctest, fuzz.sh's CI mode
#   FDMSURF_FUZZ_SECONDS=0 scripts/sanitize.sh   # the suite only
#
# Environment: FDMSURF_SAN_BUILD_DIR (default build-san); FDMSURF_FUZZ_SECONDS (0: no fuzzing,
# unset: fuzz.sh's CI mode, fixed runs per harness, S: S seconds per harness);
# extra arguments go to ctest (e.g. -R Structure).
#
# Everything but the benchmarks is built with the sanitizers: the test binary, the CLI it runs,
# the Python module (its tests preload the shared ASan runtime into the interpreter:
# python/CMakeLists.txt), the MSMS reader test and the glTF validator test. The CLI and the
# module link the shared ASan runtime, the other programs the static one (CMakeLists.txt,
# FDMSURF_SANITIZE).
# Leak reports are on. tests/sanitizers/keep_loaded.c, preloaded, keeps the Vulkan driver and
# layers mapped to the end (the loader's dlclose would unmap them, and memory that only their
# globals still point to would then be reported as leaked, in "<unknown module>");
# tests/sanitizers/lsan.supp lists the suppressions, each inside Mesa (lavapipe, LLVM) or the
# Vulkan loader and layer, with its reason.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${FDMSURF_SAN_BUILD_DIR:-build-san}
export FDMSURF_SAN_BUILD_DIR=$build_dir

./scripts/setup-debian.sh --sanitizers

cmake -S . -B "$build_dir" -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DFDMSURF_SANITIZE=ON -DFDMSURF_FUZZ=ON -DFDMSURF_PYTHON=ON -DFDMSURF_BUILD_BENCH=OFF
cmake --build "$build_dir" -j2

# The glTF validator that scripts/test.sh installed into build/ (npm), when it is there.
if [[ -d build/tools/gltf-validator && ! -e $build_dir/tools/gltf-validator ]]; then
    mkdir -p "$build_dir/tools"
    ln -s "$(pwd)/build/tools/gltf-validator" "$build_dir/tools/gltf-validator"
fi

supp="$(pwd)/tests/sanitizers"
cc -shared -fPIC -O1 -o "$build_dir/keep_loaded.so" "$supp/keep_loaded.c"
export LD_PRELOAD="$(realpath "$build_dir")/keep_loaded.so${LD_PRELOAD:+:$LD_PRELOAD}"
# verify_asan_link_order=0: keep_loaded.so is preloaded ahead of the shared ASan runtime that
# the CLI links, which ASan would otherwise refuse; keep_loaded.so only defines dlclose and
# allocates nothing.
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:verify_asan_link_order=0"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-$(command -v llvm-symbolizer || command -v llvm-symbolizer-14)}

source scripts/lib/ctest_no_skips.sh
gltf_missing=0
[[ -d build/tools/gltf-validator ]] || gltf_missing=1
status=0
ctest_no_skips "$build_dir" "$gltf_missing" sanitize.sh "$@" || status=$?
if ((status)); then
    echo "sanitize.sh: the suite failed under AddressSanitizer + UndefinedBehaviorSanitizer" >&2
fi

if [[ ${FDMSURF_FUZZ_SECONDS:-60} != 0 ]]; then
    ./scripts/fuzz.sh || status=1
fi
exit $status
