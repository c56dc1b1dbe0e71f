"""A certificate does not depend on the number of threads (issue 18: a pool build, a dask cluster and a serial
build give the same reports; the number of cores of the machine must not change them either).

Clarabel's parallel factorization adds in an order that depends on its thread count (``RAYON_NUM_THREADS``, by
default the machine's cores), and so do some OpenBLAS routines; the SOS alternation carries that rounding along its
path. glidectl therefore runs Clarabel with ``sdp_solvers.CLARABEL_THREADS`` (one) thread in every program it solves,
and its certifying functions with ``blas_threads.BLAS_THREADS`` (one) BLAS thread. The end-to-end check (a serial
build against a spawned pool) is in tests/test_report_parallel.py."""

from __future__ import annotations

import os
import subprocess
import sys
import warnings

import cvxpy as cp
import numpy as np
import pytest
from cvxpy.reductions.solvers.conic_solvers.clarabel_conif import CLARABEL
from threadpoolctl import threadpool_info, threadpool_limits

import glidectl as gc
from glidectl.roa import SOSProgram, blas_threads, max_level, resolve_box, sdp_solvers
from glidectl.roa.programs import lyapunov_quadratic

warnings.filterwarnings("ignore", message="Solution may be inaccurate")

# one certificate of the reduced chapter-5 glider by Clarabel (a few seconds); prints a hash of V's coefficients.
# "auto" restores Clarabel's own default thread count (0: RAYON_NUM_THREADS, else one per core)
PROBE = """
import hashlib, sys
import glidectl as gc
from glidectl.roa import sdp_solvers
if sys.argv[1] == "auto":
    sdp_solvers.CLARABEL_THREADS = 0
rm = gc.singular_perturbation(gc.load_vehicle("sphere_ch5")).reduced_model()
c = gc.certify_roa(rm, degree=4, iterations=1, solver="CLARABEL",
                  sampling=dict(n_truth=256, n_verify=500, n_simulate=4))
print(hashlib.sha256(c.V.arrays()[1].tobytes()).hexdigest(), repr(c.rho))
"""


def _certificate_hash(rayon_threads: int, mode: str) -> str:
    env = dict(os.environ, RAYON_NUM_THREADS=str(rayon_threads), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", PROBE, mode], env=env, capture_output=True, text=True, timeout=600,
                         check=True)
    return out.stdout.strip().splitlines()[-1]


def test_a_certificate_is_bitwise_the_same_with_one_or_two_clarabel_threads():
    one, two = _certificate_hash(1, "pinned"), _certificate_hash(2, "pinned")
    assert one == two
    # and the test can fail: with Clarabel's default (threads from RAYON_NUM_THREADS) two threads give another V
    assert _certificate_hash(2, "auto") != two


@pytest.fixture
def clarabel_calls(monkeypatch):
    """Every Clarabel solve from here on: ``(its solver options, the BLAS threads while it runs)``."""
    calls: list[tuple[dict, dict[str, int]]] = []
    real = CLARABEL.solve_via_data

    def spy(self, data, warm_start, verbose, solver_opts, solver_cache=None):
        calls.append((dict(solver_opts), _blas_threads()))
        return real(self, data, warm_start, verbose, solver_opts, solver_cache)

    monkeypatch.setattr(CLARABEL, "solve_via_data", spy)
    return calls


