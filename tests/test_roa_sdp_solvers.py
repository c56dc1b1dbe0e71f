"""The moment-form SDP route (``CVXOPT_MOMENT``): same optimum and feasible points as Clarabel, exact recovery of the
eliminated variables, dependent data, infeasible and unbounded programs, which programs it hands to Clarabel,
solver names."""
from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import glidectl as gc
from glidectl.errors import ArgumentError, SolverError
from glidectl.roa import MOMENT_POLICY, Poly, SOSProgram, monomials, sdp_solvers, solve_moment
from glidectl.roa import moment as sdp
from glidectl.roa.moment import moment_form, moment_pays
from glidectl.roa.sdp_solvers import MOMENT, solver_argument, solver_options


@pytest.fixture
def moment_calls(monkeypatch: pytest.MonkeyPatch) -> list:
    """Records every call of the moment route (``solve_moment``) made by ``CvxoptMoment``."""
    calls: list = []
    real = sdp.solve_moment

    def counted(*a: object, **k: object) -> object:
        calls.append(a[5])
        return real(*a, **k)

    monkeypatch.setattr(sdp, "solve_moment", counted)
    return calls


def _clarabel_data(prob: cp.Problem) -> tuple:
    data, _, _ = prob.get_problem_data(cp.CLARABEL)
    d = data["dims"]
    return data["A"], data["b"], data["c"], d.zero, d.nonneg, list(d.psd)


def _svec_blocks(s: np.ndarray, nonneg: int, psd: list[int]) -> list[np.ndarray]:
    out, k = [], nonneg
    for nb in psd:
        M = np.zeros((nb, nb))
        for j in range(nb):
            for i in range(j + 1):
                M[i, j] = M[j, i] = s[k] if i == j else s[k] / np.sqrt(2.0)
                k += 1
        out.append(M)
    return out


def _random_sdp(seed: int, n: int, m: int) -> tuple[cp.Problem, cp.Variable]:
    """``min <C, X> + t0 - t1`` over ``X >= 0`` with ``m`` trace equations, a bound and a free pair (t0, t1)."""
    rng = np.random.default_rng(seed)
    C = rng.standard_normal((n, n))
    As = [rng.standard_normal((n, n)) for _ in range(m + 1)]
    X = cp.Variable((n, n), symmetric=True)
    t = cp.Variable(2)
    X0 = np.eye(n) + 0.1 * (lambda B: B @ B.T)(rng.standard_normal((n, n)))     # strictly feasible point
    cons = [X >> 0, t[0] >= -1, cp.trace(X) + t[0] <= np.trace(X0) + 5.0, t[1] == cp.trace((As[m] + As[m].T) @ X)]
    cons += [cp.trace((As[i] + As[i].T) @ X) == np.trace((As[i] + As[i].T) @ X0) for i in range(m)]
    return cp.Problem(cp.Minimize(cp.trace((C + C.T) @ X) + t[0] - t[1]), cons), X


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(2, 7), m=st.integers(1, 6))
def test_moment_form_gives_clarabels_optimum_and_a_feasible_point(seed: int, n: int, m: int) -> None:
    prob, _ = _random_sdp(seed, n, m)
    ref = prob.solve(solver="CLARABEL")
    A, b, c, zero, nonneg, psd = _clarabel_data(prob)
    r = solve_moment(A, b, c, zero, nonneg, psd)
    assert r.status in ("Solved", "AlmostSolved")
    assert r.obj_val == pytest.approx(ref, rel=1e-5, abs=1e-5)      # no constant in the objective
    # the point is feasible in the original data: equations, nonnegative rows and PSD blocks
    res = A @ r.x + np.concatenate([np.zeros(zero), r.s]) - b
    assert np.max(np.abs(res)) < 1e-6 * (1.0 + np.max(np.abs(b)))
    assert np.all(r.s[:nonneg] >= -1e-8)
    for M in _svec_blocks(r.s, nonneg, psd):
        assert np.linalg.eigvalsh(M)[0] >= -1e-7


