#!/usr/bin/env bash
# Issue 41: the momentum leak of fix deform's box flips, measured, and its cure.
#
#   validation/le_flip/run.sh            # every run, then the summary
#   validation/le_flip/run.sh summary    # the summary of the finished runs
#
# The tutorial's fluid (in.equil, a copy of docs/manual/tutorial.md's step 2) sheared at rate 3
# (in.couette) for SEEDS pair seeds in two modes of fix flip/momentum: `check` (the flipped
# atoms keep their velocities, as with plain fix deform in LAMMPS; counted and reported) and
# `jump` (they get remap v's velocity jump). Per run: kT (temp/deform, mean of the second half
# of the production run, with `dpdnl analyze couette`'s estimate of its error), eta*
# (dpdnl analyze couette), the atoms put through y at flips and the momentum relative to the
# profile that they changed (the end-of-run line), so V = P/N. The summary puts the seed mean and
# the seed-to-seed spread beside the per-run error estimates.
# Environment: DPDNL [target/release/dpdnl], SEEDS ["1 2 3 4 5 6 7"], PAR [2] runs at a time,
# NPROD [20000] production steps.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
DPDNL="$(realpath "${DPDNL:-${CARGO_TARGET_DIR:-$root/target}/release/dpdnl}")"
SEEDS="${SEEDS:-1 2 3 4 5 6 7}"; PAR="${PAR:-2}"; NPROD="${NPROD:-20000}"
work="$here/work"; res="$here/results"
mkdir -p "$work" "$res"
if [ "${1:-}" != summary ]; then
    # The commit the binary was built from (the tree must be committed: results of a commit).
    git -C "$root" log -1 --format=%h > "$work/commit.txt"
    ( cd "$work" && cp "$here/in.equil" "$here/in.couette" . &&
      "$DPDNL" run in.equil --threads "$PAR" --log log.equil --quiet )
    echo "run,engine,atoms,steps,seconds" > "$res/runtimes.csv"
    one() { # MODE SEED
        local tag="$1_s$2" t0=$SECONDS
        ( cd "$work" && "$DPDNL" run in.couette --threads 1 --quiet --log "log.$tag" \
            -var mode "$1" -var seed "$2" -var tag "$tag" -var nprod "$NPROD" > /dev/null )
        echo "$tag,dpdnl,1600,$((2000 + NPROD)),$((SECONDS - t0))" >> "$res/runtimes.csv"
    }
    n=0
    for mode in check jump; do for s in $SEEDS; do
        one "$mode" "$s" &
        n=$((n + 1)); if [ $((n % PAR)) = 0 ]; then wait; fi
    done; done
    wait
fi
python3 "$here/summary.py" "$work" "$res" "$DPDNL" "$NPROD"
