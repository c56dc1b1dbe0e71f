"""Concurrent builds of ``glidectl report`` (issue 18 part 2): a process pool and a dask cluster give the files a
serial build gives; errors and progress output."""

from __future__ import annotations

import io
import multiprocessing
import pickle
import sys
from pathlib import Path

import pytest

import glidectl as gc
from glidectl.cli import main
from glidectl.report import load_design
from glidectl.report.parallel import DesignFailure, build_designs, build_one

# two tiny designs with seeded random numbers and a figure (whose PNG must be identical too)
DESIGN = '''
import numpy as np
import glidectl as gc
from glidectl.report import Report, new_figure

TITLE = "tiny {name}"


def design(progress, quick=False):
    rng = np.random.default_rng({seed})
    veh = gc.load_vehicle("rogue")
    progress("glides")
    gammas = np.radians(-45.0 + 10.0 * rng.random(3))
    glides = [gc.steady_glide(veh, 0.3, g, r_p3=0.05) for g in gammas]
    rep = Report(TITLE, vehicle=veh)
    rep.number("m0", [g.m0 for g in glides], "kg")
    rep.number("alpha", [g.alpha for g in glides], "rad")
    fig, ax = new_figure()
    ax.plot(gammas, [g.m0 for g in glides], "o-")
    rep.figure("m0", fig, "m0 versus gamma")
    return rep
'''


