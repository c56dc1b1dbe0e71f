"""Threads of a build's worker processes (``glidectl.report.threads``): a pool of ``jobs`` workers gives each
``cores // jobs`` library threads through the environment, a value the user set stays, and the environment is
restored afterwards."""

from __future__ import annotations

import io
import json
import multiprocessing
import os

import pytest

import glidectl as gc
from glidectl.report import load_design
from glidectl.report.parallel import build_designs
from glidectl.report.threads import THREAD_VARIABLES, worker_threads

THREADS_DESIGN = '''
import os

from glidectl.report import Report

TITLE = "threads"


def design(progress, quick=False):
    rep = Report(TITLE)
    for k in {names!r}:
        rep.number(k, int(os.environ.get(k, "0")), "1")
    return rep
'''


@pytest.fixture
def clean_env(monkeypatch):
    for k in THREAD_VARIABLES:
        monkeypatch.delenv(k, raising=False)


@pytest.mark.parametrize(("jobs", "cores", "per"), [(2, 2, "1"), (2, 8, "4"), (3, 8, "2"), (4, 2, "1"), (1, 6, "6")])
def test_each_worker_gets_its_share_of_the_cores(clean_env, jobs, cores, per):
    with worker_threads(jobs, cores=cores) as new:
        assert new == dict.fromkeys(THREAD_VARIABLES, per)
        assert all(os.environ[k] == per for k in THREAD_VARIABLES)
    assert not any(k in os.environ for k in THREAD_VARIABLES)


def test_a_value_the_user_set_is_kept(clean_env, monkeypatch):
    monkeypatch.setenv("OMP_NUM_THREADS", "3")
    with worker_threads(2, cores=2) as new:
        assert "OMP_NUM_THREADS" not in new and os.environ["OMP_NUM_THREADS"] == "3"
        assert os.environ["RAYON_NUM_THREADS"] == "1"
    assert os.environ["OMP_NUM_THREADS"] == "3" and "RAYON_NUM_THREADS" not in os.environ


def test_the_environment_is_restored_when_the_block_raises(clean_env):
    with pytest.raises(RuntimeError), worker_threads(2, cores=2):
        raise RuntimeError("a design failed")
    assert not any(k in os.environ for k in THREAD_VARIABLES)


def test_bad_arguments_are_refused():
    with pytest.raises(gc.ArgumentError, match="jobs"), worker_threads(0):
        pass
    with pytest.raises(gc.ArgumentError, match="cores"), worker_threads(1, cores=0):
        pass


def test_a_spawned_worker_inherits_the_limits(clean_env):
    with worker_threads(2, cores=2), multiprocessing.get_context("spawn").Pool(1) as pool:
        got = pool.map(os.getenv, THREAD_VARIABLES)
    assert got == ["1"] * len(THREAD_VARIABLES)


def test_designs_on_the_build_pool_run_with_the_limits(clean_env, tmp_path, fast_mp):
    designs = []
    for name in ("threads_a", "threads_b"):    # two designs: one alone is built in this process
        path = tmp_path / "designs" / f"{name}.py"
        path.parent.mkdir(exist_ok=True)
        path.write_text(THREADS_DESIGN.format(names=THREAD_VARIABLES).replace('"threads"', repr(name)))
        designs.append(load_design(path))
    build_designs(designs, tmp_path / "out", quick=True, jobs=2, use_cache=False, stream=io.StringIO(),
                  mp_context=fast_mp)
    for name in ("threads_a", "threads_b"):
        got = {n["name"]: n["value"] for n in json.loads((tmp_path / "out" / name / "numbers.json").read_text())}
        assert got == dict.fromkeys(THREAD_VARIABLES, max(1, (os.cpu_count() or 1) // 2))
    assert not any(k in os.environ for k in THREAD_VARIABLES)


def test_blocks_that_overlap_in_two_threads_keep_the_limits_until_the_last_ends(clean_env):
    import threading

    entered, release = threading.Event(), threading.Event()

    def other():
        with worker_threads(2, cores=2):
            entered.set()
            release.wait(10)

    t = threading.Thread(target=other)
    t.start()
    assert entered.wait(10)
    with worker_threads(2, cores=2) as new:     # the other thread's block set them: the same values
        assert new == dict.fromkeys(THREAD_VARIABLES, "1")
    assert all(os.environ[k] == "1" for k in THREAD_VARIABLES)     # the other block is still open
    release.set()
    t.join(10)
    assert not any(k in os.environ for k in THREAD_VARIABLES)
