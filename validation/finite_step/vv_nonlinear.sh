#!/usr/bin/env bash
# Issue 14, section 4: the finite-step temperature of velocity-Verlet (fix nve) on the non-linear
# paper's fluid (3-D, n = 16, kT0 = 0.1, gamma0 = 5, r_c = 1; examples/nonlinear/common.in), for
# each friction/noise model, at several dt. T/T0 is the block-averaged mean of the run's thermo
# Temp after the first EQ time units (the `dpdnl run` summary of the second half).
# Usage: validation/finite_step/vv_nonlinear.sh [OUT.csv]   (from the repository root)
# Environment: DPDNL (binary), N (atoms, default 2000), DTS, MODELS, TIME (tau per run, default 6).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
dpdnl=${DPDNL:-$root/target/release/dpdnl}
# Absolute: the runs below work in examples/nonlinear/ (a relative OUT.csv is the caller's).
out=$(realpath -m "${1:-$here/vv_nonlinear.csv}")
natoms=${N:-2000}
dts=${DTS:-"0.001 0.003 0.01"}
models=${MODELS:-"ref dot_plain dot_corrected twostep_dot"}
total=${TIME:-6}
dtc=$("$dpdnl" theory --gamma 5 --s 2 --density 16 --rc 1 --kt 0.1 --dim 3 --dt 0.001 | awk '/^dt_c =/{print $3}')
echo "model,dt,dt_over_dtc,N,steps,T_over_T0,err,eq22_euler,seconds" > "$out"
cd "$root/examples/nonlinear"
for m in $models; do
  for dt in $dts; do
    steps=$(python3 -c "print(max(6000, round($total/$dt)))")
    pred=$("$dpdnl" theory --gamma 5 --s 2 --density 16 --rc 1 --kt 0.1 --dim 3 --dt "$dt" | awk '/^T_eq\/T0 =/{print $3}')
    t0=$(date +%s.%N)
    o=$("$dpdnl" run "in.$m" -var N "$natoms" -var steps "$steps" -var dt "$dt" -log none)
    t1=$(date +%s.%N)
    read -r T E < <(echo "$o" | awk '/^ *Temp = /{print $3, $5}')
    python3 - "$m" "$dt" "$dtc" "$natoms" "$steps" "$T" "$E" "$pred" "$t0" "$t1" >> "$out" <<'PY'
import sys
m, dt, dtc, natoms, steps, T, E, pred, t0, t1 = sys.argv[1:]
dt, dtc, T, E, t0, t1 = float(dt), float(dtc), float(T), float(E), float(t0), float(t1)
print(f"{m},{dt:g},{dt / dtc:.4f},{natoms},{steps},{T / 0.1:.5f},{E / 0.1:.5f},{float(pred):.5f},{t1 - t0:.1f}")
PY
    tail -1 "$out"
  done
done