def test_sparse_kkt_follows_cvxopts_own_kkt_solver() -> None:
    prob, _ = _random_sdp(3, 6, 4)
    A, b, c, zero, nonneg, psd = _clarabel_data(prob)
    ours = solve_moment(A, b, c, zero, nonneg, psd)
    theirs = solve_moment(A, b, c, zero, nonneg, psd, kktsolver="qr")
    assert ours.iterations == theirs.iterations
    assert np.allclose(ours.x, theirs.x, atol=1e-7)


def test_eliminated_variables_are_recovered_exactly() -> None:
    prob, _ = _random_sdp(5, 5, 3)
    A, b, c, zero, _, _ = _clarabel_data(prob)
    mf = moment_form(A, b, c, zero)
    rng = np.random.default_rng(0)
    x = rng.standard_normal(c.size)
    s = b[zero:] - A[zero:] @ x                 # any x: its cone slack
    assert np.allclose(mf.primal(x[mf.R], s, c.size), x)
    # the reduced equations and objective are those of the original program at (x, s)
    eq_residual = np.r_[A[:zero] @ x - b[:zero], np.zeros(len(mf.f) - zero)]
    assert np.allclose(mf.E_R @ x[mf.R] + mf.E_s @ s, mf.f + eq_residual)
    obj_r = mf.g @ x[mf.R] + mf.h @ s + (mf.dinv * c[mf.P]) @ mf.b_p
    assert obj_r == pytest.approx(c @ x, rel=1e-10, abs=1e-10)


def test_dependent_equations_and_free_columns_are_dropped() -> None:
    X = cp.Variable((4, 4), symmetric=True)
    a, b2 = cp.Variable(), cp.Variable()
    cons = [X >> 0, cp.trace(X) == 2.0, 2 * cp.trace(X) == 4.0,          # a repeated equation
            X[0, 1] + a + b2 == 0.3, 2 * X[0, 1] + 2 * a + 2 * b2 == 0.6]   # and a + b2 only as a sum
    prob = cp.Problem(cp.Minimize(X[0, 0] + a + b2), cons)
    ref = prob.solve(solver="CLARABEL")
    r = solve_moment(*_clarabel_data(prob))
    assert r.status == "Solved"
    assert r.obj_val == pytest.approx(ref, abs=1e-6)


def _sextic_bound(solver: str) -> tuple[float, object]:
    """A lower bound of a sextic in 5 variables (a 56 x 56 Gram matrix, above MOMENT_POLICY.min_block) by ``solver``:
    the optimal value and the Gram check."""
    nv = 5
    rng = np.random.default_rng(1)
    hb = monomials(nv, 3)
    assert len(hb) >= MOMENT_POLICY.min_block
    p = Poly({tuple(6 * int(k == i) for k in range(nv)): 1.0 for i in range(nv)}, nv)
    for e in monomials(nv, 4):
        if 0 < sum(e):
            p = p + Poly({e: float(rng.normal(scale=0.3))}, nv)
    prog = SOSProgram(nv)
    gu, g = prog.scalar("gamma")
    prog.add_sos("bound", g + p, hb)
    prog.constraints.append(gu.var >= -1e6)         # a far bound (the level programs cap rho at 1e6)
    return prog.solve(cp.Minimize(gu.var[0]), solver=solver), prog.check()[0]


def test_big_block_programs_go_through_cvxopt_and_agree_with_clarabel(moment_calls: list) -> None:
    ref, _ = _sextic_bound("CLARABEL")
    assert moment_calls == []
    val, check = _sextic_bound(MOMENT)
    assert len(moment_calls) == 1 and max(moment_calls[0]) == 56          # the MOMENT solve took the route
    assert val == pytest.approx(ref, rel=1e-5, abs=1e-6)
    # the identity p + gamma = m' Q m holds as tightly as Clarabel's
    assert check.max_residual < 1e-6 and check.min_eig > -1e-7


