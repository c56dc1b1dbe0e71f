"""CTOL certificate speed (issue 17 part 5, issue 18): SDPs that feed nothing are not solved, and the programs
that are solved give the same certificate."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import glidectl as gc
from glidectl.roa import Poly, alternation, certificate, dVdt, polynomial_system, programs, routes  # noqa: F401
from glidectl.roa.sos import SOSProgram


def cheap(solver: dict | None = None, sampling: dict | None = None, **kw) -> dict:
    """Cheap certify_roa arguments, with ``solver`` and ``sampling`` options added to the cheap ones."""
    return {"degree": 2, "iterations": 1, "solver": {"backoff": 0.003, **(solver or {})},
            "sampling": {"n_truth": 64, "n_verify": 500, "n_simulate": 4, **(sampling or {})}, **kw}


def _cubic_2d():
    """A 2-state cubic with a bounded region of attraction and no sign symmetry in its quadratic part."""
    x, y = Poly.variables(2)
    F = [-x + 0.5 * y + x * x * y - 0.2 * x * x, -0.5 * x - y + 0.3 * x * y * y]
    return polynomial_system("cubic2", ("x", "y"), F, box=(np.array([-2.0, -2.0]), np.array([2.0, 2.0])))


def _count_solves(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    calls = [0]
    orig = SOSProgram.solve

    def counting(self, *a, **k):
        calls[0] += 1
        return orig(self, *a, **k)

    monkeypatch.setattr(SOSProgram, "solve", counting)
    return calls


def test_last_level_is_not_centred_and_certificate_unchanged(monkeypatch):
    """With one alternation at the final degree, the centred re-solve of the last level problem feeds no V step:
    it is skipped (4 programs: initial level + its centring, V step, last level, final margin program, i.e. 5 solves
    instead of 6), and the certificate is exactly the one the old path (centring every level) gives."""
    ps = gc.benchmarks.van_der_pol()
    calls = _count_solves(monkeypatch)
    new = gc.certify_roa(ps, **cheap(solver=dict(reuse=False)))  # every SDP built and solved anew: one solve() each
    n_new = calls[0]
    orig = programs.solve_level

    def always_centred(*a, **k):
        k["center"] = k.get("center") or 0.05
        return orig(*a, **k)

    monkeypatch.setattr(alternation, "solve_level", always_centred)
    calls[0] = 0
    old = gc.certify_roa(ps, **cheap(solver=dict(reuse=False)))
    assert n_new == 5 and calls[0] == 6
    assert new.rho == old.rho and new.rho_star == old.rho_star
    assert new.V.terms == old.V.terms
    assert new.certified and old.certified


def test_two_iterations_still_centre_the_first_level(monkeypatch):
    """The skip is only for the last level: with two alternations the first new level is centred (8 solves:
    2 + (V step + level + centring) + (V step + level) + final)."""
    calls = _count_solves(monkeypatch)
    cert = gc.certify_roa(_cubic_2d(), **cheap(dict(reuse=False), dict(horizon=8.0), iterations=2))
    steps = [h.step for h in cert.history]
    n_alt = sum(s == "V step + level" for s in steps)
    assert n_alt == 2
    assert calls[0] == 8


def test_certified_set_has_negative_true_derivative():
    """Soundness of the certificate on the synthetic cubic: the true dV/dt is negative at points of the certified
    set (drawn in it and on its boundary), and the set is nonempty."""
    ps = _cubic_2d()
    cert = gc.certify_roa(ps, **cheap(sampling=dict(horizon=8.0)))
    assert cert.certified
    X = np.concatenate([cert.sample(400, seed=1), cert.sample(200, seed=2, boundary=True)])
    assert np.all(cert.contains(X))
    r2 = np.sum(X**2, axis=1)
    d = dVdt(cert.V, ps.lift, ps.rhs, X)
    assert np.all(d[r2 > 1e-8] < 0)


def test_margin_checks_failing_on_the_moment_route_are_taken_again_by_clarabel(monkeypatch):
    """The moment route stops at a singular Schur complement with residuals near 1e-6: when the final margin
    program's Gram check fails at every backoff there, the same backoff steps are taken again with Clarabel, and the
    certificate is the one Clarabel gives. (The checks are made to fail: Van der Pol's programs are small and go to
    Clarabel anyway, so the certificate equals the plain Clarabel run's.)"""
    ps = gc.benchmarks.van_der_pol()
    ref = gc.certify_roa(ps, **cheap(solver=dict(name="CLARABEL")))
    real = SOSProgram.check
    seen = {"margin": 0}

    def failing(self, *a, **k):
        out = real(self, *a, **k)
        if getattr(self, "margin", None) is not None and seen["margin"] < 4:
            seen["margin"] += 1
            return [dataclasses.replace(c, min_eig=-1.0, projected_min_eig=-1.0) for c in out]
        return out

    monkeypatch.setattr(SOSProgram, "check", failing)
    cert = gc.certify_roa(ps, **cheap(solver=dict(name="CVXOPT_MOMENT")))
    steps = [h.step for h in cert.history]
    assert seen["margin"] == 4
    margins = [s for s in steps if s.startswith("final margin")]
    assert margins == [f"final margin at backoff {b:g}" for b in (0.003, 0.009, 0.027, 0.081)] + [
        "final margin at backoff 0.003 (Clarabel)"]
    assert any(s.endswith("the same steps by Clarabel from backoff 0.003") for s in steps)
    assert cert.certified and cert.rho == pytest.approx(ref.rho, rel=1e-12)
