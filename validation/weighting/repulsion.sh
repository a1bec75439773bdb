#!/usr/bin/env bash
# The weighting paper's proposed DPD with its soft repulsion (issue 14 section 1): the repulsion
# a that the Groot-Warren compressibility rule gives for this 2-D fluid, then the paper's DPD
# cases rerun with it (validation/weighting/README.md, "Soft repulsion").
#
#   validation/weighting/repulsion.sh [STEP ...]
#
# Steps (all by default, in this order):
#   eos          <P>(n) at rest for the mean-field a = 180 kT/(pi n rc^3), rc = 1 and 2.5, and the a
#                for kappa^-1 = 16 from the measured slope (results/eos_rc*_a*.txt)
#   t3           Table 3 (rc = 1, eta0 = 10, s = 1/2), 5 rates, standalone and LAMMPS
#   t5           Table 5, 3 rows of Sc0 = 400 and 3 of Sc0 = 1000 spanning s, 5 rates standalone,
#                gamma-dot = 0.2 in LAMMPS for the smallest s of each Sc0
#   t2           Table 2's proposed DPD rows (rc = 2.5, s = 1/2, eta0 = 10 and 50), 5 rates standalone
#                (eta0 = 10 with 40000 steps: its stress is 5 times smaller than eta0 = 50's), gamma-dot
#                = 0.2 in LAMMPS for both
#   diffusion    Fig. 4 (Sc0 = 400, eta0 = 49) at rest
#   schmidt      Fig. 5's DPD: Sc = eta*/(m n D) for Sc0 in SC0S ["10 100 1000"] (s = 1/2), standalone
#   sensitivity  eta*(a) of the Table 3 fluid at gamma-dot = 0.2 for a = 0, a_derived/2, 2 a_derived (a_derived
#                itself is the t3 step's run) and the 3-D readings a = 75 kT/n = 18.75 and a = 25
#   summary      results/repulsion.md (no simulation)
# Environment: A1, A25 (the repulsions at rc = 1 and 2.5; default: read from the eos results,
# rounded to 4 digits), PAR [2], and what run.sh reads (DPDNL, LMP, N ...).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
res="$here/results"
run="$here/run.sh"
export PAR="${PAR:-2}"
steps=("$@")
[ ${#steps[@]} -gt 0 ] || steps=(eos t3 t5 t2 diffusion schmidt sensitivity summary)

# derived RC: the a of results/eos_rc<RC>_a<mean field>.txt's last line, 4 significant digits.
derived() {
    local f
    f=$(ls "$res"/eos_rc"$1"_a*.txt 2>/dev/null | head -1)
    [ -n "$f" ] || { echo "repulsion.sh: no $res/eos_rc$1_a*.txt: run the eos step first" >&2; exit 1; }
    awk '/^a for kappa/ {printf "%.4g", $NF}' "$f"
}

for st in "${steps[@]}"; do
    case "$st" in
    eos) "$run" eos ;;
    t3)
        A="${A1:-$(derived 1)}" CASES="t3:1.0:10:0.5:60000" LMP_RATES="0.05 0.1 0.2 0.5 1" EXT_RATES="" \
            "$run" couette ;;
    t5)
        # LAMMPS at gamma-dot = 0.2 for the smallest s of each Sc0 (LMP5 ["0.2"]; "" for none).
        a25="${A25:-$(derived 2.5)}"
        A="$a25" LMP_RATES="${LMP5-0.2}" EXT_RATES="" CASES="t5a:2.5:49:0.0700:20000 t5s1000e79:2.5:79:0.0025:20000" \
            RATES="${RATES5-0.05 0.1 0.2 0.5 1}" "$run" couette
        A="$a25" LMP_RATES="" EXT_RATES="" RATES="${RATES5-0.05 0.1 0.2 0.5 1}" \
            CASES="t5s400e39:2.5:39:0.9692:20000 t5s400e31:2.5:31:2.1096:20000 t5s1000e59:2.5:59:1.1686:20000
                   t5s1000e49:2.5:49:2.1113:20000" "$run" couette ;;
    t2)
        A="${A25:-$(derived 2.5)}" LMP_RATES="0.2" EXT_RATES="" RATES="0.05 0.1 0.2 0.5 1" \
            CASES="t2e10:2.5:10:0.5:40000 t2e50:2.5:50:0.5:20000" "$run" couette ;;
    diffusion) A="${A25:-$(derived 2.5)}" "$run" diffusion ;;
    schmidt) A="${A25:-$(derived 2.5)}" SDPD=0 ENGINE=standalone SC0S="${SC0S:-10 100 1000}" "$run" sdpd-schmidt ;;
    sensitivity)
        a1="${A1:-$(derived 1)}"
        # a = 0.0 (not 0) names the runs _a0.0, apart from the committed a = 0 results.
        for a in 0.0 $(awk -v a="$a1" 'BEGIN {printf "%.4g %.4g", a/2, 2*a}') 18.75 25; do
            while [ "$(jobs -rp | wc -l)" -ge "$PAR" ]; do wait -n; done
            A="$a" CASES="t3:1.0:10:0.5:60000" RATES="0.2" LMP_RATES="" EXT_RATES="" "$run" couette &
        done
        wait ;;
    summary) python3 "$here/summary_repulsion.py"; python3 "$here/../sync_tables.py" "$here/README.md" ;;
    *) sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 2 ;;
    esac
done
