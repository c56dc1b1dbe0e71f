"""The ``glidectl`` command: list presets and designs, build reports."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence

from . import studies
from .errors import GlidectlError
from .params import list_presets, load_vehicle


def _progress(prefix: str, t0: float):
    step = {"k": 0}

    def report(msg: str) -> None:
        step["k"] += 1
        print(f"  {prefix} [{step['k']:2d}] {time.perf_counter() - t0:7.1f} s  {msg}", flush=True)

    return report


def _cmd_list(args: argparse.Namespace) -> int:
    print("vehicle presets:")
    for name in list_presets():
        v = load_vehicle(name)
        print(f"  {name:<14} {v.kind:<18} {v.title}")
    print("designs (glidectl report NAME):")
    for name in sorted(studies.REGISTRY):
        print(f"  {name:<20} {studies.get(name).TITLE}")
    return 0


def _cmd_report(args: argparse.Namespace) -> int:
    names = sorted(studies.REGISTRY) if args.name == "all" else [args.name]
    for i, name in enumerate(names, 1):
        mod = studies.get(name)
        t0 = time.perf_counter()
        print(f"[{i}/{len(names)}] {name}: {mod.TITLE}", flush=True)
        pdf = mod.build(args.out, _progress(name, t0))
        print(f"[{i}/{len(names)}] {name}: done in {time.perf_counter() - t0:.1f} s -> {pdf}", flush=True)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``glidectl`` command."""
    parser = argparse.ArgumentParser(prog="glidectl", description="Control design for gliding vehicles.")
    sub = parser.add_subparsers(dest="cmd", required=True)
    sub.add_parser("list", help="list vehicle presets and designs").set_defaults(func=_cmd_list)
    rp = sub.add_parser("report", help="build a design report (PDF, PNGs, numbers.json)")
    rp.add_argument("name", nargs="?", default="all", help="design name or 'all' (default)")
    rp.add_argument("--out", default="reports", help="output folder (default: ./reports)")
    rp.set_defaults(func=_cmd_report)
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except GlidectlError as exc:
        print(f"glidectl: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
