"""Region-of-attraction certification (glidectl.roa): polynomial layer, SOS programs, exact recasting, level
problem against known answers and Drake, certificates and their soundness on the true models."""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import glidectl as gc
from glidectl.batch import integrate_batch
from glidectl.errors import (
    ArgumentError,
    ArgumentTypeError,
    BudgetError,
    GlidectlError,
    ModelError,
    SolverError,
)
from glidectl.roa import Poly, SOSProgram, max_level, monomials, polynomial_system, recast
from glidectl.roa.programs import lyapunov_quadratic

# ------------------------------------------------------------------------------------------- polynomials
coef = st.floats(-3, 3, allow_nan=False, allow_infinity=False)
expo = st.tuples(st.integers(0, 3), st.integers(0, 3), st.integers(0, 2))
polys = st.dictionaries(expo, coef, max_size=6).map(lambda d: Poly(d, 3))


@settings(max_examples=60, deadline=None)
@given(polys, polys, st.lists(st.floats(-2, 2), min_size=3, max_size=3))
def test_poly_algebra_matches_evaluation(p, q, z):
    z = np.array(z)
    assert (p * q)(z) == pytest.approx(p(z) * q(z), rel=1e-9, abs=1e-9)
    assert (p - q)(z) == pytest.approx(p(z) - q(z), rel=1e-9, abs=1e-9)
    # partial derivatives against central differences, Lie derivative = grad . F
    h = 1e-6
    for i in range(3):
        e = np.eye(3)[i] * h
        assert p.diff(i)(z) == pytest.approx((p(z + e) - p(z - e)) / (2 * h), rel=1e-5, abs=1e-5)
    F = [q, p, q * 2.0]
    assert p.lie(F)(z) == pytest.approx(sum(p.diff(i)(z) * F[i](z) for i in range(3)), rel=1e-9, abs=1e-8)


def test_poly_substitution_and_complex_evaluation():
    x, y = Poly.variables(2)
    p = x**2 * y - 3.0 * y + 1.0
    sub = p.substitute([x + y, x * y])            # (x+y)^2 x y - 3 x y + 1
    z = np.array([0.7, -1.3])
    assert sub(z) == pytest.approx((z.sum()) ** 2 * z.prod() - 3 * z.prod() + 1)
    zc = z + 1e-30j * np.array([1.0, 0.0])
    assert np.imag(p(zc)) / 1e-30 == pytest.approx(p.diff(0)(z))
    assert monomials(2, 2) == [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]
    assert (0, 2, 0) not in monomials(3, 2, max_exponent={1: 1})
    with pytest.raises(GlidectlError):
        Poly({(1, 0): 1.0}, 3)
    with pytest.raises(GlidectlError):
        p ** -1


def test_poly_quadratic_form_evaluates_ztpz():
    rng = np.random.default_rng(2)
    P = rng.standard_normal((3, 3))                 # not symmetric: both P_ij and P_ji enter
    V = Poly.quadratic(P)
    Z = rng.standard_normal((50, 3))
    np.testing.assert_allclose(V(Z), np.einsum("ki,ij,kj->k", Z, P, Z), rtol=1e-13, atol=1e-13)
    assert V.degree == 2 and V.nvars == 3
    for bad in (np.ones((2, 3)), np.zeros((0, 0)), np.array([[np.nan]])):
        with pytest.raises(GlidectlError):
            Poly.quadratic(bad)


def test_sos_program_gram_check_and_infeasibility():
    """x^4 + 2x^2 + 1 = (x^2 + 1)^2 is SOS (exact, positive margin); -x^2 is not (solver failure is an error)."""
    x = Poly.variables(1)[0]
    prog = SOSProgram(1)
    from glidectl.roa.sos import LinPoly

    prog.add_sos("p", LinPoly(x**4 + 2.0 * x**2 + 1.0), monomials(1, 2))
    import cvxpy as cp

    prog.solve(cp.Minimize(0))
    (chk,) = prog.check()
    assert chk.passed and chk.slack > 0 and chk.margin > 1 and chk.max_residual < 1e-7
    bad = SOSProgram(1)
    bad.add_sos("q", LinPoly(-(x**2)), monomials(1, 1))
    with pytest.raises(SolverError):
        bad.solve(cp.Minimize(0))


# ------------------------------------------------------------------------------------------- level problem
def test_level_known_answer_cubic():
    """x' = -x + x^3 has region of attraction (-1, 1); with V = x^2 the level problem gives rho = 1."""
    x = Poly.variables(1)[0]
    ps = polynomial_system("cubic", ("x",), [-x + x**3], box=((-2.0,), (2.0,)))
    r = max_level(ps, x**2)
    assert r.rho == pytest.approx(1.0, abs=1e-4)


def test_level_linear_system_is_global():
    """A stable linear system: V = x'Px decreases everywhere, so the level reaches the cap (global)."""
    x1, x2 = Poly.variables(2)
    ps = polynomial_system("linear", ("x1", "x2"), [-x1 + 2.0 * x2, -3.0 * x2], box=((-1, -1), (1, 1)))
    V = lyapunov_quadratic(ps)
    r = max_level(ps, V, rho_cap=1e4)
    assert r.rho == pytest.approx(1e4, rel=1e-6)


