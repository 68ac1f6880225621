#!/usr/bin/env bash
# The Debian package as a user meets it: builds fdmsurf_VERSION_ARCH.deb in build-deb
# (scripts/build-deb.sh: CPack's DEB generator, cmake/FdmsurfPackaging.cmake), checks its control
# fields and contents, installs it with `apt-get install ./fdmsurf_*.deb`, then uses the installed
# files alone: fdmsurf and msms from PATH, the man page, bash completion through bash-completion's
# loader, the message without a Vulkan driver, examples/embed built against /usr with
# find_package(fdmsurf), the module imported by /usr/bin/python3; then purges it and checks that
# none of the paths `dpkg -L` listed is left (folders other packages own aside).
#
# As root, after scripts/setup-debian.sh (scripts/test.sh), from anywhere:
# ./scripts/package-test.sh. Refuses to run where fdmsurf is installed already (a package, or a
# `cmake --install` under /usr/local that would shadow it). The package is purged on the way out,
# whatever happens. Environment: FDMSURF_DEB_BUILD_DIR (default build-deb).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
repo=$(pwd)
work=$(mktemp -d)
installed=0
cleanup() {
    if ((installed)); then
        DEBIAN_FRONTEND=noninteractive apt-get purge -y fdmsurf >/dev/null 2>&1 || true
    fi
    rm -rf "$work"
}
trap cleanup EXIT

script=package-test.sh
source scripts/lib/steps.sh  # fail, step

((EUID == 0)) || fail "run as root (apt-get install and purge)"
if dpkg-query -W -f='${db:Status-Status}' fdmsurf 2>/dev/null | grep -qv not-installed; then
    fail "the fdmsurf package is installed already: apt-get purge fdmsurf first"
fi
for path in /usr/local/bin/fdmsurf /usr/local/lib/cmake/fdmsurf \
    /usr/local/lib/python3*/dist-packages/fdmsurf; do
    [[ ! -e $path ]] || fail "$path (a cmake --install) would shadow the package's files"
done

