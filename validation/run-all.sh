#!/usr/bin/env bash
# Regenerates the committed validation results from one commit's binaries (issue 14, section 3).
#
#   validation/run-all.sh [full|quick] [--dry-run] [--only GROUP ...]
#
#   full   (default) every documented command of every case, in place: the results/ of
#          nonlinear/, finite_step/ and weighting/, their summaries and figures. Hours on a 2-core
#          machine (the per-run wall times are in each case's results/runtimes.csv).
#   quick  a subset (estimated 10-15 minutes on 2 idle cores from the per-run wall times; not yet
#          timed as a whole) that reruns the headline runs in place and
#          checks them against the documented bands of validation/bands.csv
#          (validation/check_bands.py). A slow tier: not part of .ci/run.
#   --dry-run  print the commands only.
#   --only GROUP ...  (full) only these groups, in this order: nonlinear (MB/EH, the n = 16 NEMD
#          points, the two engines), seeds (independent repeats), nemd32 (Tables 5-7, all 27
#          points), size (box sizes at n = 16 and n = 32), timestep (Table 8 / Appendix B),
#          finite_step, weighting, sdpd[:STEP,...] (cs couette diffusion schmidt peer analyse,
#          all by default), repulsion[:STEP,...] (validation/weighting/repulsion.sh
#          steps, all by default); the summaries of the touched cases run after them.
#
# Before running it builds the release binary and the LAMMPS shim from the working tree and
# appends one block to validation/BINARIES: commit, the code id (the git tree made of src/,
# capi/, lammps-plugin/, examples/, Cargo.toml and Cargo.lock, what the binaries and the scripts
# the cases copy are built from: commits that differ only in validation/ or the documents share
# it, so a full tier run in parts over several sessions is still one code's), dirty flag, date,
# host, tier and groups. It refuses a tree with uncommitted changes outside validation/ (the binaries would not
# be a commit's) unless FORCE=1. Runs are
# deterministic: with the same commit's binaries the rerun results equal the committed ones bit
# for bit wherever the run and its thread count are the same, so `git diff --stat validation/`
# after a run shows what a change of code moved.
# Environment: PAR [2] (runs at a time where a case allows it), FORCE [0].
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
mode=full; dry=0; only=()
while [ $# -gt 0 ]; do
    case "$1" in
        full|quick) mode=$1 ;;
        --dry-run) dry=1 ;;
        --only) shift; while [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; do only+=("$1"); shift; done; continue ;;
        *) sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 2 ;;
    esac
    shift
done
export PAR="${PAR:-2}"
v=validation

