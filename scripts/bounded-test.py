#!/usr/bin/env python3
"""Run a test command with a time limit on every single test, and one on the whole command.

    python3 scripts/bounded-test.py [--per-test S] [--total S] -- cargo test --workspace ...

Rust's test harness (libtest) prints `test NAME has been running for over 60 seconds` when a
test passes one minute, and `test NAME ... ok|FAILED|ignored` when it ends. This wrapper passes
the command's output through unchanged, and stops the whole command (its process group: the
test binaries and what they started) when a test that announced itself still has not ended
S seconds after it started (`--per-test`, default $DPDNL_TEST_LIMIT or 900), or when the
command runs longer than `--total` seconds (default: no limit). It then names the test and
exits 1, so a hung test fails CI in minutes instead of holding it for hours.

No new dependency: the limit rides on libtest's own minute warning, so a test is only ever
measured from its start (the warning comes 60 s after it).
"""

import argparse
import os
import re
import signal
import subprocess
import sys
import threading
import time

WARN = re.compile(r"^test (\S+) has been running for over (\d+) seconds")
DONE = re.compile(r"^test (\S+) \.\.\. ")
BINARY = re.compile(r"^\s+Running ")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--per-test", type=float, default=float(os.environ.get("DPDNL_TEST_LIMIT", 900)))
    ap.add_argument("--total", type=float, default=0.0)
    ap.add_argument("cmd", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.cmd[1:] if a.cmd[:1] == ["--"] else a.cmd
    if not cmd:
        ap.error("no command given")
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        start_new_session=True,
        bufsize=0,
    )
    start = time.monotonic()
    running = {}  # test name -> the time it started (its warning time less the warning's age)
    lock = threading.Lock()
    why = []

    def stop(reason):
        why.append(reason)
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass

    def watch():
        while proc.poll() is None:
            now = time.monotonic()
            with lock:
                late = [(n, now - t0) for n, t0 in running.items() if now - t0 > a.per_test]
            if late:
                stop("test {} ran {:.0f} s, over the per-test limit of {:.0f} s".format(late[0][0], late[0][1], a.per_test))
                return
            if a.total and now - start > a.total:
                stop("the command ran over its limit of {:.0f} s".format(a.total))
                return
            time.sleep(1.0)

    t = threading.Thread(target=watch, daemon=True)
    t.start()
    buf = b""
    assert proc.stdout is not None
    while True:
        chunk = proc.stdout.read1(65536) if hasattr(proc.stdout, "read1") else proc.stdout.read(4096)
        if not chunk:
            break
        sys.stdout.buffer.write(chunk)
        sys.stdout.buffer.flush()
        buf += chunk
        *lines, buf = buf.split(b"\n")
        for raw in lines:
            line = raw.decode("utf-8", "replace")
            m = WARN.match(line)
            with lock:
                if m:
                    running.setdefault(m.group(1), time.monotonic() - float(m.group(2)))
                elif DONE.match(line):
                    running.pop(DONE.match(line).group(1), None)
                elif BINARY.match(line):
                    running.clear()
    rc = proc.wait()
    if why:
        print(f"\nERROR (scripts/bounded-test.py): {why[0]}; the command was stopped", flush=True)
        return 1
    return rc


if __name__ == "__main__":
    sys.exit(main())
