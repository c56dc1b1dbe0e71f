"""Benchmark: where the CPU of the README's main job goes, from one sampling profile of the whole cold build.

``bench_report_all.py`` times each design and profiles it alone under ``cProfile``, which slows Python-heavy code (a
matplotlib report page: 2.3 times) much more than numpy or a compiled solver, and never sees the build's own
costs (process starts, imports, waits). This script samples the build itself, every process of it:

1. runs ``python -m glidectl report all --no-cache --jobs N --out DIR`` (the README's main job, cold) under
   ``py-spy record --subprocesses --format raw`` (``pip install -e ".[bench]"`` installs py-spy);
2. reads the collapsed stacks and gives each sample to one **activity**: the innermost frame of the stack that
   belongs to one (an SDP solve inside a level program is "SDP: Clarabel", a batch simulation inside the final
   verification is "batch simulations"), else "other";
3. gives each sample to the **design** whose file is outermost in its stack (a part that runs a function of its
   design file counts for that design); "(no design frame)" holds the rest: process starts and imports, the main
   process, and parts that run a library function directly (ch8_helix's sweeps, ch7_ctol's runs);
4. converts shares to CPU seconds with the build's measured user + system CPU (``getrusage`` of the children).

py-spy samples the stacks of running *and* runnable threads (idle ones, waiting on a lock, a pipe or a sleep, are
left out), so a share is a share of busy samples; with at most ``N`` processes computing (the build's slots) it is
close to a share of CPU, except at the start, when the pool's workers import at once.

Run from the project root::

    python bench/bench_report_spy.py                     # the full settings, --jobs 2, 40 samples/s
    python bench/bench_report_spy.py --read RAW          # only read a raw file recorded before
    python bench/bench_report_spy.py --quick --rate 100  # the quick settings

Writes ``bench/results/report_spy.json`` (``--tag`` adds a suffix) and keeps the raw stacks next to it.

Measured 2026-12-04 13:02-13:10 (eleventh session, main a00860b, ``python bench/bench_report_spy.py``): 40 644 busy
samples; the build took 470.2 s under py-spy, CPU 917.0 s (py-spy's own sampling included; the same build alone
without it took 400.1 s, CPU 780.7 s, at 12:28, a slow hour of this 2-core machine: 345.8 s the day before):

=======================================  ======  =======
activity (innermost frame)               share   CPU s
=======================================  ======  =======
SDP: Clarabel (interior point)           27.4 %  251.1
batch simulations (Rosenbrock, stiff)    15.4 %  141.3
other                                    11.8 %  108.5
single-trajectory runs (LSODA)           10.9 %  100.0
SDP: moment route (CVXOPT)               8.1 %   74.0
imports (process starts, lazy imports)   7.4 %   68.2
certificate sampling / radii / checks    6.8 %   62.2
report writing (figures, PDF, PNG)       4.6 %   42.1
surrogates and sector systems            4.2 %   38.6
SDP: building programs (cvxpy)           3.4 %   31.2
=======================================  ======  =======

By design: roa_certification 53.2 %, slocum_dive_cycle 15.8 % (it computes the user glider's LQR-loop certificate
that roa_certification reads), ch7_ctol 8.4 %, no design frame 19.0 % (process starts, ch8_helix's and ch7_ctol's
parts that run library functions). An earlier recording (12:49-12:57, by hand) gave the same shares within 3
points (imports 10.2 %).

Outside the SDP solves (35.5 % together), no activity holds more than a sixth of the build, and none of them is
waste:

- the batch simulations are stiff. The 4-state glider's linearization has eigenvalues -1999, -533, -1.65 and -1.26.
  RK45 took a median of 11 783 steps per run where the Rosenbrock batch takes 450, and 166 s for 20 runs against
  4.6 s for the batch of 2048;
- the report writing is about 3-11 s per design in a fresh process (quick settings), mostly matplotlib text layout
  of figures drawn twice (PNG and PDF page);
- the imports are about 2.7 s per spawned process (11 processes). Their share is inflated: at the start the main
  process and the four design workers import at once on 2 cores.

The quick settings (``--quick --rate 100``, 13:23-13:25: 125.5 s, CPU 244.5 s, 12 processes) turn this over: the
build's fixed costs lead, imports 27.3 % and report writing 17.5 %, then batch simulations 9.8 % and Clarabel 6.0 %.

The self time is just as flat. Clarabel is 26.9 %; the next function, the moment route's Schur complement, is
3.9 %. Then come model right-hand sides, polynomial evaluation and batched inverses of 1-3 % each.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: (activity, frames that start it: (function name, file name)); the innermost matching frame of a stack wins.
ACTIVITIES: tuple[tuple[str, tuple[tuple[str, str], ...]], ...] = (
    ("SDP: Clarabel (interior point)", (("CLARABEL.solve_via_data", "clarabel_conif.py"),)),
    ("SDP: moment route (CVXOPT)", (("solve_moment", "sdp_solvers.py"),)),
    ("SDP: building programs (cvxpy)", (("Problem.get_problem_data", "problem.py"), ("SOSProgram.add_sos", "sos.py"),
                                        ("SOSProgram.add_zero", "sos.py"), ("_build", "certify.py"))),
    ("batch simulations (Rosenbrock, stiff)", (("integrate_batch", "batch.py"),)),
    ("single-trajectory runs (LSODA)", (("_integrate", "sim.py"), ("solve_ivp", "ivp.py"))),
    ("certificate sampling / radii / checks", (("_verify", "certify.py"), ("_sample_set", "certify.py"),
                                               ("_volume_directed", "certify.py"), ("_radii", "certify.py"),
                                               ("_contains", "certify.py"), ("SOSProgram.check", "sos.py"))),
    ("surrogates and sector systems", (("surrogate_system", "surrogate.py"), ("sector_system", "sector.py"))),
    ("report writing (figures, PDF, PNG)", (("Report._write", "document.py"),)),
    ("imports (process starts, lazy imports)", (("_find_and_load", "<frozen importlib._bootstrap>"),)),
)

_IDLE = ("sleep", "wait (threading", "Condition.wait", "acquire", "select (", "poll (", "Connection._recv",
         "Connection._poll", "accept (")


def _frame(f: str) -> tuple[str, str]:
    """``(function, file name)`` of one py-spy frame ``"name (path/file.py:line)"``."""
    name, _, where = f.partition(" (")
    return name, where.rsplit(":", 1)[0].rsplit("/", 1)[-1]


def read_raw(path: Path, designs: list[str]) -> dict:
    """Shares of the busy samples of a py-spy raw file by activity, by design and by function (self and inclusive).

    Parameters
    ----------
    path : Path
        ``py-spy record --format raw`` output (one ``frame;frame;... count`` line per distinct stack).
    designs : list of str
        Design file stems (``ch2_longitudinal``...) that name the design of a stack.

    Returns
    -------
    dict
        ``samples``, ``idle_samples``, ``activity`` / ``design`` / ``self`` / ``inclusive`` shares (fractions).
    """
    lookup = {fr: act for act, frames in ACTIVITIES for fr in frames}
    files = {f"{d}.py": d for d in designs}
    act: Counter[str] = Counter()
    des: Counter[str] = Counter()
    own: Counter[str] = Counter()
    inc: Counter[str] = Counter()
    busy = idle = 0
    with open(path) as fh:
        for line in fh:
            stack, _, count = line.rstrip("\n").rpartition(" ")
            if not stack:
                continue
            n = int(count)
            frames = [f for f in stack.split(";") if not f.startswith("process ")]
            if not frames or any(k in frames[-1] for k in _IDLE):
                idle += n
                continue
            busy += n
            parsed = [_frame(f) for f in frames]
            act[next((lookup[p] for p in reversed(parsed) if p in lookup), "other")] += n
            des[next((files[p[1]] for p in parsed if p[1] in files), "(no design frame)")] += n
            own[f"{parsed[-1][0]} [{parsed[-1][1]}]"] += n
            for key in {f"{p[0]} [{p[1]}]" for p in parsed}:
                inc[key] += n

    def shares(c: Counter[str], top: int | None = None) -> dict[str, float]:
        return {k: v / busy for k, v in c.most_common(top)} if busy else {}

    return {"samples": busy, "idle_samples": idle, "activity": shares(act), "design": shares(des),
            "self": shares(own, 30), "inclusive": shares(inc, 60)}


def record(raw: Path, out: Path, jobs: int, quick: bool, rate: int) -> tuple[float, float]:
    """Run the cold build under py-spy into ``raw``; its wall time and its children's user + system CPU (s)."""
    spy = shutil.which("py-spy")
    if spy is None:
        raise SystemExit("py-spy is not installed: pip install -e '.[bench]' (or pip install py-spy)")
    cmd = [spy, "record", "--subprocesses", "--nonblocking", "--rate", str(rate), "--format", "raw", "--output",
           str(raw), "--", sys.executable, "-m", "glidectl", "report", "all", "--no-cache", "--jobs", str(jobs),
           "--out", str(out)] + (["--quick"] if quick else [])
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, cwd=ROOT, env=env, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--rate", type=int, default=40, help="samples per second per process (default 40)")
    ap.add_argument("--quick", action="store_true", help="the designs' quick settings")
    ap.add_argument("--read", type=Path, help="read this raw file instead of recording a build")
    ap.add_argument("--cpu", type=float, help="with --read: the build's CPU (s), to convert shares to seconds")
    ap.add_argument("--tag", default="")
    args = ap.parse_args()
    from glidectl.report import find_designs

    designs = sorted(find_designs(ROOT / "designs"))
    results = ROOT / "bench" / "results"
    results.mkdir(parents=True, exist_ok=True)
    suffix = f"_{args.tag}" if args.tag else ""
    wall = cpu = None
    if args.read is None:
        raw = results / f"report_spy{suffix}.raw"
        with tempfile.TemporaryDirectory() as tmp:
            wall, cpu = record(raw, Path(tmp) / "reports", args.jobs, args.quick, args.rate)
    else:
        raw, cpu = args.read, args.cpu
    res = read_raw(raw, designs)
    res.update({"wall_s": wall, "cpu_s": cpu, "jobs": args.jobs, "rate": args.rate, "quick": args.quick,
                "raw": str(raw)})
    print(f"{res['samples']} busy samples ({res['idle_samples']} idle left out)"
          + (f"; build wall {wall:.1f} s" if wall else "") + (f", CPU {cpu:.1f} s" if cpu else ""))
    for title, key in (("activity (innermost frame)", "activity"), ("design (outermost design file)", "design"),
                       ("functions, self", "self")):
        print(f"\n{title:52s} share" + ("   CPU s" if cpu else ""))
        for k, v in list(res[key].items())[:20]:
            print(f"  {k[:50]:50s} {100 * v:5.1f} %" + (f" {v * cpu:7.1f}" if cpu else ""))
    path = results / f"report_spy{suffix}.json"
    path.write_text(json.dumps(res, indent=2))
    print(f"\nwrote {path}")


if __name__ == "__main__":
    main()