def test_van_der_pol_level_equals_drake():
    """The fixed-V problem of Drake's RegionOfAttraction example: rho = 2.3045 (V from A'P + PA = -I)."""
    vdp = gc.benchmarks.van_der_pol()
    V = lyapunov_quadratic(vdp)
    P = np.array([[1.5, -0.5], [-0.5, 1.0]])
    assert V(np.array([0.3, -0.2])) == pytest.approx(np.array([0.3, -0.2]) @ P @ np.array([0.3, -0.2]))
    assert max_level(vdp, V).rho == pytest.approx(2.3045, abs=1e-3)


def test_van_der_pol_area_constant():
    """The true region (inside of the limit cycle) has area 13.72: recomputed from the simulated cycle."""
    sol = solve_ivp(lambda t, x: [x[1], -x[0] + (1 - x[0] ** 2) * x[1]], (0, 60), [2.0, 0.0], rtol=1e-11,
                    atol=1e-11, dense_output=True)
    t = np.linspace(60 - 6.6633, 60, 40001)
    x, y = sol.sol(t)
    area = 0.5 * abs(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))
    assert area == pytest.approx(gc.benchmarks.VAN_DER_POL_AREA, abs=0.01)


# ------------------------------------------------------------------------------------------- recasting
def test_recast_glider_models_exact():
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    for model in (sp.reduced_model(), sp.full_model()):
        ps = recast(model)
        assert ps.recast_residual < 1e-12
        rng = np.random.default_rng(3)
        X = rng.uniform(-0.3, 0.3, (200, model.equilibrium.size))
        # the polynomial field, pushed back through the lift, is the model's right-hand side
        h = 1e-30
        Zd = np.imag(ps.lift(X + 1j * h * model.rhs(X))) / h
        assert np.max(np.abs(ps.zdot(ps.lift(X)) - Zd)) < 1e-10 * np.max(np.abs(Zd))
        # the lift lies on the variety
        for hq in ps.equalities:
            assert np.max(np.abs(hq(ps.lift(X)))) < 1e-14


def test_recast_refuses_non_polynomial_model_unless_mixed_angle():
    """x' = -x + sin(x) y^2 is not polynomial in x alone: refused; declared a mixed angle it is recast exactly."""

    class Model:
        state_names = ("x", "y")
        equilibrium = np.zeros(2)
        positive_state = None
        box = (np.array([-1.0, -1.0]), np.array([1.0, 1.0]))

        def __init__(self, mixed):
            self.mixed_angle_states = mixed

        def rhs(self, X):
            X = np.asarray(X)
            return np.stack([-X[..., 0] + np.sin(X[..., 0]) * X[..., 1] ** 2, -X[..., 1]], axis=-1)

    with pytest.raises(ModelError, match="not polynomial"):
        recast(Model(()), max_degree=4)
    ps = recast(Model((0,)))
    assert ps.recast_residual < 1e-9 and ps.z_names == ("x", "sin(x)", "1-cos(x)", "y")
    assert ps.slots == ((0, 1, 2), (3,))


def test_certify_rejects_bad_inputs():
    vdp = gc.benchmarks.van_der_pol()
    with pytest.raises(ArgumentError, match="even"):
        gc.certify_roa(vdp, degree=3)
    x1, x2 = Poly.variables(2)
    unstable = polynomial_system("unstable", ("x1", "x2"), [x1 + x2, -x2], box=((-1, -1), (1, 1)))
    with pytest.raises(ModelError, match="not exponentially stable"):
        gc.certify_roa(unstable, degree=2)
    with pytest.raises(ArgumentError, match="origin is not an equilibrium"):
        polynomial_system("shifted", ("x1", "x2"), [x1 + 1.0, -x2], box=((-1, -1), (1, 1)))


VDP = gc.benchmarks.van_der_pol()


