#!/usr/bin/env bash
# Finite-step paper, Fig. 1 analogue: equilibrium temperature of the 2-D ideal DPD fluid under the
# Euler integrator (fix nve/euler), gamma = sigma = 1 (kT0 = 0.5), w_D = (1 - r)^2 (weight 2),
# N = 1600 atoms, for densities n and steps dt = frac * dt_c (eq. 25), measured T/T0 against eq. 22.
# Usage: validation/finite_step/sweep.sh [OUT.csv]   (from the repository root; ~20 min on 2 cores)
# Environment: DPDNL (binary, default target/release/dpdnl), DENSITIES, FRACS, TIME (tau per run),
# INTEGRATOR (nve/euler, the paper's scheme, by default; nve: velocity-Verlet, issue 14 section 4,
# where eq22 is still printed for comparison though it is the Euler prediction).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
dpdnl=${DPDNL:-$root/target/release/dpdnl}
out=${1:-$here/sweep.csv}
densities=${DENSITIES:-"1 4 16"}
fracs=${FRACS:-"0.02 0.05 0.1 0.2 0.35 0.5 0.7"}
total=${TIME:-300}
integrator=${INTEGRATOR:-nve/euler}
case "$integrator" in nve/euler|nve) ;; *) echo "INTEGRATOR must be nve/euler or nve" >&2; exit 2;; esac
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "n,dt,dt_over_dtc,gamma_dt,neighbours,N,steps,T_over_T0,err,eq22,seconds" > "$out"
for n in $densities; do
  dtc=$("$dpdnl" theory --gamma 1 --s 2 --density "$n" --rc 1 --kt 0.5 --dim 2 --dt 0.001 | awk '/^dt_c =/{print $3}')
  L=$(python3 -c "print(round((1600/$n)**0.5, 6))")
  for f in $fracs; do
    dt=$(python3 -c "print(f'{$f*$dtc:.6g}')")
    pred=$("$dpdnl" theory --gamma 1 --s 2 --density "$n" --rc 1 --kt 0.5 --dim 2 --dt "$dt" | awk '/^T_eq\/T0 =/{print $3}')
    steps=$(python3 -c "print(round($total/$dt))")
    every=$(python3 -c "print(max(1, round(0.5/$dt)))")
    sed -e "s/^run .*/run \${steps}/" -e "s/^thermo  .*/thermo $every/" \
        -e "s/^variable        steps .*/variable steps equal $steps/" \
        -e "s|^fix             1 all nve/euler|fix             1 all $integrator|" \
        "$root/examples/finite_step/in.euler2d" > "$work/in.sweep"
    t0=$(date +%s.%N)
    if "$dpdnl" run "$work/in.sweep" -var dt "$dt" -var n "$n" -var L "$L" -log none \
        > "$work/out.txt" 2> "$work/err.txt"; then
      read -r T E < <(awk '/^ *Temp = /{print $3, $5}' "$work/out.txt")
    elif grep -q 'blow-up at step' "$work/err.txt"; then
      # The engine's blow-up check stopped a run-away point: T is recorded as inf.
      T=inf; E=nan
    else
      cat "$work/err.txt" >&2; exit 1
    fi
    t1=$(date +%s.%N)
    N=$(python3 -c "print(round($n*$L*$L))")
    python3 - "$n" "$dt" "$f" "$N" "$steps" "$T" "$E" "$pred" "$t0" "$t1" >> "$out" <<'PY'
import math, sys
n, dt, f, N, steps, T, E, pred, t0, t1 = sys.argv[1:]
n, dt, T, E, t0, t1 = float(n), float(dt), float(T), float(E), float(t0), float(t1)
nb = math.pi * n  # neighbours within r_c = 1 in 2-D
print(f"{n:g},{dt:g},{f},{dt:g},{nb:.3f},{N},{steps},{T/0.5:.5f},{E/0.5:.5f},{float(pred):.5f},{t1-t0:.1f}")
PY
    tail -1 "$out"
  done
done
