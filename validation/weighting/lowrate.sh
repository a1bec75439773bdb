#!/usr/bin/env bash
# Issue 31's study of Table 4's low-rate excess (validation/weighting/README.md, "The low-rate
# excess of Table 4"): one fluid (Sc0 = 400, eta0 = 49, s = 0.0700) with pair seeds 1-4 at three
# sound speeds (dt scaled as 1/c0) and three run lengths, in LAMMPS + shim (run.sh sdpd-couette),
# then results/lowrate.csv (summary_lowrate.py --collect). The summary tables come from
# validation/weighting/summary.sh.
#   validation/weighting/lowrate.sh        (PAR [2], and what run.sh reads)
# 44 runs; the results are results/sdpd_t4s400e49{c20,c40,c80,long,vlong,c20long,c80long}_*_lmp.*
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
run="$here/run.sh"
S="1 2 3 4"
C0=20 DT=0.01   CASES="t4s400e49c20:2.5:p0.0700:49:600:1000"      RATES="0.05 0.2" SEEDS="$S" "$run" sdpd-couette
C0=40 DT=0.005  CASES="t4s400e49c40:2.5:p0.0700:49:1200:2000"     RATES="0.05 0.2" SEEDS="$S" "$run" sdpd-couette
C0=80 DT=0.0025 CASES="t4s400e49c80:2.5:p0.0700:49:2400:4000"     RATES="0.05 0.2" SEEDS="$S" "$run" sdpd-couette
C0=40 DT=0.005  CASES="t4s400e49long:2.5:p0.0700:49:6000:2000"    RATES="0.05 0.2" SEEDS="$S" "$run" sdpd-couette
C0=40 DT=0.005  CASES="t4s400e49vlong:2.5:p0.0700:49:12000:2000"  RATES="0.05"     SEEDS="$S" "$run" sdpd-couette
C0=20 DT=0.01   CASES="t4s400e49c20long:2.5:p0.0700:49:3000:1000" RATES="0.05"     SEEDS="$S" "$run" sdpd-couette
C0=80 DT=0.0025 CASES="t4s400e49c80long:2.5:p0.0700:49:12000:4000" RATES="0.05"    SEEDS="$S" "$run" sdpd-couette
python3 "$here/summary_lowrate.py" --collect