@pytest.mark.parametrize(("exc", "kwargs"), [
    (ArgumentTypeError, dict(degree=float("nan"))),
    (ArgumentTypeError, dict(degree=4.0)),
    (ArgumentTypeError, dict(degree="4")),
    (ArgumentTypeError, dict(degree=True)),
    (ArgumentError, dict(degree=0)),
    (ArgumentError, dict(degree=-2)),
    (ArgumentError, dict(degree=3)),
    (ArgumentError, dict(degree=2, solver=dict(backoff=-1.0))),
    (ArgumentError, dict(degree=2, solver=dict(backoff=1.0))),
    (ArgumentError, dict(degree=2, solver=dict(backoff=2.0))),
    (ArgumentError, dict(degree=2, solver=dict(backoff=float("nan")))),
    (ArgumentError, dict(degree=2, iterations=0)),
    (ArgumentError, dict(degree=4, iterations=(3,))),          # one count per degree 2, 4
    (ArgumentError, dict(degree=4, iterations=(3, 1, 1))),
    (ArgumentError, dict(degree=4, iterations=(3, 0))),
    (ArgumentTypeError, dict(degree=4, iterations=(3, 1.0))),
    (ArgumentTypeError, dict(degree=4, iterations="31")),
    (ArgumentTypeError, dict(degree=4, iterations=b"\x03\x01")),
    (ArgumentTypeError, dict(degree=4, iterations=np.array(3))),
    (ArgumentTypeError, dict(degree=4, iterations=[[3, 1]])),
    (ArgumentError, dict(degree=2, solver=dict(eps=0.0))),
    (ArgumentError, dict(degree=2, solver=dict(center=1.0))),
    (ArgumentError, dict(degree=2, sampling=dict(n_truth=0))),
    (ArgumentError, dict(degree=2, sampling=dict(n_verify=0))),
    (ArgumentError, dict(degree=2, sampling=dict(horizon=-1.0))),
    (ArgumentError, dict(degree=2, solver="BOGUS")),
    (ArgumentError, dict(degree=2, surrogate=dict(speed_floor=0.0))),
    (ArgumentError, dict(degree=2, solver=dict(extra=-2))),
    (ArgumentError, dict(degree=2, budget=dict(time_limit=0.0))),
    (ArgumentError, dict(degree=2, budget=dict(memory_limit=-1.0))),
    (ArgumentError, dict(degree=2, budget=dict(on_budget="ignore"))),
    (ArgumentError, dict(degree=2, initial=Poly.variables(3)[0] ** 2)),
    (ArgumentError, dict(degree=2, initial=Poly.const(1.0, 2) + Poly.variables(2)[0] ** 2)),
    (ArgumentTypeError, dict(degree=2, initial="x1^2 + x2^2")),
    (ArgumentTypeError, dict(degree=2, solver=[1])),
    (ArgumentTypeError, dict(degree=2, sampling=3)),
    (ArgumentError, dict(degree=2, sampling=dict(n_trth=5))),
    (ArgumentError, dict(degree=2, solver=dict(name="CLARABEL", bogus=1))),
])
def test_certify_roa_checks_every_argument(exc, kwargs):
    t0 = time.perf_counter()
    with pytest.raises(exc):
        gc.certify_roa(VDP, **kwargs)
    assert time.perf_counter() - t0 < 2.0, "refused before any SDP"


def test_iterations_per_degree():
    """``iterations`` as one count per degree: at most that many V steps at each (fewer when two in a row do not
    enlarge the set); one integer is the same count at every degree, with the same result."""
    kw = dict(degree=4, sampling=dict(n_truth=256, n_verify=2000, n_simulate=8))
    staged = gc.certify_roa(VDP, iterations=(3, 1), **kw)
    steps = [h.degree for h in staged.history if h.step == "V step + level"]
    assert steps.count(4) == 1 and 1 <= steps.count(2) <= 3 and staged.certified
    # the counts are taken in the order of the degrees (a reversed lookup would run three quadratic steps here)
    rev = gc.certify_roa(VDP, iterations=(1, 3), **kw)
    steps = [h.degree for h in rev.history if h.step == "V step + level"]
    assert steps.count(2) == 1 and 1 <= steps.count(4) <= 3 and steps[0] == 2
    same = gc.certify_roa(VDP, iterations=(2, 2), **kw)
    one = gc.certify_roa(VDP, iterations=2, **kw)
    assert same.V.terms == one.V.terms and same.rho == one.rho
    assert [h.step for h in same.history] == [h.step for h in one.history]


def test_history_sdp_times_add_up_to_solve_time_when_a_level_program_fails(monkeypatch):
    """A V step whose level program fails: its row carries the V step's SDP time, which ``solve_time`` counts (it
    showed 0 before), so the rows add up to ``solve_time``; the certificate is the last good V's."""
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    real, calls = programs.solve_level, []

    def failing(*a, **k):
        calls.append(1)
        # the initial level, the first V step's level, then the second's: fails; its retry's multiplier (4th), the
        # retried V step's level (5th): fails too
        if len(calls) in (3, 5):
            raise SolverError("level program failed (test)")
        return real(*a, **k)

    monkeypatch.setattr(alternation, "solve_level", failing)
    cert = gc.certify_roa(VDP, degree=2, iterations=3, sampling=dict(n_truth=256, n_verify=2000, n_simulate=8))
    failed = [h for h in cert.history if h.step.startswith("V step failed")]
    assert len(failed) == 2 and "retried" in failed[0].step and "retried" not in failed[1].step
    assert all(h.sdp_time > 0 for h in failed)
    assert cert.stopped_by == "solver failure" and cert.certified
    assert sum(h.sdp_time for h in cert.history) == pytest.approx(cert.solve_time, rel=1e-12)


