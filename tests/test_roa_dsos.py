"""DSOS/SDSOS inner approximations of the Gram cone (issue 17 part 5): ``SOSProgram(cone=...)``, ``dd_gram`` and
``certify_roa(inner=...)``, whose final certificate stays a full SOS one."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.roa import Poly
from glidectl.roa.sos import GRAM_CONES, LinPoly, SOSProgram, dd_gram


def _min_linear(C: np.ndarray, cone: str) -> tuple[float, np.ndarray]:
    """min trace(C Q) over the cone with trace(Q) = 1."""
    n = C.shape[0]
    if cone == "sos":
        Q = cp.Variable((n, n), symmetric=True)
        cons = [Q >> 0]
    else:
        Q, cons = dd_gram(n, "Q", cone)
    prob = cp.Problem(cp.Minimize(cp.trace(C @ Q)), [*cons, cp.trace(Q) == 1])
    prob.solve(solver="CLARABEL")
    return float(prob.value), np.asarray(Q.value)


@settings(max_examples=12, deadline=None)
@given(st.integers(0, 2**31 - 1), st.integers(1, 6), st.sampled_from(["sdsos", "dsos"]))
def test_dd_gram_is_psd_and_dominant(seed, n, cone):
    """The optimum of a random linear objective over the DD/SDD cone is PSD; a DD one is diagonally dominant with a
    nonnegative diagonal, and its value is >= the PSD optimum (lambda_min(C))."""
    rng = np.random.default_rng(seed)
    C = rng.normal(size=(n, n))
    C = C + C.T
    val, Q = _min_linear(C, cone)
    assert np.allclose(Q, Q.T, atol=1e-12)
    assert np.linalg.eigvalsh(Q)[0] >= -1e-7
    if cone == "dsos":
        off = np.sum(np.abs(Q), axis=1) - np.abs(np.diag(Q))
        assert np.all(np.diag(Q) >= off - 1e-7)
    assert val >= np.linalg.eigvalsh(C)[0] - 1e-6


@settings(max_examples=8, deadline=None)
@given(st.floats(-3, 3), st.floats(-3, 3), st.floats(-3, 3))
def test_two_by_two_exact_values(a, b, c):
    """2 x 2: SDD = PSD, so min trace(CQ) is lambda_min(C); DD's extreme rays are e_i e_i^T and
    (e_1 +- e_2)(e_1 +- e_2)^T / 2, so its minimum is min(a, c, (a + c)/2 - |b|)."""
    C = np.array([[a, b], [b, c]])
    v_sdd, _ = _min_linear(C, "sdsos")
    v_dd, _ = _min_linear(C, "dsos")
    assert v_sdd == pytest.approx(np.linalg.eigvalsh(C)[0], abs=1e-6)
    assert v_dd == pytest.approx(min(a, c, 0.5 * (a + c) - abs(b)), abs=1e-6)


def _max_gamma(cone: str) -> tuple[float, SOSProgram]:
    """max gamma s.t. p - gamma is SOS/SDSOS/DSOS on the basis (1, x, y), p = (x - 1)^2 + (y + 2)^2 + 3."""
    x, y = Poly.variables(2)
    p = (x - 1.0) ** 2 + (y + 2.0) ** 2 + 3.0
    prog = SOSProgram(2, cone=cone)
    g, gl = prog.scalar("gamma")
    prog.add_sos("p", LinPoly(p) - gl, [(0, 0), (1, 0), (0, 1)])
    return prog.solve(cp.Maximize(g.var[0])), prog


def test_cone_optima_exact_on_a_separable_square():
    """p - 3 = (x - 1)^2 + (y + 2)^2. Each coefficient of p - gamma comes from one Gram entry on (1, x, y) (no two
    products of the basis coincide), so the Gram matrix is unique: [[8 - gamma, -1, 2], [-1, 1, 0], [2, 0, 1]]. It is
    a sum of 2 x 2 PSD blocks on the pairs (1, x), (1, y) exactly when 8 - gamma >= 1 + 4, so SOS and SDSOS both
    reach gamma = 3; its row y (1 < |2|) is never diagonally dominant, so DSOS is infeasible for every gamma."""
    v_sos, _ = _max_gamma("sos")
    v_sdd, prog_sdd = _max_gamma("sdsos")
    assert v_sos == pytest.approx(3.0, abs=1e-6)
    assert v_sdd == pytest.approx(3.0, abs=1e-6)
    with pytest.raises(gc.SolverError):
        _max_gamma("dsos")
    # the SDSOS Gram matrix is an SOS certificate: PSD, coefficients matched
    (chk,) = prog_sdd.check()
    assert chk.min_eig >= -1e-7 and chk.max_residual < 1e-7
    # shifted so that DSOS is feasible: p2 = (x - 1)^2 + (y + 1)^2 + 3, unique Gram [[5 - g, -1, 1], [-1, 1, 0],
    # [1, 0, 1]]: DD iff 5 - g >= 2, so the three cones agree at gamma = 3
    x, y = Poly.variables(2)
    vals = []
    for cone in GRAM_CONES:
        pr = SOSProgram(2, cone=cone)
        g, gl = pr.scalar("gamma")
        pr.add_sos("p", LinPoly((x - 1.0) ** 2 + (y + 1.0) ** 2 + 3.0) - gl, [(0, 0), (1, 0), (0, 1)])
        vals.append(pr.solve(cp.Maximize(g.var[0])))
    assert vals == pytest.approx([3.0, 3.0, 3.0], abs=1e-6)


def test_sos_program_rejects_unknown_cone():
    with pytest.raises(gc.ArgumentError):
        dd_gram(3, "Q", "psd")
    assert GRAM_CONES == ("sos", "sdsos", "dsos")


def _cubic_system():
    """x' = -x + y^2 / 2, y' = -y + x^3 (scaled): a 2-state polynomial system with a bounded region of attraction."""
    from glidectl.roa import polynomial_system

    x, y = Poly.variables(2)
    return polynomial_system("cubic", ("x", "y"), [-x + 0.5 * y * y, -y + x * x * x], box=([-2.0, -2.0], [2.0, 2.0]))


@pytest.mark.parametrize("inner", ["sdsos", "dsos"])
def test_certify_with_inner_approximation_is_sos_and_verified(inner):
    """With an inner approximation the final certificate is still a full SOS one: the final SOS level of the kept V
    is >= its inner level (1), every Gram check is exact, the sampled true dV/dt < 0 inside and the simulations
    converge (``certified``), and the certified set is not empty."""
    ps = _cubic_system()
    kw = dict(degree=2, iterations=1, sampling=dict(n_truth=64, n_verify=2000, n_simulate=16))
    cert = gc.certify_roa(ps, **kw, solver=dict(backoff=0.01, inner=inner))
    steps = [h.step for h in cert.history]
    fin = [h for h in cert.history if h.step.startswith("final SOS level")]
    assert len(fin) == 1 and fin[0].rho >= 1.0 - 1e-6, steps
    assert cert.certified, cert.verification.summary()
    assert cert.verification.gram_passed and cert.verification.max_Vdot < 0
    assert cert.volume(n=2**10) > 0


def test_certify_inner_bad_value():
    with pytest.raises(gc.ArgumentError):
        gc.certify_roa(_cubic_system(), degree=2, solver=dict(inner="psd"))