# Build: scripts/build-deb.sh (the prefix /usr, CPack).
version=$(sed -n 's/^project(fdmsurf VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
start=$SECONDS
deb=$(./scripts/build-deb.sh) || fail "scripts/build-deb.sh failed (above)"
echo "package-test.sh: build-deb.sh ($((SECONDS - start)) s)"
echo "package-test.sh: $(basename "$deb"): $(du -h "$deb" | cut -f1)"

# Control fields and contents.
control=$(dpkg-deb -f "$deb")
echo "$control" | grep -E '^(Package|Version|Architecture|Depends|Recommends|Suggests):' |
    sed 's/^/  /'
depends=$(dpkg-deb -f "$deb" Depends)
for package in libvulkan1 libc6 libstdc++6; do
    [[ ", $depends," == *", $package"[\ ,]* ]] || fail "Depends lacks $package: $depends"
done
for package in mesa-vulkan-drivers python3-numpy; do
    [[ $(dpkg-deb -f "$deb" Recommends) == *"$package"* ]] || fail "Recommends lacks $package"
done
dpkg-deb -c "$deb" | awk '{print $6 ($7 ? " " $7 " " $8 : "")}' >"$work/contents"
multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH)
ext=$(/usr/bin/python3 -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
for path in ./usr/bin/fdmsurf "./usr/bin/msms -> fdmsurf" "./usr/lib/$multiarch/libfdmsurf.a" \
    ./usr/include/fdmsurf/fdmsurf.hpp "./usr/lib/$multiarch/cmake/fdmsurf/fdmsurfConfig.cmake" \
    "./usr/lib/$multiarch/cmake/fdmsurf/fdmsurfTargets.cmake" \
    "./usr/lib/python3/dist-packages/fdmsurf/_fdmsurf$ext" \
    ./usr/lib/python3/dist-packages/fdmsurf/__init__.pyi \
    ./usr/lib/python3/dist-packages/fdmsurf/batch.py \
    ./usr/lib/python3/dist-packages/fdmsurf/trajectory.py \
    ./usr/lib/python3/dist-packages/fdmsurf/_objects.py \
    ./usr/share/man/man1/fdmsurf.1.gz "./usr/share/man/man1/msms.1.gz -> fdmsurf.1.gz" \
    ./usr/share/bash-completion/completions/fdmsurf \
    "./usr/share/bash-completion/completions/msms -> fdmsurf"; do
    grep -qxF "$path" "$work/contents" || fail "the package lacks $path"
done

# Install, as a user does.
installed=1
step install env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "$deb"
dpkg -L fdmsurf >"$work/files"
echo "package-test.sh: installed $(wc -l <"$work/files") paths"

cd "$work"
[[ $(command -v fdmsurf) == /usr/bin/fdmsurf ]] || fail "fdmsurf on PATH is $(command -v fdmsurf)"
[[ $(fdmsurf --version | head -1) == "fdmsurf $version" ]] ||
    fail "fdmsurf --version: $(fdmsurf --version)"
fdmsurf --version | sed 's/^/  /'
step surface fdmsurf "$repo/tests/data/1crn.pdb" -o x.ply
[[ $(head -c 3 x.ply) == ply ]] || fail "fdmsurf tests/data/1crn.pdb -o x.ply wrote no PLY"
grep -E 'vertices|closed' "$work/surface.log" | sed 's/^/  /' | head -2
step msms msms -if "$repo/tests/data/1crn.xyzrn" -of 1crn -af 1crn -probe_radius 1.5
[[ -s 1crn.vert && -s 1crn.face && -s 1crn.area ]] || fail "msms wrote no .vert/.face/.area"
zcat /usr/share/man/man1/fdmsurf.1.gz | grep -q -- 'list\\-devices' ||
    fail "the man page lacks --list-devices"
if command -v man >/dev/null; then
    for page in fdmsurf msms; do  # man -w follows msms.1.gz, the link, to fdmsurf.1.gz
        [[ $(man -w $page) == /usr/share/man/man1/fdmsurf.1.gz ]] ||
            fail "man -w $page: $(man -w $page)"
    done
fi
# bash-completion's loader finds the completion for both names, and it completes.
for command in fdmsurf msms; do
    completed=$(bash -c 'source /usr/share/bash-completion/bash_completion
        _completion_loader "$1"; complete -p "$1" >/dev/null &&
        if [[ $1 == msms ]]; then COMP_WORDS=(msms -surface ""); else
            COMP_WORDS=(fdmsurf --surface ""); fi &&
        COMP_CWORD=2 && _fdmsurf && echo "${COMPREPLY[*]}"' bash "$command") ||
        fail "bash-completion does not load the completion of $command"
    [[ $completed == "ses vdw sas" || $completed == "tses ses ases" ]] ||
        fail "the completion of $command offers '$completed'"
done
# No Vulkan driver: the loader pointed at none; the program says what to install.
no_driver=(env VK_ICD_FILENAMES="$work/none.json" VK_DRIVER_FILES="$work/none.json")
listed=$("${no_driver[@]}" fdmsurf --list-devices) ||
    fail "fdmsurf --list-devices without a driver failed"
[[ $listed == *"install a Vulkan driver"*mesa-vulkan-drivers* ]] ||
    fail "--list-devices without a driver says: $listed"
status=0
"${no_driver[@]}" fdmsurf "$repo/tests/data/1crn.pdb" -o y.ply 2>"$work/no-driver.log" || status=$?
((status == 4)) && grep -q mesa-vulkan-drivers "$work/no-driver.log" ||
    fail "a surface without a driver: exit $status, $(cat "$work/no-driver.log")"
echo "package-test.sh: without a driver: $listed"
# examples/embed against the installed package: find_package(fdmsurf) from /usr alone.
step embed-configure cmake -S "$repo/examples/embed" -B "$work/embed" -G Ninja \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
    -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF
found=$(sed -n 's/^fdmsurf_DIR:PATH=//p' "$work/embed/CMakeCache.txt")
[[ $found == /usr/lib/$multiarch/cmake/fdmsurf ]] || fail "examples/embed found fdmsurf in '$found'"
step embed-build cmake --build "$work/embed"
step embed-run "$work/embed/fdmsurf_embed" "$repo/tests/data/3al1.pdb" "$work/3al1.png" --validation
[[ $(head -c 8 "$work/3al1.png" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] ||
    fail "examples/embed wrote no PNG"
# The module, with Debian's python3.
status=0
/usr/bin/python3 - "$repo/tests/data/1crn.pdb" "$version" <<'EOF' || status=$?
import sys
import fdmsurf
path, version = sys.argv[1:]
assert fdmsurf.__file__ == "/usr/lib/python3/dist-packages/fdmsurf/__init__.py", fdmsurf.__file__
assert fdmsurf.__version__ == version
r = fdmsurf.surface(path, spacing=1.0)
assert r.closed_manifold, r
print(f"  /usr/bin/python3: {fdmsurf.__file__}: {r}")
EOF
((status == 0)) || fail "/usr/bin/python3 cannot use the installed module"
step batch-help /usr/bin/python3 -m fdmsurf.batch --help
cd "$repo"

# Purge, and nothing of it is left: each listed path is gone, or a folder another package owns.
step purge env DEBIAN_FRONTEND=noninteractive apt-get purge -y fdmsurf
installed=0
[[ -z $(dpkg-query -W -f='${db:Status-Status}' fdmsurf 2>/dev/null) ]] ||
    fail "dpkg still knows fdmsurf after the purge"
left=()
while IFS= read -r path; do
    [[ $path == /. ]] && continue
    if [[ -e $path || -L $path ]]; then
        [[ -d $path && ! -L $path ]] && dpkg-query -S "$path" >/dev/null 2>&1 && continue
        left+=("$path")
    fi
done <"$work/files"
((${#left[@]} == 0)) || fail "the purge left: ${left[*]}"
echo "package-test.sh: $(basename "$deb") built, installed, used from /usr and purged; nothing left"
