#!/usr/bin/env bash
# Beyond the papers (issue 29, part 5): Couette flow of a dilute polymer solution in the
# shear-thinning solvent. Does the non-linear solvent change the polymer's thinning?
#
#   validation/polymer/run.sh            # every point of POINTS, then the summary
#   validation/polymer/run.sh summary    # the table and figure from the finished runs
#
# System: examples/polymer/in.couette_polymer on examples/polymer/solution.data (16 chains of 10
# beads in 1376 solvent beads, n = 3, L = 8; Groot-Warren at kT = 0.1: a = 2.5, gamma0 = 4.5,
# bonds K = 2.5, r0 = 0.7, special_bonds lj 0 1 1; dt = 0.04), sheared by fix deform erate RATE
# remap v. Series: friction none (gamma1 = 0) and cross with gamma1 = 1 (the non-linear
# paper's gamma1 at its kT = 0.1).
# Environment (defaults in brackets):
#   POINTS ["none:0.1 none:0.2 none:0.35 none:0.5 none:1.0 cross:0.1 cross:0.2 cross:0.35 cross:0.5 cross:1.0"]
#   ENGINE [dpdnl]: dpdnl runs the standalone engine DPDNL [target/release/dpdnl] with
#          THREADS [2] (results in results/); lammps runs LMP [build/lmp_dpdnl] (Debian's LAMMPS
#          with the styles; results in results/lammps/, the same runs in the other engine)
#   EQ [5000]  STEPS [20000]  PAR [1] runs at a time
# Raw outputs go to validation/polymer/work/ (ignored); the summary (summary.md, summary.csv,
# flowcurve.png/svg) and the wall time of every run (runtimes.csv) to results/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
cd "$root"
DPDNL="$(realpath "${DPDNL:-${CARGO_TARGET_DIR:-$root/target}/release/dpdnl}")"
ENGINE="${ENGINE:-dpdnl}"
THREADS="${THREADS:-2}"
EQ="${EQ:-5000}"; STEPS="${STEPS:-20000}"; PAR="${PAR:-1}"
POINTS="${POINTS:-none:0.1 none:0.2 none:0.35 none:0.5 none:1.0 cross:0.1 cross:0.2 cross:0.35 cross:0.5 cross:1.0}"
work="$here/work"; res="$here/results"
if [ "$ENGINE" = lammps ]; then work="$here/work/lammps"; res="$here/results/lammps"; fi
mkdir -p "$work" "$res"
[ -f "$res/runtimes.csv" ] || echo "run,engine,atoms,steps,seconds" > "$res/runtimes.csv"

run_point() { # FRICTION RATE
    local fr=$1 rate=$2 g1=0.0
    [ "$fr" = none ] || g1=1.0
    local name="${fr}_r$rate" d="$work/${fr}_r$rate"
    rm -rf "$d"; mkdir -p "$d"
    cp "$root/examples/polymer/in.couette_polymer" "$root/examples/polymer/solution.data" "$d/"
    local t0=$SECONDS vars=(-var friction "$fr" -var gamma1 "$g1" -var rate "$rate" -var eq "$EQ" -var steps "$STEPS")
    if [ "$ENGINE" = lammps ]; then
        local lmp; lmp="$(realpath "${LMP:-$root/build/lmp_dpdnl}")"
        ( cd "$d" && "$lmp" -in in.couette_polymer "${vars[@]}" -log log.lammps -screen none -nocite ) ||
            { echo "$name: LAMMPS failed (see $d/log.lammps)" >&2; tail -3 "$d/log.lammps" >&2; return 0; }
    else
        ( cd "$d" && "$DPDNL" run in.couette_polymer --threads "$THREADS" --log log.dpdnl "${vars[@]}" > screen.txt 2>&1 ) ||
            { echo "$name: dpdnl failed (see $d/screen.txt)" >&2; return 0; }
    fi
    echo "$name,$ENGINE,1536,$((EQ + STEPS)),$((SECONDS - t0))" >> "$res/runtimes.csv"
}

summary() {
    python3 "$here/summary.py" "$work" "$res" "$DPDNL"
}

case "${1:-all}" in
summary) summary ;;
all)
    for p in $POINTS; do
        IFS=: read -r fr rate <<<"$p"
        run_point "$fr" "$rate" &
        while [ "$(jobs -rp | wc -l)" -ge "$PAR" ]; do wait -n || true; done
    done
    wait
    summary ;;
*) sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 2 ;;
esac
