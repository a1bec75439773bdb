#!/usr/bin/env bash
# Build build/lmp_dpdnl: the Rust C ABI (release, static) then the LAMMPS styles and launcher.
# Idempotent: cargo and make only redo what changed.
# Needs (Debian 12): apt-get install -y lammps liblammps-dev libfmt-dev openmpi-bin make g++
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
cargo build --release -p dpdnl-capi --target-dir "$ROOT/build/cargo"
make -C "$ROOT/lammps-plugin" -j"${JOBS:-2}" BUILD="$ROOT/build" CXX="${CXX:-mpicxx}"
echo "built $ROOT/build/lmp_dpdnl"
