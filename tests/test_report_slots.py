"""Compute slots of a pool build (``glidectl.report.slots``): designs on a pool of ``jobs`` workers, each with its
own parts pool, never compute in more than ``jobs`` processes at once; a design that waits for its parts or for
another design's shared value lends its slot."""

from __future__ import annotations

import io
import multiprocessing
import threading
import time
from pathlib import Path

import pytest

from glidectl.report import load_design, slots
from glidectl.report.parallel import build_designs

# a design whose parts sleep and log the interval in which they computed (monotonic clock: system-wide on Linux);
# BODY computes `rows`
PARTS = '''
import os
import time
from pathlib import Path

from glidectl.report import Report, cached, map_parts

TITLE = "{name}"
LOG = Path({log!r})


def part(i):
    t0 = time.monotonic()
    time.sleep({sleep})
    (LOG / f"{name}-{{i}}-{{os.getpid()}}").write_text(f"{{t0!r}} {{time.monotonic()!r}}")
    return i


def slow_shared():
    time.sleep(1.0)         # the other design reaches the lock and waits (a loaded machine: a wide margin)
    return map_parts(part, [0, 1])


def design(progress, quick=False):
    rows = {body}
    rep = Report(TITLE)
    rep.number("parts", len(rows), "1")
    return rep
'''


def _designs(tmp: Path, body: str, names: tuple[str, ...], sleep: float) -> tuple[list, Path]:
    log = tmp / "log"
    log.mkdir()
    folder = tmp / "designs"
    folder.mkdir()
    designs = []
    for name in names:
        p = folder / f"{name}.py"
        p.write_text(PARTS.format(name=name, log=str(log), sleep=sleep, body=body))
        designs.append(load_design(p))
    return designs, log


def _intervals(log: Path) -> list[tuple[float, float]]:
    return [tuple(map(float, f.read_text().split())) for f in sorted(log.iterdir())]


def _most_at_once(intervals: list[tuple[float, float]]) -> int:
    """The largest number of intervals that contain a common instant (checked at every start)."""
    return max(sum(a <= t < b for a, b in intervals) for t, _ in intervals)


def test_two_designs_with_parts_compute_in_at_most_jobs_processes(tmp_path, fast_mp):
    designs, log = _designs(tmp_path, "map_parts(part, [0, 1, 2, 3])", ("parts_a", "parts_b"), 0.4)
    res = build_designs(designs, tmp_path / "out", quick=True, jobs=2, use_cache=False, stream=io.StringIO(),
                        mp_context=fast_mp)
    assert [r.name for r in res] == ["parts_a", "parts_b"]
    spans = _intervals(log)
    assert len(spans) == 8
    # two designs x two part workers would compute 4 at once without the build's slots
    assert _most_at_once(spans) <= 2


def test_a_design_waiting_for_a_shared_value_lends_its_slot(tmp_path, fast_mp):
    # both designs ask for the same cached value; the one that computes it maps two parts under the lock, and they
    # run at once only if the waiting design has lent its slot (jobs 2: the computing design lent its own)
    designs, log = _designs(tmp_path, "cached(('shared', str(LOG)), slow_shared)", ("wait_a", "wait_b"), 0.8)
    build_designs(designs, tmp_path / "out", quick=True, jobs=2, use_cache=False, stream=io.StringIO(),
                  mp_context=fast_mp)
    spans = _intervals(log)
    assert len(spans) == 2          # computed once, by one of the two designs
    assert _most_at_once(spans) == 2


@pytest.fixture
def one_slot():
    sem = slots.Slots(1, multiprocessing.get_context("spawn"))
    slots.install(sem)
    yield sem
    slots.install(None)


def test_holding_lent_and_repay_on_one_slot(one_slot):
    assert slots.current() is one_slot and one_slot.held() == 0
    with slots.holding():
        assert one_slot.held() == 1
        with slots.holding():                           # a thread holds one slot, not two
            assert one_slot.held() == 1
        with slots.lent():
            assert one_slot.held() == 0                 # given back while lent ...
        assert one_slot.held() == 1                     # ... and taken again after
    assert one_slot.held() == 0
    slots.repay()                                       # nothing held: nothing to give back
    assert one_slot.held() == 0
    one_slot.acquire()                                  # a slot lost with a dead worker comes back
    slots.repay()
    assert one_slot.held() == 0
    with slots.holding():
        assert one_slot.held() == 1


def test_slots_are_served_first_come_first_served(one_slot):
    # a holder that gives its slot back and asks again at once comes after the request already waiting
    order = []
    one_slot.acquire()
    waiter = threading.Thread(target=lambda: (one_slot.acquire(), order.append("waiter"), one_slot.release()))
    waiter.start()
    deadline = time.monotonic() + 30
    while one_slot._issued.value < 2 and time.monotonic() < deadline:     # the waiter has taken its ticket
        time.sleep(0.01)
    one_slot.release()
    one_slot.acquire()
    order.append("holder again")
    one_slot.release()
    waiter.join(30)
    assert order == ["waiter", "holder again"]


def test_without_a_semaphore_the_slots_do_nothing():
    assert slots.current() is None
    with slots.holding(), slots.lent():
        slots.repay()
