"""The robustness design (designs/robustness.py) end to end with its quick settings: slocum_shallow with +-30 %
intervals on its hydrodynamic and damping coefficients, robust stability of two linear dive controllers and the
pitch behaviour kept at their nominal design, dive cycles of sampled vehicles, and the robust against the nominal
region of attraction."""

from __future__ import annotations

DESIGN = "robustness"


def test_settings_presets(design):
    m = design.module
    assert m.FULL == m.Settings() and m.Settings.__dataclass_params__.frozen
    assert m.FULL.relative == m.QUICK.relative == 0.3 and m.FULL.n_stability == 1000
    veh = m.uncertain_vehicle(m.FULL)
    assert set(veh.uncertainty) == set(m.COEFFICIENTS)
    for k, u in veh.uncertainty.items():
        nominal = veh.params[k]
        half = abs(nominal) * 0.3
        assert u.kind == "interval" and abs(u.low - (nominal - half)) < 1e-12 and abs(u.high - (nominal + half)) < 1e-12


def test_report_files_and_numbers(quick_build):
    _, _, pdf, numbers = quick_build
    assert pdf.exists() and pdf.stat().st_size > 30_000
    assert {p.stem for p in pdf.parent.glob("*.png")} == {"stability_lqr", "stability_place", "stability_behaviours",
                                                         "missions", "robust_certificate"}
    for key in ("lqr", "place", "behaviours"):
        p = numbers[f"{key}_probability_stable"]["value"]
        assert 0.0 <= p <= 1.0
        # the worst case in the box is at least as bad as the nominal loop, and the margin says where it fails
        assert numbers[f"{key}_worst_max_real"]["value"] >= numbers[f"{key}_nominal_max_real"]["value"]
        margin = numbers[f"{key}_margin"]["value"]
        assert (margin >= 1.0) == (numbers[f"{key}_worst_max_real"]["value"] < 0)
    assert numbers["missions_failed"]["value"] == 0
    assert numbers["missions_energy_per_km_p95"]["value"] >= numbers["missions_energy_per_km_median"]["value"] > 0


def test_robust_certificate_holds_at_every_vehicle_checked(quick_build):
    _, _, _, numbers = quick_build
    # one shape about every vehicle's own equilibrium, a positive extent along each of the 8 free states
    ratios = {k: v["value"] for k, v in numbers.items()
              if k.startswith("robust_extent_ratio_") and k != "robust_extent_ratio_min"}
    assert len(ratios) == 8 and all(0.0 < r < 2.0 for r in ratios.values())
    assert numbers["robust_extent_ratio_min"]["value"] == min(ratios.values())
    assert numbers["robust_certificate_certified"]["value"] is True
    n = numbers["robust_check_converged"]
    assert n["value"] > 0 and f"of {n['value']} simulations" in n["source"]       # every run converged
