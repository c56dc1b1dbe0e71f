"""The chapter-8 design (designs/ch8_helix.py) end to end with its quick settings (the real build uses FULL)."""

from __future__ import annotations

import math

import pytest

DESIGN = "ch8_helix"
STEMS = {"fig8_2_trajectory", "fig8_3_position_orientation", "fig8_4_velocities", "fig8_5", "fig8_6", "fig8_7",
         "fig8_8", "fig8_9", "fig8_10", "fig8_11", "fig8_12", "fig8_existence_scan", "fig8_13_rbh_real_parts",
         "fig8_14_rbh_locus"}


def test_settings_presets(design):
    mod = design.module
    full, quick = mod.FULL, mod.QUICK
    assert full == mod.Settings()
    assert full.sim_t == 2000.0 and full.rbh_grid == (-0.03, 0.10, 261) and full.scan_starts == 30
    assert full.fold_step == 2e-6 and len(full.map_cases) == 8 and len(full.design_targets) == 4
    assert [c[0] for c in quick.map_cases] == [c[0] for c in full.map_cases]
    assert sum(c[2][2] for c in quick.map_cases) < sum(c[2][2] for c in full.map_cases) / 4
    with pytest.raises(AttributeError):
        full.sim_t = 1.0  # frozen


def test_ch8_report_files(quick_build):
    pdf = quick_build.pdf
    assert pdf.exists() and pdf.stat().st_size > 100_000
    pngs = {p.stem: p for p in pdf.parent.glob("*.png")}
    assert set(pngs) == STEMS
    assert all(p.stat().st_size > 10_000 for p in pngs.values())


def test_ch8_printed_helix_reproduced(quick_build):
    nums = quick_build.numbers
    for entry in nums.values():
        assert {"name", "value", "published", "unit", "rel_err", "source", "reproduced"} <= set(entry)
    for name, value in (("helix_radius_m", 66.59957), ("helix_speed_mps", 0.729354), ("helix_pitch_m", 206.2100),
                        ("helix_period_s", 639.6174)):
        assert nums[name]["reproduced"] is True, name
        assert nums[name]["value"] == pytest.approx(value, rel=1e-5), name
    assert nums["helix_radius_m"]["published"] == pytest.approx(66.60)
    assert nums["helix_residual"]["value"] < 1e-12
    assert nums["helix_max_re_eig"]["value"] < 0
    assert nums["sim_final_error"]["value"] < 1e-6  # 300 s already converge to the trimmed helix
    assert nums["helix_beta_deg"]["value"] == pytest.approx(1.1586, abs=1e-3)


def test_ch8_bottom_heaviness(quick_build):
    nums = quick_build.numbers
    assert nums["rbh_nominal_m"]["reproduced"] is True
    assert nums["rbh_bifurcation_m"]["reproduced"] is False  # the thesis reads -0.004 m off a plot
    assert nums["rbh_bifurcation_m"]["value"] == pytest.approx(-0.0070104, abs=1e-6)
    assert nums["rbh_bifurcation_resolved_m"]["value"] == pytest.approx(-0.0273122, abs=1e-6)
    kinds = nums["rbh_break_points_frozen"]["note"]
    assert "break-away at -0.02243 m" in kinds and "break-in at 0.08906 m" in kinds


def test_ch8_inverse_design(quick_build):
    nums = quick_build.numbers
    r_p1, r_p2, r_p3, m0 = nums["design_radius50_pitch150"]["value"]
    assert -0.05 <= r_p1 <= 0.05 and -0.05 <= r_p2 <= 0.05 and 0 <= r_p3 <= 0.08 and -0.5 <= m0 <= 0.5
    assert "radius 50.0000 m, pitch 150.0000 m" in nums["design_radius50_pitch150"]["note"]
    assert nums["design_radius1_pitch1000"]["value"] == "infeasible"


def test_ch8_maps_and_claims(quick_build):
    nums = quick_build.numbers
    for key in ("fig8_5", "fig8_6", "fig8_7", "fig8_8", "fig8_9", "fig8_10", "fig8_11", "fig8_12"):
        assert nums[f"{key}_points_without_motion"]["value"] == 0, key
    assert "branch jumps (folds) after [0.015]" in nums["fig8_9_points_without_motion"]["note"]
    ex = nums["claim_no_equilibria_m0_rP1_opposite"]
    assert ex["reproduced"] is False and ex["value"] == 2  # motions at both claimed-empty points
    assert nums["claim_beta_sign_rule"]["reproduced"] is False and nums["claim_beta_sign_rule"]["value"] == "0/16"
    assert nums["claim_fig8_7_8_symmetry"]["reproduced"] is True
    assert nums["claim_fig8_7_8_symmetry"]["value"] < 1e-8
    assert nums["claim_fig8_7_8_roll_range"]["reproduced"] is True
    crit = nums["claim_fig8_9_critical_rP3"]
    assert crit["reproduced"] is True and crit["value"] == pytest.approx([0.0215296], abs=1e-6)
    # the fold walk ran: the two branch ends overlap (a hysteresis pair of folds near 1.54 cm)
    assert "the branch from small r_P3 continues up to 1.54" in crit["note"]
    assert "the branch of the nominal helix down to 1.53" in crit["note"]
    assert nums["claim_fig8_10_smooth"]["reproduced"] is True
    speed = nums["claim_speed_linear_in_m0"]
    assert speed["reproduced"] is False and all(0.4 < n < 0.6 for n in speed["value"])
    assert nums["claim_m0_radius_decreases"]["reproduced"] is True
    assert nums["claim_fig8_5_trends"]["reproduced"] is None
    for name in ("typo_2_5_torque", "typo_2_6_ppdot", "typo_table_8_2_2", "typo_8_3_rbh_equilibrium"):
        assert nums[name]["reproduced"] is False and nums[name]["published"], name
    assert not any(isinstance(v["value"], float) and math.isnan(v["value"]) for v in nums.values())