def test_every_clarabel_program_gets_the_pinned_thread_count(clarabel_calls):
    """Clarabel called directly (``solver="CLARABEL"``), by ``CVXOPT_MOMENT`` for a program it hands on (a small
    one), and by the LMI path: every call carries ``max_threads = CLARABEL_THREADS``."""
    seen = clarabel_calls
    vdp = gc.benchmarks.van_der_pol()
    V = lyapunov_quadratic(vdp)
    for solver in ("CLARABEL", sdp_solvers.MOMENT):
        before = len(seen)
        assert max_level(vdp, V, solver=solver).rho > 0
        assert len(seen) > before
    n = 1
    sl = gc.SaturatedLoop("scalar", ("x1",), ("u",), lambda X, W: X + W, np.zeros(n), np.array([[-2.0]]),
                          np.array([-1.0]), np.array([1.0]), (-np.full(n, 2.0), np.full(n, 2.0)))
    before = len(seen)
    assert gc.certify_roa_lmi(sl, backoff=0.0).certified
    assert len(seen) > before
    assert seen and all(o.get("max_threads") == sdp_solvers.CLARABEL_THREADS == 1 for o, _ in seen)


def test_solver_options_are_clarabels_thread_count_only_and_a_callers_own_option_wins(clarabel_calls):
    assert sdp_solvers.solver_options("CLARABEL") == {"max_threads": 1}
    assert sdp_solvers.solver_options(sdp_solvers.MOMENT) == {}
    prog = SOSProgram(1)
    x = cp.Variable()
    prog.constraints.append(x >= 1.0)
    assert prog.solve(cp.Minimize(x), solver="CLARABEL", max_threads=2) == pytest.approx(1.0)
    assert prog.resolve(solver="CLARABEL") == pytest.approx(1.0)
    assert [o["max_threads"] for o, _ in clarabel_calls] == [2, 1]


def _blas_threads() -> dict[str, int]:
    """Threads of every BLAS library loaded (numpy's and SciPy's OpenBLAS; SCS's is built with one)."""
    return {i["filepath"]: i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}


def _count(d: dict[str, int]) -> set[int]:
    return set(d.values())


def test_certifying_functions_run_with_one_blas_thread_and_restore_the_callers(clarabel_calls):
    """Every SDP solve (spied in Clarabel) and the right-hand-side calls of a surrogate build see one BLAS thread,
    though the caller set two; the caller's count is back afterwards. (With two OpenBLAS threads the saturated user
    glider's SOS certificate had volume 3.6618e-12 instead of 3.4762e-12.)"""
    assert blas_threads.BLAS_THREADS == 1
    with threadpool_limits(limits=2, user_api="blas"):
        before = _blas_threads()
        assert 2 in _count(before)
        vdp = gc.benchmarks.van_der_pol()
        assert max_level(vdp, lyapunov_quadratic(vdp), solver="CLARABEL").rho > 0
        seen_rhs: list[set[int]] = []
        sph = gc.load_vehicle("sphere_ch5")
        loop = gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0))

        class Spied:
            state_names, input_names, equilibrium = loop.state_names, (), loop.equilibrium

            def rhs(self, X):
                seen_rhs.append(_blas_threads())
                return loop.rhs(X)

        gc.roa.surrogate_system(Spied(), _small_box(loop))
        assert _blas_threads() == before            # restored
    assert clarabel_calls and all(_count(d) == {1} for _, d in clarabel_calls)
    assert seen_rhs and all(_count(d) == {1} for d in seen_rhs)


def _small_box(loop):
    """5 % of the loop's own box about its equilibrium (a quick surrogate)."""
    lo, hi = resolve_box(loop, None, np.asarray(loop.equilibrium))
    xe = np.asarray(loop.equilibrium)
    return xe + 0.05 * (lo - xe), xe + 0.05 * (hi - xe)


def test_blas_threads_none_leaves_the_callers_count(monkeypatch):
    monkeypatch.setattr(blas_threads, "BLAS_THREADS", None)
    seen: list[set[int]] = []

    @blas_threads.pinned_blas
    def f():
        seen.append(_count(_blas_threads()))

    with threadpool_limits(limits=2, user_api="blas"):
        before = _blas_threads()
        f()
    monkeypatch.setattr(blas_threads, "BLAS_THREADS", 1)
    with threadpool_limits(limits=2, user_api="blas"):
        f()
        assert _blas_threads() == before
    assert seen == [_count(before), {1}] and 2 in seen[0]
