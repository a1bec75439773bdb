#!/usr/bin/env bash
# Issue 14, section 4: velocity-Verlet (fix nve) T/T0 at rest for the weighting paper's Table 3
# fluid (2-D, n = 4, r_c = 1, kT = 1, eta0 = 10, s = 1/2: gamma = 15.67; N = 1600), the fluid of
# its Couette runs, at several dt. T/T0 from the `dpdnl run` summary (second half).
# Usage: validation/finite_step/vv_weighting.sh [OUT.csv]   (from the repository root)
# Environment: DPDNL (binary), DTS, TIME (tau per run, default 200).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
dpdnl=${DPDNL:-$root/target/release/dpdnl}
out=${1:-$here/vv_weighting.csv}
dts=${DTS:-"0.0025 0.005 0.01"}
total=${TIME:-200}
gamma=$(python3 -c "import math; s=0.5; K=(s+1)*(s+2)*(s+3)*(s+4)/(6*math.pi); print(repr(2*4*10*K/(4**2*1**4)))")
dtc=$("$dpdnl" theory --gamma "$gamma" --s 0.5 --density 4 --rc 1 --kt 1 --dim 2 --dt 0.001 | awk '/^dt_c =/{print $3}')
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "dt,dt_over_dtc,gamma,N,steps,T_over_T0,err,eq22_euler,seconds" > "$out"
for dt in $dts; do
  steps=$(python3 -c "print(round($total/$dt))")
  every=$(python3 -c "print(max(1, round(0.5/$dt)))")
  pred=$("$dpdnl" theory --gamma "$gamma" --s 0.5 --density 4 --rc 1 --kt 1 --dim 2 --dt "$dt" | awk '/^T_eq\/T0 =/{print $3}')
  cat > "$work/in.vv" <<IN
units lj
dimension 2
atom_style atomic
region box block 0 20 0 20 -0.5 0.5
create_box 1 box
create_atoms 1 random 1600 8675 box
mass 1 1.0
velocity all create 1.0 4928 mom yes dist gaussian
pair_style dpd/nonlinear 1.0 1.0 34387 weight 0.5
pair_coeff 1 1 0.0 $gamma 0.0
neighbor 0.3 bin
neigh_modify delay 0 every 1 check yes
timestep $dt
fix 1 all nve
fix 2 all enforce2d
thermo $every
run $steps
IN
  t0=$(date +%s.%N)
  o=$("$dpdnl" run "$work/in.vv" -log none)
  t1=$(date +%s.%N)
  read -r T E < <(echo "$o" | awk '/^ *Temp = /{print $3, $5}')
  python3 - "$dt" "$dtc" "$gamma" "$steps" "$T" "$E" "$pred" "$t0" "$t1" >> "$out" <<'PY'
import sys
dt, dtc, gamma, steps, T, E, pred, t0, t1 = sys.argv[1:]
dt, dtc, T, E, t0, t1 = float(dt), float(dtc), float(T), float(E), float(t0), float(t1)
print(f"{dt:g},{dt / dtc:.4f},{float(gamma):.4f},1600,{steps},{T:.5f},{E:.5f},{float(pred):.5f},{t1 - t0:.1f}")
PY
  tail -1 "$out"
done