def _designs(folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, seed in (("tiny_a", 1), ("tiny_b", 2)):
        p = folder / f"{name}.py"
        p.write_text(DESIGN.format(name=name, seed=seed))
        paths.append(p)
    return paths


def _files(out: Path, names: list[str]) -> dict[str, bytes]:
    return {f"{n}/{f}": (out / n / f).read_bytes() for n in names for f in ("numbers.json", "m0.png")}


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The two tiny designs built serially: (designs, their names, the files written)."""
    tmp = tmp_path_factory.mktemp("serial")
    designs = [load_design(p) for p in _designs(tmp / "designs")]
    names = [d.name for d in designs]
    build_designs(designs, tmp / "out", quick=True, jobs=1, use_cache=False, stream=io.StringIO())
    files = _files(tmp / "out", names)
    assert b'"m0"' in files["tiny_a/numbers.json"] and files["tiny_a/numbers.json"] != files["tiny_b/numbers.json"]
    return designs, names, files


def test_pool_builds_what_the_serial_build_builds(serial, tmp_path, fast_mp):
    designs, names, files = serial
    stream = io.StringIO()
    res = build_designs(designs, tmp_path / "pool", quick=True, jobs=2, use_cache=False, stream=stream,
                        mp_context=fast_mp)
    assert [r.name for r in res] == names and not any(r.from_cache for r in res)
    assert _files(tmp_path / "pool", names) == files
    text = stream.getvalue()
    assert text.count("done in") == 2 and "glides" in text  # progress messages come back from the workers


def test_cluster_builds_what_the_serial_build_builds(serial, tmp_path):
    distributed = pytest.importorskip("distributed")  # the dask extra (installed by .ci/run)
    designs, names, files = serial
    with distributed.LocalCluster(processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None) as lc:
        res = build_designs(designs, tmp_path / "cluster", quick=True, scheduler=lc.scheduler_address,
                            use_cache=False, stream=io.StringIO())
    assert [r.name for r in res] == names
    assert _files(tmp_path / "cluster", names) == files


def test_build_one_returns_files_and_failures_without_raising(tmp_path):
    p = _designs(tmp_path)[0]
    res = build_one("tiny_a", str(p), p.read_bytes(), True)
    assert {"numbers.json", "m0.png", "report.pdf"} <= set(res.files)
    assert res.provenance == (gc.load_vehicle("rogue").provenance,)
    # a remote worker without the file loads the shipped source
    moved = build_one("tiny_a", str(tmp_path / "elsewhere" / "tiny_a.py"), p.read_bytes(), True)
    assert moved.files["numbers.json"] == res.files["numbers.json"]
    bad = build_one("bad", str(tmp_path / "bad.py"), b"TITLE = 'x'\n\ndef design(progress, quick=False):\n"
                                                     b"    return 1 / 0\n", True)
    assert bad.name == "bad" and "ZeroDivisionError" in bad.message and "bad.py:4" in bad.message


def test_the_jobs_are_spawn_safe(tmp_path):
    """What the pool sends to a spawned worker pickles by reference to importable names, and comes back."""
    p = _designs(tmp_path)[0]
    job = pickle.loads(pickle.dumps((build_one, ("tiny_a", str(p), p.read_bytes(), True, None))))
    assert job[0] is build_one
    res = pickle.loads(pickle.dumps(job[0](*job[1])))
    assert res.name == "tiny_a" and "numbers.json" in res.files
    fail = pickle.loads(pickle.dumps(DesignFailure("x", "ZeroDivisionError: division by zero (x.py:4)")))
    assert fail.message.endswith("(x.py:4)")


RAISES = "TITLE = 'x'\n\ndef design(progress, quick=False):\n    return 1 / 0\n"


def test_a_failing_design_is_one_line_and_the_others_are_built(tmp_path, capsys, fast_mp):
    folder = tmp_path / "designs"
    _designs(folder)
    (folder / "raises.py").write_text(RAISES)
    out = tmp_path / "out"
    assert main(["report", "all", "--designs", str(folder), "--out", str(out), "--jobs", "1", "--quick"]) == 2
    cap = capsys.readouterr()
    assert cap.err.count("\n") == 1 and "ZeroDivisionError" in cap.err and "raises.py:4" in cap.err
    assert (out / "tiny_a" / "numbers.json").exists() and (out / "tiny_b" / "numbers.json").exists()
    designs = [load_design(p) for p in sorted(folder.glob("*.py"))]
    with pytest.raises(gc.DesignError, match=r"ZeroDivisionError.*raises\.py:4"):  # the same from a pool
        build_designs(designs, tmp_path / "pool", quick=True, jobs=2, use_cache=False, stream=io.StringIO(),
                      mp_context=fast_mp)
    assert (tmp_path / "pool" / "tiny_b" / "numbers.json").exists()


def test_jobs_and_scheduler_errors(tmp_path, capsys, monkeypatch):
    p = _designs(tmp_path)[0]
    for bad in ("0", "-1", "two"):
        with pytest.raises(SystemExit) as info:
            main(["report", str(p), "--jobs", bad])
        assert info.value.code == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--jobs" in err
    with pytest.raises(gc.ArgumentError, match="jobs"):
        build_designs([load_design(p)], tmp_path / "o", jobs=0)
    monkeypatch.setitem(sys.modules, "distributed", None)  # dask not installed
    assert main(["report", str(p), "--out", str(tmp_path / "o"), "--scheduler", "tcp://127.0.0.1:1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "dask" in err and "pip install" in err
    assert not (tmp_path / "o" / "tiny_a" / "numbers.json").exists()  # refused before building


def test_progress_is_plain_lines_without_a_terminal(tmp_path):
    p = _designs(tmp_path)[0]
    stream = io.StringIO()
    build_designs([load_design(p)], tmp_path / "o", quick=True, jobs=1, stream=stream)
    lines = stream.getvalue().splitlines()
    assert "\r" not in stream.getvalue() and "\x1b" not in stream.getvalue()  # no bar redraws in CI logs
    assert lines[0].startswith("[1/1] tiny_a: tiny tiny_a (quick settings) (last build: ?)")
    assert lines[-1].startswith("[1/1] tiny_a: done in") and "(computed)" in lines[-1]
    stream = io.StringIO()
    build_designs([load_design(p)], tmp_path / "o", quick=True, jobs=1, stream=stream)
    assert "(cache hit, built in " in stream.getvalue()
    (tmp_path / "tiny_a.py").write_text(p.read_text() + "\n# edited\n")
    stream = io.StringIO()
    build_designs([load_design(p)], tmp_path / "o", quick=True, jobs=1, stream=stream)
    assert "(last build: " in stream.getvalue() and "(last build: ?)" not in stream.getvalue()  # estimate


def test_progress_bars_on_a_terminal(tmp_path):
    p = _designs(tmp_path)[0]

    class Tty(io.StringIO):
        def isatty(self) -> bool:
            return True

    stream = Tty()
    build_designs([load_design(p)], tmp_path / "o", quick=True, jobs=1, stream=stream)
    text = stream.getvalue()
    assert "\r" in text and "tiny_a" in text and "done in" in text  # a tqdm bar, then the summary line


def test_declared_expected_seconds_order_the_first_build_longest_first(tmp_path):
    """Before any build is recorded, the designs' own EXPECTED_SECONDS order the build (longest first) and give the
    estimate; after one build the recorded time takes over."""
    a, b = _designs(tmp_path)
    a.write_text(a.read_text() + '\nEXPECTED_SECONDS = {"quick": 1.0, "full": 2.0}\n')
    b.write_text(b.read_text() + '\nEXPECTED_SECONDS = {"quick": 50.0, "full": 900.0}\n')
    stream = io.StringIO()
    build_designs([load_design(a), load_design(b)], tmp_path / "o", quick=True, jobs=1, stream=stream)
    starts = [ln for ln in stream.getvalue().splitlines() if "(expected: " in ln]
    assert [ln.split(":")[0].split()[-1] for ln in starts] == ["tiny_b", "tiny_a"]   # the longer one first
    assert "(expected: 50" in starts[0] and "last build" not in stream.getvalue()
    stream = io.StringIO()
    build_designs([load_design(a), load_design(b)], tmp_path / "o", quick=True, jobs=1, stream=stream,
                  use_cache=False)
    assert "(last build: " in stream.getvalue() and "(expected: " not in stream.getvalue()


@pytest.mark.parametrize("decl", ["300", "{'full': -1.0}", "{'full': float('nan')}", "{'slow': 3.0}",
                                  "{'full': True}"])
def test_invalid_expected_seconds_is_refused(tmp_path, decl):
    p = _designs(tmp_path)[0]
    p.write_text(p.read_text() + f"\nEXPECTED_SECONDS = {decl}\n")
    with pytest.raises(gc.DesignError, match="EXPECTED_SECONDS must be"):
        build_designs([load_design(p)], tmp_path / "o", quick=True, jobs=1, stream=io.StringIO())


def test_summary_line_gives_the_designs_own_build_time(tmp_path, fast_mp):
    """'done in' is the time measured in the design's worker (what timings.json records), not the time since the
    start line (a pool hands a design to the call queue before a worker is free)."""
    import json
    import re

    paths = _designs(tmp_path)
    stream = io.StringIO()
    build_designs([load_design(p) for p in paths], tmp_path / "o", quick=True, jobs=2, stream=stream,
                  mp_context=fast_mp)
    recorded = json.loads((tmp_path / "o" / ".cache" / "timings.json").read_text())
    shown = dict(re.findall(r"\] (tiny_\w): done in ([0-9.]+) s", stream.getvalue()))
    assert set(shown) == {"tiny_a", "tiny_b"}
    for name, s in shown.items():
        assert abs(float(s) - recorded[f"{name}:quick"]) <= 0.051


def test_a_queued_design_starts_its_line_when_a_worker_takes_it(tmp_path, fast_mp):
    """With 2 jobs (4 design workers: twice the slots) and 5 designs, the fifth design's start line comes after
    another design's last step: it is printed when a worker takes the design (the worker's first message), not when
    the pool hands it to its call queue, which happens at once, before any worker is free."""
    import re

    folder = tmp_path / "d"
    folder.mkdir()
    paths = []
    names = ("slow_a", "slow_b", "slow_c", "slow_d", "slow_e")
    for seed, name in enumerate(names, 1):
        p = folder / f"{name}.py"
        p.write_text(DESIGN.format(name=name, seed=seed).replace(
            "    rng = np.random", "    import time\n    time.sleep(1.5)\n    rng = np.random"))
        paths.append(p)
    stream = io.StringIO()
    build_designs([load_design(p) for p in paths], tmp_path / "o", quick=True, jobs=2, stream=stream,
                  mp_context=fast_mp)
    lines = stream.getvalue().splitlines()
    starts = {m.group(1): i for i, ln in enumerate(lines) if (m := re.search(r"\] (slow_\w): tiny", ln))}
    assert set(starts) == set(names), lines
    third = max(starts, key=starts.get)
    last_steps = [i for i, ln in enumerate(lines) if "writing the report" in ln and third not in ln]
    assert last_steps and starts[third] > min(last_steps), lines
    # ... and after the summary line of the design whose worker it took (the worker sent that result first)
    dones = {m.group(1): i for i, ln in enumerate(lines) if (m := re.search(r"(slow_\w)\b.*done in", ln))}
    assert set(dones) == set(names), lines
    assert starts[third] > min(dones[d] for d in dones if d != third), lines


def test_on_a_cluster_a_queued_design_starts_its_line_when_a_worker_takes_it(tmp_path):
    """One dask worker with one thread and two designs: the second design's start line comes after the first one's
    summary line (it is printed when the worker starts the design, not when it is submitted), and the progress
    messages from inside the designs reach the display (through the scheduler's event topic)."""
    import re

    distributed = pytest.importorskip("distributed")  # the dask extra (installed by .ci/run)
    folder = tmp_path / "d"
    folder.mkdir()
    paths = []
    for name, seed in (("slow_a", 1), ("slow_b", 2)):
        p = folder / f"{name}.py"
        p.write_text(DESIGN.format(name=name, seed=seed).replace(
            "    rng = np.random", "    import time\n    time.sleep(1.0)\n    rng = np.random"))
        paths.append(p)
    stream = io.StringIO()
    with distributed.LocalCluster(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as lc:
        build_designs([load_design(p) for p in paths], tmp_path / "o", quick=True, scheduler=lc.scheduler_address,
                      use_cache=False, stream=stream)
    lines = stream.getvalue().splitlines()
    starts = {m.group(1): i for i, ln in enumerate(lines) if (m := re.search(r"\] (slow_\w): tiny", ln))}
    dones = {m.group(1): i for i, ln in enumerate(lines) if (m := re.search(r"\] (slow_\w): done in", ln))}
    assert set(starts) == set(dones) == {"slow_a", "slow_b"}, lines
    first, second = sorted(starts, key=starts.get)
    assert starts[second] > dones[first], lines             # not shown as running while it waited for the thread
    for name in (first, second):                             # the design's own steps, between its start and end
        steps = [i for i, ln in enumerate(lines) if ln.startswith(f"  {name} [")]
        assert [lines[i].split(" s  ", 1)[1] for i in steps] == ["glides", "writing the report"], lines
        assert starts[name] < min(steps) and max(steps) < dones[name], lines


# a design with an SOS certificate whose numbers follow the thread count unless the ROA layer pins it (Clarabel's
# max_threads, BLAS through threadpoolctl): the reduced chapter-5 glider at degree 4, one V step (a few seconds)
CERTIFYING = """
import glidectl as gc
from glidectl.report import Report

TITLE = "certifying"


def design(progress, quick=False):
    rm = gc.singular_perturbation(gc.load_vehicle("sphere_ch5")).reduced_model()
    c = gc.certify_roa(rm, degree=4, iterations=1, solver="CLARABEL", sampling=dict(n_truth=256, n_verify=500,
                                                                                    n_simulate=4))
    rep = Report(TITLE)
    rep.number("rho", c.rho, "-")
    rep.number("V", [float(v) for v in c.V.arrays()[1]], "-")
    return rep
"""


def test_a_certificate_is_the_same_from_a_serial_build_and_from_a_spawned_pool(tmp_path):
    """The serial build runs in this process with the libraries' default threads (one per core), the pool's spawned
    workers with ``cores // jobs`` (a second design makes it a pool); the ledgers are byte-identical because the ROA
    layer holds BLAS and Clarabel to one thread (without that, 2 threads against 1 gave another certificate)."""
    folder = tmp_path / "designs"
    _designs(folder)
    (folder / "certifying.py").write_text(CERTIFYING)
    designs = [load_design(folder / f"{n}.py") for n in ("certifying", "tiny_a")]
    for where, jobs in (("serial", 1), ("pool", 2)):
        stream = io.StringIO()
        build_designs(designs, tmp_path / where, quick=True, jobs=jobs, use_cache=False, stream=stream,
                      mp_context=multiprocessing.get_context("spawn"))
    serial, pool = ((tmp_path / w / "certifying" / "numbers.json").read_bytes() for w in ("serial", "pool"))
    assert b'"rho"' in serial and serial == pool
