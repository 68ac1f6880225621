#!/usr/bin/env bash
# Regenerates the accuracy tables of docs/accuracy.md: fdmsurf (fdm, fdm + refine, edt, paper
# settings) against the analytical SES of ../shared/reference/ses, on 1CRN and 4HHB at 1.0, 0.5
# and 0.25 Å, with Mol* measured beside it when bench/.cache/molstar is installed (bench/run.sh
# installs it). Arguments go to scripts/accuracy.py (--help lists them).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
extra=()
[[ -d bench/.cache/molstar/node_modules ]] && command -v node > /dev/null && extra=(--molstar)
exec python3 scripts/accuracy.py "${extra[@]}" "$@"
