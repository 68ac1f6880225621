#!/usr/bin/env bash
# Builds the Debian package fdmsurf_VERSION_ARCH.deb (CPack's DEB generator,
# cmake/FdmsurfPackaging.cmake) in build-deb and prints its path: a Release build for the prefix
# /usr without the tests and benchmarks (the library in lib/ARCH, the module in
# lib/python3/dist-packages for /usr/bin/python3), then cpack. Install it with
# `apt-get install ./build-deb/packages/fdmsurf_*.deb` (docs/install.md).
#
# After scripts/setup-debian.sh (it installs help2man, dpkg-dev and file, which the man page and
# CPack need), from anywhere: ./scripts/build-deb.sh. Incremental. Environment:
# FDMSURF_DEB_BUILD_DIR (default build-deb).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
build_dir=${FDMSURF_DEB_BUILD_DIR:-build-deb}
log=$(mktemp)
trap 'rm -f "$log"' EXIT

step() {  # step NAME COMMAND...: COMMAND's output shown only when it fails
    local name=$1
    shift
    if ! "$@" >"$log" 2>&1; then
        cat "$log" >&2
        echo "build-deb.sh: $name failed (its output is above)" >&2
        exit 1
    fi
}

step configure cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_INSTALL_PREFIX=/usr -DPython3_EXECUTABLE=/usr/bin/python3 -DFDMSURF_PYTHON=ON \
    -DFDMSURF_MAN=ON -DFDMSURF_BUILD_TESTS=OFF -DFDMSURF_BUILD_BENCH=OFF
step build cmake --build "$build_dir"
rm -f "$build_dir"/packages/fdmsurf_*.deb
step cpack bash -c "cd '$build_dir' && cpack -G DEB"
version=$(sed -n 's/^project(fdmsurf VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
deb=$(realpath "$build_dir")/packages/fdmsurf_${version}_$(dpkg --print-architecture).deb
if [[ ! -f $deb ]]; then
    echo "build-deb.sh: cpack made $(ls "$build_dir/packages"), not $(basename "$deb")" >&2
    exit 1
fi
echo "$deb"