# run [VAR=value ...] command args...: print, then run unless --dry-run; the wall time goes to
# the log line.
run() {
    echo "+ $*"
    [ "$dry" = 1 ] && return 0
    local t0=$SECONDS
    env "$@"
    echo "  ($((SECONDS - t0)) s)"
}
want() { [ ${#only[@]} -eq 0 ] && return 0; local g; for g in "${only[@]}"; do [ "${g%%:*}" = "$1" ] && return 0; done; return 1; }
# steps_of GROUP: the comma-separated steps after "GROUP:" in --only (empty: all).
steps_of() { local g; for g in "${only[@]}"; do [ "${g%%:*}" = "$1" ] && [ "$g" != "$1" ] && echo "${g#*:}" | tr , ' '; done; return 0; }
for g in "${only[@]}"; do
    case "${g%%:*}" in nonlinear|seeds|nemd32|size|timestep|finite_step|weighting|sdpd|repulsion) ;;
    *) echo "run-all.sh: unknown group '$g'" >&2; exit 2 ;; esac
done

# --- binaries ---------------------------------------------------------------------------------
if [ "$dry" = 0 ]; then
    if [ -n "$(git status --porcelain -- . ':!validation' 2>/dev/null)" ] && [ "${FORCE:-0}" != 1 ]; then
        echo "run-all.sh: uncommitted changes outside validation/ (the binaries would not be a commit's):" >&2
        git status --short -- . ':!validation' >&2
        echo "commit them, or FORCE=1" >&2
        exit 1
    fi
fi
run cargo build --release --bin dpdnl
run bash lammps-plugin/build.sh
if [ "$dry" = 0 ]; then
    dirty=$([ -n "$(git status --porcelain -- . ':!validation')" ] && echo yes || echo no)
    code=$(git ls-tree HEAD -- src capi lammps-plugin examples Cargo.toml Cargo.lock | git mktree)
    { echo; echo "commit $(git rev-parse HEAD)"; echo "code id (tree of src capi lammps-plugin examples Cargo.*) $code"
      echo "dirty (outside validation/) $dirty"
      echo "date $(date -u +%Y-%m-%dT%H:%M:%SZ)"; echo "host $(uname -n), $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
      echo "tier $mode${only[*]:+, groups ${only[*]}}"; echo "binaries ${CARGO_TARGET_DIR:-target}/release/dpdnl, build/lmp_dpdnl"; } >> "$v/BINARIES"
fi

# --- quick ------------------------------------------------------------------------------------
if [ "$mode" = quick ]; then
    run SCHEMES="ref dot_plain twostep_dot" $v/nonlinear/run.sh eq
    run POINTS="ref:0.05" $v/nonlinear/run.sh nemd
    run A=14.72 CASES="t3:1.0:10:0.5:60000" RATES="0.2" LMP_RATES="0.2" EXT_RATES="" $v/weighting/run.sh couette
    run A=0.9324 CASES="t5a:2.5:49:0.0700:20000" RATES="1" LMP_RATES="" EXT_RATES="" $v/weighting/run.sh couette
    run python3 $v/check_bands.py quick
    exit 0
fi

# --- full -------------------------------------------------------------------------------------
nl=$v/nonlinear/run.sh
if want nonlinear; then
    # The eq runs (one at a time in run.sh) as two concurrent lists of about equal length.
    ( run SCHEMES="ref cross dot_plain" $nl eq && run N=6000 STEPS=100000 SUFFIX=_N6000 SCHEMES="ref" $nl eq ) & bg=$!
    run SCHEMES="dot_corrected twostep_dot" $nl eq
    run N=6000 STEPS=100000 SUFFIX=_N6000 SCHEMES="cross" $nl eq
    wait "$bg"
    # Tables 3-4 (n = 16), Table 2's N-EQ column (0.01), Table 8's delta t = 1e-3 row (0.2).
    run PAR="$PAR" POINTS="ref:0.01 ref:0.025 ref:0.05 ref:0.075 ref:0.1 ref:0.15 ref:0.2
        cross:0.01 cross:0.025 cross:0.05 cross:0.075 cross:0.1 cross:0.15 cross:0.2
        dot_corrected:0.01 dot_corrected:0.05 dot_corrected:0.2 twostep_dot:0.01 twostep_dot:0.05
        twostep_dot:0.2" $nl nemd
    run $nl engines
fi
if want seeds; then
    # Independent repeats (pair seeds 1-4): Table 2's N-EQ column, and Ref at Pi = 13.68 for
    # Appendix B's delta t comparison.
    run PAR="$PAR" SEEDS="1 2 3 4" POINTS="ref:0.01 cross:0.01 dot_corrected:0.01 twostep_dot:0.01 ref:0.2" $nl nemd
fi
if want nemd32; then
    # Every point of the paper's Tables 5-7 (the copy in validation/reference/).
    # shellcheck source=nonlinear/paper.sh
    p32=""; ref=$v/reference; . $v/nonlinear/paper.sh
    for s in ref dot_corrected twostep_dot; do for d in $(paper_dps $s 32); do p32+=" $s:$d"; done; done
    run PAR="$PAR" DENSITY=32 L=3 POINTS="$p32" $nl nemd
fi
if want size; then
    run SIZES="3 4" $nl size
    run SIZES="5 6" STEPS=80000 FROM=40000 $nl size
    # Issue 31: Pi = 13.68 (dp 0.2) in the L = 5 box with pair seeds: Dot-corrected (its seed
    # mean is bands.csv's nemd_dot_13.68), Two-step-dot and Ref.
    run PAR="$PAR" SIZES=5 STEPS=80000 FROM=40000 SIZE_POINTS="dot_corrected:0.2" SEEDS="1 2 3 4" $nl size
    run PAR="$PAR" SIZES=5 STEPS=80000 FROM=40000 SIZE_POINTS="twostep_dot:0.2" SEEDS="1 2" $nl size
    run SIZES=5 STEPS=80000 FROM=40000 SIZE_POINTS="ref:0.2" SEEDS="1" $nl size
    run PAR="$PAR" SIZES=6 STEPS=100000 FROM=60000 SIZE_POINTS="dot_corrected:0.2" SEEDS="1 2" $nl size
    # n = 32: L = 4 against the L = 3 of nemd32 (the same points) at a low and the highest stress.
    run PAR="$PAR" DENSITY=32 SIZES="4" SIZE_POINTS="ref:0.075 dot_corrected:0.55" $nl size
fi
if want timestep; then
    # Table 8 (delta t = 1e-3 is the nonlinear group's 0.2 point); Ref at 1e-4 for Appendix B.
    # The three 1e-4 runs take 25 min each here: two of them one after the other in the
    # background, the third and the shorter delta t beside them (two runs at a time in all).
    run PAR=1 DT=0.0001 POINTS="ref:0.2 dot_corrected:0.2" $nl nemd & bg=$!
    run PAR=1 DT=0.0001 POINTS="twostep_dot:0.2" $nl nemd
    for dt in 0.0005 0.005 0.01 0.05; do
        run PAR=1 DT=$dt POINTS="dot_corrected:0.2 twostep_dot:0.2" $nl nemd
    done
    wait "$bg" # (its status: a failed background run fails the tier)
fi
if want nonlinear || want seeds || want nemd32 || want size || want timestep; then
    run $v/nonlinear/summary.sh
fi
if want finite_step; then
    fs=$v/finite_step
    run $fs/sweep.sh $fs/results/sweep_300tau.csv
    run FRACS="0.25 0.3 0.4 0.45" $fs/sweep.sh $fs/results/sweep_300tau_extra.csv
    run DENSITIES="1 4" FRACS="0.01 0.02 0.05" TIME=3000 $fs/sweep.sh $fs/results/sweep_3000tau.csv
    run INTEGRATOR=nve DENSITIES="1 4 16" FRACS="0.02 0.05 0.1 0.2 0.35 0.5" TIME=300 $fs/sweep.sh $fs/results/vv_sweep_300tau.csv
    run INTEGRATOR=nve DENSITIES="1" FRACS="0.005 0.01" TIME=1500 $fs/sweep.sh $fs/results/vv_sweep_fine.csv
    run INTEGRATOR=nve DENSITIES="4" FRACS="0.01" TIME=1000 $fs/sweep.sh $fs/work_n4.csv
    if [ "$dry" = 0 ]; then tail -n +2 $fs/work_n4.csv >> $fs/results/vv_sweep_fine.csv; rm -f $fs/work_n4.csv; fi
    run $fs/vv_nonlinear.sh $fs/results/vv_nonlinear.csv
    run $fs/vv_weighting.sh $fs/results/vv_weighting.csv
    run cargo run --release --example finite_step_plot -- $fs/results/t_vs_dt $fs/results/sweep_300tau.csv \
        $fs/results/sweep_300tau_extra.csv $fs/results/sweep_3000tau.csv
    run python3 $fs/vv_tables.py
    run python3 $v/sync_tables.py $fs/README.md
fi
if want weighting; then
    w=$v/weighting/run.sh
    run SIZES="1600 400" $w diffusion
    run $w viscosity
    run DT=0.001 STEPS=50000 EQ=2000 CASES=t3:1.0:10:0.5 $w viscosity
    run $w couette
fi
if want sdpd; then
    w=$v/weighting/run.sh
    # sdpd[:STEP,...]: only these steps (cs couette diffusion schmidt peer analyse; all by default).
    ssteps=" $(steps_of sdpd) "; [ "$ssteps" = "  " ] && ssteps=" cs couette diffusion schmidt peer analyse "
    sstep() { [[ "$ssteps" == *" $1 "* ]]; }
    if sstep cs; then run $w sdpd-cs; fi
    if sstep couette; then
        run SET=all $w sdpd-couette
        run ENGINE=standalone CASES="t2prop50:2.5:p0.5:50:3000" RATES=0.2 $w sdpd-couette
        run ENGINE=standalone CASES="t3lucy:1.0:lucy:10:12000:1000:300" RATES=0.2 $w sdpd-couette
    fi
    if sstep diffusion; then run $w sdpd-diffusion; fi
    if sstep schmidt; then run DPD_COUETTE=0 SC0S="10 100 1000" $w sdpd-schmidt; fi
    if sstep peer; then run $w sdpd-peer; fi
    if sstep analyse; then run $w sdpd-analyse; fi
fi
if want repulsion; then
    # Named steps get the summary after them (once, also when it is named).
    rsteps=$(steps_of repulsion); [ -n "$rsteps" ] && rsteps="${rsteps//summary/} summary"
    # shellcheck disable=SC2086
    run $v/weighting/repulsion.sh $rsteps
fi
if want weighting || want sdpd || want repulsion; then
    run $v/weighting/summary.sh
fi
run python3 $v/check_bands.py full
