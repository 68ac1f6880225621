#!/bin/sh
# Packs what a bare GPU machine needs to run fdmsurf's tests and GPU benchmark into
# .gpu/bundle.tar.gz (git-ignored through .git/info/exclude): the built CLI and test binary
# (build/, Release), the shared libraries a CUDA image lacks (tinygltf, stb, meshoptimizer,
# FFTW for the CPU references, the Vulkan loader), the Khronos validation layer with its
# manifest, libglvnd's Debian packages (the NVIDIA ICD needs libGLdispatch), the structures
# of the benchmark (from ../shared/data) and lavapipe meshes of 1CRN and 4HHB to compare with.
#
#   bench/gpu/bundle.sh          # after: cmake --build build
#   (optional: a baseline build/fdmsurf copied to .gpu/fdmsurf-base, for run.sh ab)
# then, on the GPU machine, from the repository root: bench/gpu/run.sh (see docs/gpu.md).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
shared=${FDMSURF_SHARED:-$root/../shared}
stage=$root/.gpu/stage
[ -x "$root/build/fdmsurf" ] && [ -x "$root/build/tests/fdmsurf_tests" ] || {
    echo "bundle: build/fdmsurf and build/tests/fdmsurf_tests are needed: cmake --build build" >&2; exit 1; }
[ -d "$shared/data" ] || { echo "bundle: $shared/data is missing (the benchmark's structures)" >&2; exit 1; }
rm -rf "$stage/bin" "$stage/lib" "$stage/layers" "$stage/data" "$stage/debs"
mkdir -p "$stage/bin" "$stage/lib" "$stage/layers" "$stage/data" "$stage/debs" "$stage/ref"
cp "$root/build/fdmsurf" "$root/build/tests/fdmsurf_tests" "$stage/bin/"
strip "$stage/bin/fdmsurf" "$stage/bin/fdmsurf_tests" 2>/dev/null || true
# The FFT multi-buffer benchmark (run.sh fft), when it was built.
[ -x "$root/build/fdmsurf_bench_fft_multibuffer" ] && \
    cp "$root/build/fdmsurf_bench_fft_multibuffer" "$stage/bin/" && \
    { strip "$stage/bin/fdmsurf_bench_fft_multibuffer" 2>/dev/null || true; }
# A baseline CLI for before/after runs (run.sh ab), when one was put at .gpu/fdmsurf-base.
[ -x "$root/.gpu/fdmsurf-base" ] && cp "$root/.gpu/fdmsurf-base" "$stage/bin/fdmsurf-base"
libdir=/usr/lib/x86_64-linux-gnu
for lib in libtinygltf.so.2d libstb.so.0 libmeshoptimizer.so.2d libfftw3.so.3 libvulkan.so.1 \
           libVkLayer_khronos_validation.so; do
    cp -L "$libdir/$lib" "$stage/lib/"
done
cp /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json "$stage/layers/"
# libglvnd: downloaded once as the device tool's README says (apt-get download into .gl).
if [ ! -d "$root/.gl" ] || [ -z "$(ls "$root/.gl"/*.deb 2>/dev/null)" ]; then
    mkdir -p "$root/.gl" /tmp/amd64/partial
    o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
    apt-get $o update >/dev/null
    (cd "$root/.gl" && apt-get $o download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi
cp "$root/.gl"/libglvnd0_*.deb "$root/.gl"/libglx0_*.deb "$root/.gl"/libegl1_*.deb "$stage/debs/"
for s in 1crn.pdb 4hhb.pdb 1aon.pdb.gz 4yvs.cif.gz; do cp "$shared/data/$s" "$stage/data/"; done
for s in 1crn 4hhb; do
    [ -f "$stage/ref/$s-lvp.ply" ] || "$root/build/fdmsurf" "$shared/data/$s.pdb" -o "$stage/ref/$s-lvp.ply" --quiet
done
rm -f "$stage/ref/1aon-lvp.ply"
git -C "$root" rev-parse HEAD > "$stage/commit"
git -C "$root" status --short --untracked-files=no | sed 's/^/dirty: /' >> "$stage/commit"
tar czf "$root/.gpu/bundle.tar.gz" -C "$stage" .
ls -la "$root/.gpu/bundle.tar.gz"
