#!/usr/bin/env bash
# Install what the tests need on a fresh Debian 12 machine, then run every test tier that is
# not marked slow: Rust unit/integration tests, formatting and lints, the committed C header
# check, and the LAMMPS shim's tests against Debian's LAMMPS. Fails loudly on the first error.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
need_pkgs=()
for p in lammps liblammps-dev libfmt-dev openmpi-bin libopenmpi-dev make g++ python3; do
  dpkg -s "$p" >/dev/null 2>&1 || need_pkgs+=("$p")
done
if [ "${#need_pkgs[@]}" -gt 0 ]; then
  echo "== apt-get install ${need_pkgs[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_pkgs[@]}"
fi
command -v cargo >/dev/null || { echo "ERROR: cargo not found (install Rust with rustup)"; exit 1; }
rustup component list --installed 2>/dev/null | grep -q clippy || rustup component add clippy rustfmt || true

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy -D warnings"
cargo clippy --workspace --all-targets -- -D warnings
echo "== build build/lmp_dpdnl (Debian LAMMPS + this project's styles)"
bash lammps-plugin/build.sh
echo "== cargo test (workspace; cross-engine golden tests require build/lmp_dpdnl)"
DPDNL_REQUIRE_LAMMPS=1 cargo test --workspace
echo "== LAMMPS shim tests (newton on/off, 1 vs 2 ranks, restart, errors)"
bash lammps-plugin/tests/run.sh
echo "== all tests passed"
