#!/usr/bin/env python3
"""Checks the headline validation numbers against the documented bands of validation/bands.csv.

    python3 validation/check_bands.py [quick|full]

quick checks the rows of tier quick, full every row. Prints one line per band (value, band,
reference) and exits 1 when a value is outside its band or its result file is missing.
Standard library only."""
import csv
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    tier = sys.argv[1] if len(sys.argv) > 1 else "full"
    if tier not in ("quick", "full"):
        sys.exit(__doc__.splitlines()[2].strip())
    with open(os.path.join(HERE, "bands.csv"), newline="") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    bad = 0
    for r in rows:
        if tier == "quick" and r["tier"] != "quick":
            continue
        path = os.path.join(HERE, r["file"])
        try:
            with open(path) as fh:
                value = float(json.load(fh)[r["key"]])
        except (OSError, KeyError, ValueError, TypeError) as e:
            print(f"MISSING  {r['id']}: {r['file']} [{r['key']}]: {e}")
            bad += 1
            continue
        lo, hi = float(r["low"]), float(r["high"])
        ok = lo <= value <= hi
        bad += not ok
        print(f"{'ok      ' if ok else 'OUTSIDE '} {r['id']}: {r['key']} = {value:.6g} in [{lo:g}, {hi:g}]? "
              f"({r['reference']})")
    print(f"{tier}: {'all within their bands' if not bad else f'{bad} outside or missing'}")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
