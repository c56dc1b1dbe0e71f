"""The chapter-4 design (designs/ch4_phugoid.py) end to end with its quick settings (fewer samples and output
points; same four runs, horizon and tolerances as the full build)."""

from __future__ import annotations

import pytest

from glidectl.report import Report

DESIGN = "ch4_phugoid"
TAGS = ("2_3", "0_4", "0", "m0_5")


def test_settings_presets(design):
    m = design.module
    assert m.FULL == m.Settings()
    assert (m.FULL.t_final, m.FULL.n_t, m.FULL.n_samples, m.FULL.seed) == (6.0, 6001, 2000, 2006)
    assert tuple(tag for tag, _ in m.FULL.c_runs) == TAGS
    assert m.QUICK.n_samples < m.FULL.n_samples and m.QUICK.c_runs == m.FULL.c_runs
    assert (m.MASS, m.M0, m.K_LIFT) == (14.0, 1.0, 100.0)  # Fig 4.1


def test_ch4_report_builds(quick_build):
    _, rep, pdf, nums = quick_build
    out = pdf.parent
    assert isinstance(rep, Report) and pdf.exists() and pdf.stat().st_size > 10_000
    for stem in ("fig4_1_trajectories", "conservation", "period_vs_C"):
        assert (out / f"{stem}.png").exists()
    for name in ("xdot_e_mps", "C_steady_level", "class_C_0_4", "class_C_m0_5", "cusp_period_s",
                 "mismatch_omega_B", "mismatch_legendre_E0", "typo_4_31_matrix", "typo_4_46_pdot"):
        assert name in nums
    assert nums["xdot_e_mps"]["value"] == pytest.approx((1.0 * 9.81 / 100.0) ** 0.5, rel=1e-15)
    assert nums["C_steady_level"]["reproduced"] is True
    assert all(nums[f"class_C_{t}"]["reproduced"] for t in TAGS)
    for key in ("canonical_2d", "omega_B", "charged_particle", "euler_lagrange_E0", "legendre_E0",
                "pendulum_driven_base"):
        assert nums[f"mismatch_{key}"]["value"] < 1e-12
        assert nums[f"mismatch_{key}"]["reproduced"] is True
    assert nums["mismatch_omega_B_printed"]["reproduced"] is False
    assert max(nums[f"drift_E_rel_C_{t}"]["value"] for t in TAGS) < 1e-8
    # the cusp orbit C = 0 has a finite period (not the 'infinite time interval' of 4.1), seen in the simulation
    assert nums["cusp_period_s"]["reproduced"] is False
    assert nums["period_C_0_s"]["value"] == pytest.approx(nums["cusp_period_s"]["value"], rel=1e-6)
    assert all(nums[name]["reproduced"] is False for name in nums if name.startswith("typo_"))
