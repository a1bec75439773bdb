#!/usr/bin/env bash
# One command for the LAMMPS-side tests: build build/lmp_dpdnl, then run them.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$HERE/../build.sh"
exec python3 "$HERE/run_tests.py" "$@"
