"""The build cache of ``glidectl report`` (issue 18 part 3): hits, exact invalidation, corrupt entries, --no-cache,
and the sub-result helper ``glidectl.report.cached``."""

from __future__ import annotations

import json
import pickle
from pathlib import Path

import pytest

import glidectl as gc
from glidectl.cli import main
from glidectl.report import cached, load_design
from glidectl.report.cache import DesignCache, design_key, recording, settings_of
from glidectl.report.parallel import build_designs

ROGUE = Path(gc.__file__).resolve().parent / "vehicles" / "rogue.toml"

TINY = '''
from dataclasses import dataclass
from pathlib import Path

import glidectl as gc
from glidectl.report import Report

TITLE = "tiny"
VEHICLE = {vehicle!r}
OVERRIDES = {overrides!r}


@dataclass(frozen=True)
class Settings:
    scale: float = 2.0


FULL = Settings()
QUICK = Settings(scale={quick_scale!r})


def design(progress, quick=False):
    s = QUICK if quick else FULL
    with open(Path(__file__).with_suffix(".runs"), "a") as f:  # counts the computations
        f.write("x")
    veh = gc.load_vehicle(VEHICLE, **OVERRIDES)
    rep = Report(TITLE, vehicle=veh)
    progress("numbers")
    rep.number("scaled_mbar", veh.mbar * s.scale, "kg")
    rep.number("K_M", veh.K_M, "kg/rad")
    return rep
'''


def _write_design(folder: Path, name: str, vehicle: str, overrides: dict | None = None,
                  quick_scale: float = 1.0) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    p = folder / f"{name}.py"
    p.write_text(TINY.format(vehicle=vehicle, overrides=overrides or {}, quick_scale=quick_scale))
    return p


def _runs(path: Path) -> int:
    f = path.with_suffix(".runs")
    return len(f.read_text()) if f.exists() else 0


def _build(paths: list[Path], out: Path, **kw) -> dict[str, gc.report.cache.BuildResult]:
    res = build_designs([load_design(p) for p in paths], out, quick=True, jobs=1, stream=_Null(), **kw)
    return {r.name: r for r in res}


class _Null:
    def write(self, s: str) -> int:
        return len(s)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False


def _numbers(out: Path, name: str) -> dict[str, float]:
    return {n["name"]: n["value"] for n in json.loads((out / name / "numbers.json").read_text())}


@pytest.fixture
def project(tmp_path):
    veh = tmp_path / "vehicles" / "my_rogue.toml"
    veh.parent.mkdir()
    veh.write_text(ROGUE.read_text())
    designs = tmp_path / "designs"
    a = _write_design(designs, "uses_file", str(veh))
    b = _write_design(designs, "uses_preset", "rogue")
    return tmp_path, veh, a, b


def test_unchanged_rebuild_is_a_hit_and_writes_the_same_files(project):
    tmp, _, a, b = project
    out = tmp / "out"
    first = _build([a, b], out)
    assert not any(r.from_cache for r in first.values())
    assert str(tmp / "vehicles" / "my_rogue.toml") in first["uses_file"].deps  # the vehicle file it read
    assert any(p.endswith("rogue.toml") for p in first["uses_preset"].deps)  # presets are tracked too
    before = {n: (out / n / "numbers.json").read_bytes() for n in first}
    (out / "uses_file" / "numbers.json").unlink()
    second = _build([a, b], out)
    assert all(r.from_cache for r in second.values())
    assert _runs(a) == 1 and _runs(b) == 1  # not computed again
    assert {n: (out / n / "numbers.json").read_bytes() for n in second} == before  # rewritten from the cache
    assert _numbers(out, "uses_file") == {"scaled_mbar": 2.0, "K_M": -36.5}
    timings = DesignCache(out / ".cache").timings()
    assert set(timings) == {"uses_file:quick", "uses_preset:quick"} and all(t > 0 for t in timings.values())


