#!/usr/bin/env bash
# The Python package's tests on a fresh Debian 12 machine with Rust installed: builds the dpdnl
# CLI (the tests compare the package with it), creates the venv .venv-python at the repository
# root, installs the package the way the README says (pip install ./python; pip fetches maturin
# as the build backend), runs pytest and the example. Fails loudly on the first error.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

command -v cargo >/dev/null || { echo "ERROR: cargo not found (install Rust with rustup)"; exit 1; }
command -v python3 >/dev/null || { echo "ERROR: python3 not found"; exit 1; }
if ! python3 -c 'import ensurepip, venv' 2>/dev/null; then
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
  echo "== apt-get install python3-venv"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq python3-venv
fi

echo "== cargo build --release --bin dpdnl (the CLI the tests compare with)"
cargo build --release --bin dpdnl
TARGET="${CARGO_TARGET_DIR:-$ROOT/target}"
export DPDNL_BIN="$TARGET/release/dpdnl"
export DPDNL_REQUIRE_CLI=1
[ -x "$DPDNL_BIN" ] || { echo "ERROR: $DPDNL_BIN was not built"; exit 1; }

VENV="$ROOT/.venv-python"
if [ ! -x "$VENV/bin/python" ]; then
  echo "== python3 -m venv .venv-python"
  python3 -m venv "$VENV"
fi
echo "== pip install ./python pytest pytest-timeout numpy"
"$VENV/bin/pip" install --quiet --disable-pip-version-check ./python pytest pytest-timeout numpy

echo "== pytest python/tests"
# From python/, so that 'import dpdnl' is the installed package (python/python/dpdnl is the
# source of its pure-Python part, not importable from here).
# Every test has a time limit (pytest-timeout, 300 s; the whole suite takes about 15 s): a test
# that hangs fails with its stack instead of holding the run.
(cd python && "$VENV/bin/python" -m pytest -q -p no:cacheprovider --timeout=300 tests)

echo "== python/examples/paper_figures.py (short run)"
OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
MPLBACKEND=Agg "$VENV/bin/python" python/examples/paper_figures.py "$OUT" --steps 4000
echo "== python tests passed"
