"""The waypoint-mission design (designs/slocum_waypoint_mission.py) end to end with its quick settings: two
controller sets on a waypoint mission in a depth-varying current, and a designed turn flown as a spiral."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc

DESIGN = "slocum_waypoint_mission"


def test_settings_presets(design):
    m = design.module
    assert m.FULL == m.Settings() and m.Settings.__dataclass_params__.frozen
    assert len(m.FULL.waypoints) == 4 and m.FULL.depths == (5.0, 100.0)
    assert m.CONTROLLERS == ("behaviours", "lqr")


def test_report_files_and_numbers(quick_build):
    _, rep, pdf, numbers = quick_build
    assert pdf.exists() and pdf.stat().st_size > 50_000
    assert {p.stem for p in pdf.parent.glob("*.png")} == {"mission_behaviours", "mission_lqr", "mission_3d",
                                                           "designed_turn"}
    assert not rep.has_ledger
    truth = np.array(numbers["depth_mean_current"]["value"])
    for name in ("behaviours", "lqr"):
        assert numbers[f"{name}_waypoints_reached"]["value"] == 2
        # the estimate tracks the depth-mean current: within the GPS noise over a dive plus the dead reckoning's
        # own speed error (a few percent of the 0.35 m/s glide)
        assert numbers[f"{name}_current_estimate_error"]["value"] < 0.35 * 0.1 + 2 * 5.0 * math.sqrt(2) / 600.0
        assert numbers[f"{name}_pump_energy_per_km"]["value"] < numbers[f"{name}_energy_per_km"]["value"]
    # the first dive dead-reckons without any current: its error is the depth-mean current times the dive time
    for name in ("behaviours", "lqr"):
        expected = float(np.hypot(*truth)) * numbers[f"{name}_first_dive_time"]["value"]
        assert numbers[f"{name}_first_dive_dr_error"]["value"] == pytest.approx(expected, rel=0.1)
    assert numbers["turn_radius_flown"]["value"] == pytest.approx(150.0, rel=0.02)


def test_depth_mean_of_a_profile(design):
    c = gc.Current.profile([0.0, 100.0], [0.2, 0.0], [0.0, 0.1])
    np.testing.assert_allclose(design.module.depth_mean(c, 0.0, 100.0), [0.1, 0.05], atol=1e-12)
    np.testing.assert_allclose(design.module.depth_mean(c, 0.0, 50.0), [0.15, 0.025], atol=1e-12)
