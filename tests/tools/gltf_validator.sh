#!/usr/bin/env bash
# ctest GltfValidator: the fdmsurf program writes GLB files of crambin (plain; coloured with
# atoms and three properties; an open patch of 3AL1) and the Khronos glTF validator (npm
# gltf-validator, through validate_glb.js) must report no errors in any of them.
#   gltf_validator.sh FDMSURF DATA_DIR MODULE_DIR WORK_DIR
# Exit 77 (ctest SKIP_RETURN_CODE) when node or the validator is missing (scripts/test.sh
# installs it into MODULE_DIR when npm is there) or when there is no Vulkan device;
# FDMSURF_REQUIRE_DEVICE=1 makes the last a failure.
set -uo pipefail

fdmsurf=$1 data=$2 modules=$3 work=$4
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

if ! command -v node >/dev/null 2>&1; then
    echo "SKIP: node is not installed (Debian: apt-get install nodejs npm)"
    exit 77
fi
if [[ ! -d $modules/node_modules/gltf-validator ]]; then
    echo "SKIP: the glTF validator is not installed in $modules; scripts/test.sh installs it," \
         "or: npm install --prefix '$modules' gltf-validator"
    exit 77
fi

rm -rf "$work"
mkdir -p "$work"
runs=(
    "plain.glb|$data/1crn.pdb"
    "attributes.glb|$data/1crn.pdb --color chain --properties coulombic,mean_curvature,shape_index"
    "patch.glb|$data/3al1.pdb --patch A --color element --spacing 0.6"
)
files=()
for run in "${runs[@]}"; do
    name=${run%%|*}
    read -r -a args <<<"${run#*|}"
    "$fdmsurf" "${args[@]}" -o "$work/$name" --quiet 2>"$work/stderr"
    status=$?
    if ((status == 4)) && [[ ${FDMSURF_REQUIRE_DEVICE:-} != 1 ]]; then
        echo "SKIP: no usable Vulkan device: $(cat "$work/stderr")"
        exit 77
    fi
    if ((status != 0)); then
        echo "FAIL: fdmsurf ${args[*]} -o $work/$name exited with $status:"
        cat "$work/stderr"
        exit 1
    fi
    files+=("$work/$name")
done

node "$here/validate_glb.js" "$modules" "${files[@]}"