def test_changed_setting_recomputes_that_design_only(project):
    tmp, veh, a, b = project
    out = tmp / "out"
    _build([a, b], out)
    _write_design(a.parent, "uses_file", str(veh), quick_scale=3.0)  # QUICK changes
    res = _build([a, b], out)
    assert not res["uses_file"].from_cache and res["uses_preset"].from_cache
    assert _numbers(out, "uses_file")["scaled_mbar"] == pytest.approx(6.0)
    assert _runs(a) == 2 and _runs(b) == 1


def test_changed_vehicle_file_recomputes_exactly_the_designs_that_read_it(project):
    tmp, veh, a, b = project
    out = tmp / "out"
    _build([a, b], out)
    veh.write_text(veh.read_text().replace("value = -36.5", "value = -40.0"))
    res = _build([a, b], out)
    assert not res["uses_file"].from_cache and res["uses_preset"].from_cache
    assert _numbers(out, "uses_file")["K_M"] == -40.0
    assert _numbers(out, "uses_preset")["K_M"] == -36.5
    assert _build([a, b], out)["uses_file"].from_cache  # and the new result is cached in turn


def test_different_vehicle_override_recomputes(project):
    tmp, veh, a, _ = project
    out = tmp / "out"
    _build([a], out)
    _write_design(a.parent, "uses_file", str(veh), overrides={"K_M": -50.0})
    res = _build([a], out)
    assert not res["uses_file"].from_cache and _numbers(out, "uses_file")["K_M"] == -50.0


def test_key_depends_on_settings_quick_flag_and_source(project):
    _, _, a, _ = project
    d = load_design(a)
    src = a.read_bytes()
    k = design_key(d.name, src, True, settings_of(d.module, True))
    assert k == design_key(d.name, src, True, settings_of(d.module, True))
    assert settings_of(d.module, True) == "Settings(scale=1.0)"
    assert settings_of(d.module, False) == "Settings(scale=2.0)"
    others = {design_key(d.name, src, False, settings_of(d.module, False)), design_key(d.name, src + b"#", True,
              settings_of(d.module, True)), design_key("other", src, True, settings_of(d.module, True))}
    assert k not in others and len(others) == 3
    with pytest.raises(gc.ArgumentTypeError):
        design_key(d.name, "text", True, "")


@pytest.mark.parametrize("garbage", [b"", b"not a pickle", b"\x80\x05\x95truncated",
                                     pickle.dumps({"format": "old", "result": 1}),
                                     pickle.dumps({"format": "glidectl-cache-1", "key": "x", "result": None})])
def test_corrupt_entries_are_ignored_and_rebuilt(project, garbage):
    tmp, _, a, _ = project
    out = tmp / "out"
    _build([a], out)
    entries = list((out / ".cache" / "designs" / "uses_file").glob("*.pkl"))
    assert len(entries) == 1
    entries[0].write_bytes(garbage)
    res = _build([a], out)
    assert not res["uses_file"].from_cache and _runs(a) == 2
    assert _numbers(out, "uses_file")["scaled_mbar"] == 2.0
    assert _build([a], out)["uses_file"].from_cache  # the rebuilt entry replaced the corrupt one


def test_no_cache_forces_a_cold_build_from_the_command_line(project, capsys):
    tmp, _, a, _ = project
    out = tmp / "out"
    argv = ["report", str(a), "--out", str(out), "--quick", "--jobs", "1"]
    assert main(argv) == 0
    assert main(argv) == 0
    assert _runs(a) == 1 and "cache hit" in capsys.readouterr().out
    assert main([*argv, "--no-cache"]) == 0
    assert _runs(a) == 2 and "computed" in capsys.readouterr().out
    assert main(argv) == 0  # the cold build refreshed the cache
    assert _runs(a) == 2 and "cache hit" in capsys.readouterr().out


