"""The README's usage example runs as printed (it is the public API's front page)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_example_runs(capsys):
    import matplotlib

    matplotlib.use("Agg")  # the example draws; no window in a test
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "README has no python example"
    ns: dict = {}
    exec(compile(blocks[0], str(README), "exec"), ns)
    h, d, cert = ns["h"], ns["d"], ns["cert"]
    assert abs(h.radius - 66.60) < 0.01 and h.stable
    assert d.helix.stable and abs(d.helix.radius - 50.0) < 1e-3 * 50
    assert cert.certified == (cert.mu < cert.mu_d)
    assert np.all(ns["sw"].exists)
    assert capsys.readouterr().out  # the example prints its results
    loop = ns["loop"]
    assert np.abs(loop.rhs(loop.equilibrium)).max() < 1e-9
    assert ns["rep"].numbers[0].value == ns["g"].m0 and len(ns["rep"].figures) == 1


def test_readme_uses_only_the_public_api():
    """The README example imports glidectl and glidectl.report only, and every gc.NAME it uses is public."""
    import glidectl as gc

    text = README.read_text()
    code = "\n".join(re.findall(r"```python\n(.*?)```", text, flags=re.S))
    modules = set(re.findall(r"^\s*(?:from|import)\s+(glidectl[\w.]*)", code, flags=re.M))
    assert modules <= {"glidectl", "glidectl.report"}, modules
    used = set(re.findall(r"\bgc\.(\w+)", code))
    assert used <= set(gc.__all__), sorted(used - set(gc.__all__))
    assert "../shared" not in text and "/work/" not in text


def test_readme_flight_example_runs(tmp_path, monkeypatch, capsys):
    """The README's flight-model example reads the shipped record, fits, predicts and writes a vehicle file that
    loads back to the fitted values."""
    import matplotlib

    import glidectl as gc

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HOME", str(tmp_path))  # dbdreader's default cache folder for the record's .cac file
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    block = next(b for b in blocks if "fit_flight_model" in b)
    ns: dict = {"gc": gc, "np": np}
    exec(compile(block, str(README), "exec"), ns)
    fit = ns["fit"]
    assert fit.law == "gliderflight" and fit.rms < 0.07 and fit.cv_rms is not None
    assert "Cd0" in capsys.readouterr().out
    back = gc.load_vehicle(tmp_path / "my_glider.toml")
    assert back.law == "gliderflight" and back.params["Cd0"] == fit.params["Cd0"]
    assert back.params["volume"] == fit.params["volume"] and back.provenance == fit.uncertain_vehicle().provenance


def test_readme_mission_example_runs(capsys):
    """The README's mission example flies the box, prints its table and draws; the designed turn is flown."""
    import matplotlib

    import glidectl as gc

    matplotlib.use("Agg")
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    block = next(b for b in blocks if "fly_mission" in b)
    ns: dict = {"gc": gc, "np": np}
    exec(compile(block, str(README), "exec"), ns)
    run, turn = ns["run"], ns["turn"]
    assert all(leg.arrived for leg in run.legs) and len(run.legs) == 4
    assert "arrived" in capsys.readouterr().out
    assert abs(turn.helices[1].radius - 150.0) < 1e-6 and turn.steer == "rudder"
    assert ns["spiral"].ended_by.startswith("duration")


def test_readme_fleet_example_runs():
    """The README's fleet example flies three gliders in a triangle whose spacing follows the schedule."""
    import matplotlib

    import glidectl as gc

    matplotlib.use("Agg")
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    block = next(b for b in blocks if "fly_fleet" in b)
    ns: dict = {"gc": gc, "np": np}
    exec(compile(block, str(README), "exec"), ns)
    times, spacing, fleet = ns["times"], ns["spacing"], ns["fleet"]
    late = times > 48 * 3600
    assert fleet.size == 3 and abs(np.mean(spacing[late]) - 3000.0) < 300.0


def test_readme_robustness_example_runs(capsys):
    """The README's robustness example: a Monte Carlo of a study, robust stability of the LQR loop and dive cycles
    of sampled vehicles."""
    import matplotlib

    import glidectl as gc

    matplotlib.use("Agg")
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    block = next(b for b in blocks if "robust_stability" in b)
    ns: dict = {"gc": gc, "np": np}
    exec(compile(block, str(README), "exec"), ns)
    mc, rs, ens = ns["mc"], ns["rs"], ns["ens"]
    assert len(ns["sample"].vehicles) == 1000 and mc.ok.all() and mc.names == ("m0",)
    assert rs.probability == 1.0 and rs.worst_case.max_real >= rs.nominal_max_real and rs.margin > 1
    q = ens.quantiles("energy_per_km")
    assert q[0] <= q[1] <= q[2] and ens.ok.all()
    assert "margin" in capsys.readouterr().out
