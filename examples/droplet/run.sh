#!/usr/bin/env bash
# The drop's deformation against the capillary number, friction none and cross (issue 46).
#
#   bash examples/droplet/run.sh [OUTDIR]     (default: a new folder under /tmp)
#
# 1. gen_drop.py writes the drop (radius 2.5 in a 10 box, number density 6.5) and a flat
#    layer of liquid 1 in liquid 2 (the interfacial tension Gamma, from the pressure tensor of a
#    run at rest: Gamma = (Lz/2)(Pzz - (Pxx + Pyy)/2), two interfaces);
# 2. in.droplet runs at each shear rate of RATES for friction none and for friction cross
#    (gamma1 = GAMMA1) in the standalone engine (DPDNL, default target/release/dpdnl);
# 3. the cargo example droplet_plot reads the dumps and logs: the drop's deformation
#    D = (L - B)/(L + B) from its gyration tensor in the shear plane, Ca = R0 sigma / Gamma with
#    sigma = -<Pxy> the measured shear stress; it writes OUTDIR/droplet.{png,svg,md}.
# Environment: RATES (default "0.1 0.2 0.3 0.4"), GAMMA1 (0.5), STEPS (4000), EQ (1000),
# SEED (4242). About 3 minutes on 2 cores.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$(mktemp -d /tmp/dpdnl-droplet.XXXX)}"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
dpdnl="${DPDNL:-$root/target/release/dpdnl}"
[ -x "$dpdnl" ] || { echo "run.sh: $dpdnl not found: cargo build --release" >&2; exit 1; }
rates="${RATES:-0.1 0.2 0.3 0.4}"
gamma1="${GAMMA1:-0.5}"
steps="${STEPS:-4000}"
eq="${EQ:-1000}"
seed="${SEED:-4242}"

cp "$here/in.droplet" "$out/"
cd "$out"
python3 "$here/gen_drop.py" drop.data 10 2.5 6.5 2024
python3 "$here/gen_drop.py" layer.data 10 2.5 6.5 2024 layer

run() { # NAME VAR VALUE ...
  local name="$1"; shift
  local args=()
  while [ $# -gt 0 ]; do args+=(-var "$1" "$2"); shift 2; done
  echo "== $name"
  "$dpdnl" run in.droplet -var engine "$name" -var eq "$eq" -var steps "$steps" -var every 50 \
    -var seed "$seed" "${args[@]}" > "log.$name" 2>&1 || { tail -5 "log.$name" >&2; exit 1; }
}

run layer data layer.data rate 0.0
for r in $rates; do
  run "none_$r" rate "$r" friction none gamma1 0.0
  run "cross_$r" rate "$r" friction cross gamma1 "$gamma1"
done
cd "$root"
cargo run --quiet --release --example droplet_plot -- "$out/droplet" "$out" 2.5 $rates
echo "wrote $out/droplet.svg, $out/droplet.png and $out/droplet.md"
