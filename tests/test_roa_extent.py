"""Per-axis extents (``cert.extent()``, ``gc.convergent_extent``), the certificate protocol shared by the SOS and LMI
certificates, and the grouped options of ``gc.certify_roa``."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.roa import Poly, polynomial_system


@pytest.fixture(scope="module")
def vdp_cert():
    return gc.certify_roa(gc.benchmarks.van_der_pol(), degree=4, iterations=2,
                          sampling={"n_truth": 256, "n_verify": 2000, "n_simulate": 8})


@pytest.fixture(scope="module")
def buoyancy_lmi():
    sph = gc.load_vehicle("sphere_ch5")
    sl = gc.saturated_loop(gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0)))
    return sl, gc.certify_roa_lmi(sl, rounds=1, n_radii=4, refine=1, n_hessian=128, n_verify=500, n_simulate=4)


def _axis_points(ext: gc.Extent, k: int, scale: float) -> np.ndarray:
    """The states at ``x_e + scale (lo - x_e)`` and ``x_e + scale (hi - x_e)`` on axis ``k``."""
    X = np.tile(ext.equilibrium, (2, 1))
    X[0, k] = ext.equilibrium[k] - scale * ext.below[k]
    X[1, k] = ext.equilibrium[k] + scale * ext.above[k]
    return X


def test_sos_extent_ends_are_the_boundary_of_the_certified_set(vdp_cert):
    """Just inside each end the states are in the set, just beyond they are not (bisection on contains)."""
    ext = vdp_cert.extent()
    assert ext.names == ("x1", "x2") and ext.rigorous and vdp_cert.rigorous
    assert np.all(ext.below > 0.5) and np.all(ext.above > 0.5)
    for k in range(2):
        assert np.all(vdp_cert.contains(_axis_points(ext, k, 1.0 - 1e-6)))
        assert not np.any(vdp_cert.contains(_axis_points(ext, k, 1.0 + 1e-6)))


def test_convergent_extent_of_van_der_pol_is_its_limit_cycle():
    """The time-reversed Van der Pol converges from inside the limit cycle: along x1 the interval ends where the
    cycle crosses x2 = 0 (|x1| = 2.0086, the classical amplitude for mu = 1), along x2 where it crosses x1 = 0,
    both taken from the simulated cycle."""
    conv = gc.convergent_extent(gc.benchmarks.van_der_pol(), steps=16)
    cycle, _ = gc.benchmarks.van_der_pol_limit_cycle(20001)

    def crossing(along: int) -> float:       # |x_along| where the cycle crosses the other axis (interpolated)
        other = cycle[:, 1 - along]
        i = np.flatnonzero(np.sign(other[:-1]) != np.sign(other[1:]))
        w = other[i] / (other[i] - other[i + 1])
        return float(np.max(np.abs(cycle[i, along] + w * (cycle[i + 1, along] - cycle[i, along]))))

    amp_x1, amp_x2 = crossing(0), crossing(1)
    assert amp_x1 == pytest.approx(2.0086, abs=2e-3)
    np.testing.assert_allclose(conv.above, [amp_x1, amp_x2], rtol=3e-3)
    np.testing.assert_allclose(conv.below, [amp_x1, amp_x2], rtol=3e-3)     # the cycle is odd-symmetric
    assert conv.rigorous is None and conv.what.startswith("convergent")


def test_convergent_extent_of_a_stable_linear_loop_is_the_whole_box():
    x1, x2 = Poly.variables(2)
    ps = polynomial_system("linear", ("x1", "x2"), [-x1 + 0.5 * x2, -2.0 * x2], box=((-1.0, -2.0), (3.0, 2.0)))
    conv = gc.convergent_extent(ps, n=4, steps=0)
    np.testing.assert_allclose(conv.lo, [-1.0, -2.0])
    np.testing.assert_allclose(conv.hi, [3.0, 2.0])


def test_convergent_extent_within_the_box_stops_where_runs_leave_it():
    """x1' = -x1, x2' = 10 x1 - x2: from (a, 0), x2(t) = 10 a t e^-t peaks at 10 a / e. Every run converges, but
    with |x2| <= 1 the runs that stay in the box start at |x1| <= e / 10 (the reference a certificate in that box
    can reach); without within_box the whole x1 interval."""
    x1, x2 = Poly.variables(2)
    ps = polynomial_system("overshoot", ("x1", "x2"), [-x1, 10.0 * x1 - x2], box=((-1.0, -1.0), (1.0, 1.0)))
    inside = gc.convergent_extent(ps, n=8, steps=16)
    anywhere = gc.convergent_extent(ps, n=8, steps=16, within_box=False)
    np.testing.assert_allclose(inside.hi, [math.e / 10, 1.0], rtol=1e-3)
    np.testing.assert_allclose(inside.lo, [-math.e / 10, -1.0], rtol=1e-3)
    np.testing.assert_allclose(anywhere.hi, [1.0, 1.0])
    assert inside.what.startswith("convergent in the box") and anywhere.what.startswith("convergent (")


def test_convergent_extent_cuts_at_the_first_gap_along_an_axis():
    """x1' = -x1 (x1 - 1)(x1 - 2) / 2: a stable origin, an unstable point at 1: from the positive side the runs converge
    only below 1 (the interval, not the stable point at 2 beyond it)."""
    x1, x2 = Poly.variables(2)
    ps = polynomial_system("gap", ("x1", "x2"), [-0.5 * x1 * (x1 - 1.0) * (x1 - 2.0), -x2],
                           box=((-1.0, -1.0), (3.0, 1.0)))
    conv = gc.convergent_extent(ps, n=8, steps=14)
    assert conv.hi[0] == pytest.approx(1.0, abs=1e-3) and conv.lo[0] == pytest.approx(-1.0)
    assert conv.hi[1] == pytest.approx(1.0) and conv.lo[1] == pytest.approx(-1.0)


def test_ellipsoid_extent_is_the_axis_of_the_ellipsoid(buoyancy_lmi):
    sl, cert = buoyancy_lmi
    ext = cert.extent()
    f = list(sl.free)
    np.testing.assert_allclose(ext.above[f], 1.0 / np.sqrt(np.diag(cert.P)), rtol=1e-12)
    assert np.all(ext.below[list(sl.held)] == 0) and np.all(ext.above[list(sl.held)] == 0)
    for k in f:
        assert np.all(cert.contains(_axis_points(ext, k, 1.0 - 1e-9)))
        assert not np.any(cert.contains(_axis_points(ext, k, 1.0 + 1e-6)))
    assert cert.rigorous is (cert.certified and not np.any(cert.remainder))


def test_both_certificates_follow_one_protocol(vdp_cert, buoyancy_lmi):
    """The same names on the SOS and the LMI certificate, the same sample signature, plot returns Axes."""
    import matplotlib
    matplotlib.use("Agg")
    _, lmi = buoyancy_lmi
    for cert in (vdp_cert, lmi):
        assert isinstance(cert, gc.Certificate)
        X = cert.sample(16, seed=3, boundary=False)
        assert X.shape == (16, len(cert.extent().names)) and np.all(cert.contains(X))
        assert cert.volume() > 0 and cert.rho > 0 and isinstance(cert.method, str)
        assert cert.in_box is (cert is lmi)           # the exact recast's set may reach beyond its box
        assert hasattr(cert.plot(), "get_xlabel")
    with pytest.raises(TypeError):
        lmi.sample(4, 0, True)              # boundary is keyword-only on both
    with pytest.raises(TypeError):
        vdp_cert.sample(4, 0, True)


def test_ellipsoid_slice_plots_angles_in_degrees():
    """The conventions page: angles in degrees on figure axes (states stay in radians)."""
    import matplotlib
    matplotlib.use("Agg")
    ev = gc.load_vehicle("elevator_ch6")
    eq = gc.elevator_equilibrium(ev, 1.0, -math.pi / 4)
    sl = gc.saturated_loop(gc.closed_loop(gc.ElevatorBuoyancyController(eq, ev, 1.0)))
    cert = gc.certify_roa_lmi(sl, rounds=1, n_radii=4, refine=1, n_hessian=128, n_verify=500, n_simulate=4)
    ax = cert.plot(dims=("gamma", "m0"))
    assert "[deg]" in ax.get_xlabel() and "[kg]" in ax.get_ylabel()
    k = sl.state_names.index("gamma")
    lo, hi = math.degrees(cert.box[0][k]), math.degrees(cert.box[1][k])
    x0, x1 = ax.get_xlim()                              # the box (drawn) with margins, in degrees
    assert x0 <= lo < hi <= x1 and x1 - x0 < 1.2 * (hi - lo)


def test_extent_bar_chart_and_ratio(vdp_cert):
    import matplotlib
    matplotlib.use("Agg")
    ext = vdp_cert.extent()
    conv = gc.convergent_extent(gc.benchmarks.van_der_pol(), n=8, steps=6)
    below, above = ext.ratio(conv)
    np.testing.assert_allclose(below, ext.below / conv.below)
    assert np.all((above > 0.3) & (above <= 1.0 + 1e-9))
    ax = ext.plot(other=conv)
    assert len(ax.patches) == 8                  # 2 axes x 2 directions x (certified, convergent)
    assert len(ext.table(conv)) == 2 and len(ext.table(conv)[0]) == 6
    other = gc.Extent(("a", "b"), ext.lo, ext.hi, ext.equilibrium, ext.box)
    with pytest.raises(gc.ArgumentError):
        ext.ratio(other)


def test_convergent_extent_refuses_bad_input():
    x1, x2 = Poly.variables(2)
    unstable = polynomial_system("unstable", ("x1", "x2"), [x1, -x2], box=((-1.0, -1.0), (1.0, 1.0)))
    with pytest.raises(gc.ModelError, match="not exponentially stable"):
        gc.convergent_extent(unstable)
    vdp = gc.benchmarks.van_der_pol()
    with pytest.raises(gc.ArgumentError, match="equilibrium"):
        gc.convergent_extent(vdp, box=((0.5, -1.0), (1.0, 1.0)))
    with pytest.raises(gc.ModelError, match="too short to tell"):
        gc.convergent_extent(vdp, horizon=1e-3)
    with pytest.raises(gc.ArgumentError):
        gc.convergent_extent(vdp, n=1)
    veh = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    with pytest.raises(gc.ArgumentError, match="inputs"):
        gc.convergent_extent(gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration")).plant)


def test_options_are_grouped_and_checked():
    assert gc.SamplingOptions().n_truth == 2048 and gc.SolverOptions().name == "CVXOPT_MOMENT"
    with pytest.raises(gc.ArgumentError):
        gc.SamplingOptions(n_verify=0)
    with pytest.raises(gc.ArgumentError):
        gc.BudgetOptions(on_budget="later")
    with pytest.raises(gc.ArgumentError):
        gc.SurrogateOptions(degree=7)
    with pytest.raises(gc.ArgumentError):
        gc.SolverOptions(name="NOPE")
    cert = gc.certify_roa(gc.benchmarks.van_der_pol(), degree=2, iterations=1, solver="CLARABEL",
                          sampling=gc.SamplingOptions(n_truth=64, n_verify=500, n_simulate=4), budget=600.0)
    assert cert.certified and all(isinstance(h, gc.HistoryRow) for h in cert.history)
    assert cert.history[0].step == "initial level" and cert.history[-1].step.startswith("final margin")


def test_convergent_slice_of_van_der_pol_is_the_inside_of_its_limit_cycle(vdp_cert):
    """A grid point converges exactly when it lies inside the (simulated) limit cycle, up to the grid points next to
    the cycle; the certified set lies inside the converging part, and plots over it."""
    import matplotlib
    from matplotlib.path import Path as MplPath
    matplotlib.use("Agg")
    sl = gc.convergent_slice(gc.benchmarks.van_der_pol(), dims=("x1", "x2"), n=25)
    cycle, area = gc.benchmarks.van_der_pol_limit_cycle(4001)
    A, B = np.meshgrid(sl.x, sl.y)
    inside = MplPath(cycle).contains_points(np.column_stack([A.ravel(), B.ravel()])).reshape(A.shape)
    assert np.mean(sl.converged == inside) > 0.97
    assert sl.fraction == pytest.approx(area / (6.0 * 7.0), rel=0.1)
    cert_in = vdp_cert.contains(np.column_stack([A.ravel(), B.ravel()])).reshape(A.shape)
    assert not np.any(cert_in & ~sl.converged)              # the certificate is sound on the grid
    ax = sl.plot()
    vdp_cert.plot(ax=ax, n=41, samples=False)
    assert any("convergent" in t.get_text() for t in ax.get_legend().get_texts())
    with pytest.raises(gc.ArgumentError):
        gc.convergent_slice(gc.benchmarks.van_der_pol(), dims=("x1", "x1"))


def test_convergent_slice_window_grids_a_part_and_refuses_one_outside_the_box():
    vdp = gc.benchmarks.van_der_pol()
    sl = gc.convergent_slice(vdp, dims=(0, 1), n=5, window=((-1.0, 1.0), (-0.5, 0.5)))
    np.testing.assert_allclose(sl.x, np.linspace(-1.0, 1.0, 5))
    assert sl.converged.all()                                   # well inside the limit cycle
    with pytest.raises(gc.ArgumentError, match="window"):
        gc.convergent_slice(vdp, dims=(0, 1), n=5, window=((-4.0, 1.0), (-0.5, 0.5)))
