"""Independent parts inside one design (issue 18 part 2): ``glidectl.report.map_parts`` gives the serial results on a
process pool and on a dask cluster, and what a part reads or caches in another process counts for the design's
cache entry."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest

import glidectl as gc
from glidectl.report import cached, load_design, map_parts
from glidectl.report.parallel import build_designs, build_one
from glidectl.report.parts import parts_context

ROGUE = Path(gc.__file__).resolve().parent / "vehicles" / "rogue.toml"

# a design whose three parts each load the vehicle file, trim a glide and cache a value; pid and a seed per part
PARTED = '''
import os
import time

import numpy as np

import glidectl as gc
from glidectl.report import Report, cached, map_parts

TITLE = "parted"
VEHICLE = {vehicle!r}


def part(gamma_deg):
    time.sleep(0.5)     # long enough that the pool's second worker takes a part (fast parts may all go to one)
    veh = gc.load_vehicle(VEHICLE)
    g = gc.steady_glide(veh, 0.3, np.radians(gamma_deg), r_p3=0.05)
    noise = cached(("noise", gamma_deg), lambda: float(np.random.default_rng(int(-gamma_deg)).random()))
    scale = veh.K_M
    return g.m0, (lambda x: scale * x), noise, os.getpid()  # a closure comes back too (cloudpickle)


def design(progress, quick=False):
    rows = map_parts(part, [-45.0, -35.0, -25.0])
    rep = Report(TITLE, vehicle=gc.load_vehicle(VEHICLE))
    rep.number("m0", [r[0] for r in rows], "kg")
    rep.number("K_M", [r[1](1.0) for r in rows], "kg/rad")
    rep.number("noise", [r[2] for r in rows], "1")
    rep.number("processes", len({{r[3] for r in rows}}), "1")
    return rep
'''


def _numbers(out: Path) -> dict:
    return {n["name"]: n["value"] for n in json.loads((out / "parted" / "numbers.json").read_text())}


@pytest.fixture
def parted(tmp_path):
    veh = tmp_path / "my_rogue.toml"
    veh.write_text(ROGUE.read_text())
    p = tmp_path / "designs" / "parted.py"
    p.parent.mkdir()
    p.write_text(PARTED.format(vehicle=str(veh)))
    return p, veh


def test_outside_a_build_map_parts_is_a_plain_map():
    assert map_parts(abs, [-1, 2, -3]) == [1, 2, 3]
    with parts_context("x", "x.py", b"", jobs=1):  # one job: serial too, in this process
        assert map_parts(abs, (-4,)) == [4]


def test_bad_arguments_are_refused():
    with pytest.raises(gc.ArgumentTypeError, match="module-level"):
        map_parts(lambda x: x, [1, 2])
    with pytest.raises(gc.ArgumentTypeError, match="sequence"):
        map_parts(abs, iter([1, 2]))
    with pytest.raises(gc.ArgumentTypeError, match="function"):
        map_parts(3, [1])
    with pytest.raises(gc.ArgumentError, match="positive integer"), parts_context("x", "x.py", b"", jobs=0):
        pass
    with pytest.raises(gc.ArgumentError, match="start_method"), parts_context("x", "x.py", b"", 2, start_method="no"):
        pass


def test_pool_and_cluster_parts_equal_the_serial_parts_and_count_as_the_design_reads(parted, tmp_path, fast_mp):
    path, veh = parted
    design = load_design(path)
    serial = tmp_path / "serial"
    build_designs([design], serial, quick=True, jobs=1, use_cache=False, stream=io.StringIO())
    ref = _numbers(serial)
    assert ref["processes"] == 1 and ref["K_M"] == [-36.5] * 3
    # one design, two jobs: its three parts run on a pool of two spawned workers
    res = build_one("parted", str(path), path.read_bytes(), True, cache_root=str(tmp_path / "cache"), jobs=2,
                    start_method=fast_mp.get_start_method())
    assert res.sub_misses == 3 and res.sub_hits == 0  # the parts' cached() calls reach the build's cache
    assert str(veh) in res.deps  # the vehicle file read inside the workers is a dependency
    got = {n["name"]: n["value"] for n in json.loads(res.files["numbers.json"])}
    assert got["processes"] == 2
    assert {k: v for k, v in got.items() if k != "processes"} == {k: v for k, v in ref.items() if k != "processes"}
    again = build_one("parted", str(path), path.read_bytes(), True, cache_root=str(tmp_path / "cache"), jobs=2,
                      start_method=fast_mp.get_start_method())
    assert again.sub_hits == 3 and again.sub_misses == 0
    distributed = pytest.importorskip("distributed")  # the dask extra (installed by .ci/run)
    with distributed.LocalCluster(processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None) as lc:
        build_designs([design], tmp_path / "cluster", quick=True, scheduler=lc.scheduler_address, use_cache=False,
                      stream=io.StringIO())
    assert _numbers(tmp_path / "cluster") == ref  # threads of one process: the same pid, the same numbers


def test_a_changed_file_read_only_inside_a_part_invalidates_the_design(parted, tmp_path, fast_mp):
    path, veh = parted
    design = load_design(path)
    out = tmp_path / "out"
    first = build_designs([design], out, quick=True, jobs=2, stream=io.StringIO(), mp_context=fast_mp)[0]
    assert not first.from_cache and str(veh) in first.deps
    assert build_designs([design], out, quick=True, jobs=2, stream=io.StringIO(), mp_context=fast_mp)[0].from_cache
    veh.write_text(veh.read_text().replace("value = -36.5", "value = -40.0"))
    res = build_designs([design], out, quick=True, jobs=2, stream=io.StringIO(), mp_context=fast_mp)[0]
    assert not res.from_cache and _numbers(out)["K_M"] == [-40.0] * 3


def test_cached_inside_a_serial_part_is_the_plain_helper():
    assert cached(("plain", 1), lambda: 7) == 7


def test_a_fresh_worker_loads_the_design_it_runs_a_part_of(parted, tmp_path):
    """What a spawned worker (or a remote dask worker without the file) does: load the shipped design source, then
    call the part by name; the result, reads and cache counts come back pickled."""
    import pickle
    import sys

    from glidectl.report.parts import _run_part

    path, veh = parted
    module = load_design(path).module.__name__
    del sys.modules[module]  # a new process has not loaded it
    blob = _run_part(module, "part", ("parted", str(tmp_path / "gone" / "parted.py"), path.read_bytes()),
                     pickle.dumps(-35.0), None, False)
    m0, K_M, _, _ = pickle.loads(blob)[0]
    assert module in sys.modules and K_M(2.0) == -73.0
    assert str(veh) in pickle.loads(blob)[1]
    assert m0 == gc.steady_glide(gc.load_vehicle(str(veh)), 0.3, -35.0 * 3.141592653589793 / 180, r_p3=0.05).m0


def test_parts_started_inside_a_cached_computation_take_no_lock(tmp_path, monkeypatch):
    """A design that runs map_parts inside cached() holds that key's lock while its parts run: the parts then take
    no lock of their own (a part waiting for a lock that another design holds while that design waits for this
    design's key would be a cycle). Outside cached() they lock as usual. The spy reaches forked workers."""
    from glidectl.report import parts
    from glidectl.report.cache import recording

    log = tmp_path / "locks.txt"
    real = parts.recording

    def spy(cache_root, refresh=False, build=None, lock=True):
        with log.open("a") as f:
            f.write(f"{int(lock)}\n")
        return real(cache_root, refresh, build, lock)

    monkeypatch.setattr(parts, "recording", spy)
    cache = tmp_path / "cache"
    with recording(cache), parts_context("x", "x.py", b"", jobs=2, cache_root=str(cache), start_method="fork"):
        assert map_parts(abs, [-1, -2]) == [1, 2]
        assert cached(("outer",), lambda: map_parts(abs, [-3, -4])) == [3, 4]
    assert log.read_text().split() == ["1", "1", "0", "0"]