@pytest.mark.parametrize("bad", [0.0, -0.0, -1e-9, math.nan])
def test_a_v_step_whose_level_is_not_positive_stops_the_alternation(monkeypatch, bad):
    """A V step whose level program returns rho <= 0 (an inaccurate V step did: rho = -0.0) or NaN is not used:
    before, ``V / rho`` was infinite and the next V step started from its multiplier. When its retry (the deeper
    multiplier) gives such a level too, the alternation stops as for a failed solve, each row counts its SDPs, and
    the certificate is the last good V's."""
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    real, calls = programs.solve_level, []

    def zero_level(*a, **k):
        calls.append(1)
        out = real(*a, **k)
        # the second V step's level (3rd call) and that of its retry (5th; the 4th centres the retry's multiplier)
        return dataclasses.replace(out, rho=bad) if len(calls) in (3, 5) else out

    monkeypatch.setattr(alternation, "solve_level", zero_level)
    cert = gc.certify_roa(VDP, degree=2, iterations=3, sampling=dict(n_truth=256, n_verify=2000, n_simulate=8))
    failed = [h for h in cert.history if h.step.startswith("V step failed")]
    assert len(failed) == 2 and all("not positive" in h.step and h.sdp_time > 0 for h in failed)
    assert "retried with the multiplier centred at (1 - 0.25) rho*" in failed[0].step
    assert [h.step for h in cert.history].count("V step + level") == 1
    assert cert.stopped_by == "solver failure" and cert.certified
    assert np.all(np.isfinite(cert.V.arrays()[1])) and cert.rho > 0
    assert sum(h.sdp_time for h in cert.history) == pytest.approx(cert.solve_time, rel=1e-12)


def test_a_v_step_whose_level_is_not_positive_is_retried_from_a_deeper_multiplier(monkeypatch):
    """One V step whose new V has no positive level (as Clarabel without iterative refinement gave on the saturated
    user glider) is tried again with the current V's multiplier centred at ``(1 - RETRY_CENTER) rho*``: the
    alternation goes on instead of stopping, the retry's multiplier really is the deeper one, and the certificate is
    sound. With ``RETRY_CENTER = 0`` (no retry) the same failure stops the alternation, as before."""
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    real = programs.solve_level

    def run(retry: float) -> tuple[gc.ROACertificate, list[float]]:
        calls, centers = [], []

        def once(*a, **k):
            calls.append(1)
            centers.append(k.get("center"))
            out = real(*a, **k)
            return dataclasses.replace(out, rho=-2.8e-7) if len(calls) == 3 else out   # the second V step's level

        monkeypatch.setattr(alternation, "solve_level", once)
        monkeypatch.setattr(alternation, "RETRY_CENTER", retry)
        return gc.certify_roa(VDP, degree=2, iterations=3, sampling=dict(n_truth=256, n_verify=2000,
                                                                         n_simulate=8)), centers

    cert, centers = run(alternation.RETRY_CENTER)
    steps = [h.step for h in cert.history]
    assert sum(s.startswith("V step failed (the level of the new V is -2.8e-07, not positive): retried") for s in
               steps) == 1
    assert centers[3] == alternation.RETRY_CENTER == 0.25 and centers[1] == 0.05 and centers[2] == 0.05
    assert steps.count("V step + level") == 3 and cert.stopped_by != "solver failure"
    assert cert.certified and cert.verification.passed and cert.verification.max_Vdot < 0
    assert sum(h.sdp_time for h in cert.history) == pytest.approx(cert.solve_time, rel=1e-12)
    plain, _ = run(0.0)
    assert plain.stopped_by == "solver failure" and [h.step for h in plain.history].count("V step + level") == 1
    assert not any("retried" in h.step for h in plain.history)


def test_a_retry_whose_multiplier_fails_stops_the_alternation(monkeypatch):
    """A failed V step whose retry cannot get its deeper multiplier (that level program fails too) stops the
    alternation with one row naming both failures; the certificate is the last good V's."""
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    real, calls = programs.solve_level, []

    def failing(*a, **k):
        calls.append(1)
        if len(calls) in (3, 4):        # the second V step's level, then the retry's multiplier
            raise SolverError(f"level program {len(calls)} failed (test)")
        return real(*a, **k)

    monkeypatch.setattr(alternation, "solve_level", failing)
    cert = gc.certify_roa(VDP, degree=2, iterations=3, sampling=dict(n_truth=256, n_verify=2000, n_simulate=8))
    failed = [h.step for h in cert.history if h.step.startswith("V step failed")]
    assert failed == ["V step failed: level program 3 failed (test); its retry's multiplier: level program 4 failed "
                      "(test)"]
    # no V step after the retry's failed multiplier: no level program after the 4th
    assert cert.stopped_by == "solver failure" and cert.certified and len(calls) == 4
    assert sum(h.sdp_time for h in cert.history) == pytest.approx(cert.solve_time, rel=1e-12)


def test_a_failed_v_step_with_no_time_left_for_its_retry_stops_at_the_time_limit(monkeypatch):
    """A V step that fails when the time limit has passed is not retried: its row says so, the alternation stops as
    at any time limit (``stopped_by = "time_limit"``, not a solver failure), and the last good V is certified."""
    from glidectl import checks
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    real, calls, late = programs.solve_level, [], []

    def failing(*a, **k):
        calls.append(1)
        if len(calls) == 3:             # the second V step's level fails after the time limit
            late.append(True)
            raise SolverError("level program failed (test)")
        return real(*a, **k)

    elapsed = checks.Deadline.elapsed
    monkeypatch.setattr(checks.Deadline, "elapsed", property(lambda d: 1e9 if late else elapsed.fget(d)))
    monkeypatch.setattr(alternation, "solve_level", failing)
    cert = gc.certify_roa(VDP, degree=2, iterations=3, sampling=dict(n_truth=256, n_verify=2000, n_simulate=8),
                          budget=dict(time_limit=1e6, on_budget="stop"))
    failed = [h.step for h in cert.history if h.step.startswith("V step failed")]
    assert failed == ["V step failed: level program failed (test); not retried: time limit"]
    assert len(calls) == 3 and cert.stopped_by == "time_limit" and cert.certified
    assert [h.step for h in cert.history].count("V step + level") == 1


