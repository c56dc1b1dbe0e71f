"""bench/bench_report_spy.py: how a py-spy recording of the build is read (the innermost activity wins, idle stacks
are left out, a stack counts for the design whose file is in it)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def spy():
    spec = importlib.util.spec_from_file_location("bench_report_spy", ROOT / "bench" / "bench_report_spy.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


P = 'process 1:"python -m glidectl report all";process 2:"python -c spawn_main"'
DESIGN = "_part (designs/roa_certification.py:190)"
CERT = "certify_roa (glidectl/roa/certify.py:2462)"
VERIFY = "_verify (glidectl/roa/certify.py:1911)"
BATCH = "integrate_batch (glidectl/batch.py:418)"
CLARABEL = "CLARABEL.solve_via_data (cvxpy/reductions/solvers/conic_solvers/clarabel_conif.py:267)"
LEVEL = "_level (glidectl/roa/certify.py:1017)"


def _write(tmp_path: Path, lines: list[tuple[list[str], int]]) -> Path:
    raw = tmp_path / "build.raw"
    raw.write_text("".join(";".join([P, *frames]) + f" {n}\n" for frames, n in lines))
    return raw


def test_each_busy_sample_goes_to_its_innermost_activity_and_its_design(spy, tmp_path):
    raw = _write(tmp_path, [
        ([DESIGN, CERT, VERIFY, BATCH, "rhs (glidectl/models/reduced.py:208)"], 30),   # simulation inside a check
        ([DESIGN, CERT, LEVEL, CLARABEL], 50),                                          # a solve inside a level
        ([DESIGN, CERT, VERIFY, "Poly.__call__ (glidectl/roa/polynomial.py:249)"], 10),
        (["_find_and_load (<frozen importlib._bootstrap>:1176)", "<module> (cvxpy/__init__.py:1)"], 8),
        (["design (designs/ch2_longitudinal.py:300)", "trim (glidectl/trim.py:10)"], 2),
        ([DESIGN, "Condition.wait (threading.py:320)"], 500),                           # idle: left out
    ])
    res = spy.read_raw(raw, ["roa_certification", "ch2_longitudinal"])
    assert res["samples"] == 100 and res["idle_samples"] == 500
    act = res["activity"]
    assert act["batch simulations (Rosenbrock, stiff)"] == pytest.approx(0.30)
    assert act["SDP: Clarabel (interior point)"] == pytest.approx(0.50)
    assert act["certificate sampling / radii / checks"] == pytest.approx(0.10)
    assert act["imports (process starts, lazy imports)"] == pytest.approx(0.08)
    assert act["other"] == pytest.approx(0.02)
    assert sum(act.values()) == pytest.approx(1.0)
    des = res["design"]
    assert des == pytest.approx({"roa_certification": 0.90, "(no design frame)": 0.08, "ch2_longitudinal": 0.02})
    # inclusive shares count a function once per stack, self shares only the leaf
    assert res["inclusive"]["certify_roa [certify.py]"] == pytest.approx(0.90)
    assert res["inclusive"]["_verify [certify.py]"] == pytest.approx(0.40)
    assert "certify_roa [certify.py]" not in res["self"]


def test_an_empty_recording_has_no_shares(spy, tmp_path):
    raw = _write(tmp_path, [([DESIGN, "time.sleep (<built-in>:0)"], 7)])
    res = spy.read_raw(raw, ["roa_certification"])
    assert res["samples"] == 0 and res["idle_samples"] == 7
    assert res["activity"] == {} and res["design"] == {}
