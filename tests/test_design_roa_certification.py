"""The ROA design (designs/roa_certification.py) end to end with its quick settings (low degrees, few samples, one
full-model case, no CTOL closed loop). The real build uses FULL: about 8 minutes of work in one process on a 2-core
machine (485.6 s with ``--jobs 1`` on 2026-12-04, the user glider's shared certificate included; the CTOL
certificate 35.7 s of it). The CTOL part's own checks are in tests/test_roa_ctol_speed.py and
tests/test_ctol_lyapunov.py."""

from __future__ import annotations

import math

import pytest

from glidectl.report import Report

DESIGN = "roa_certification"


def test_settings_presets(design):
    m = design.module
    F, Q = m.FULL, m.QUICK
    assert F == m.Settings()
    assert (F.vdp_degree, F.vdp_iterations, F.reduced_degree, F.reduced_iterations) == (6, 6, 4, 4)
    assert (F.full_degree, F.full_iterations, F.full_KM) == (2, 8, (-50.0, -100.0))
    assert (F.n_volume, F.n_truth_2d, F.n_truth_4d, F.n_guide) == (2**16, 201, 4096, 2048)
    assert F.ctol and (F.ctol_degree, F.ctol_iterations, F.ctol_k3, F.ctol_k4) == (2, 4, 10.0, 5.0)
    assert (F.backoff, F.torque_speed, F.taylor_order, F.n_trap) == (0.003, 1.5, 3, 200_000)
    assert (Q.vdp_degree, Q.vdp_iterations, Q.reduced_iterations, Q.full_iterations, Q.full_KM) == (4, 2, 1, 1,
                                                                                                  (-100.0,))
    assert (Q.n_volume, Q.n_truth_2d, Q.n_truth_4d, Q.n_guide, Q.ctol) == (2**12, 21, 64, 256, False)
    assert m.DRAKE_RHO == 2.3045 and m.VDP_TRUE_AREA == 13.72
    assert F.saturated and (F.sat_rounds, F.sat_user_rounds, F.sat_n_truth, F.sat_sos_degree) == (6, 2, 256, 2)
    assert set(F.sat_sos_cases) == {"user_unsat", "user_sat", "buoyancy", "elevator"}
    assert Q.sat_sos_cases == ("elevator",)
    assert Q.saturated and (Q.sat_rounds, Q.sat_user_rounds, Q.sat_n_truth) == (2, 1, 32)


def test_roa_report_builds_with_required_numbers(quick_build):
    _, rep, pdf, nums = quick_build
    assert isinstance(rep, Report) and pdf.exists() and pdf.stat().st_size > 0
    assert nums["vdp_fixed_V_rho"]["reproduced"] is True          # Drake's rho = 2.3045 within 1e-3
    assert nums["vdp_fixed_V_rho"]["published"] == 2.3045
    assert nums["vdp_fixed_V_rho"]["value"] == pytest.approx(2.3045, abs=1e-3)
    assert nums["vdp_true_area"]["reproduced"] is True
    assert nums["vdp_true_area"]["value"] == pytest.approx(13.72, abs=0.02)
    assert nums["vdp_verified"]["value"] is True and nums["reduced_verified"]["value"] is True
    assert nums["vdp_fraction_of_true"]["value"] > nums["vdp_drake_fraction_of_true"]["value"]
    assert nums["reduced_ratio_to_thesis"]["value"] > 1.0
    # closed form of the thesis set {Phi < 2/3}: sqrt(3) * int_{-pi/2}^{pi/2} sqrt(cos g) dg
    assert nums["reduced_thesis_phi_area"]["value"] == pytest.approx(4.150479522309, rel=1e-9)
    assert 0 <= nums["reduced_recast_residual"]["value"] < 1e-12
    assert nums["taylor_trap_true_dVdt_positive"]["value"] > 0     # the Taylor certificate is not the glider's
    assert nums["full_KM100_verified"]["value"] is True
    assert 0 < nums["full_KM100_certified_volume"]["value"] <= nums["full_KM100_true_volume"]["value"] + 1e-2
    assert nums["full_ch6_torque_verified"]["value"] is True       # the chapter-6 torque closed loop
    assert "full_KM50_certified_volume" not in nums                # quick: one full-model case
    assert not any(name.startswith("ctol_") for name in nums)      # quick: no CTOL closed loop
    assert all(math.isfinite(nums[n]["value"]) for n in nums if n.endswith("_volume"))
    pngs = {p.name for p in pdf.parent.glob("*.png")}
    assert pngs == {"vdp_roa.png", "reduced_roa.png", "full_roa_slices.png", "sat_user_unsat.png", "sat_user_sat.png",
                    "sat_buoyancy.png", "sat_elevator.png", "sat_poly_sos_sector.png", "KM100_extent.png",
                    "ch6_torque_extent.png", "sat_user_unsat_extent.png", "sat_user_sat_extent.png",
                    "sat_buoyancy_extent.png", "sat_elevator_extent.png"}
    # certified against convergent extent, per loop: a ratio in (0, 1] (a sound certificate reaches no further
    # than the runs converge), the exact recasts of the 4-state glider well above the LMI ellipsoids
    ratios = {n: nums[n]["value"] for n in nums if n.endswith("_min_extent_ratio")}
    assert set(ratios) >= {"KM100_min_extent_ratio", "sat_buoyancy_min_extent_ratio",
                           "sat_elevator_sos_min_extent_ratio"}
    assert all(0 < r <= 1.0 + 1e-3 for r in ratios.values())       # (1e-3: the bisections' resolution)
    assert ratios["KM100_min_extent_ratio"] > ratios["sat_buoyancy_min_extent_ratio"]


def test_roa_report_saturated_loops(quick_build):
    # issue 17 part 7: the user glider's LQR loop (unsaturated, saturated) and the chapter-6 loops by the LMI path,
    # the SOS path with the saturation graph on a polynomial loop (it refuses the non-polynomial glider plants)
    nums = quick_build[3]
    for key in ("user_unsat", "user_sat", "buoyancy", "elevator"):
        assert nums[f"sat_{key}_verified"]["value"] is True
        assert 0 < nums[f"sat_{key}_fraction_of_box"]["value"] < 1
        assert 0 < nums[f"sat_{key}_true_fraction"]["value"] <= 1
        assert nums[f"sat_{key}_tightness_scale"]["value"] > 1       # the certified set is not beyond its own V
    # the SOS path on a glider loop (QUICK: the elevator loop only): a surrogate of the plant with the saturation
    # graph, certified, its volume compared with the LMI ellipsoid's
    assert nums["sat_elevator_sos_certified"]["value"] is True
    assert "sos-sector+remainder" in nums["sat_elevator_sos_certified"]["source"]
    assert nums["sat_elevator_sos_volume_ratio"]["value"] > 0
    assert "remainder-box search" in nums["sat_elevator_sos_volume_ratio"]["note"]
    # the second remainder-box round is kept on this loop (its box follows the certified set, not the starting V)
    assert "round 2 kept" in nums["sat_elevator_sos_volume_ratio"]["note"]
    assert nums["sat_elevator_sos_volume_ratio"]["value"] > 1
    assert "sat_buoyancy_sos_certified" not in nums and "sat_user_sat_sos_certified" not in nums
    assert "sos-sector" in nums["sat_poly_sos_sector_fraction"]["source"]
    assert nums["sat_poly_sos_sector_fraction"]["value"] > nums["sat_poly_lmi_fraction"]["value"] > 0