def test_cached_helper(tmp_path):
    calls = []

    def f(x):
        calls.append(x)
        return {"value": x * 2}

    assert cached(("double", 3), lambda: f(3)) == {"value": 6} and calls == [3]  # no build running: computed
    assert cached(("double", 3), lambda: f(3)) == {"value": 6} and calls == [3, 3]
    veh = gc.load_vehicle("rogue")
    with recording(tmp_path) as rec:
        assert cached(("double", 3, veh), lambda: f(3)) == {"value": 6}
        assert cached(("double", 3, veh), lambda: f(3)) == {"value": 6}  # hit
        assert cached(("double", 3, veh.with_overrides(K_M=-40.0)), lambda: f(3)) == {"value": 6}  # other vehicle
        assert cached(("double", 3.0000001, veh), lambda: f(3)) == {"value": 6}  # other key
    assert len(calls) == 5 and (rec.run.hits, rec.run.misses) == (1, 3)
    for p in (tmp_path / "results").glob("*.pkl"):
        p.write_bytes(b"\x80\x05garbage")  # corrupt: recomputed, never an error
    with recording(tmp_path) as rec:
        assert cached(("double", 3, veh), lambda: f(3)) == {"value": 6}
    assert rec.run.misses == 1 and len(calls) == 6
    with recording(tmp_path, refresh=True) as rec:  # --no-cache: computed again, entry overwritten
        assert cached(("double", 3, veh), lambda: {"value": "new"}) == {"value": "new"}
    with recording(tmp_path) as rec:
        assert cached(("double", 3, veh), lambda: f(3)) == {"value": "new"}
    assert rec.run.hits == 1
    with recording(tmp_path) as rec:  # results holding closures (certificates, models) are cached too
        for _ in range(2):
            g = cached(("closure", 2), lambda: {"f": (lambda k: (lambda x: k * x))(2.5)})
            assert g["f"](4.0) == 10.0
    assert (rec.run.hits, rec.run.misses) == (1, 1)
    with pytest.raises(gc.ArgumentTypeError, match="callable"):
        cached("k", 3)
    with pytest.raises(gc.ArgumentTypeError, match="canonical"):
        cached(object(), lambda: 1)


# ------------------------------------------------------------------ one value shared by the designs of a build
def _slow_double(args: tuple[str, str, str, bool, float]) -> tuple[int, list[bool]]:
    """A process that asks for a cached value which takes ``delay`` s: logs each computation to ``log``; returns
    the value and whether, inside the computation, this process held the key's lock."""
    import time as _t

    from glidectl.report.cache import holds_lock

    root, log, build, refresh, delay = args
    held: list[bool] = []

    def compute() -> int:
        held.append(holds_lock())
        with open(log, "a") as f:
            f.write("x")
        _t.sleep(delay)
        return 42

    with recording(Path(root), refresh=refresh, build=build):
        return cached(("shared", 1), compute), held


def test_a_value_two_processes_of_one_cold_build_ask_for_is_computed_once(tmp_path):
    """Two processes of the same --no-cache build (refresh, same build id) ask for one key at the same time: one
    computes it under the key's lock, the other waits and reads it. A later cold build (another id) computes it
    again; a warm one (no refresh) reads it whatever its id."""
    import multiprocessing

    log = tmp_path / "log"
    args = (str(tmp_path), str(log), "build-1", True, 1.5)
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        out = pool.map(_slow_double, [args, args])
    assert [v for v, _ in out] == [42, 42]
    assert log.read_text() == "x"                      # computed once
    assert [h for _, h in out if h] == [[True]]        # by the process that held the lock
    # another cold build: an entry of build-1 is stale for it
    assert _slow_double((str(tmp_path), str(log), "build-2", True, 0.0)) == (42, [True])
    assert log.read_text() == "xx"
    # the same cold build again, and a warm build: the entry is read
    assert _slow_double((str(tmp_path), str(log), "build-2", True, 0.0)) == (42, [])
    assert _slow_double((str(tmp_path), str(log), "build-3", False, 0.0)) == (42, [])
    assert log.read_text() == "xx"
    # a cold run without a build id (a design run alone under recording(refresh=True)) always computes
    assert _slow_double((str(tmp_path), str(log), None, True, 0.0)) == (42, [True])
    assert log.read_text() == "xxx"


