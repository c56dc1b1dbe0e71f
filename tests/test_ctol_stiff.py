"""The stiff steady-glide tracking runs (printed gains k3 = 7e5, k4 = 250: the pitch loop rings at 1522 rad/s): the
exact closed-loop Jacobian handed to the implicit solvers, and the default solution against a tight-tolerance
reference from an independent (explicit, 8th-order) method."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import glidectl as gc
from glidectl.controllers import ctol_tracking
from glidectl.controllers.ctol import SteadyGlideController
from glidectl.controllers.ctol_tracking import _augmented, _closed_loop_jacobian, track_with_steady_glides
from glidectl.derivatives import central_difference_jacobians
from glidectl.models.ctol import CTOLAircraft
from glidectl.trim.ctol import _roots, angle_equation

VEH = gc.load_vehicle("dc8_ctol")
TRAJ = gc.climb_trajectory(VEH, 0.85)
MODEL = CTOLAircraft(VEH)


@pytest.mark.parametrize(("k3", "k4", "V", "gamma"), [(7e5, 250.0, 0.3, 0.2), (10.0, 5.0, 0.155, 0.0),
                                                      (1e4, 200.0, 0.5, -0.4)])
def test_tracking_jacobian_matches_central_differences(k3, k4, V, gamma):
    glide = gc.ctol_glide(VEH, V, gamma)
    ctrl = SteadyGlideController(VEH, glide, k3, k4)
    z = np.r_[glide.full_state((1.0, -2.0)), 0.5, 2.0, 2.5] + np.array([0, 0, 0.03, -0.02, 0.05, 0.4, 0, 0, 0])
    J = _closed_loop_jacobian(MODEL, ctrl)(0.0, z)
    Jc = central_difference_jacobians(lambda x, u: _augmented(MODEL, ctrl, x), z, np.zeros(0), h=1e-7)[0]
    assert J.shape == (9, 9)
    scale = np.maximum(np.abs(Jc).max(axis=1, keepdims=True), 1.0)
    assert np.max(np.abs(J - Jc) / scale) < 1e-6
    # the pitch loop's stiffness is in the Jacobian: dOmega2'/dtheta = -(k3/eps) cos(theta - theta_e) - ...
    assert J[5, 4] < -0.5 * k3 / VEH.epsilon
    # the quadrature states do not feed back
    assert np.all(J[:, 6:] == 0)


def test_implicit_methods_get_the_exact_jacobian(monkeypatch):
    seen = []

    def spy(fun, span, y0, **kw):
        seen.append((kw["method"], kw.get("jac")))
        return solve_ivp(fun, span, y0, **kw)

    monkeypatch.setattr(ctol_tracking, "solve_ivp", spy)
    for method in ("LSODA", "BDF", "RK45"):
        track_with_steady_glides(VEH, TRAJ, dt=0.05, k3=10.0, k4=5.0, t_final=0.05, method=method)
    jacs = {m: j for m, j in seen}
    assert jacs["RK45"] is None
    z = np.r_[gc.ctol_glide(VEH, TRAJ.speed, 0.0).full_state((0.0, 0.0)), 0.0, 0.0, 0.0]
    glide = gc.ctol_glide(VEH, TRAJ.speed, 0.0)  # the first chord of the climb from its level start
    x0 = glide.full_state((0.0, 0.0))
    chord = TRAJ.position(0.05) - x0[:2]
    first = gc.ctol_glide(VEH, float(np.hypot(*chord)) / 0.05, float(np.arctan2(chord[1], chord[0])))
    expected = _closed_loop_jacobian(MODEL, SteadyGlideController(VEH, first, 10.0, 5.0))(0.0, z)
    for m in ("LSODA", "BDF"):
        assert callable(jacs[m])
        assert np.array_equal(jacs[m](0.0, z), expected)


def test_printed_gains_default_solution_equals_tight_reference():
    """One replanning interval with the printed gains (the first kick: the pitch loop rings at 1522 rad/s): the
    default run (LSODA, rtol 1e-8, exact Jacobian) equals DOP853 at rtol 1e-12 (an independent method)."""
    a = track_with_steady_glides(VEH, TRAJ, dt=0.1, t_final=0.1)
    b = track_with_steady_glides(VEH, TRAJ, dt=0.1, t_final=0.1, method="DOP853", rtol=1e-12, atol=1e-14)
    assert a.completed and b.completed
    scale = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1e3])  # Omega2 rings with amplitude ~1e3 x its final value
    assert np.max(np.abs(a.x[-1] - b.x[-1]) / scale) < 1e-7
    assert a.peak_u2 == pytest.approx(b.peak_u2, rel=1e-9)  # the jump at t = 0: exact
    assert a.rms_u2 == pytest.approx(b.rms_u2, rel=1e-6)    # the quadrature state over the ringing
    assert a.rms_u1 == pytest.approx(b.rms_u1, rel=1e-6)
    # max |e| is taken on the solver's step points: equal to the sampling resolution
    assert a.max_error == pytest.approx(b.max_error, rel=2e-3)


@pytest.mark.parametrize(("V", "gamma"), [(0.155, 0.0), (0.05, -1.2), (0.6, 1.3), (0.3, 3.0)])
def test_angle_equation_roots_are_all_the_sign_changes(V, gamma):
    a = np.linspace(-np.pi, np.pi, 4001)
    f = angle_equation(VEH, V, gamma, a)
    roots = _roots(VEH, V, gamma)
    expected = int(np.sum(f[:-1] * f[1:] < 0) + np.sum(f[:-1] == 0))
    assert len(roots) == expected >= 1
    assert np.all(np.diff(roots) > 0)
    assert np.max(np.abs(angle_equation(VEH, V, gamma, np.array(roots)))) < 1e-12 * max(1.0, 30 * V * V)
