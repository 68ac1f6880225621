#!/usr/bin/env bash
# Installs the build into a temporary prefix, then configures, builds and runs examples/embed
# against that installed package (find_package(fdmsurf CONFIG REQUIRED), nothing from the source
# or build tree), as an application would: its own Vulkan instance and device handed to
# fdmsurf::Engine, the surface left in device buffers, its own draw of them, with the Vulkan
# validation layer on. Fails unless the example exits 0 (its picture shows the surface in the
# colours of both chains of 3AL1, no validation message) and wrote a PNG.
#
# Run from anywhere after a build: ./scripts/embed-example.sh (scripts/test.sh runs it after
# ctest). Environment: FDMSURF_BUILD_DIR (default build). The picture is kept as
# $FDMSURF_BUILD_DIR/embed-example/3al1.png.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
build_dir=${FDMSURF_BUILD_DIR:-build}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

step() {  # step NAME COMMAND...: runs COMMAND with its output in a log shown on failure
    local name=$1
    shift
    if ! "$@" >"$work/$name.log" 2>&1; then
        echo "embed-example.sh: $name failed:" >&2
        cat "$work/$name.log" >&2
        exit 1
    fi
}

prefix=$work/prefix
step install cmake --install "$build_dir" --prefix "$prefix"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
step configure cmake -S examples/embed -B "$work/build" "${generator[@]}" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF
found=$(sed -n 's/^fdmsurf_DIR:PATH=//p' "$work/build/CMakeCache.txt")
if [[ $found != "$prefix"/* ]]; then
    echo "embed-example.sh: the example found fdmsurf in '$found', not in the installed prefix" >&2
    exit 1
fi
step build cmake --build "$work/build"
mkdir -p "$build_dir/embed-example"
picture=$build_dir/embed-example/3al1.png
rm -f "$picture"
if ! "$work/build/fdmsurf_embed" tests/data/3al1.pdb "$picture" --validation; then
    echo "embed-example.sh: the example failed (see above)" >&2
    exit 1
fi
if [[ ! -s $picture ]] || [[ $(head -c 8 "$picture" | od -An -tx1 | tr -d ' \n') != 89504e470d0a1a0a ]]; then
    echo "embed-example.sh: the example did not write a PNG at $picture" >&2
    exit 1
fi
echo "embed-example.sh: examples/embed built against the installed package ($found) and drew the surface: $picture"
