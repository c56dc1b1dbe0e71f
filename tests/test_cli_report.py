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
from glidectl.cli import main
from glidectl.report import Number, Report, load_design

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = ROOT / "designs"

REQUIRED = ("permissible_gamma_deg", "eig_uncontrolled_m45", "rbh_stability_boundary_m", "mbar_threshold_kg")


def test_list_shows_presets_and_designs(capsys):
    assert main(["list", "--designs", str(DESIGNS)]) == 0
    out = capsys.readouterr().out
    for name in gc.list_presets():
        assert name in out
    assert "ch2_longitudinal" in out
    assert set(gc.list_presets()) >= {"rogue", "sphere_ch5", "elevator_ch6", "slocum_ch8", "dc8_ctol"}


def test_unknown_design_is_a_clear_error(capsys, tmp_path):
    assert main(["report", "no_such_design", "--designs", str(DESIGNS), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "no_such_design" in err and "ch2_longitudinal" in err


def test_report_number_verdicts():
    n = Number("x", 1.005, "m", "§0", published=1.0, tolerance=0.01)
    assert n.reproduced is True and n.rel_err == pytest.approx(0.005)
    assert Number("x", 1.02, "m", "§0", published=1.0, tolerance=0.01).reproduced is False
    assert Number("x", 1.0, "m", "§0").reproduced is None
    assert Number("x", [1.0, 2.0], "m", "§0", published=[3.0], verdict=False).reproduced is False
    rep = Report("t")
    rep.number("a", 1.0, "m", "§0")
    with pytest.raises(ValueError, match="duplicate"):
        rep.number("a", 2.0, "m", "§0")


@pytest.fixture(scope="module")
def ch2_report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("reports")
    # the installed console script, as a user runs it
    proc = subprocess.run([sys.executable, "-m", "glidectl.cli", "report", "ch2_longitudinal", "--out", str(out)],
                          capture_output=True, text=True, timeout=600, cwd=ROOT)
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
        assert {"name", "value", "published", "unit", "rel_err", "source", "reproduced", "note"} <= set(entry)
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
    assert boundary["published"] == pytest.approx(-0.0068)
    assert boundary["reproduced"] in (True, False)


def test_every_design_file_loads():
    names = {p.stem for p in DESIGNS.glob("*.py") if not p.name.startswith("_")}
    assert {"ch2_longitudinal", "ch4_phugoid", "ch5_singular_perturbation", "ch6_controllers", "ch7_ctol",
            "ch8_helix", "roa_certification"} <= names
    for name in names:
        d = load_design(name, DESIGNS)
        assert d.name == name and d.title and callable(d.module.design)


USER_DESIGN = '''
import numpy as np
import glidectl as gc
from glidectl.report import Report, new_figure

TITLE = "My own glider: glide speeds"


def design(progress, quick=False):
    veh = gc.load_vehicle("rogue")
    rep = Report(TITLE, vehicle=veh)
    gammas = np.radians([-45.0, -35.0] if quick else [-45.0, -40.0, -35.0])
    progress("steady glides")
    glides = [gc.steady_glide(veh, 0.3, g, r_p3=0.05) for g in gammas]
    for g in glides:
        rep.number(f"m0_{np.degrees(g.gamma):.0f}deg", g.m0, "kg", source="steady_glide")
    fig, ax = new_figure()
    ax.plot(np.degrees(gammas), [g.m0 for g in glides], "o-")
    ax.set_xlabel("gamma [deg]")
    ax.set_ylabel("m0 [kg]")
    rep.figure("m0_vs_gamma", fig, "Net buoyancy of the steady glides.")
    rep.table("Glides", ["gamma [deg]", "m0 [kg]"], [[f"{np.degrees(g.gamma):.0f}", f"{g.m0:.4f}"] for g in glides])
    return rep
'''


def test_user_design_file_outside_the_repository(tmp_path):
    """A user's own design file, in a folder of its own, goes through the report system like ours."""
    work = tmp_path / "project"
    work.mkdir()
    (work / "my_glider.py").write_text(USER_DESIGN)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "glidectl.cli", "report", str(work / "my_glider.py"), "--out",
                           str(out), "--quick"], capture_output=True, text=True, timeout=300, cwd=work)
    assert proc.returncode == 0, proc.stderr
    res = out / "my_glider"
    assert (res / "report.pdf").stat().st_size > 10_000
    assert (res / "m0_vs_gamma.png").stat().st_size > 5_000
    data = json.loads((res / "numbers.json").read_text())
    assert [d["name"] for d in data] == ["m0_-45deg", "m0_-35deg"]  # quick settings
    veh = gc.load_vehicle("rogue")
    assert data[0]["value"] == pytest.approx(gc.steady_glide(veh, 0.3, math.radians(-45.0), r_p3=0.05).m0)
    assert all(d["published"] is None and d["reproduced"] is None for d in data)
    # no publication: a plain results table and no thesis citation on the title page
    rep = load_design(work / "my_glider.py").report(quick=True)
    assert not rep.has_ledger and rep.reference is None


