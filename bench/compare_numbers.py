"""Compare the numbers.json of two report builds (a refactoring must leave every number unchanged).

    python bench/compare_numbers.py OLD_REPORTS NEW_REPORTS [DESIGN ...] [--rtol 1e-12]

Numbers in seconds whose names say they are times are skipped. Prints every number that differs by more than
``rtol`` relative (NaN equals NaN) or was removed, and the numbers added; exits 1 on a difference or a removal.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path


def is_timing(row: dict) -> bool:
    """A wall time: a number in seconds whose name says it is a time."""
    name = row["name"]
    return (row.get("unit") == "s" and any(w in name for w in ("time", "seconds", "_s_", "wall"))) \
        or name.endswith(("_s", "_time_s", "_seconds"))


def same(a: object, b: object, rtol: float) -> bool:
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, int | float) or not isinstance(b, int | float):
        return a == b
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return a == b or abs(a - b) <= rtol * max(abs(a), abs(b))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("designs", nargs="*")
    ap.add_argument("--rtol", type=float, default=1e-12)
    args = ap.parse_args()
    designs = args.designs or sorted(p.parent.name for p in args.old.glob("*/numbers.json"))
    bad = 0
    for d in designs:
        old = {r["name"]: r for r in json.loads((args.old / d / "numbers.json").read_text())}
        new = {r["name"]: r for r in json.loads((args.new / d / "numbers.json").read_text())}
        n = 0
        for name in sorted(set(old) | set(new)):
            if name not in new:
                print(f"{d}: {name} removed")
                bad += 1
                continue
            if name not in old:
                print(f"{d}: {name} added")
                continue
            if is_timing(old[name]):
                continue
            n += 1
            if not same(old[name]["value"], new[name]["value"], args.rtol):
                print(f"{d}: {name}: {old[name]['value']!r} -> {new[name]['value']!r}")
                bad += 1
        print(f"{d}: {n} numbers compared (timings skipped)")
    print("equal" if not bad else f"{bad} differences")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