def test_a_first_level_that_is_not_positive_is_a_clear_error(monkeypatch):
    """The starting V's level <= 0 with SOS multipliers: a SolverError that says so (it said 'use inner=sos',
    which was the option in use)."""
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    real = programs.solve_level
    monkeypatch.setattr(alternation, "solve_level", lambda *a, **k: dataclasses.replace(real(*a, **k), rho=0.0))
    with pytest.raises(gc.SolverError, match="not positive: the starting V is not certified") as e:
        gc.certify_roa(VDP, degree=2, iterations=1, sampling=dict(n_truth=256, n_verify=2000, n_simulate=8))
    assert "use inner" not in str(e.value)


def test_a_v_step_cut_off_by_the_time_limit_keeps_its_sdp_time_in_the_history(monkeypatch):
    """``on_budget="stop"``: a V step solved when the time limit has passed is not used, and its row says so with
    its SDP time (there was no row before, though ``solve_time`` counted it). The clock is the test's: no time
    passes until the first V step is solved, then the limit is over (a loaded machine cannot move the cut)."""
    from glidectl import checks
    from glidectl.roa import alternation, certificate, programs, routes  # noqa: F401

    real, over = programs.solve_v_step, []

    def solved_then_late(*a, **k):
        out = real(*a, **k)
        over.append(True)                                   # past the limit once it is solved
        return out

    monkeypatch.setattr(alternation, "solve_v_step", solved_then_late)
    monkeypatch.setattr(checks.Deadline, "elapsed",
                        property(lambda self: (self.limit or 0.0) + 1.0 if over else 0.0))
    cert = gc.certify_roa(VDP, degree=2, iterations=3, sampling=dict(n_truth=256, n_verify=2000, n_simulate=8),
                          budget=dict(time_limit=8.0, on_budget="stop"))
    cut = [h for h in cert.history if h.step.startswith("V step solved, not used")]
    assert len(cut) == 1 and cut[0].sdp_time > 0 and cert.stopped_by == "time_limit"
    assert not any(h.step == "V step + level" for h in cert.history)
    assert sum(h.sdp_time for h in cert.history) == pytest.approx(cert.solve_time, rel=1e-12)


def test_certify_roa_refuses_systems_it_cannot_certify():
    with pytest.raises(ArgumentTypeError, match="PolySystem"):
        gc.certify_roa("vdp")
    with pytest.raises(ArgumentTypeError, match="equilibrium"):        # a model with inputs and no equilibrium
        gc.certify_roa(gc.LongitudinalGlider(gc.load_vehicle("rogue")), degree=2)
    x1, x2 = Poly.variables(2)
    centre = polynomial_system("centre", ("x1", "x2"), [-x2, 1.0 * x1], box=((-1, -1), (1, 1)))
    # a marginally stable centre (even a nonlinearly stable one) is refused with a message, not ZeroDivisionError
    weak = polynomial_system("weak centre", ("x1", "x2"), [-x2 - x1**3, x1 - x2**3], box=((-1, -1), (1, 1)))
    for ps in (centre, weak):
        with pytest.raises(ModelError, match="marginally stable"):
            gc.certify_roa(ps, degree=2)
        with pytest.raises(ModelError, match="marginally stable"):
            gc.lyapunov_matrix(ps)
        with pytest.raises(ModelError):
            gc.certify_roa(ps, degree=2, initial=x1**2 + x2**2, sampling=dict(horizon=10.0))


def test_degree_100_is_refused_quickly_with_what_fits():
    t0 = time.perf_counter()
    with pytest.raises(BudgetError, match="largest degree within the limits is 8") as info:
        gc.certify_roa(VDP, degree=100)
    assert time.perf_counter() - t0 < 1.0
    assert "max_degree = 8" in str(info.value) and isinstance(info.value, RuntimeError)
    # the memory limit alone: degree 12 needs ~250 MB
    with pytest.raises(BudgetError, match=r"above memory_limit = 100 MB.*largest degree within the limits is 8"):
        gc.certify_roa(VDP, degree=12, budget=dict(max_degree=12, memory_limit=1e8))
    with pytest.raises(BudgetError, match="no degree fits"):
        gc.certify_roa(VDP, degree=2, budget=dict(memory_limit=1e6))
    with pytest.raises(BudgetError, match="max_degree"):
        gc.max_level(VDP, Poly.variables(2)[0] ** 10 + Poly.variables(2)[1] ** 2)


