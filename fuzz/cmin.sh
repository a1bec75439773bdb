#!/usr/bin/env bash
# Minimise a target's corpus (libFuzzer -merge=1 with -use_counters=0 -use_cmp=0, or
# $CMIN_FLAGS: the fewest inputs that keep every edge covered by the working corpus and the
# committed one) and replace fuzz/corpus/TARGET with it.
#
#   fuzz/cmin.sh TARGET [WORK_DIR]      (the WORK_DIR of fuzz/run.sh, default /tmp/dpdnl-fuzz)
#
# Runs the inputs as fuzz/run.sh does (nice 19, user nobody when root, scratch directory,
# caps), since replaying the script target's inputs writes files.
set -euo pipefail
target=$1
work=${2:-/tmp/dpdnl-fuzz}
here=$(cd "$(dirname "$0")" && pwd)
bin=${CARGO_TARGET_DIR:-$here/target}/x86_64-unknown-linux-gnu/release/$target
rm -rf "$work/$target/min"
mkdir -p "$work/$target"/{min,corpus,cwd}
as_user=()
if [ "$(id -u)" = 0 ]; then
  chown -R nobody:nogroup "$work/$target"
  as_user=(setpriv --reuid=nobody --regid=nogroup --clear-groups)
fi
(
  cd "$work/$target/cwd"
  trap '' XFSZ
  ulimit -f 200000
  ulimit -v 4000000
  nice -n 19 "${as_user[@]}" env RAYON_NUM_THREADS=1 "$bin" -merge=1 -timeout=10 ${CMIN_FLAGS:--use_counters=0 -use_cmp=0} \
    -rss_limit_mb=2048 ../min ../corpus "$here/corpus/$target" > "$work/$target.cmin.log" 2>&1
)
rm -rf "$here/corpus/$target"
mkdir -p "$here/corpus/$target"
cp "$work/$target/min"/* "$here/corpus/$target/"
echo "$target: $(ls "$here/corpus/$target" | wc -l) files, $(du -sk "$here/corpus/$target" | cut -f1) kB"
