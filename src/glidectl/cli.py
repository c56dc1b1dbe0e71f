"""The ``glidectl`` command: list designs and vehicle presets, build design reports.

``glidectl report NAME|PATH|all [--designs DIR] [--out DIR] [--quick] [--jobs N] [--scheduler ADDRESS]
[--no-cache]`` builds designs found in ``./designs`` (or ``--designs DIR``), or any design file, on ``N`` processes
(default: all cores) or a dask cluster, reusing what ``OUT/.cache`` holds from earlier builds; ``glidectl list``
shows the designs found and the vehicle presets. Every
error exits with status 2 and a one-line message; the output folder is checked before anything is computed.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

from .errors import GlidectlError
from .params import list_presets, load_vehicle
from .report.designs import check_writable, find_designs, load_design
from .report.parallel import build_designs, require_dask

__all__ = ["main"]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line usage errors (``glidectl: error: ...``, exit status 2)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"glidectl: error: {message} (see {self.prog} --help)\n")


def _where(exc: BaseException) -> str:
    """``file:line`` of the innermost frame of ``exc``'s traceback (where a design file failed)."""
    frames = traceback.extract_tb(exc.__traceback__)
    return f" ({Path(frames[-1].filename).name}:{frames[-1].lineno})" if frames else ""


def _cmd_list(args: argparse.Namespace) -> int:
    print("vehicle presets (gc.load_vehicle(NAME)):")
    for name in list_presets():
        v = load_vehicle(name)
        print(f"  {name:<14} {v.kind:<18} {v.title}")
    try:
        found = find_designs(args.designs)
    except GlidectlError as exc:
        print(f"designs: none ({exc})")
        return 0
    print(f"designs in {args.designs}/ (glidectl report NAME):")
    for name, path in found.items():
        try:
            title = load_design(path).title
        except GlidectlError as exc:
            title = f"(cannot load: {exc})"
        print(f"  {name:<26} {title}")
    return 0


def _cmd_report(args: argparse.Namespace) -> int:
    specs: list[str | Path] = list(find_designs(args.designs).values()) if args.name == "all" else [args.name]
    designs = [load_design(s, args.designs) for s in specs]
    for d in designs:  # every output folder is checked before anything is computed
        check_writable(Path(args.out) / d.name)
    if args.scheduler is not None:
        require_dask()  # a missing dask is reported before anything is built
    t0 = time.perf_counter()
    results = build_designs(designs, args.out, quick=args.quick, jobs=args.jobs, scheduler=args.scheduler,
                            use_cache=not args.no_cache)
    if len(results) > 1:
        hits = sum(r.from_cache for r in results)
        print(f"{len(results)} designs in {time.perf_counter() - t0:.1f} s ({hits} from the cache)", flush=True)
    return 0


def _jobs(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"--jobs must be a positive integer, got {text!r}")
    return n


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``glidectl`` command.

    Parameters
    ----------
    argv : sequence of str, optional
        Command-line arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0 on success, 2 on any error (a one-line message on stderr): a glidectl error, an exception
        raised by a design file (with its file and line), or a usage error (argparse exits with status 2).

    Raises
    ------
    SystemExit
        With status 2 on a usage error (one line on stderr), or 0 after ``--help``.
    """
    parser = _Parser(prog="glidectl", description="Control design for gliding vehicles.")
    sub = parser.add_subparsers(dest="cmd", required=True)
    lp = sub.add_parser("list", help="list vehicle presets and designs")
    lp.add_argument("--designs", default="designs", help="folder of design files (default: ./designs)")
    lp.set_defaults(func=_cmd_list)
    rp = sub.add_parser("report", help="build design reports (PDF, PNGs, numbers.json)")
    rp.add_argument("name", nargs="?", default="all",
                    help="design name (looked up in --designs), path of a design file, or 'all' (default)")
    rp.add_argument("--designs", default="designs", help="folder of design files (default: ./designs)")
    rp.add_argument("--out", default="reports", help="output folder; a design writes OUT/NAME/ (default: ./reports)")
    rp.add_argument("--quick", action="store_true", help="use each design's quick settings (smaller studies)")
    rp.add_argument("--jobs", "-j", type=_jobs, default=os.cpu_count() or 1,
                    help="processes that compute at once (designs and their parts; default: all cores)")
    rp.add_argument("--scheduler", metavar="ADDRESS", default=None,
                    help="build on a dask.distributed cluster at ADDRESS instead (needs the dask extra)")
    rp.add_argument("--no-cache", action="store_true",
                    help="ignore the cache in OUT/.cache and build everything again (the cache is refreshed)")
    rp.set_defaults(func=_cmd_report)
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except GlidectlError as exc:
        print(f"glidectl: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    except Exception as exc:  # a design file's own failure: one line, where it happened, status 2
        print(f"glidectl: error: {type(exc).__name__}: {' '.join(str(exc).split())}{_where(exc)}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