def test_the_key_lock_is_held_while_the_value_is_computed(tmp_path):
    """While one process computes a key, its lock file is taken (a non-blocking try fails), and free afterwards:
    what makes a second process of the build wait instead of computing the value again."""
    import fcntl
    import multiprocessing
    import time

    log = tmp_path / "log"
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        res = pool.apply_async(_slow_double, [(str(tmp_path), str(log), "b", True, 3.0)])
        t0 = time.perf_counter()
        while not log.exists() and time.perf_counter() - t0 < 60:
            time.sleep(0.05)
        lock, = tmp_path.joinpath("results").glob("*.lock")
        with open(lock, "a+b") as f:
            with pytest.raises(BlockingIOError):
                fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
            assert res.get(timeout=60) == (42, [True])
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)      # released: taken at once


def test_threads_of_one_process_share_a_value_too(tmp_path):
    """Threads (a dask worker runs designs on threads) lock per thread: the second waits for the first's lock and
    reads the value, so it is computed once."""
    import threading
    import time

    calls, out = [], []

    def compute() -> int:
        calls.append(1)
        time.sleep(1.0)
        return 5

    def ask() -> None:
        with recording(tmp_path, refresh=True, build="t"):
            out.append(cached(("threads", 1), compute))

    threads = [threading.Thread(target=ask) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert out == [5, 5] and len(calls) == 1


def test_nested_cached_calls_take_one_lock_and_never_wait_for_themselves(tmp_path):
    """Only the outermost cached call of a process locks (a nested call with the same key would otherwise wait for
    its own lock forever); the parts a design starts under a lock are told not to lock."""
    from glidectl.report.cache import holds_lock

    seen = []
    with recording(tmp_path):
        def inner() -> int:
            seen.append(holds_lock())
            return cached(("outer",), lambda: 7) + 1     # the same key as the outer call: no self-wait

        assert cached(("outer",), inner) == 8
        assert not holds_lock()
    assert seen == [True]
    locks = sorted(tmp_path.joinpath("results").glob("*.lock"))
    assert len(locks) == 1                              # the outer key's
    with recording(tmp_path, lock=False):
        assert cached(("unlocked",), lambda: holds_lock()) is False
    assert sorted(tmp_path.joinpath("results").glob("*.lock")) == locks


def test_two_designs_of_a_cold_parallel_build_share_a_cached_value(tmp_path):
    """The build machinery gives every design of one build the same id: with --no-cache and two workers, a value
    both designs cache under the same key is computed once, and both reports show it."""
    src = '''
from pathlib import Path
import time
from glidectl.report import Report, cached

TITLE = "shares"


def design(progress, quick=False):
    def compute():
        with open(Path(__file__).parent / "computed.log", "a") as f:
            f.write("x")
        time.sleep(1.0)
        return 2.5

    rep = Report(TITLE)
    rep.number("shared", cached(("shared value", 1), compute), "-")
    return rep
'''
    folder = tmp_path / "designs"
    folder.mkdir()
    paths = []
    for name in ("first", "second"):
        p = folder / f"{name}.py"
        p.write_text(src)
        paths.append(p)
    out = tmp_path / "out"
    for round_ in (1, 2):
        res = build_designs([load_design(p) for p in paths], out, quick=True, jobs=2, use_cache=False,
                            stream=_Null())
        assert [_numbers(out, r.name)["shared"] for r in res] == [2.5, 2.5]
        assert (folder / "computed.log").read_text() == "x" * round_   # once per cold build
        assert sorted((r.sub_hits, r.sub_misses) for r in res) == [(0, 1), (1, 0)]