def test_estimate_sos_size_counts_what_is_built():
    """The closed-form counts equal the Gram matrices the builder creates, for a plain and a lifted system."""
    from glidectl.roa.programs import auto_extra, build_program, scaled_field

    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    for system, degree in ((VDP, 4), (recast(sp.reduced_model()), 4), (recast(sp.full_model()), 2)):
        size = gc.estimate_sos_size(system, degree)
        ex = auto_extra(system, None)
        F = scaled_field(system)
        prog, _ = build_program(system, F, degree, V=None, lam=Poly.const(1.0, system.nz), rho=1.0, eps=1e-6, extra=ex,
                         symmetry=False)
        built = sorted(u.var.shape[0] for u in prog.unknowns if u.gram)
        assert built == sorted(k for _, k in size.gram), (system.name, size.gram)
        # the exact basis reduction only shrinks the program: the estimate is an upper bound of what is solved
        red, _ = build_program(system, F, degree, V=None, lam=Poly.const(1.0, system.nz), rho=1.0, eps=1e-6, extra=ex)
        assert sum(u.var.shape[0] ** 2 for u in red.unknowns if u.gram) <= sum(k * k for k in built)
        assert size.n_gram_entries == sum(k * (k + 1) // 2 for k in built)
        assert len(prog.constraints) > 0 and size.n_constraints > 0 and size.bytes > 0
    big = gc.estimate_sos_size(VDP, 100)
    assert big.largest_gram == 1484 and big.bytes > 1e14 and "degree 100" in big.summary()
    with pytest.raises(ArgumentError):
        gc.estimate_sos_size(VDP, 3)
    with pytest.raises(ArgumentTypeError):
        gc.estimate_sos_size(VDP, float("nan"))


def test_time_limit_raises_or_certifies_the_best_so_far():
    cheap = dict(sampling=dict(n_truth=128, n_verify=2000, n_simulate=8))
    with pytest.raises(BudgetError, match=r"time limit of 0\.01 s"):
        gc.certify_roa(VDP, degree=4, **cheap, budget=dict(time_limit=0.01))
    c = gc.certify_roa(VDP, degree=4, **cheap, budget=dict(time_limit=0.01, on_budget="stop"))
    assert c.stopped_by == "time_limit" and c.certified and c.degree == 2
    steps = [h.step for h in c.history]
    assert "time limit" in steps[-1] or ("time limit" in steps[-2] and steps[-1].startswith("final margin"))


def test_contains_checks_n_path_and_shapes(vdp_cert):
    X = np.array([[0.5, 0.5]])
    with pytest.raises(ArgumentError, match="n_path"):
        vdp_cert.contains(X, n_path=0)             # n_path=0 used to return True for every point
    with pytest.raises(ArgumentTypeError):
        vdp_cert.contains(X, n_path=2.5)
    with pytest.raises(ArgumentError, match="dimension 2"):
        vdp_cert.contains(np.zeros(3))
    assert vdp_cert.contains(np.array([0.1, 0.1])).tolist() == [True]
    assert vdp_cert.contains(np.array([[np.nan, 0.0], [2.9, 3.4]]), n_path=1).tolist() == [False, False]
    with pytest.raises(ArgumentError):
        vdp_cert.value([[np.nan, 0.0]])
    with pytest.raises(ArgumentError):
        vdp_cert.volume(n=0)
    with pytest.raises(ArgumentError):
        vdp_cert.volume(box=((1.0, 1.0), (0.0, 0.0)))
    assert vdp_cert.stopped_by in ("iterations", "no improvement", "solver failure")


def test_level_lyapunov_and_helpers_check_inputs():
    V = lyapunov_quadratic(VDP)
    with pytest.raises(ArgumentError):
        gc.max_level(VDP, V, rho_cap=-1.0)
    with pytest.raises(ArgumentTypeError):
        gc.max_level(VDP, "V")
    with pytest.raises(ArgumentError):
        gc.max_level(VDP, Poly.variables(3)[0] ** 2)
    with pytest.raises(ArgumentError):
        gc.dVdt(V, VDP.lift, VDP.rhs, np.zeros(3))
    with pytest.raises(ArgumentError):
        gc.taylor_system(VDP, order=0)
    with pytest.raises(ArgumentTypeError):
        gc.taylor_system(VDP, order=2.0)
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    with pytest.raises(ArgumentError):
        gc.recast(sp.reduced_model(), speed_floor=0.0)
    with pytest.raises(ArgumentTypeError):
        gc.recast(object())
    x = Poly.variables(2)[0]
    with pytest.raises(ArgumentTypeError):
        Poly({(1, 0): "a"}, 2)
    with pytest.raises(ArgumentError):
        Poly({(-1, 0): 1.0}, 2)
    with pytest.raises(ArgumentError):
        x / 0
    with pytest.raises(ArgumentTypeError):
        x ** 1.5
    with pytest.raises(ArgumentError):
        x(np.zeros(3))
    t0 = time.perf_counter()
    with pytest.raises(BudgetError):
        monomials(3, 10**6)
    assert time.perf_counter() - t0 < 1.0


# ------------------------------------------------------------------------------------------- certificates
@pytest.fixture(scope="module")
def vdp_cert():
    return gc.certify_roa(gc.benchmarks.van_der_pol(), degree=6, iterations=6, solver=dict(backoff=0.003))


def test_van_der_pol_certificate_target(vdp_cert):
    c = vdp_cert
    assert c.certified, c.verification.summary()
    assert c.degree == 6
    assert c.volume() >= 0.95 * gc.benchmarks.VAN_DER_POL_AREA
    # the 60 s wall-time target is measured by bench/bench_roa.py, not asserted here (machine dependent)


def test_certificate_soundness_van_der_pol(vdp_cert):
    """No certified point diverges: every certified sample converges; points outside the limit cycle are never
    certified."""
    c = vdp_cert
    rng = np.random.default_rng(11)
    X = rng.uniform([-3, -3.5], [3, 3.5], (4000, 2))
    inside = c.contains(X)
    assert inside.sum() > 1000
    res = integrate_batch(c.system.rhs, X[inside], 40.0, bound=1e3)
    assert np.all(res.finished) and np.max(np.linalg.norm(res.x_final, axis=1)) < 1e-4
    # true dV/dt < 0 on the certified samples (true model, not the polynomial)
    from glidectl.roa import dVdt

    vd = dVdt(c.V, c.system.lift, c.system.rhs, X[inside])
    assert np.all(vd[np.linalg.norm(X[inside], axis=1) > 1e-6] < 0)
    # contains: equilibrium in, far point out, shape check
    assert c.contains(np.zeros((1, 2)))[0] and not c.contains(np.array([[2.5, 2.5]]))[0]
    with pytest.raises(GlidectlError):
        c.contains(np.zeros((1, 3)))


@pytest.fixture(scope="module")
def reduced_cert():
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    return gc.certify_roa(sp.reduced_model(), degree=2, iterations=3, sampling=dict(n_verify=5000, n_simulate=64))


def test_reduced_glider_certificate_sound(reduced_cert):
    c = reduced_cert
    assert c.certified, c.verification.summary()
    assert c.verification.gram_passed and c.verification.failing() == {}
    rng = np.random.default_rng(5)
    X = rng.uniform(c.system.box[0], c.system.box[1], (3000, 2))
    inside = c.contains(X)
    assert inside.sum() > 100
    res = integrate_batch(c.system.rhs, X[inside], 30.0, bound=1e3)
    assert np.all(res.finished) and np.max(np.abs(res.x_final)) < 1e-4
    # every certified point has V > 0.1 V_e (the denominator cut)
    assert np.all(X[inside, 0] >= -0.9)
    # gammabar is an angle: the certificate is 2 pi periodic through the lift
    shifted = X[inside][:50] + np.array([0.0, 2 * math.pi])
    assert np.allclose(c.value(shifted), c.value(X[inside][:50]))


def test_full_glider_certificate_sound():
    """4-state glider (K_M = -100), one alternation: certified points all converge on the true model, and the
    certificate never claims a point outside the denominator cut. (The volume targets are measured by the
    roa_certification design with more alternations.)"""
    veh = gc.load_vehicle("sphere_ch5", K_M=-100.0)
    model = gc.singular_perturbation(veh).full_model()
    c = gc.certify_roa(model, degree=2, iterations=1, sampling=dict(n_truth=256, n_verify=4000, n_simulate=32))
    assert c.certified, c.verification.summary()
    lo, hi = model.box
    rng = np.random.default_rng(2)
    X = rng.uniform(lo, hi, (4000, 4))
    inside = c.contains(X)
    assert inside.sum() > 200
    res = integrate_batch(model.rhs, X[inside][:300], 30.0, bound=1e3)
    assert np.all(res.finished) and np.max(np.abs(res.x_final)) < 1e-4
    assert np.all(X[inside, 0] > -0.9)


def test_recast_mixed_angle_ctol_closed_loop():
    """CTOL closed loop (7.16)-(7.20) in (Vbar, gammabar, alphabar, Omega2bar): alphabar enters polynomially (lift,
    drag) and through sin/cos; it is kept and lifted, the Taylor enclosures hold on the whole graph, and the
    recovered polynomial reproduces the closed loop's own right-hand side."""
    from glidectl.models.ctol_closed_loop import ClosedLoopCTOL

    veh = gc.load_vehicle("dc8_ctol")
    gl = gc.ctol_glide(veh, speed=0.85 / math.sqrt(30.0), gamma=0.0)
    model = ClosedLoopCTOL(veh, gl, 10.0, 5.0).roa_model()
    ps = recast(model)
    assert ps.mixed_states == (2,) and len(ps.valid) == 4 and len(ps.equalities) == 2
    assert ps.recast_residual < 1e-9
    rng = np.random.default_rng(4)
    X = rng.uniform(-0.4, 0.4, (300, 4))
    h = 1e-30
    Zd = np.imag(ps.lift(X + 1j * h * model.rhs(X))) / h
    assert np.max(np.abs(ps.zdot(ps.lift(X)) - Zd)) < 1e-8 * np.max(np.abs(Zd))
    # the shear alphabar = thetabar - gammabar is the closed loop itself
    assert np.allclose(model.to_theta(X)[:, 2] - X[:, 1], X[:, 2])
    # Taylor enclosures valid for every real angle (not only small ones)
    wide = np.zeros((2000, 4))
    wide[:, 2] = rng.uniform(-12.0, 12.0, 2000)
    Zw = ps.lift(wide)
    for v in ps.valid:
        assert np.min(v(Zw)) >= -1e-12


def _angle_pairs(ps):
    """``(base, s, c)`` of every lifted angle (``base`` None for a pure angle)."""
    return [((sl[0] if len(sl) == 3 else None), sl[-2], sl[-1]) for i, sl in enumerate(ps.slots)
            if i in ps.angle_states or i in ps.mixed_states]


def _ctol_and_glider_systems():
    from glidectl.models.ctol_closed_loop import ClosedLoopCTOL

    veh = gc.load_vehicle("dc8_ctol")
    gl = gc.ctol_glide(veh, speed=0.85 / math.sqrt(veh.a_L), gamma=0.0)
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    return (recast(ClosedLoopCTOL(veh, gl, 10.0, 5.0).roa_model()), recast(sp.reduced_model()),
            recast(sp.full_model()))


def test_recast_lifted_angles_follow_the_chain_rule_exactly():
    """d(sin x)/dt = (1 - c) dx/dt and d(1 - cos x)/dt = s dx/dt hold as polynomial identities modulo
    s^2 + c^2 - 2c (not only at sample points): (1 - c) F_c - s F_s reduces to 0, and for a mixed angle F_s and F_c
    are those of the kept state x. Then the terms of degree 1 of dV/dt for a V without linear terms outside the
    c's are in the c's alone, which the equality multipliers cancel (the old fit of each lifted variable had
    1e-3 (alpha - sin alpha) in d(1 - cos gamma)/dt: a linear term of dV/dt no SOS certificate can absorb)."""
    from glidectl.roa.systems import _reduce_angle

    for ps in _ctol_and_glider_systems():
        Z = Poly.variables(ps.nz)
        pairs = _angle_pairs(ps)
        assert pairs
        # the equilibrium is exact: no rounding-level constant term survives the sparse refit
        assert all(sum(e) > 0 for f in ps.F for e in f.terms)
        for base, s, c in pairs:
            scale = max(max(abs(v) for v in ps.F[k].terms.values()) for k in (s, c))
            diff = _reduce_angle((1.0 - Z[c]) * ps.F[c] - Z[s] * ps.F[s], s, c)
            assert all(abs(v) <= 1e-12 * scale for v in diff.terms.values())
            if base is not None:
                d_s = _reduce_angle((1.0 - Z[c]) * ps.F[base], s, c) - ps.F[s]
                assert all(abs(v) <= 1e-12 * scale for v in d_s.terms.values())
            # d(1 - cos x)/dt has terms of degree 1 in c only
            lin = [e for e, v in ps.F[c].terms.items() if sum(e) == 1 and abs(v) > 0]
            assert all(e[c] == 1 for e in lin), lin
        V = lyapunov_quadratic(ps)
        lin_V = [e for e, v in V.terms.items() if sum(e) == 1 and abs(v) > 0]
        cs = {c for _, _, c in pairs}
        assert all(any(e[c] for c in cs) for e in lin_V)
        W = V.lie(list(ps.F))
        tol = 1e-12 * max(abs(x) for x in W.terms.values())
        lin_W = [e for e, v in W.terms.items() if sum(e) == 1 and abs(v) > tol]
        assert all(any(e[c] for c in cs) for e in lin_W), lin_W


def test_recast_ctol_degrees_are_those_of_the_states():
    """Each state's derivative is recovered at its own smallest degree; the CTOL closed loop's pitch and angle of
    attack are cubic in the lift, its speed quintic (the old joint fit put every derivative at degree 5)."""
    ps = _ctol_and_glider_systems()[0]
    deg = {ps.z_names[k]: f.degree for k, f in enumerate(ps.F)}
    assert deg["alphabar"] == 3 and deg["Omega2bar"] == 3 and deg["Vbar"] == 5
    assert deg["sin(alphabar)"] == deg["1-cos(alphabar)"] == 4


@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_taylor_system_error_order(order):
    """The Taylor model agrees with the glider to order ``order``: halving the state divides the error by about
    2^(order + 1)."""
    from glidectl.roa.systems import taylor_system

    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5"))
    ps = recast(sp.reduced_model())
    tp = taylor_system(ps, order)
    x = np.array([[0.02, -0.03]])
    e1 = np.linalg.norm(tp.rhs(x) - ps.rhs(x))
    e2 = np.linalg.norm(tp.rhs(x / 2) - ps.rhs(x / 2))
    assert e1 / e2 == pytest.approx(2.0 ** (order + 1), rel=0.15)


def test_history_table_rows(vdp_cert):
    rows = vdp_cert.history_table("VdP")
    assert len(rows) == len(vdp_cert.history) and len(rows[0]) == len(gc.ROACertificate.HISTORY_HEADER)
    for row, h in zip(rows, vdp_cert.history, strict=True):
        assert row[0] == "VdP" and row[1] == str(h.degree) and row[2] == h.step[:60]
        assert float(row[3]) == pytest.approx(h.rho, rel=1e-5)
        assert float(row[4]) == pytest.approx(h.volume, rel=1e-3)
    assert vdp_cert.history_table()[0][0] == ""
    with pytest.raises(gc.ArgumentTypeError, match="label"):
        vdp_cert.history_table(1)
