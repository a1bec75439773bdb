#!/usr/bin/env bash
# Run one fuzz target for SECONDS (default 1800) under nice 19, as the unprivileged user
# `nobody` when started as root, in a scratch directory (the script target writes dump, data,
# log and restart files wherever a mutated script names them), with memory and file-size caps.
#
#   fuzz/run.sh TARGET [SECONDS] [WORK_DIR]      TARGET: script | readers | grammar | restart
#
# WORK_DIR (default /tmp/dpdnl-fuzz) gets TARGET/{corpus,artifacts,cwd} and TARGET.log; the
# corpus starts from fuzz/corpus/TARGET (and from WORK_DIR/seeds/TARGET when fuzz/seed.py
# wrote one there). New inputs stay in WORK_DIR: minimise them into fuzz/corpus/TARGET with
# fuzz/cmin.sh. Build first (fuzz/README.md). FORK=1: libFuzzer's fork mode with one job, which
# records a crash, timeout or out-of-memory in artifacts/ and goes on fuzzing (the plain mode
# stops at the first).
set -euo pipefail
target=$1
secs=${2:-1800}
work=${3:-/tmp/dpdnl-fuzz}
here=$(cd "$(dirname "$0")" && pwd)
bin=${CARGO_TARGET_DIR:-$here/target}/x86_64-unknown-linux-gnu/release/$target
case $target in
  script) max_len=8192 ;;
  readers) max_len=65536 ;;
  grammar) max_len=2048 ;;
  restart) max_len=16384 ;;
  *) echo "unknown target $target" >&2; exit 2 ;;
esac
mkdir -p "$work/$target"/{corpus,artifacts,cwd} "$here/corpus/$target"
if [ -d "$work/seeds/cwd" ]; then cp -n "$work/seeds/cwd"/* "$work/$target/cwd/"; fi
extra=()
if [ "${FORK:-0}" = 1 ]; then extra=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1); fi
dirs=("../corpus" "$here/corpus/$target")
if [ -d "$work/seeds/$target" ]; then dirs+=("$work/seeds/$target"); fi
as_user=()
if [ "$(id -u)" = 0 ]; then
  chown -R nobody:nogroup "$work/$target"
  as_user=(setpriv --reuid=nobody --regid=nogroup --clear-groups)
fi
cd "$work/$target/cwd"
# Over-long files fail with EFBIG (an I/O error the interpreter reports), not SIGXFSZ.
trap '' XFSZ
ulimit -f 200000   # 200 MB per file
ulimit -v 4000000  # 4 GB of address space
exec nice -n 19 "${as_user[@]}" env RAYON_NUM_THREADS=1 "$bin" \
  -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" \
  -dict="$here/dpdnl.dict" -artifact_prefix=../artifacts/ -print_final_stats=1 \
  "${extra[@]}" "${dirs[@]}" > "$work/$target.log" 2>&1
