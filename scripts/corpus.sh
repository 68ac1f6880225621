#!/usr/bin/env bash
# The corpus check (docs/structure.md, "A corpus of real files"): installs the Debian packages
# that ship structure files (test and example data of PyMOL, FreeSASA, Biopython, OpenMM,
# PDBFixer, CSB, APBS, garlic, Raster3D, MUSTANG, RDKit and GROMACS) and MDAnalysis as a third
# reader, then runs scripts/corpus.py: the CLI over every file (a closed surface, or a refusal
# for a file without atoms) and fdmsurf's reading of each against gemmi, Biopython and
# MDAnalysis. Needs the build of scripts/setup-debian.sh (FDMSURF_BUILD_DIR, default build).
# Extra arguments go to scripts/corpus.py (e.g. --markdown corpus.md).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

packages=(pymol-data freesasa python-biopython-doc python3-simtk python3-pdbfixer python3-csb
          apbs garlic raster3d-doc mustang rdkit-data gromacs-data
          python3-gemmi python3-biopython python3-mdanalysis python3-scipy)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
    sudo=""
    ((EUID == 0)) || sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
        "${missing[@]}" >/dev/null
fi
export FDMSURF_BUILD_DIR=${FDMSURF_BUILD_DIR:-build}
exec /usr/bin/python3 -W ignore scripts/corpus.py "$@"
