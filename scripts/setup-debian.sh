#!/usr/bin/env bash
# Installs fdmsurf's build and test dependencies on Debian 12 and builds it in build/ (Release).
#
# Run as root (or through sudo) from anywhere: ./scripts/setup-debian.sh [--sanitizers]
# --sanitizers also installs clang, its sanitizer and libFuzzer runtimes and llvm-symbolizer,
# for scripts/sanitize.sh and scripts/fuzz.sh.
# Idempotent: when every package is already installed apt is skipped entirely (fast, works
# offline), and the CMake build is incremental.
# Environment: FDMSURF_BUILD_DIR (default build), FDMSURF_BUILD_TYPE (default Release).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${FDMSURF_BUILD_DIR:-build}
build_type=${FDMSURF_BUILD_TYPE:-Release}

packages=(
    # compilers and build tools
    build-essential cmake ninja-build pkg-config git
    # Vulkan loader and headers; lavapipe, the CPU driver (a Vulkan device on machines without
    # a GPU); the validation layer (--validation and the tests); vulkaninfo for diagnosis
    libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
    # shaders are compiled at build time (glslangValidator); VkFFT compiles its own at run time
    # through glslang's library, which needs SPIRV-Tools
    glslang-tools glslang-dev spirv-tools libvkfft-dev
    # structure input: gemmi is header-only and its CIF parser needs PEGTL, which gemmi-dev
    # does not pull in (docs/structure.md); zlib for .gz
    gemmi-dev tao-pegtl-dev zlib1g-dev
    # GLB output and input: tinygltf (Debian ships it as a shared library: no json or stb needed)
    libtinygltf-dev
    # mesh simplification and vertex-cache/fetch reordering (--simplify, --optimize)
    libmeshoptimizer-dev
    # PNG pictures of the surface (-o FILE.png, --image; src/render/)
    libpng-dev
    # GoogleTest, FFTW (CPU reference of the filter), glm (tests)
    libglm-dev libgtest-dev libfftw3-dev
    # ../shared/tools/meshstat.py; python3 also parses --stats json in scripts/all-structures.sh
    python3 python3-numpy python3-scipy
    # the Python module (python/, docs/python.md): pybind11 and Python's headers build it; Dask's
    # distributed scheduler runs fdmsurf.batch; pytest runs the module's tests under ctest
    pybind11-dev python3-dev python3-distributed python3-pytest
    # other readers of structure files: scripts/cross-check-readers.py (scripts/test.sh) compares
    # fdmsurf's reading with theirs; the structure objects fdmsurf.surface and Engine.trajectory
    # take (python/fdmsurf/_objects.py, docs/trajectories.md), whose tests read the same files
    # through each library; mdtraj is also the reference of bench/trajectory.py
    python3-gemmi python3-biopython python3-mdanalysis python3-mdtraj
    # gzip; GNU time (/usr/bin/time -v) for the peak memory column of scripts/all-structures.sh
    gzip time
    # FreeSASA (Lee-Richards areas): the reference of the vdw and sas area tests and of
    # scripts/crease-accuracy.py
    freesasa
    # the installs (docs/install.md): help2man makes the man page from --help, groff checks it;
    # bash-completion loads the completion in scripts/package-test.sh; python3-venv makes the
    # venvs of scripts/pip-test.sh; CPack's Debian package needs dpkg-shlibdeps and file
    help2man groff-base bash-completion python3-venv dpkg-dev file
)
if [[ ${1:-} == --sanitizers ]]; then
    # clang 14 with AddressSanitizer, UndefinedBehaviorSanitizer and libFuzzer
    # (libclang-rt-14-dev) and llvm-symbolizer (llvm-14) for readable stacks
    packages+=(clang libclang-rt-14-dev llvm-14)
elif (($#)); then
    echo "setup-debian: unknown argument $1 (the only one is --sanitizers)" >&2
    exit 2
fi
# node and npm for the Khronos glTF validator (scripts/test.sh installs npm's gltf-validator),
# unless something else provides them already (NodeSource's nodejs bundles npm and conflicts
# with Debian's npm package)
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
    status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
    [[ $status == installed ]] || missing+=("$p")
done

if ((${#missing[@]})); then
    echo "setup-debian: installing ${missing[*]}"
    as_root=()
    if ((EUID != 0)); then
        if command -v sudo >/dev/null 2>&1; then
            as_root=(sudo)
        else
            echo "setup-debian: these packages are missing and this is not root (no sudo either):" >&2
            echo "  ${missing[*]}" >&2
            echo "run this script as root" >&2
            exit 1
        fi
    fi
    # env, not export: sudo drops the caller's environment
    "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
    "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y --no-install-recommends "${missing[@]}"
else
    echo "setup-debian: all ${#packages[@]} packages are installed; apt skipped"
fi

# A build folder made by another generator cannot be reused with -G Ninja.
cache="$build_dir/CMakeCache.txt"
if [[ -f $cache ]] && ! grep -qx 'CMAKE_GENERATOR:INTERNAL=Ninja' "$cache"; then
    echo "setup-debian: $build_dir/ was configured with another generator" \
         "($(sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$cache")); remove it or set FDMSURF_BUILD_DIR" >&2
    exit 1
fi

cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type"
cmake --build "$build_dir"
echo "setup-debian: built $(pwd)/$build_dir/fdmsurf"
# The FFT plans of the grid sizes small structures are rounded to, and the kernels of the
# default surfaces run once, so that a first surface compiles nothing (docs/performance.md,
# "Cold start"). The caches are the user's: under sudo, prepared for the user who ran sudo. Not a
# reason to fail: without a Vulkan device now, the first run builds what it needs itself.
prepare=("$build_dir/fdmsurf" prepare --quiet)
if ((EUID == 0)) && [[ -n ${SUDO_USER:-} && $SUDO_USER != root ]] && command -v sudo >/dev/null 2>&1; then
    prepare=(sudo -u "$SUDO_USER" -H "${prepare[@]}")
fi
if "${prepare[@]}"; then
    echo "setup-debian: prepared the FFT plans and kernels (fdmsurf prepare)"
else
    echo "setup-debian: fdmsurf prepare failed (see above); a first run will compile its own kernels" >&2
fi
