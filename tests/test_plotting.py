"""``.plot()`` of the results users draw: each builds a small result, draws it and checks what was drawn (lines,
collections, labels with units); the library leaves the backend and the user's rc settings alone."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
BACKEND = matplotlib.get_backend()

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

import glidectl as gc  # noqa: E402
from glidectl import plotting  # noqa: E402
from glidectl.analysis.closed_loop import compare_controllers, lqr_state_feedback  # noqa: E402
from glidectl.analysis.locus import parameter_locus  # noqa: E402
from glidectl.controllers.ctol_runs import TrackingRun  # noqa: E402
from glidectl.controllers.ctol_tracking import ParetoStudy, pareto_front, track_with_steady_glides  # noqa: E402
from glidectl.controllers.ctol_trajectory import ClimbTrajectory  # noqa: E402

SPHERE = gc.load_vehicle("sphere_ch5")
SLOCUM = gc.load_vehicle("slocum_ch8")


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _locus():
    # lambda^2 + k lambda + 1 = 0: stability boundary at k = 0, break-in (complex pair lands) at k = 2
    return parameter_locus(lambda k: np.linalg.eigvals([[0.0, 1.0], [-1.0, -k]]), np.linspace(-1.0, 3.0, 80),
                           "k", "kg/s")


# ------------------------------------------------------------------------------------------------ backend, style
def test_importing_and_plotting_keep_the_users_backend(python_output):
    assert matplotlib.get_backend() == BACKEND  # importing glidectl and glidectl.plotting above changed nothing
    _locus().plot()
    assert matplotlib.get_backend() == BACKEND
    code = ("import sys, matplotlib; matplotlib.use('svg'); import numpy as np; import glidectl; "
            "assert 'glidectl.plotting' not in sys.modules; "
            "from glidectl.analysis.locus import parameter_locus; "
            "parameter_locus(lambda p: np.array([-p, -1.0]), [1.0, 2.0], 'k', 'kg').plot(kind='real'); "
            "print(matplotlib.get_backend())")
    assert python_output(code) == "svg"


def test_report_figures_is_a_re_export_of_plotting():
    import glidectl.report as report
    from glidectl.report import figures

    for name in ("STYLE", "label", "new_figure", "style"):
        assert getattr(report, name) is getattr(plotting, name)
    for name in figures.__all__:
        assert getattr(figures, name) is getattr(plotting, name)
    assert set(plotting.__all__) >= set(figures.__all__)


def test_plots_draw_in_the_glidectl_style_and_restore_the_users_settings():
    with matplotlib.rc_context({"axes.titlesize": 15, "axes.grid": False}):
        ax = _locus().plot(kind="real")
        assert ax.title.get_fontsize() == plotting.STYLE["axes.titlesize"]
        assert matplotlib.rcParams["axes.titlesize"] == 15 and not matplotlib.rcParams["axes.grid"]


# ------------------------------------------------------------------------------------------------ loci
def test_parameter_locus_plot_complex_and_real():
    loc = _locus()
    assert loc.crossings == (0.0,) and len(loc.breakpoints) == 1
    ax = loc.plot()
    assert sum(isinstance(c, LineCollection) for c in ax.collections) == 2  # one per branch
    assert ax.get_xlabel() == r"Re $\lambda$ [1/s]" and ax.get_ylabel() == r"Im $\lambda$ [1/s]"
    cbar = [a for a in ax.figure.axes if a is not ax]
    assert len(cbar) == 1 and cbar[0].get_ylabel() == "k [kg/s]"
    assert "eigenvalues versus k" in ax.get_title()
    ax = loc.plot(kind="real")
    # two branches, Re = 0, the crossing and the break point
    assert len(ax.lines) == 5
    assert ax.get_xlabel() == "k [kg/s]" and ax.get_ylabel() == r"Re $\lambda$ [1/s]"
    assert len(ax.get_legend().get_texts()) == 2
    with pytest.raises(gc.GlidectlError, match="kind"):
        loc.plot(kind="imaginary")


def test_parameter_locus_plot_into_given_axes():
    _, axs = plt.subplots(1, 2)
    assert _locus().plot(axs[1], kind="real") is axs[1]
    assert len(axs[1].lines) == 5 and not axs[0].lines


def test_helix_rbh_locus_plot():
    hl = gc.helix_rbh_locus(SLOCUM, (0.02, -0.02, 0.04), 0.25, np.linspace(-0.03, 0.1, 27), frozen=True)
    loc = hl.locus
    k = loc.branches.shape[1]
    ax = hl.plot()
    # branches, Re = 0, crossings, break points, nominal r_bh
    assert len(ax.lines) == k + 1 + len(loc.crossings) + len(loc.breakpoints) + 1
    assert ax.get_xlabel() == r"$r_{bh}$ [m]" and "[1/s]" in ax.get_ylabel()
    assert "frozen" in ax.get_title()
    assert len(ax.child_axes) == 1 and len(ax.child_axes[0].lines) >= k  # zoom on the slowest eigenvalues
    ax = hl.plot(kind="complex")
    assert sum(isinstance(c, LineCollection) for c in ax.collections) == k
    with pytest.raises(gc.GlidectlError, match="kind"):
        hl.plot(kind="both")


# ------------------------------------------------------------------------------------------------ simulations
def test_simulation_plot():
    sp = gc.singular_perturbation(SPHERE)
    model = gc.ReducedLongitudinalGlider(SPHERE)
    sim = gc.simulate(model, sp.equilibrium + np.array([0.1, 0.05, 0.02, 0.2]), 2.0, t_eval=np.linspace(0, 2, 201))
    axes = sim.plot(names=["V", "gamma", "Omega2"])
    assert len(axes) == 3 and all(len(a.lines) == 1 for a in axes)
    assert [a.get_ylabel() for a in axes] == ["$V$ [m/s]", r"$\gamma$ [deg]", r"$\Omega_2$ [deg/s]"]  # degrees
    np.testing.assert_allclose(axes[1].lines[0].get_ydata(), np.degrees(sim.state("gamma")), rtol=1e-15)
    assert axes[-1].get_xlabel() == "t [s]" and "ReducedLongitudinalGlider" in axes[0].get_title()
    np.testing.assert_array_equal(axes[0].lines[0].get_ydata(), sim.state("V"))
    # the former argument order (names first) and a display scale
    axes = sim.plot(["alpha"], scale={"alpha": (180 / math.pi, "deg")})
    assert len(axes) == 1 and axes[0].get_ylabel() == r"$\alpha$ [deg]"
    _, ax = plt.subplots()
    with pytest.raises(gc.GlidectlError, match="axes"):
        sim.plot(ax, names=["V", "gamma"])


def test_ensemble_plot():
    sp = gc.singular_perturbation(SPHERE)
    xe = sp.equilibrium
    rng = np.random.default_rng(1)
    X0 = xe + rng.uniform([-0.5 * xe[0], -0.5, -0.05, -0.2], [0.5 * xe[0], 0.5, 0.05, 0.2], (12, 4))
    X0[:3, 0] = 0.01 * xe[0]  # frozen at once
    model = gc.ReducedLongitudinalGlider(SPHERE)
    ens = gc.simulate_many(model, X0, 30.0, freeze=lambda X: X[:, 0] < 0.05 * xe[0])
    assert ens.state_names == model.state_names and ens.frozen[:3].all()
    conv = (np.max(np.abs(ens.x_final - xe), axis=1) <= 1e-2) & ~ens.frozen
    ax = ens.plot(dims=("V", "gamma"), x_e=xe, tol=1e-2)
    groups = [conv, ~conv & ~ens.frozen, ens.frozen]
    assert len(ax.lines) == sum(bool(g.any()) for g in groups) + 1  # one line per outcome, the equilibrium
    assert sum(len(line.get_xdata()) for line in ax.lines[:-1]) == len(X0)
    assert ax.get_xlabel() == "$V$ [m/s]" and ax.get_ylabel() == r"$\gamma$ [deg]"
    ax = ens.plot(dims=(2, 3))  # without an equilibrium: frozen or not
    assert len(ax.lines) == 2 and ax.get_xlabel() == r"$\alpha$ [deg]" and ax.get_ylabel() == r"$\Omega_2$ [deg/s]"
    with pytest.raises(gc.GlidectlError, match="two different"):
        ens.plot(dims=("V", 0))


class _Linear:
    state_names = ("theta", "Omega2")
    input_names = ("u1",)
    A = np.array([[0.0, 1.0], [2.0, -1.0]])
    B = np.array([[0.0], [1.0]])

    def rhs(self, x, u):
        return np.asarray(x) @ self.A.T + np.asarray(u) @ self.B.T


def test_batch_comparison_plot():
    m = _Linear()
    X0 = np.random.default_rng(0).uniform(-1.0, 1.0, (40, 2))
    free = lqr_state_feedback(m, [0.0, 0.0], [0.0])
    sat = lqr_state_feedback(m, [0.0, 0.0], [0.0], u_min=[-1.0], u_max=[1.0], name="sat")
    out = compare_controllers(m, {"LQR": free, "saturated": sat}, X0, [0.0, 0.0], [0.0], 15.0,
                              diverged=lambda X: np.abs(X).max(axis=1) > 50)
    assert out.state_names == ("theta", "Omega2")
    ax = out.plot()
    assert len(ax.lines) == 2 * 2 + 1  # converges / does not per controller, the equilibrium
    n_fail = int(np.sum(~out.records["saturated"].converged))
    assert len(ax.lines[3].get_xdata()) == n_fail > 0
    assert ax.get_xlabel() == r"$\theta$ [deg]" and ax.get_ylabel() == r"$\Omega_2$ [deg/s]"
    assert any("saturated: converges" in t.get_text() for t in ax.get_legend().get_texts())
    ax = out.plot(dims=("Omega2", "theta"))
    assert ax.get_xlabel() == r"$\Omega_2$ [deg/s]"


# ------------------------------------------------------------------------------------------------ helices
def test_helix_sweep_plot():
    sw = gc.helix_sweep(SLOCUM, "r_P1", np.linspace(0.01, 0.02, 5), r_p=(0.02, 0.02, 0.04), m0=0.25)
    ax = sw.plot(column="speed")
    uns = sw.exists & ~sw.stable
    assert len(ax.lines) == 1 + bool(uns.any())
    assert ax.get_xlabel() == r"$r_{P1}$ [m]" and ax.get_ylabel() == "speed [m/s]"
    assert "speed versus" in ax.get_title() and "m0 = 0.25 kg" in ax.get_title()
    np.testing.assert_allclose(ax.lines[0].get_ydata(), sw.speed)
    with pytest.raises(gc.GlidectlError, match="unknown column"):
        sw.plot(column="nope")


def test_existence_scan_plot():
    scan = gc.existence_scan(SLOCUM, [-0.02, 0.02], [-0.25, 0.25], n_starts=4, continuation=False)
    ax = scan.plot()
    assert len(ax.collections) == 2  # the two quadrants of the claim region
    su = scan.n_stable_upright > 0
    groups = [su, scan.exists & ~su, ~scan.exists]
    assert len(ax.lines) == sum(bool(g.any()) for g in groups) + 2  # outcomes, the axes m0 = 0 and r_P1 = 0
    assert len(ax.texts) == int(np.sum(scan.exists))  # number of motions at each point with one
    assert ax.get_xlabel() == "$r_{P1}$ [cm]" and ax.get_ylabel() == "$m_0$ [kg]"


# ------------------------------------------------------------------------------------------------ certificates
@pytest.fixture(scope="module")
def vdp_cert():
    return gc.certify_roa(gc.benchmarks.van_der_pol(), degree=2, iterations=1,
                          sampling=dict(n_truth=128, n_verify=2000, n_simulate=8))


def test_roa_certificate_plot(vdp_cert):
    c = vdp_cert
    ax = c.plot(n=61)
    assert len(ax.collections) == 2  # the set (filled) and its boundary
    # random points of the set, the outermost points (the verification's simulation starts), the equilibrium
    assert len(ax.lines) == 3
    assert [ln.get_label().split(" ", 1)[1] for ln in ax.lines[:2]] == [
        "random points of the set", "outermost points (simulation starts)"]
    assert ax.lines[2].get_label() == "equilibrium"
    pts = np.column_stack([ax.lines[0].get_xdata(), ax.lines[0].get_ydata()])
    assert pts.shape == (61, 2) and c.contains(pts).all()
    outer = np.column_stack([ax.lines[1].get_xdata(), ax.lines[1].get_ydata()])
    # outermost: on the level set's boundary, i.e. just inside and just outside under a 1 % radial change
    assert c.contains(0.99 * outer).all() and not c.contains(1.01 * outer).any()
    assert ax.get_xlabel() == "$x_1$ [-]" and ax.get_ylabel() == "$x_2$ [-]"
    lo, hi = c.system.box
    assert ax.get_xlim() == (lo[0], hi[0]) and ax.get_ylim() == (lo[1], hi[1])
    assert "van_der_pol" in ax.get_title()
    ax = c.plot(dims=("x2", "x1"), n=41, samples=False)
    assert len(ax.lines) == 1 and ax.get_xlabel() == "$x_2$ [-]"
    with pytest.raises(gc.GlidectlError, match="two different"):
        c.plot(dims=(0, 0))
    with pytest.raises(gc.GlidectlError, match="fixed"):
        c.plot(fixed=[0.0, 0.0, 0.0])


def test_composite_certificate_plot():
    cl = gc.composite_lyapunov(gc.load_vehicle("sphere_ch5", K_M=-100.0))
    ax = cl.plot(n=81)
    assert len(ax.collections) == 3  # L* filled and its boundary, Phi = v0
    assert len(ax.lines) == 2  # the box B_p, the steady glide
    assert ax.get_xlabel() == r"$\bar V$ [-]" and ax.get_ylabel() == r"$\bar\gamma$ [deg]"
    box = ax.lines[0].get_ydata()                                   # the box B_p, drawn in degrees
    np.testing.assert_allclose([box.min(), box.max()], np.degrees(cl.domain.gammabar), rtol=1e-12)
    assert ("NOT certified" in ax.get_title()) == (not cl.certified)
    assert len(ax.get_legend().get_texts()) == 4


# ------------------------------------------------------------------------------------------------ CTOL tracking
def test_tracking_run_plot():
    veh = gc.load_vehicle("dc8_ctol")
    speed = 0.85 / math.sqrt(30.0)
    level = ClimbTrajectory(speed, forcing=0.0)
    x0 = gc.ctol_glide(veh, speed, 0.0).full_state((0.0, 0.05))
    gt = track_with_steady_glides(veh, level, dt=4.0, k3=10.0, k4=10.0, t_final=20.0, x0=x0)
    axes = gt.run.plot()
    assert len(axes) == 3
    assert [len(a.lines) for a in axes] == [2, 1, 1]
    assert axes[0].get_ylabel() == "position error [m]"
    assert axes[1].get_ylabel().endswith("[N]") and axes[2].get_ylabel().endswith("[N m]")
    assert axes[-1].get_xlabel() == "t [s]" and "steady gliding" in axes[0].get_title()
    assert len(gt.plot(input_scale="symlog")) == 3  # GlideTracking draws its run
    # a run stopped early: its end is marked on every axes
    t = np.linspace(0.0, 1.0, 11)
    u = np.column_stack([np.ones(11), np.r_[np.full(10, 0.5), 1e3]])
    run = TrackingRun.from_arrays("test", t, np.zeros((11, 6)), u, np.zeros((11, 2)), stopped_at=1.0)
    axes = run.plot(input_scale="symlog")
    assert [len(a.lines) for a in axes] == [3, 2, 2]
    # only the input with a spike (peak > 100 x its median) goes on a symmetric log scale
    assert axes[1].get_yscale() == "linear" and axes[2].get_yscale() == "symlog"
    with pytest.raises(gc.GlidectlError, match="input_scale"):
        run.plot(input_scale="log")


def test_pareto_study_plot():
    pts = [(0.1, 1.0, 10.0, 1.0, 50.0), (0.1, 1e3, 60.0, 0.2, 400.0), (0.5, 1.0, 10.0, 3.0, 5.0),
           (0.5, 1e3, 60.0, 1.0, 800.0), (1.0, 1e3, 60.0, 9.0, 900.0)]
    recs = [{"dt": d, "k3": k3, "k4": k4, "completed": i != 4, "max_error": e, "effort": f}
            for i, (d, k3, k4, e, f) in enumerate(pts)]
    done = [i for i, r in enumerate(recs) if r["completed"]]
    front = [done[j] for j in pareto_front([(recs[i]["max_error"], recs[i]["effort"]) for i in done])]
    study = ParetoStudy(tuple(recs), tuple(front), 20.0)
    ax = study.plot()
    assert len(ax.lines) == len(done) + 1  # one marker per completed run, the front
    np.testing.assert_allclose(ax.lines[-1].get_xdata(), [recs[i]["effort"] for i in front])
    assert ax.get_ylabel() == "max position error [m]" and "[-]" in ax.get_xlabel()
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert len(ax.get_legend().get_texts()) == 2 + 3 + 1  # gain pairs, replanning intervals, front
    assert "1 stopped" in ax.get_title()
