"""The Slocum dive-cycle design (designs/slocum_dive_cycle.py) end to end with its quick settings (a one-cycle
5-30 m mission, a coarser envelope grid)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.controllers.dive_cycle import LQG_NOISE

DESIGN = "slocum_dive_cycle"


def test_settings_presets(design):
    m = design.module
    assert m.FULL == m.Settings() and m.Settings.__dataclass_params__.frozen
    assert dataclasses.is_dataclass(m.Settings)
    # the mission of issue 16: three cycles between 5 and 100 m at 0.35 m/s, +-25 deg
    assert (m.FULL.depths, m.FULL.cycles, m.FULL.speed, m.FULL.gamma_deg) == ((5.0, 100.0), 3, 0.35, 25.0)
    assert m.QUICK.depths[1] < m.FULL.depths[1] and m.QUICK.cycles <= m.FULL.cycles
    assert (m.QUICK.vehicle, m.QUICK.speed, m.QUICK.noise, m.QUICK.seed) == (m.FULL.vehicle, m.FULL.speed,
                                                                             m.FULL.noise, m.FULL.seed)
    assert dict(m.FULL.noise) == pytest.approx(LQG_NOISE)  # the design flies the documented sensor noise
    assert m.CONTROLLERS == ("lqr", "lqg", "nonlinear", "pid")


def test_report_files_and_parameter_table(quick_build):
    _, rep, pdf, _ = quick_build
    assert pdf.exists() and pdf.stat().st_size > 50_000
    assert {p.stem for p in pdf.parent.glob("*.png")} == {"glide_envelope", "mission_lqr", "mission_lqg",
                                                          "mission_pid"}
    assert not rep.has_ledger  # no published results for this glider: a plain results table
    assert [v.name for v in rep.vehicles] == ["slocum_shallow"]
    # the parameter table carries the [actuators] rows: pump and battery with range and rate, r_P3 fixed
    rows = {r[0]: r for r in rep.vehicles[0].summary_rows()}
    assert {"[actuator] m0", "[actuator] r_P1", "[actuator] r_P3"} <= set(rows)
    assert "0.25" in rows["[actuator] m0"][1] and "0.01" in rows["[actuator] m0"][1]
    assert "fixed" in rows["[actuator] r_P3"][1] and "0.05" in rows["[actuator] r_P3"][1]
    headings = [h for h, _ in rep.sections]
    assert "Region of attraction of the LQR loop" in headings
    body = dict(rep.sections)["Region of attraction of the LQR loop"]
    # certify_roa gets the loop's default box (no refusal for lack of one), holds the two locked r_P3 states (no
    # refusal for their zero eigenvalues) and answers within the design's budget; unless it certified, the report
    # points to the LMI certificate of the loop
    assert "no limits known" not in body and "gc.validity_box" in body and "8 states" in body
    assert "not exponentially stable" not in body
    assert ("BudgetError" in body and "roa_certification" in body and "Saturated loops" in body) or \
        "certified: ROACertificate" in body
    # the table of that box is gc.validity_box of the loop (the same box gc.saturated_loop defaults to)
    veh = gc.load_vehicle("slocum_shallow")
    loop = gc.closed_loop(gc.lqr_glide(veh, gc.steady_glide(veh, 0.35, -math.radians(25), r_p3=0.05),
                                       inputs="acceleration"))
    lo, hi = gc.validity_box(loop)
    (rows,) = [r for c, _, r in rep.tables if "gc.validity_box" in c]
    assert [r[0] for r in rows] == list(loop.state_names)
    np.testing.assert_allclose([[float(r[1]), float(r[3])] for r in rows], np.c_[lo, hi], rtol=1e-5)
    np.testing.assert_allclose(np.c_[lo, hi], np.c_[gc.saturated_loop(loop).box], rtol=0, atol=0)


def test_envelope_and_mission_glides(quick_build):
    nums = quick_build.numbers
    veh = gc.load_vehicle("slocum_shallow")
    assert nums["mission_glides_feasible"]["value"] is True
    g = gc.steady_glide(veh, 0.35, -math.radians(25), r_p3=0.05)
    assert nums["mission_glide_m0"]["value"] == pytest.approx([g.m0, -g.m0], rel=1e-9)
    assert nums["mission_glide_r_p1"]["value"] == pytest.approx([g.r_p1, -g.r_p1], rel=1e-9)
    lo, hi = veh.actuators["r_P1"].bounds
    assert lo <= g.r_p1 <= hi
    assert 0 < nums["envelope_feasible_fraction"]["value"] < 1
    # the mission's horizontal speed is inside the envelope's range
    assert 0.35 * math.cos(math.radians(25)) < nums["envelope_max_horizontal_speed"]["value"] <= 0.8


def test_lqr_and_lqg_designs_are_stable(quick_build):
    nums = quick_build.numbers
    for leg in ("down", "up"):
        poles = np.array(nums[f"lqr_{leg}_poles"]["value"])
        est = np.array(nums[f"lqg_{leg}_estimator_poles"]["value"])
        assert poles.shape == (7, 2) and np.all(poles[:, 0] < 0)  # theta, Omega2, v1, v3, r_P1, rdot_P1, m0
        assert est.shape == (8, 2) and np.all(est[:, 0] < 0)  # and the depth
        assert nums[f"lqr_path_{leg}_max_real_pole"]["value"] < 0
    # the report's regulator poles are those of lqg_glide at the glide (recomputed here)
    veh = gc.load_vehicle("slocum_shallow")
    g = gc.steady_glide(veh, 0.35, -math.radians(25), r_p3=0.05)
    d = gc.lqg_glide(veh, g, ("z", "theta", "Omega2"), LQG_NOISE, inputs="acceleration")
    np.testing.assert_allclose(np.sort(np.array(nums["lqr_down_poles"]["value"])[:, 0]),
                               np.sort(d.regulator_poles.real), rtol=1e-9)


def test_mission_comparison_numbers(quick_build, design):
    nums = quick_build.numbers
    s = design.module.QUICK
    top, bottom = s.depths
    gamma = math.radians(s.gamma_deg)
    for c in ("lqr", "lqg", "pid"):
        dist = nums[f"mission_{c}_distance_per_cycle"]["value"]
        dur = nums[f"mission_{c}_duration_per_cycle"]["value"]
        e = nums[f"mission_{c}_energy_per_cycle"]["value"]
        sat = nums[f"mission_{c}_saturated_time_per_cycle"]["value"]
        assert np.isfinite([dist, dur, e, sat]).all() and e > 0 and 0 <= sat <= dur
        # the two straight legs alone cover 2 (bottom - top) / tan(gamma); the inflections glide flatter
        assert dist > 2 * (bottom - top) / math.tan(gamma)
        assert 0 <= nums[f"mission_{c}_max_overshoot"]["value"] < 10.0
    # the linear designs fly the requested glide: the cycle lasts about the two legs at 0.35 m/s, plus inflections
    nominal = 2 * (bottom - top) / (0.35 * math.sin(gamma))
    for c in ("lqr", "lqg"):
        assert nominal < nums[f"mission_{c}_duration_per_cycle"]["value"] < 1.3 * nominal
    # the PID baseline runs the pump to its ends: faster than the 0.35 m/s glides
    assert nums["mission_pid_duration_per_cycle"]["value"] < nums["mission_lqr_duration_per_cycle"]["value"]
    # the chapter-6 controller is refused on this vehicle, naming the assumption it breaks
    refused = nums["mission_nonlinear_refused"]["value"]
    assert "ModelError" in refused and "r_P = 0" in refused
    # QUICK gives certify_roa 20 s: on this machine it answers with the budget (FULL, without a limit, certifies
    # it); either way the number, the volume and the text agree
    body = dict(quick_build[1].sections)["Region of attraction of the LQR loop"]
    if nums["roa_lqr_certified"]["value"]:
        assert nums["roa_lqr_volume"]["value"] > 0 and "The certified set has volume" in body
    else:
        assert "roa_lqr_volume" not in nums and "without one (the FULL settings) it certifies it" in body
        assert "a budget of 20 s it answered: BudgetError" in body


def test_the_lqr_loop_certificate_is_shared_with_roa_certification(design, monkeypatch):
    """slocum_dive_cycle (FULL) and roa_certification ask ``cached`` for the user glider's LQR-loop certificate
    under the same key and the same call, so a build computes it once; a QUICK run (20 s budget, which can change
    the certificate) asks under another key."""
    import json

    from glidectl.report import load_design
    from glidectl.report.cache import _digest

    other = load_design(design.path.parent / "roa_certification.py").module
    seen: dict[str, list] = {"slocum": [], "roa": []}

    def recorder(tag):
        def fake(key, fn):
            seen[tag].append(json.dumps(_digest(key)))
            return None
        return fake

    m = design.module
    veh = gc.load_vehicle(m.FULL.vehicle)
    glide = gc.steady_glide(veh, m.FULL.speed, -math.radians(m.FULL.gamma_deg), r_p3=veh.actuators["r_P3"].fixed)
    ctrl = gc.lqr_glide(veh, glide, inputs="acceleration")
    loop = gc.closed_loop(ctrl)
    monkeypatch.setattr(m, "cached", recorder("slocum"))
    monkeypatch.setattr(other, "cached", recorder("roa"))
    m._certify_lqr_loop(veh, ctrl, loop, m.FULL.roa_time_limit)
    m._certify_lqr_loop(veh, ctrl, loop, m.QUICK.roa_time_limit)
    other._certify_lqr_loop(*other._user_glider_loop())
    full, quick = seen["slocum"]
    assert seen["roa"] == [full] and quick != full
    assert dict(m.ROA_ARGS, budget=gc.BudgetOptions(time_limit=m.FULL.roa_time_limit)) == other.USER_ROA_ARGS