@pytest.mark.parametrize("late", [True, False])
def test_a_run_stopped_at_a_singular_schur_complement(late: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    """A Schur complement that is not positive definite stops CVXOPT with its last iterate (no regularization).
    Stopped two iterations before convergence, that iterate is accepted (``AlmostSolved``: residuals below 1e-5)
    and its value is the optimum to 1e-4; stopped after three iterations it is not, and Clarabel solves the
    program instead (its optimum)."""
    with pytest.raises(ArithmeticError):
        sdp._cholesky(np.ones((2, 2)))                 # singular: a diagonal shift would have factored it
    ref, _ = _sextic_bound("CLARABEL")
    statuses: list = []
    real_solve, real_chol = sdp.solve_moment, sdp._cholesky

    def observed(*a: object, **k: object) -> object:
        r = real_solve(*a, **k)
        statuses.append((r.status, r.iterations))
        return r

    monkeypatch.setattr(sdp, "solve_moment", observed)
    _sextic_bound(MOMENT)
    (status, full), = statuses
    assert status == "Solved"
    # two factorizations per KKT system (gamma is a free variable: [H + A'A, A'; A, 0]), one system per iteration
    # and one for the starting point
    stop_at = 2 * (full - 2) + 2 if late else 2 * 3 + 2
    calls = [0]

    def failing(H: np.ndarray) -> object:
        calls[0] += 1
        if calls[0] > stop_at:
            raise ArithmeticError("forced")
        return real_chol(H)

    monkeypatch.setattr(sdp, "_cholesky", failing)
    val, check = _sextic_bound(MOMENT)
    status, iters = statuses[-1]
    assert iters < full
    if late:
        assert status == "AlmostSolved"
        assert val == pytest.approx(ref, rel=1e-4, abs=1e-5)
    else:
        assert status == "InsufficientProgress"
        assert val == pytest.approx(ref, rel=1e-6, abs=1e-7)             # Clarabel's own answer
        assert check.max_residual < 1e-7


def test_small_larger_moment_and_feasibility_programs_go_to_clarabel(moment_calls: list) -> None:
    n = MOMENT_POLICY.min_block
    X = cp.Variable((n, n), symmetric=True)
    t = cp.Variable(500)        # 1000 rows left as equations: a moment form of order > n (n + 1) / 2 = 820
    base = [X >> 0, cp.trace(X) == n, X[0, 1] == 0.5]
    programs = {
        "small block": cp.Problem(cp.Minimize(cp.trace(X[:5, :5])), [X[:5, :5] >> 0, cp.trace(X[:5, :5]) == 1]),
        "larger moment form": cp.Problem(cp.Minimize(cp.sum(t) + X[0, 0]), [*base, t >= 0, t >= X[0, 0] - 1]),
        "feasibility": cp.Problem(cp.Minimize(0), base),
    }
    for name, prob in programs.items():
        ref = prob.solve(solver="CLARABEL", **solver_options("CLARABEL"))    # with glidectl's thread count
        Xref = X.value.copy()
        val = prob.solve(solver=solver_argument(MOMENT))
        assert prob.status == cp.OPTIMAL, name
        assert val == pytest.approx(ref, abs=1e-12), name          # Clarabel's own answer, bit for bit
        assert np.array_equal(X.value, Xref), name
    assert moment_calls == []
    with pytest.raises(ArgumentError, match="nonzero objective"):
        solve_moment(*_clarabel_data(programs["feasibility"]))


def test_split_hinge_keeps_one_equation_per_sample_and_the_optimum(moment_calls: list) -> None:
    """The V step's hinge ``sum max(a_k' d - 1, 0)`` written as ``p - q`` with ``p, q >= 0`` (what
    ``_coverage_objective`` builds): its moment form has one equation per sample where ``cp.pos`` leaves two, it goes
    through the route, and it has the optimum of the ``cp.pos`` form in Clarabel."""
    n, K = MOMENT_POLICY.min_block, 30
    rng = np.random.default_rng(3)
    Am = rng.uniform(0.0, 0.1, (K, n))
    X = cp.Variable((n, n), symmetric=True)
    base = [X >> 0, cp.trace(X) == n, X[0, 1] == 0.5]
    d = cp.diag(X)
    pos = cp.Problem(cp.Minimize(cp.sum(cp.pos(Am @ d - 1))), base)
    p, q = cp.Variable(K, nonneg=True), cp.Variable(K, nonneg=True)
    split = cp.Problem(cp.Minimize(cp.sum(p)), [*base, Am @ d - 1 == p - q])
    forms = {}
    for name, prob in (("pos", pos), ("split", split)):
        A, b, c, zero, _nonneg, psd = _clarabel_data(prob)
        forms[name] = moment_form(A, b, c, zero)
        assert moment_pays(forms[name], psd)
    assert forms["split"].E_R.shape[0] == 2 + K                  # trace, X[0, 1] and one equation per sample
    assert forms["pos"].E_R.shape[0] >= 2 + 2 * K
    ref = pos.solve(solver="CLARABEL")
    assert ref > 0.1                                    # the hinge is active
    val = split.solve(solver=solver_argument(MOMENT))
    assert len(moment_calls) == 1 and split.status == cp.OPTIMAL
    assert val == pytest.approx(ref, rel=1e-6)
    assert np.allclose(p.value, np.maximum(Am @ np.diag(X.value) - 1, 0.0), atol=1e-6)


@pytest.mark.parametrize("kind", ["infeasible", "unbounded"])
def test_infeasible_and_unbounded_programs_are_reported(kind: str, moment_calls: list) -> None:
    n = MOMENT_POLICY.min_block
    X = cp.Variable((n, n), symmetric=True)
    if kind == "infeasible":
        prob = cp.Problem(cp.Minimize(X[0, 0]), [X >> 0, cp.trace(X) == -1.0])
    else:
        prob = cp.Problem(cp.Minimize(-cp.trace(X)), [X >> 0, X[0, 1] == 0.0])
    prob.solve(solver=solver_argument(MOMENT))
    assert prob.status == (cp.INFEASIBLE if kind == "infeasible" else cp.UNBOUNDED)
    assert len(moment_calls) == 1


def test_sos_program_raises_solver_error_on_an_infeasible_moment_program(moment_calls: list) -> None:
    nv = 5
    prog = SOSProgram(nv)
    p = Poly({}, nv)
    for i in range(nv):         # sum(x_i - x_i^6) + c is never SOS; its Newton polytope keeps all 56 monomials
        p = p + Poly({tuple(int(k == i) for k in range(nv)): 1.0, tuple(6 * int(k == i) for k in range(nv)): -1.0}, nv)
    cu, c = prog.scalar("c")
    prog.add_sos("neg", c + p, monomials(nv, 3))
    with pytest.raises(SolverError, match="infeasible"):
        prog.solve(cp.Minimize(cu.var[0]), solver=MOMENT)
    assert len(moment_calls) == 1


def test_solver_names_are_checked() -> None:
    assert MOMENT in gc.installed_sdp_solvers()
    assert "CLARABEL" in gc.installed_sdp_solvers()
    with pytest.raises(ArgumentError, match="CVXOPT_MOMENT"):
        ps = gc.recast(gc.benchmarks.van_der_pol())
        gc.max_level(ps, gc.lyapunov_quadratic(ps), solver="NOT_A_SOLVER")


def test_sparse_kkt_schur_complement_equals_the_dense_formula(monkeypatch: pytest.MonkeyPatch) -> None:
    """The row-grouped Schur complement of ``_SparseKKT`` (``S G_l S`` from the rows ``R_l`` of each column) equals
    ``H_kl = <G_k, S G_l S>`` (plus ``G_l' D^-2 G_l`` for the nonnegative rows) formed densely from ``G``, on the
    moment form of a 56 x 56 SOS program whose columns have 1 to 20 rows (10 groups), for random scalings."""
    made: list = []
    real = sdp._SparseKKT

    def recorded(*a: object) -> object:
        made.append(real(*a))
        return made[-1]

    monkeypatch.setattr(sdp, "_SparseKKT", recorded)
    _sextic_bound(MOMENT)
    kkt, = made
    sizes = {rg for blk in kkt.blocks for _, rg, _, _ in blk[2]}
    assert len(sizes) > 3                                   # several groups of |R_l|
    G = kkt.G.toarray()
    rng = np.random.default_rng(7)
    d = rng.uniform(0.5, 2.0, kkt.nonneg)
    rti = [rng.standard_normal((nb, nb)) for nb in kkt.dims["s"]]
    ref = (G[:kkt.nonneg] / d[:, None]).T @ (G[:kkt.nonneg] / d[:, None])
    off = kkt.nonneg
    for nb, R in zip(kkt.dims["s"], rti, strict=True):
        S = R @ R.T
        Gb = G[off:off + nb * nb].reshape(nb, nb, -1).transpose(1, 0, 2)       # column-major: [i, j, l], i >= j
        low = np.tril(np.ones((nb, nb), dtype=bool))
        Gb = np.where(low[:, :, None], Gb, 0.0)
        Gs = Gb + np.where(np.eye(nb, dtype=bool)[:, :, None], 0.0, Gb.transpose(1, 0, 2))   # symmetric
        Y = np.einsum("ip,pql,qj->ijl", S, Gs, S)
        ref += np.einsum("ijk,ijl->kl", Gs, Y)
        off += nb * nb
    H = kkt.schur({"d": d, "rti": rti})
    assert np.allclose(H, ref, rtol=1e-10, atol=1e-10 * np.max(np.abs(ref)))


def _hinge_program(seed: int, n: int = 8, k: int = 300) -> cp.Problem:
    """A V-step-like program: free coefficients ``v`` tied to a Gram matrix ``X >= 0`` (n x n) by ``<C_i, X> = v_i``
    and ``trace(X) = n``, and ``min mean(p)`` with one hinge equation per sample in ``v`` alone,
    ``b_k . v - 1 = p_k - q_k``, ``p, q >= 0`` (as ``_coverage_objective`` writes it)."""
    rng = np.random.default_rng(seed)
    X = cp.Variable((n, n), symmetric=True)
    v = cp.Variable(6)
    p, q = cp.Variable(k, nonneg=True), cp.Variable(k, nonneg=True)
    C = [(lambda M: M + M.T)(rng.standard_normal((n, n))) for _ in range(6)]
    B = rng.standard_normal((k, 6))
    cons = [X >> 0, cp.trace(X) == n, B @ v - 1 == p - q]
    cons += [cp.trace(C[i] @ X) == v[i] for i in range(6)]
    return cp.Problem(cp.Minimize(cp.sum(p) / k), cons)


def test_diagonal_elimination_is_the_same_newton_system(monkeypatch, moment_policy) -> None:
    """ELIMINATE_DIAGONAL (Woodbury on the sample columns of the Schur complement) gives the same iterations and
    optimum as the whole factorization, and finds the sample columns (each in its own nonnegative rows)."""
    prob = _hinge_program(1)
    args = _clarabel_data(prob)
    found = []
    real = sdp._SparseKKT.__init__

    def spy(self, *a, **k):
        real(self, *a, **k)
        found.append(self.diag)

    monkeypatch.setattr(sdp._SparseKKT, "__init__", spy)
    out = {}
    for flag in (False, True):
        moment_policy(eliminate_diagonal_min=256 if flag else None)
        out[flag] = solve_moment(*args)
    assert found[0] is None and found[1] is not None and len(found[1][0]) == 300
    assert out[True].status in ("Solved", "AlmostSolved") and out[False].status == out[True].status
    assert out[True].iterations == out[False].iterations
    assert out[True].obj_val == pytest.approx(out[False].obj_val, rel=1e-8, abs=1e-10)
    assert out[True].obj_val == pytest.approx(prob.solve(solver="CLARABEL"), rel=1e-5, abs=1e-6)


def test_steering_options_are_cvxopts_tolerances_on_the_moment_route_only() -> None:
    assert sdp_solvers.steering_options(sdp.MOMENT) == sdp_solvers.STEERING_TOLERANCES == {"reltol": 1e-3,
                                                                                           "feastol": 1e-5}
    assert sdp_solvers.steering_options("CLARABEL") == {}
    sdp_solvers.steering_options(sdp.MOMENT)["reltol"] = 1.0            # a copy: the module's tolerances stay
    assert sdp_solvers.STEERING_TOLERANCES["reltol"] == 1e-3


def test_the_v_step_is_solved_at_the_steering_tolerances(monkeypatch) -> None:
    """certify_roa's V steps (and only they) pass the steering tolerances; its level programs the solver's
    defaults."""
    import glidectl as gc
    from glidectl.roa.sos import SOSProgram

    seen = []
    real = SOSProgram.resolve

    def spy(self, *, solver=sdp_solvers.DEFAULT_SOLVER, **kw):
        seen.append((self.problem.objective.NAME, dict(kw)))
        return real(self, solver=solver, **kw)

    monkeypatch.setattr(SOSProgram, "resolve", spy)
    gc.certify_roa(gc.benchmarks.van_der_pol(), degree=2, iterations=1, sampling=dict(n_verify=500, n_simulate=8))
    steer = [kw for _, kw in seen if kw]
    assert steer and all(kw == sdp_solvers.STEERING_TOLERANCES for kw in steer)
    assert any(name == "maximize" and not kw for name, kw in seen)      # the level programs: defaults


# ------------------------------------------------------------------- cvxpy's "may be inaccurate" warning
def _inaccurate_warnings(record: list) -> list[str]:
    return [str(w.message) for w in record if str(w.message).startswith(sdp_solvers.INACCURATE_MESSAGE)]


def test_inaccuracy_checked_silences_that_warning_only() -> None:
    import warnings

    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        with sdp_solvers.inaccuracy_checked():
            warnings.warn(sdp_solvers.INACCURATE_MESSAGE + ". Try another solver, ...", UserWarning, stacklevel=1)
            warnings.warn("something else", UserWarning, stacklevel=1)
        warnings.warn(sdp_solvers.INACCURATE_MESSAGE + ". Try another solver, ...", UserWarning, stacklevel=1)
    assert [str(w.message) for w in record] == ["something else",
                                                sdp_solvers.INACCURATE_MESSAGE + ". Try another solver, ..."]


def test_sos_and_lmi_solves_check_an_inaccurate_status_without_passing_cvxpys_warning_on(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Every cvxpy solve warns as it does on ``optimal_inaccurate``: the SOS program and the LMI certificate, which
    check their solutions themselves, pass no such warning on; a bare cvxpy solve does (the patch works)."""
    import warnings

    from glidectl.roa.sos import LinPoly

    real, calls = cp.Problem.solve, []

    def warning_solve(self: cp.Problem, *a: object, **k: object) -> object:
        calls.append(1)
        out = real(self, *a, **k)
        warnings.warn(sdp_solvers.INACCURATE_MESSAGE + ". Try another solver, adjusting the solver settings, ...",
                      UserWarning, stacklevel=2)
        return out

    monkeypatch.setattr(cp.Problem, "solve", warning_solve)
    x = Poly.variables(1)[0]
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        prog = SOSProgram(1)
        prog.add_sos("p", LinPoly(x**4 + 2.0 * x**2 + 1.0), monomials(1, 2))
        prog.solve(cp.Minimize(0))
        loop = gc.SaturatedLoop("scalar", ("x1",), ("u",), lambda X, W: X + W, np.zeros(1), np.array([[-2.0]]),
                                np.array([-1.0]), np.array([1.0]), (-np.full(1, 2.0), np.full(1, 2.0)))
        cert = gc.certify_roa_lmi(loop, rounds=2, n_radii=4, refine=2, n_hessian=256, n_verify=1000, n_simulate=8)
        n_library = len(calls)
        cp.Problem(cp.Minimize(cp.Variable() ** 2)).solve()
    assert prog.check()[0].passed and cert.certified
    assert n_library >= 2 and len(calls) == n_library + 1
    assert len(_inaccurate_warnings(record)) == 1        # the bare solve's, and only it
