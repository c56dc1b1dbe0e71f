"""The chapter-7 design (designs/ch7_ctol.py) end to end with its quick settings (short horizon, cheap gains; the
real build uses FULL: the printed gains alone take about two minutes)."""

from __future__ import annotations

import math

import pytest

from glidectl.report import Report

DESIGN = "ch7_ctol"


def test_settings_presets(design):
    m = design.module
    assert m.FULL == m.Settings()
    assert m.FULL.printed == {"dt": 0.1, "k3": 7e5, "k4": 250.0}
    assert m.FULL.literal["k3"] == pytest.approx(7 * math.e**5)
    assert m.FULL.map_v.size == 45 and m.FULL.map_gamma.size == 65 and m.FULL.n_verify == 200_000
    assert m.QUICK.t_final < m.FULL.t_final and m.QUICK.n_verify < m.FULL.n_verify


def test_ch7_report_builds_with_required_numbers(quick_build):
    _, rep, pdf, nums = quick_build
    assert isinstance(rep, Report) and pdf.exists() and pdf.stat().st_size > 0
    assert nums["level_alpha_e_rad"]["value"] == pytest.approx(0.0632962, abs=1e-6)
    for name in ("level_k1", "level_k2", "zero_dynamics_eigenvalues", "lower_effort_than_inversion",
                 "theorem5_certified_k3_10_k4_5", "approx_lin_stopped_at"):
        assert name in nums, name
    lo, hi = nums["zero_dynamics_eigenvalues"]["value"]
    assert lo < 0 < hi and lo == pytest.approx(-hi)
    # Theorem 5 certifies the level glide with the small gains; every glide of the map is exponentially stable
    assert nums["theorem5_certified_k3_10_k4_5"]["value"] is True
    assert nums["theorem5_certified_k3_10_k4_5"]["reproduced"] is True
    for k3, k4 in ((7e5, 250.0), (1e3, 60.0), (10.0, 5.0)):
        assert nums[f"map_max_real_eig_k3_{k3:g}_k4_{k4:g}"]["value"] < 0
    # the printed-settings tracking is never counted as reproduced
    assert nums["printed_max_error"]["reproduced"] is False
    assert nums["lower_effort_than_inversion"]["reproduced"] is nums["lower_effort_than_inversion"]["value"]
    assert {p.name for p in pdf.parent.glob("*.png")} >= {"fig7_2_trajectory.png", "fig7_3_error.png",
                                                           "fig7_4_inputs.png", "pareto_front.png",
                                                           "theorem4_map.png", "zero_dynamics.png"}
