"""The ``glidectl`` command and the chapter-2 report (PDF, PNGs, numbers.json)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import glidectl as gc
from glidectl import studies
from glidectl.cli import main
from glidectl.report.document import Number, Report

REQUIRED = ("permissible_gamma_deg", "eig_uncontrolled_m45", "rbh_stability_boundary_m", "mbar_threshold_kg")


def test_list_shows_presets_and_designs(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    for name in gc.list_presets():
        assert name in out
    assert "ch2_longitudinal" in out
    assert set(gc.list_presets()) >= {"rogue", "sphere_ch5", "elevator_ch6", "slocum_ch8", "dc8_ctol"}


def test_unknown_design_is_a_clear_error(capsys, tmp_path):
    assert main(["report", "no_such_design", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "no_such_design" in err and "ch2_longitudinal" in err


def test_report_number_verdicts():
    n = Number("x", 1.005, "m", "§0", thesis=1.0, tolerance=0.01)
    assert n.reproduced is True and n.rel_err == pytest.approx(0.005)
    assert Number("x", 1.02, "m", "§0", thesis=1.0, tolerance=0.01).reproduced is False
    assert Number("x", 1.0, "m", "§0").reproduced is None
    assert Number("x", [1.0, 2.0], "m", "§0", thesis=[3.0], verdict=False).reproduced is False
    rep = Report("t", "t")
    rep.number("a", 1.0, "m", "§0")
    with pytest.raises(ValueError, match="duplicate"):
        rep.number("a", 2.0, "m", "§0")


@pytest.fixture(scope="module")
def ch2_report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("reports")
    # the installed console script, as a user runs it
    proc = subprocess.run([sys.executable, "-m", "glidectl.cli", "report", "ch2_longitudinal", "--out", str(out)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert "done in" in proc.stdout  # progress display
    return out / "ch2_longitudinal"


def test_ch2_report_files(ch2_report):
    assert (ch2_report / "report.pdf").stat().st_size > 50_000
    pngs = sorted(p.name for p in ch2_report.glob("*.png"))
    assert {"fig2_7_rbh_locus.png", "fig2_8_glide_switch.png"} <= set(pngs)


def test_ch2_numbers_json(ch2_report):
    data = json.loads((ch2_report / "numbers.json").read_text())
    nums = {n["name"]: n for n in data}
    for entry in data:
        assert {"name", "value", "thesis", "unit", "rel_err", "source", "reproduced"} <= set(entry)
    for name in REQUIRED:
        assert name in nums, name
    veh = gc.load_vehicle("rogue")
    assert nums["permissible_gamma_deg"]["value"] == pytest.approx(math.degrees(gc.permissible_gamma(veh)[1]))
    eig = np.array(nums["eig_uncontrolled_m45"]["value"])
    assert eig.shape[1] == 2 and np.all(eig[:, 0] < 0)  # stable at -45 deg with r_P3 = 0.05 m
    lam = gc.uncontrolled_eigs(veh, 0.3, math.radians(-45), r_p3=0.05)
    lam = lam[np.abs(lam) > 1e-9]
    np.testing.assert_allclose(sorted(eig[:, 0]), sorted(lam.real), atol=1e-9)
    # ledger entries carry the thesis value and a verdict
    boundary = nums["rbh_stability_boundary_m"]
    assert boundary["thesis"] == pytest.approx(-0.0068)
    assert boundary["reproduced"] in (True, False)


def test_design_script_and_registry_agree():
    assert "ch2_longitudinal" in studies.REGISTRY
    script = Path(__file__).resolve().parents[1] / "designs" / "ch2_longitudinal.py"
    assert "ch2_longitudinal" in script.read_text()
    with pytest.raises(gc.GlidectlError, match="ch2_longitudinal"):
        studies.get("nope")


def test_ch5_report_builds_with_required_numbers(tmp_path, monkeypatch):
    """The chapter-5 design end to end, with small sample counts (the real build uses the module defaults)."""
    from glidectl.studies import ch5_singular_perturbation as ch5

    monkeypatch.setattr(ch5, "N_VERIFY", 4000)
    monkeypatch.setattr(ch5, "ROA_GRID", 4)
    monkeypatch.setattr(ch5, "LSTAR_GRID", 31)
    monkeypatch.setattr(ch5, "DM_GRID", np.array([0.0, 0.2]))
    monkeypatch.setattr(ch5, "VMIN_GRID", np.array([-0.4]))
    pdf = ch5.build(tmp_path)
    assert pdf.exists() and pdf.stat().st_size > 20_000
    data = json.loads((pdf.parent / "numbers.json").read_text())
    nums = {n["name"]: n for n in data}
    for name in ("eps1", "eps2", "tau_s", "V_e", "gamma_e_deg", "reduced_eigenvalues", "boundary_layer_eigenvalues",
                 "mu_d", "d"):
        assert name in nums, name
    assert nums["eps1"]["reproduced"] is True and nums["tau_s"]["reproduced"] is True
    assert nums["V_e"]["reproduced"] is False  # the printed 1.684 is a transposition of 1.648
    assert nums["boundary_layer_eigenvalues"]["reproduced"] is False
    assert nums["worst_bound_ratio"]["value"] <= 1.0 + 1e-9
    assert {p.name for p in pdf.parent.glob("*.png")} >= {"fig5_1_reduction.png", "fig5_2_roa.png",
                                                           "fig5_3_unequal_mass.png"}


def test_ch7_report_builds_with_required_numbers(tmp_path, monkeypatch):
    """The chapter-7 design end to end on a short horizon with cheap settings (the real build uses the defaults:
    the printed gains alone take about two minutes)."""
    from glidectl.studies import ch7_ctol as ch7

    cheap = {"dt": 1.0, "k3": 10.0, "k4": 10.0}
    monkeypatch.setattr(ch7, "PRINTED", cheap)
    monkeypatch.setattr(ch7, "LITERAL", {"dt": 2.0, "k3": 10.0, "k4": 10.0})
    monkeypatch.setattr(ch7, "GRID_DT", (0.5, 1.0))
    monkeypatch.setattr(ch7, "GRID_GAINS", ((10.0, 10.0),))
    monkeypatch.setattr(ch7, "T_FINAL", 8.0)
    monkeypatch.setattr(ch7, "MAP_V", np.linspace(0.1, 0.4, 5))
    monkeypatch.setattr(ch7, "MAP_GAMMA", np.radians(np.linspace(-60.0, 60.0, 7)))
    monkeypatch.setattr(ch7, "LYAP_GAINS", ((10.0, 5.0),))
    monkeypatch.setattr(ch7, "N_VERIFY", 4000)
    pdf = ch7.build(tmp_path)
    assert pdf.exists()
    nums = {n["name"]: n for n in json.loads((pdf.parent / "numbers.json").read_text())}
    assert nums["level_alpha_e_rad"]["value"] == pytest.approx(0.0632962, abs=1e-6)
    for name in ("level_k1", "level_k2", "zero_dynamics_eigenvalues", "lower_effort_than_inversion",
                 "theorem5_certified_k3_10_k4_5", "approx_lin_stopped_at"):
        assert name in nums, name
    lo, hi = nums["zero_dynamics_eigenvalues"]["value"]
    assert lo < 0 < hi and lo == pytest.approx(-hi)
    assert {p.name for p in pdf.parent.glob("*.png")} >= {"fig7_2_trajectory.png", "fig7_3_error.png",
                                                           "fig7_4_inputs.png", "pareto_front.png"}


def test_ch6_report_builds_with_required_numbers(tmp_path, monkeypatch):
    """The chapter-6 design end to end with few batch runs (the real build uses the module defaults)."""
    from glidectl.studies import ch6_controllers as ch6

    monkeypatch.setattr(ch6, "N_BOX", 12)
    monkeypatch.setattr(ch6, "T_TORQUE", 20.0)
    monkeypatch.setattr(ch6, "T_ELEV", 20.0)
    monkeypatch.setattr(ch6, "REALIZED_T", 5.0)
    monkeypatch.setattr(ch6, "BUOY_T", 30.0)
    pdf = ch6.build(tmp_path)
    nums = {n["name"]: n for n in json.loads((pdf.parent / "numbers.json").read_text())}
    for name in ("elevator_alpha_e_deg", "elevator_m0e_kg", "elevator_eps1"):
        assert nums[name]["reproduced"] is True, name
    assert nums["elevator_eps2"]["reproduced"] is None  # J2 was inferred from the printed eps2: no verdict
    assert nums["elevator_K_De_eff"]["value"] > 0  # Theorem 3
    assert nums["buoyancy_nu_b_Kb_1"]["value"] is False and nums["buoyancy_nu_b_Kb_1000"]["value"] is True
    assert {p.name for p in pdf.parent.glob("*.png")} >= {"fig6_2_elevator.png", "realized_torque.png",
                                                           "roa_comparison.png"}


def test_roa_report_builds_with_required_numbers(tmp_path, monkeypatch):
    """The ROA design end to end with low degrees and few samples (the real build uses the module defaults)."""
    from glidectl.studies import roa_certification as roa

    monkeypatch.setattr(roa, "VDP", {"degree": 4, "iterations": 2})
    monkeypatch.setattr(roa, "REDUCED", {"degree": 4, "iterations": 1})
    monkeypatch.setattr(roa, "FULL", {"degree": 2, "iterations": 1})
    monkeypatch.setattr(roa, "FULL_KM", (-100.0,))
    monkeypatch.setattr(roa, "N_VOLUME", 2**12)
    monkeypatch.setattr(roa, "N_TRUTH_2D", 21)
    monkeypatch.setattr(roa, "N_TRUTH_4D", 64)
    monkeypatch.setattr(roa, "N_GUIDE", 256)
    monkeypatch.setattr(roa, "CTOL", None)  # ~20 min: exercised by the design run only (recast tested in test_roa)
    pdf = roa.build(tmp_path)
    nums = {n["name"]: n for n in json.loads((pdf.parent / "numbers.json").read_text())}
    assert nums["vdp_fixed_V_rho"]["reproduced"] is True          # Drake's rho = 2.3045 within 1e-3
    assert nums["vdp_true_area"]["reproduced"] is True
    assert nums["vdp_verified"]["value"] is True and nums["reduced_verified"]["value"] is True
    assert nums["vdp_fraction_of_true"]["value"] > nums["vdp_drake_fraction_of_true"]["value"]
    assert nums["reduced_ratio_to_thesis"]["value"] > 1.0
    assert nums["full_KM100_verified"]["value"] is True
    assert 0 < nums["full_KM100_certified_volume"]["value"] <= nums["full_KM100_true_volume"]["value"] + 1e-2
    assert {p.name for p in pdf.parent.glob("*.png")} >= {"vdp_roa.png", "reduced_roa.png", "full_roa_slices.png"}