def test_design_folder_errors(tmp_path, capsys):
    assert main(["report", "x", "--designs", str(tmp_path / "nope"), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "--designs" in err and err.count("\n") == 1
    bad = tmp_path / "bad.py"
    bad.write_text("TITLE = 3\n")
    assert main(["report", str(bad), "--out", str(tmp_path)]) == 2
    assert "TITLE" in capsys.readouterr().err
    broken = tmp_path / "broken.py"
    broken.write_text("import no_such_module_xyz\n")
    assert main(["report", str(broken), "--out", str(tmp_path)]) == 2
    assert "no_such_module_xyz" in capsys.readouterr().err


def test_unwritable_output_is_refused_before_computing(tmp_path, capsys):
    marker = tmp_path / "ran"
    design = tmp_path / "slow.py"
    design.write_text(f"from pathlib import Path\nTITLE = 't'\n\ndef design(progress, quick=False):\n"
                      f"    Path({str(marker)!r}).write_text('x')\n    raise SystemExit('computed')\n")
    assert main(["report", str(design), "--out", "/dev/null/x"]) == 2
    assert "cannot write" in capsys.readouterr().err
    assert not marker.exists()


def test_report_api_checks_its_inputs(tmp_path):
    with pytest.raises(TypeError, match="Vehicle"):
        Report("t", vehicle="rogue")
    rep = Report("t", vehicle=gc.load_vehicle("rogue"), reference="A. Author, A paper, 2020.")
    with pytest.raises(ValueError, match="cells"):
        rep.table("t", ["a", "b"], [["1"]])
    rep.number("a", 1.0, "m", published=1.001, tolerance=0.01)
    assert rep.has_ledger
    pdf = rep.write(tmp_path / "r")
    data = json.loads((pdf.parent / "numbers.json").read_text())
    assert data[0]["reproduced"] is True and data[0]["published"] == 1.001


def test_library_never_selects_a_backend(python_output):
    """Importing glidectl (and its report API) leaves the user's matplotlib backend alone."""
    code = ("import matplotlib; matplotlib.use('svg'); import glidectl, glidectl.report; "
            "from glidectl.report import new_figure; new_figure(); print(matplotlib.get_backend())")
    assert python_output(code) == "svg"


def test_the_command_and_batch_builds_leave_the_backend_alone(python_output, tmp_path):
    """The CLI and :func:`run_script` never select a backend (DESIGN: the library never calls matplotlib.use): a
    user's backend survives a build, and without a display matplotlib itself falls back to a non-interactive one."""
    design = tmp_path / "tiny.py"
    design.write_text(
        'import glidectl as gc\nfrom glidectl.report import Report, new_figure\nTITLE = "tiny"\n'
        'def design(progress, quick=False):\n    rep = Report(TITLE)\n    fig, ax = new_figure()\n'
        '    ax.plot([0, 1], [0, 1])\n    rep.figure("line", fig, "a line")\n    return rep\n', encoding="utf-8")
    code = ("import matplotlib; matplotlib.use('svg'); from glidectl import cli; "
            f"rc = cli.main(['report', {str(design)!r}, '--out', {str(tmp_path / 'out')!r}, '--jobs', '1']); "
            "print(rc, matplotlib.get_backend())")
    assert python_output(code).splitlines()[-1] == "0 svg"
    assert (tmp_path / "out" / "tiny" / "line.png").is_file()


# ------------------------------------------------------------------------------------------ issue 15
def test_a_design_that_raises_exits_2_with_one_line(tmp_path, capsys):
    design = tmp_path / "raises.py"
    design.write_text("TITLE = 'x'\n\ndef design(progress, quick=False):\n    return 1 / 0\n")
    assert main(["report", str(design), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "ZeroDivisionError" in err and "raises.py:4" in err


def test_usage_errors_exit_2_with_one_line(capsys):
    for argv in (["bogus"], ["report", "--quick", "extra", "args"], []):
        with pytest.raises(SystemExit) as info:
            main(argv)
        assert info.value.code == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("glidectl: error:"), err


def test_every_error_of_the_command_is_one_line_with_status_2(tmp_path, capsys):
    returns_none = tmp_path / "none.py"
    returns_none.write_text("TITLE = 'x'\n\ndef design(progress, quick=False):\n    return None\n")
    cases = [["report", "no_such_design", "--designs", str(DESIGNS), "--out", str(tmp_path)],
             ["report", "all", "--designs", str(DESIGNS), "--out", "/dev/null/x"],
             ["report", str(returns_none), "--out", str(tmp_path)]]
    for argv in cases:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("glidectl: error:"), (argv, err)


def test_report_api_errors_are_glidectl_errors(tmp_path):
    from matplotlib.figure import Figure

    with pytest.raises(gc.ArgumentTypeError):
        Report(123)
    with pytest.raises(gc.ArgumentTypeError, match="load_vehicle"):
        Report("t", vehicle="rogue")
    with pytest.raises(gc.ArgumentTypeError):
        Report("t", vehicle=[gc.load_vehicle("rogue"), "x"])
    with pytest.raises(gc.ArgumentTypeError):
        Report("t", reference=5)
    rep = Report("t")
    with pytest.raises(gc.ArgumentError, match="cells"):
        rep.table("c", ["a", "b"], [[1]])
    rep.number("x", 1.0, "m")
    with pytest.raises(gc.ArgumentError, match="duplicate"):
        rep.number("x", 2.0, "m")
    with pytest.raises(gc.ArgumentError):
        rep.number("y", 2.0, "m", published=2.0, tolerance=-1.0)
    with pytest.raises(gc.ArgumentTypeError):
        rep.figure("f", "not a figure", "cap")
    with pytest.raises(gc.ArgumentError):
        rep.figure("../f", Figure(), "cap")
    rep.figure("f", Figure(), "a")
    with pytest.raises(gc.ArgumentError, match="duplicate"):
        rep.figure("f", Figure(), "b")
    with pytest.raises(gc.ArgumentTypeError):
        rep.text(None, "body")
    with pytest.raises(gc.OutputError, match="cannot write"):
        rep.write("/dev/null/x")
    with pytest.raises(OSError):              # OutputError is also an OSError
        rep.write("/dev/null/x")
    assert rep.write(tmp_path / "ok").exists()


def test_python_dash_m_glidectl_is_the_cli():
    """``python -m glidectl list`` runs the same CLI as the ``glidectl`` script (exit 0, lists the presets)."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "glidectl", "list"], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "slocum_ch8" in out.stdout
    bad = subprocess.run([sys.executable, "-m", "glidectl", "frobnicate"], capture_output=True, text=True,
                         timeout=120)
    assert bad.returncode == 2


def test_a_long_table_caption_wraps_inside_the_page():
    """A table caption longer than a line wraps within the page, and the table starts below it (the ROA design's
    alternation-history caption ran off the page)."""
    from matplotlib.textpath import TextToPath

    figs = []

    class Pages:
        def savefig(self, fig):
            figs.append(fig)

    caption = " ".join(["level"] * 60)
    rep = Report("t")
    rep.table(caption, ["a"], [["1"]])
    rep._render(Pages(), "t")
    texts = figs[0].texts
    lines = [t for t in texts if t.get_text().startswith("level")]
    assert len(lines) >= 2 and " ".join(t.get_text() for t in lines) == caption
    page_width = 72 * figs[0].get_figwidth()
    for t in lines:  # points from the page's left edge, measured with the font's metrics as the PDF draws them
        width = TextToPath().get_text_width_height_descent(t.get_text(), t.get_fontproperties(), ismath=False)[0]
        assert 72 * t.get_position()[0] + width <= page_width
    header = next(t for t in texts if t.get_text() == "a")
    assert 72 * header.get_position()[1] <= 72 * lines[-1].get_position()[1] - lines[-1].get_fontsize()
