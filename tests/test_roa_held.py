"""certify_roa and locked (held) states (issue 17): the stability check comes before any surrogate is built, a
closed loop's states that never move are held at their equilibrium values, and the certificate says so."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

import glidectl as gc
from glidectl import checks as gc_checks
from glidectl.errors import ModelError
from glidectl.roa import alternation, certificate, dVdt, programs, routes
from glidectl.roa.routes import held_states


class Loop:
    """``x1' = -x2``, ``x2' = x1 + (x1^2 - 1) x2 x3 + k sin(x1)``, ``x3' = c x1^2`` at ``(0, 0, 1)``: with ``k = 0``,
    ``c = 0`` the reversed Van der Pol oscillator with a locked gain ``x3`` (polynomial); ``k`` makes it
    non-polynomial, ``c`` makes ``x3`` move (zero linearization row, not held)."""

    state_names = ("x1", "x2", "x3")
    equilibrium = np.array([0.0, 0.0, 1.0])

    def __init__(self, k: float = 0.0, c: float = 0.0, damping: float = 1.0, name: str = "locked loop") -> None:
        self.k, self.c, self.damping, self.name = k, c, damping, name

    def rhs(self, X):
        X = np.asarray(X)
        x1, x2, x3 = X[..., 0], X[..., 1], X[..., 2]
        return np.stack([-x2, x1 + (x1**2 - self.damping) * x2 * x3 + self.k * np.sin(x1), self.c * x1**2 + 0 * x3],
                        axis=-1)


BOX = (np.array([-3.0, -3.0, 0.5]), np.array([3.0, 3.0, 1.5]))


class Saddle:
    """``x1' = sin(x1) - x1 / 2`` (unstable), ``x2' = -x2``: not polynomial, so ``auto`` would build a surrogate."""

    state_names = ("x1", "x2")
    equilibrium = np.zeros(2)
    name = "saddle"

    def rhs(self, X):
        X = np.asarray(X)
        return np.stack([np.sin(X[..., 0]) - 0.5 * X[..., 0], -X[..., 1]], axis=-1)


def _no_route(*args, **kwargs):
    raise AssertionError("a surrogate or recast was built before the stability check")


@pytest.mark.parametrize("method", ["auto", "surrogate"])
def test_unstable_loop_refused_before_any_surrogate_or_recast(monkeypatch, method):
    monkeypatch.setattr(routes, "surrogate_system", _no_route)
    monkeypatch.setattr(routes, "recast", _no_route)
    box = (np.array([-1.0, -1.0]), np.array([1.0, 1.0]))
    with pytest.raises(ModelError) as err:
        gc.certify_roa(Saddle(), degree=2, box=box, method=method)
    # the message certify_roa gave before (after building the surrogate), with the exact eigenvalues 1 - 1/2, -1
    assert str(err.value) == (
        "the equilibrium of 'saddle' is not exponentially stable: its linearization is unstable, eigenvalues "
        "[0.5, -1.0]. A region of attraction is certified only for an exponentially stable equilibrium "
        "(every eigenvalue with negative real part)")


def test_locked_state_is_held_and_the_set_is_certified_on_the_others():
    cert = gc.certify_roa(Loop(), degree=4, box=BOX)
    assert cert.held == ("x3",) and cert.certified
    assert cert.system.state_names == ("x1", "x2", "x3") and cert.system.held == (2,)
    assert np.array_equal(cert.system.equilibrium, [0.0, 0.0, 1.0])
    X = cert.sample(400, seed=3)
    assert X.shape == (400, 3) and np.all(X[:, 2] == 1.0) and cert.contains(X).all()
    # the true dV/dt of the full loop is negative at every sampled point of the set (the held state at its value)
    r2 = np.sum(X[:, :2] ** 2, axis=1)
    keep = r2 > 1e-12
    assert np.max(dVdt(cert.V, cert.system.lift, cert.system.rhs, X[keep]) / r2[keep]) < 0
    # certified AT the held value only: moved off it, no point is in the set
    Y = X.copy()
    Y[:, 2] = 1.001
    assert not cert.contains(Y).any()
    # the volume is the area in (x1, x2): the same as measuring the slice x3 = 1 directly
    area = gc.box_measure(lambda P: cert.contains(np.column_stack([P, np.ones(len(P))])), (BOX[0][:2], BOX[1][:2]),
                          2**12, 0, dim=2)
    assert 0 < area < 36.0 and cert.volume(n=2**12) == area
    assert cert.box[0].tolist() == BOX[0].tolist() and cert.box[1].tolist() == BOX[1].tolist()
    # the plot takes the full states: a slice in (x1, x2) through the equilibrium (x3 at its value)
    import matplotlib.pyplot as plt

    ax = cert.plot(dims=("x1", "x2"), n=21, samples=False)
    assert ax.get_xlabel() and ax.get_ylabel()
    plt.close(ax.figure)


def test_a_moving_state_with_a_zero_linearization_row_is_not_held():
    # x3' = x1^2: its Jacobian row vanishes at the equilibrium but it moves on the box: not held, refused as before
    loop = Loop(c=1.0)
    lo, hi = BOX
    assert held_states(loop, loop.equilibrium, (lo, hi)) == ()
    with pytest.raises(ModelError, match=r"not exponentially stable: its linearization is marginally stable.*0j"):
        gc.certify_roa(loop, degree=2, box=BOX)


def test_held_states_do_not_hide_unstable_free_dynamics(monkeypatch):
    # x3 is held, but the free dynamics (damping -1: x2' = x1 + x2 + ...) are unstable: the refusal names the
    # eigenvalues of the free states only, before anything is built
    monkeypatch.setattr(routes, "surrogate_system", _no_route)
    monkeypatch.setattr(routes, "recast", _no_route)
    with pytest.raises(ModelError, match=r"'held' is not exponentially stable: its linearization is unstable, "
                                         r"eigenvalues \[\(0\.5\+0\.866025j\), \(0\.5-0\.866025j\)\]"):
        gc.certify_roa(Loop(damping=-1.0, name="held"), degree=2, box=BOX)


def _slocum_loop():
    veh = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    return gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration", reduce_fixed=False))


def test_slocum_lqr_loop_holds_the_states_saturated_loop_holds(monkeypatch):
    loop = _slocum_loop()
    sl = gc.saturated_loop(loop)
    held = held_states(loop, np.asarray(loop.equilibrium, float), gc.validity_box(loop))
    assert held == sl.held and [loop.state_names[i] for i in held] == ["r_P3", "rdot_P3"]

    seen = {}

    class Built(Exception):
        pass

    def spy(model, box, **kw):
        seen["names"], seen["box"] = tuple(model.state_names), box
        raise Built

    # past the stability check: the surrogate is asked for on the 8 free states and the validity box of those
    monkeypatch.setattr(routes, "surrogate_system", spy)
    with pytest.raises(Built):
        gc.certify_roa(loop, degree=2, method="surrogate", budget=dict(time_limit=60.0))
    free = [q for q in loop.state_names if q not in ("r_P3", "rdot_P3")]
    assert seen["names"] == tuple(free)
    lo, hi = gc.validity_box(loop)
    idx = [loop.state_names.index(q) for q in free]
    assert np.array_equal(seen["box"][0], lo[idx]) and np.array_equal(seen["box"][1], hi[idx])


# --------------------------------------------------------------------------------------------- time_limit (task 3)
class _Clock:
    now = 0.0


class _FakeDeadline(gc_checks.Deadline):
    """A deadline whose clock the test sets (deterministic budget tests)."""

    @property
    def elapsed(self) -> float:
        return _Clock.now


def _vdp():
    return gc.benchmarks.van_der_pol()


def test_time_limit_bounds_the_final_verification_sampling(monkeypatch):
    monkeypatch.setattr(programs.checks, "Deadline", _FakeDeadline)
    real = certificate.verify_certificate

    def late(*args, **kwargs):          # the alternation ran within the limit; the verification starts past it
        _Clock.now = 1e9
        return real(*args, **kwargs)

    _Clock.now = 0.0
    monkeypatch.setattr(alternation, "verify_certificate", late)
    with pytest.raises(gc.BudgetError, match=r"time limit of 100 s in the final verification, while sampling the "
                                             r"certified set \(n_verify = 5000 points\).*lower n_verify"):
        gc.certify_roa(_vdp(), degree=2, iterations=1, sampling=dict(n_truth=256, n_verify=5000),
                       budget=dict(time_limit=100.0))
    # on_budget="stop" documents that the final checks still run in full: the same call certifies
    _Clock.now = 0.0
    cert = gc.certify_roa(_vdp(), degree=2, iterations=1, sampling=dict(n_truth=256, n_verify=5000, n_simulate=16),
                          budget=dict(time_limit=100.0, on_budget="stop"))
    assert cert.certified and cert.verification.n_simulated == 16


def test_time_limit_bounds_the_final_simulations(monkeypatch):
    real = certificate.integrate_batch
    seen = []

    def batch(f, X0, t_final, **kw):
        if kw.get("rtol") == 1e-7:       # the verification's simulations: they get the time left, and run out
            seen.append(kw.get("time_limit"))
            raise gc.BudgetError("integrate_batch (16 runs) stopped at its time limit")
        return real(f, X0, t_final, **kw)

    monkeypatch.setattr(certificate, "integrate_batch", batch)
    with pytest.raises(gc.BudgetError, match=r"final verification ran out of its time limit while simulating "
                                             r"n_simulate = 16 runs.*lower n_simulate or horizon"):
        gc.certify_roa(_vdp(), degree=2, iterations=1, sampling=dict(n_truth=256, n_verify=5000, n_simulate=16),
                       budget=dict(time_limit=100.0))
    assert len(seen) == 1 and 0 < seen[0] <= 100.0


def test_tiny_time_limit_stops_quickly_with_a_budget_error():
    t = time.perf_counter()
    with pytest.raises(gc.BudgetError, match=r"time limit of 0\.001 s"):
        gc.certify_roa(_vdp(), degree=2, budget=dict(time_limit=1e-3))
    assert time.perf_counter() - t < 5.0


def test_budget_message_says_what_took_the_time_and_what_would_fit(monkeypatch):
    monkeypatch.setattr(programs.checks, "Deadline", _FakeDeadline)
    real = programs.solve_level
    calls = []

    def level(*args, **kwargs):         # the limit passes after the first V step's level problem
        out = real(*args, **kwargs)
        calls.append(1)
        if len(calls) == 2:
            _Clock.now = 1e9
        return out

    _Clock.now = 0.0
    monkeypatch.setattr(alternation, "solve_level", level)
    with pytest.raises(gc.BudgetError) as err:
        gc.certify_roa(_vdp(), degree=2, iterations=3, sampling=dict(n_truth=256), budget=dict(time_limit=100.0))
    msg = str(err.value)
    assert "degree 2, before a V step; time spent: building the exact recast system of 2 states" in msg
    assert "first level problem" in msg and "simulating n_truth = 256 box points" in msg
    assert "1 V step(s) with their level problems" in msg
    assert "degree 2 with iterations = 3 needs about" in msg and "raise time_limit to that" in msg


def test_the_surrogate_memory_estimate_counts_only_the_free_states():
    """A limit between the sizes of the 2-free-state and the 3-state surrogate programs: not refused (x3 is held, so
    the program has 2 states); a limit below the 2-state size: refused up front, naming the held state."""
    def size(n: int) -> float:
        sk = programs.skeleton(n, 3)
        return programs._size(sk, 4, programs.auto_extra(sk, None)).bytes

    two, three = size(2), size(3)
    assert two < three
    with pytest.raises(gc.BudgetError) as exc:
        gc.certify_roa(Loop(k=0.3), degree=4, box=BOX, method="surrogate",
                       budget=dict(memory_limit=0.5 * (two + three), time_limit=1e-9))
    assert "refused before building anything" not in str(exc.value)      # the time limit, not the memory estimate
    with pytest.raises(gc.BudgetError, match=r"2-state surrogate of degree 3 \(x3 held\).*refused before building"):
        gc.certify_roa(Loop(k=0.3), degree=4, box=BOX, method="surrogate", budget=dict(memory_limit=0.5 * two))
