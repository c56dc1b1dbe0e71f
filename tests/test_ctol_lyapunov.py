"""Theorem 5 for the CTOL closed loop (§7.2.2-§7.2.5, Appendix "Theorem 5 Calculations"):
:func:`glidectl.stability.ctol_lyapunov.ctol_lyapunov`.

Checked: the split (7.28)-(7.39) against the closed loop and against the printed formulas; ``g2 = 0`` exactly and
the form of ``f2`` that (7.23) gives; ``dQ1/dt`` along ``f1`` in closed form for any glide and vehicle scaling;
every constant of the certificate on samples independent of the construction's; the printed constants that fail;
the coupling conditions; the composite derivative (7.46) and the certified region; bad inputs.

Thesis errors pinned here:

* ``lambda1`` (7.70)-(7.72) lacks the factor ``V_e/m``: printed 3.675 at the level glide, true min of
  ``-Q1'/|x1|^2`` on the ball ``r = 0.5`` is 0.7116 (margin 0.194); ``(V_e/m) min(s1, s2) = 0.5703`` holds.
  ``Q1`` itself is a Lyapunov function of ``f1`` for every glide (k1, k2, g drop out exactly).
* (7.63) can be negative where the true ``lambda2`` is positive (``k4 = 0.6``, ``k' = 0.5``): the printed bound is
  only sufficient.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import glidectl as gc
from glidectl.errors import ModelError
from glidectl.stability.ctol_lyapunov import CTOLLyapunovCertificate, Theorem5Constants, ctol_lyapunov
from glidectl.trim.ctol import ctol_glide

VEH = gc.load_vehicle("dc8_ctol")
LEVEL = ctol_glide(VEH, 0.85 / 30**0.5, 0.0)
GAINS = {"thesis": (7e5, 250.0), "moderate": (10.0, 5.0)}


@pytest.fixture(scope="module")
def certs() -> dict[str, CTOLLyapunovCertificate]:
    return {k: ctol_lyapunov(VEH, LEVEL, k3, k4) for k, (k3, k4) in GAINS.items()}


@pytest.fixture(scope="module")
def verifications(certs):
    return {k: c.verify(n=60_000, seed=7) for k, c in certs.items()}


def _ball(n: int, r: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(n, 4))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u * (r * rng.random(n) ** 0.25)[:, None]


# --------------------------------------------------------------------------------------------------------- split
@pytest.mark.parametrize("name", list(GAINS))
def test_split_reproduces_closed_loop(certs, name):
    c = certs[name]
    x = _ball(2000, c.r, 1)
    rhs = c.closed_loop.rhs(x)
    scale = np.max(np.abs(rhs))
    assert np.max(np.abs(c.f1(x[:, :2]) + c.g1(x) - rhs[:, :2])) <= 1e-12 * scale
    assert np.max(np.abs(c.f2(x[:, 2:]) - rhs[:, 2:])) <= 1e-12 * scale
    assert np.array_equal(c.g2(x), np.zeros((2000, 2)))  # (7.35), bit for bit
    assert np.array_equal(c.g1(np.c_[x[:, :2], np.zeros((2000, 2))]), np.zeros((2000, 2)))  # gamma11 = 0


@pytest.mark.parametrize("name", list(GAINS))
def test_f2_form_from_equilibrium_7_23(certs, name):
    """(7.23) makes k1 cos theta - k2 sin theta = -k'' sin thetabar, so f22 = -(T/eps)(k3 + k'') sin - T k4 Omega."""
    c = certs[name]
    x2 = _ball(500, c.r, 2)[:, 2:]
    f22 = -(c.T / VEH.epsilon) * (c.k3 + c.k_pp) * np.sin(x2[:, 0]) - c.T * c.k4 * x2[:, 1]
    np.testing.assert_allclose(c.f2(x2)[:, 1], f22, rtol=1e-12, atol=1e-12 * np.max(np.abs(f22)))
    np.testing.assert_allclose(c.f2(x2)[:, 0], x2[:, 1] / c.T, rtol=0, atol=0)
    th = c.glide.theta
    assert c.k_pp == pytest.approx(LEVEL.k1 * math.sin(th) + LEVEL.k2 * math.cos(th), rel=1e-15)


def test_printed_split_formulas_7_29_to_7_39(certs):
    """The printed f1, g1 with the deltas (7.36)-(7.39) are exactly the closed loop's split (m = g = J = 1)."""
    c = certs["moderate"]
    aL, aD, b, cc, eps = VEH.a_L, VEH.a_D, VEH.b, VEH.c, VEH.epsilon
    gl = LEVEL
    x = _ball(1000, c.r, 3)
    Vb, gb, tb, Ob = x.T
    V, gam, alpha, ae = gl.speed * (1 + Vb), gb + gl.gamma, tb + gl.theta - gb - gl.gamma, gl.alpha
    KDe, KLe = aD * (1 + b * (1 + cc * ae) ** 2), aL * (1 + cc * ae)
    dD1 = aD * b * (cc**2 * gb**2 - 2 * cc**2 * gb * ae - 2 * cc * gb)
    dD2 = aD * b * (cc**2 * tb**2 + 2 * cc**2 * tb * ae - 2 * cc**2 * tb * gb + 2 * cc * tb)
    dL1, dL2 = -aL * cc * gb, aL * cc * tb
    k1, k2 = gl.k1, gl.k2
    f11 = (-(k1 + 1) * np.sin(gam) - k2 * np.cos(gam) - (KDe + dD1) * V**2) / gl.speed
    f12 = (-(k1 + 1) * np.cos(gam) + k2 * np.sin(gam) + (KLe + dL1) * V**2) / V
    g11 = (-dD2 * V**2 - c.k3 * np.sin(tb) * np.sin(alpha) - eps * c.k4 * Ob * np.sin(alpha)) / gl.speed
    g12 = (dL2 * V**2 + c.k3 * np.sin(tb) * np.cos(alpha) + eps * c.k4 * Ob * np.cos(alpha)) / V
    np.testing.assert_allclose(c.f1(x[:, :2]), np.c_[f11, f12], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(c.g1(x), np.c_[g11, g12], rtol=1e-10, atol=1e-12)


# --------------------------------------------------------------------------------------------------------- Q1
@pytest.mark.parametrize("kw", [{}, {"m": 2.0, "J": 3.0, "g": 9.8}, {"rho_AW_half": 1.3, "epsilon": 0.1}])
@pytest.mark.parametrize(("speed", "gamma"), [(0.12, -0.2), (0.2, 0.2)])
def test_Q1dot_closed_form_any_glide(kw, speed, gamma):
    """dQ1/dt along f1 = -(V_e/m){K_De[...] + dK_D ... - dK_L ...}: k1, k2 and g drop out (module note 1)."""
    veh = gc.load_vehicle("dc8_ctol", **kw)
    gl = ctol_glide(veh, speed * math.sqrt(veh.m * veh.g / veh.rho_AW_half), gamma)
    c = ctol_lyapunov(veh, gl, 10.0, 5.0, n=500)
    x1 = _ball(3000, 0.5, 4)[:, :2]
    lie = np.sum(c.grad_Q1(x1) * c.f1(x1), axis=1)
    cf = c.Q1dot_closed_form(x1)
    np.testing.assert_allclose(lie, cf, rtol=1e-9, atol=1e-13)
    assert np.all(lie < 0)


def test_Q1_forms_and_gradients(certs):
    c = certs["moderate"]
    x = _ball(500, c.r, 5)
    V, g = x[:, 0], x[:, 1]
    np.testing.assert_allclose(c.Q1(x[:, :2]), (1 + V) ** 3 / 3 - (1 + V) * np.cos(g) + 2 / 3, atol=1e-14)
    h = 1e-6
    for i in range(4):
        e = np.zeros(4)
        e[i] = h
        fd = (c.Q(x + e) - c.Q(x - e)) / (2 * h)
        np.testing.assert_allclose(c.grad(x)[:, i], fd, rtol=1e-6, atol=1e-9 * max(c.d1, c.d2))


# --------------------------------------------------------------------------------------------------------- constants
def test_printed_constants(certs):
    p = certs["moderate"].printed
    assert p.c11 == pytest.approx(min(1 - 0.5 / 3, 0.25 * (1 - math.pi**2 / 12)))
    assert p.c12 == pytest.approx(1 + 0.5 / 3)
    assert p.beta1 == pytest.approx(math.sqrt(2) * 2.5)
    assert p.lambda2 == pytest.approx(0.5 * (5 * 1.5 - 1))           # (7.63), second entry binds
    assert p.c21 == pytest.approx(0.25)                               # (7.59), 1 - k' binds
    assert (p.gamma11, p.gamma21, p.gamma22) == (0.0, 0.0, 0.0)
    assert certs["thesis"].printed.lambda2 == pytest.approx(0.5 * (250 * 1.5 - 1))


@pytest.mark.parametrize("name", list(GAINS))
def test_valid_constants_hold_on_independent_samples(certs, verifications, name):
    c, v = certs[name], verifications[name]
    assert v.seed != c.seed_build
    assert v.passed, v.failing()
    assert v.failing() == {}
    assert set(v.margins) >= {"c11", "c12", "lambda1", "beta1", "gamma1", "c21", "c22", "lambda2", "beta2",
                                   "gamma2", "composite (7.46)", "level on sphere", "r_a ball in level set"}
    assert v.g2_max == 0.0 and v.margins["gamma2"] == math.inf
    # the sampled gamma12 agrees with the construction's refined sup to well inside the margin
    assert v.sampled.gamma12 <= c.sampled.gamma12 * (1 + 1e-6)
    assert v.sampled.gamma12 >= 0.99 * c.sampled.gamma12


@pytest.mark.parametrize("name", list(GAINS))
def test_printed_lambda1_fails_and_is_pinned(certs, verifications, name):
    c, v = certs[name], verifications[name]
    assert set(v.failing_printed()) == {"lambda1"}
    assert c.printed.lambda1 == pytest.approx(3.67502, abs=1e-5)
    assert c.sampled.lambda1 == pytest.approx(0.711627, abs=1e-5)
    assert v.margins_printed["lambda1"] == pytest.approx(0.1936, abs=1e-3)
    # the printed value with the missing V_e/m factor holds
    assert c.lambda1_formula == pytest.approx(LEVEL.speed * c.printed.lambda1)
    assert v.lambda1_formula_margin == pytest.approx(1.2478, abs=1e-3)
    assert c.valid.lambda1 == pytest.approx(0.98 * c.sampled.lambda1)
    assert any(s.startswith("lambda1: printed") for s in c.corrections)
    # c12 is tight (attained at Vbar = r, gammabar = 0) but holds
    assert v.margins_printed["c12"] == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize(("speed", "gamma"), [(0.12, -0.2), (0.12, 0.2), (0.2, -0.2), (0.2, 0.2)])
def test_lambda1_other_glides(speed, gamma):
    c = ctol_lyapunov(VEH, ctol_glide(VEH, speed, gamma), 10.0, 5.0, n=2000)
    assert 0.5 < c.sampled.lambda1 < 1.0                      # Q1 decreases along f1 at every glide
    assert c.sampled.lambda1 / c.printed.lambda1 < 0.25        # printed (7.70) fails
    assert c.sampled.lambda1 / c.lambda1_formula > 1.1         # (V_e/m) min(s1, s2) holds
    assert c.certified


def test_lambda2_printed_is_only_sufficient():
    c = ctol_lyapunov(VEH, LEVEL, 10.0, 0.6, n=2000)
    assert c.printed.lambda2 < 0 < c.sampled.lambda2           # (7.63) negative, Q2 still decreases
    assert c.certified and c.valid.lambda2 == pytest.approx(0.98 * c.sampled.lambda2)
    bad = ctol_lyapunov(VEH, LEVEL, 10.0, 0.5, n=2000)         # k4 = k'/T^2: no damping left in Q2'
    assert bad.sampled.lambda2 < 0 and not bad.certified
    assert (bad.d1, bad.d2, bad.lam, bad.r_a) == (0.0, 0.0, 0.0, 0.0)


# --------------------------------------------------------------------------------------------------------- coupling
@pytest.mark.parametrize("name", list(GAINS))
def test_coupling_conditions(certs, name):
    c = certs[name]
    for k in (c.printed, c.valid):
        c44, c45 = k.coupling
        assert c44 == pytest.approx(k.lambda1) and c45 == pytest.approx(k.lambda1 * k.lambda2)
        assert k.certified
    assert c.certified


@pytest.mark.parametrize("name", list(GAINS))
def test_composite_derivative_negative(certs, name):
    c = certs[name]
    k = c.valid
    b = 0.5 * k.beta1 * k.gamma12
    M = np.array([[c.d1 * k.lambda1, -c.d1 * b], [-c.d1 * b, c.d2 * k.lambda2]])
    assert c.d2 > b * b / (k.lambda1 * k.lambda2)
    assert np.min(np.linalg.eigvalsh(M)) == pytest.approx(c.lam / 2, rel=1e-6)
    x = _ball(20_000, c.r, 11)
    n2 = np.sum(x * x, axis=1)
    assert np.all(c.Qdot(x) <= -(c.lam / 2) * n2)               # (7.46) with the true closed loop
    assert 0 < c.r_a < c.r
    assert np.all(c.Q(x[np.linalg.norm(x, axis=1) <= c.r_a]) <= c.level)


def test_trajectory_stays_in_level_set(certs):
    c = certs["moderate"]
    x0 = 0.9 * c.r_a * np.array([0.5, -0.5, 0.5, -0.5])
    sol = solve_ivp(lambda t, x: c.rhs(x), (0, 5), x0, rtol=1e-10, atol=1e-14, max_step=0.05)
    Q = c.Q(sol.y.T)
    assert Q[0] <= c.level and np.all(np.diff(Q) <= 1e-12 * Q[0])
    assert Q[-1] < 0.2 * Q[0]


# --------------------------------------------------------------------------------------------------------- API
def test_immutable_and_provenance(certs, verifications):
    c, v = certs["moderate"], verifications["moderate"]
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.d2 = 1.0  # type: ignore[misc]
    with pytest.raises(TypeError):
        v.margins["c11"] = 2.0  # type: ignore[index]
    assert isinstance(c.valid, Theorem5Constants)
    assert "Theorem 5" in c.provenance and "k3=10" in c.provenance
    assert v.elapsed > 0 and v.n_samples == 60_000


@pytest.mark.parametrize("kw", [
    {"k_prime": 0.0}, {"k_prime": 1.0}, {"k_prime": -0.2}, {"k_prime": math.nan},
    {"r": 0.0}, {"r": 1.0}, {"r": -0.5}, {"r": math.inf},
    {"k3": 0.0}, {"k3": -1.0}, {"k4": 0.0}, {"k4": math.nan}, {"T": 0.0}, {"T": -1.0},
    {"k3": 0.01},  # k3 + k'' < 0 at the level glide (k'' = -0.049)
    {"margin": 0.7}, {"n": 10}, {"n": 10**9}, {"seed": -1}, {"T": 1e200},  # T**2 overflows
])
def test_bad_inputs_raise_argument_error(kw):
    args = {"k3": 10.0, "k4": 5.0} | kw
    with pytest.raises(gc.ArgumentError):
        ctol_lyapunov(VEH, LEVEL, **args)
    with pytest.raises(ValueError):  # the builtin class catches it too
        ctol_lyapunov(VEH, LEVEL, **args)


@pytest.mark.parametrize("kw", [{"k3": "10"}, {"k4": None}, {"T": True}, {"k_prime": 0.5j}, {"margin": "0.1"},
                                {"n": 1000.0}, {"seed": "a"}])
def test_wrong_types_raise_argument_type_error(kw):
    args = {"k3": 10.0, "k4": 5.0} | kw
    with pytest.raises(gc.ArgumentTypeError):
        ctol_lyapunov(VEH, LEVEL, **args)


def test_wrong_vehicle_or_glide():
    with pytest.raises(ModelError):
        ctol_lyapunov(gc.load_vehicle("rogue"), LEVEL, 10.0, 5.0)
    with pytest.raises(gc.ArgumentTypeError):
        ctol_lyapunov(VEH, (0.155, 0.0), 10.0, 5.0)  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentTypeError):
        ctol_lyapunov("dc8_ctol", LEVEL, 10.0, 5.0)  # type: ignore[arg-type]
    with pytest.raises(gc.VehicleMismatchError):  # a glide of another vehicle
        ctol_lyapunov(VEH.with_overrides(c=1.0), LEVEL, 10.0, 5.0)


def test_huge_gains_do_not_return_non_finite_constants():
    """Gains that overflow the constants raise instead of returning inf/NaN constants."""
    with pytest.raises(gc.GlidectlError, match=r"finite|overflow"):
        ctol_lyapunov(VEH, LEVEL, 1e200, 5.0, n=200)


def test_certificate_methods_check_points(certs):
    c = certs["moderate"]
    for bad in (np.zeros(3), [[0.1, 0.0]], np.full(4, np.nan)):
        with pytest.raises(gc.ArgumentError):
            c.Q(bad)
    with pytest.raises(gc.ArgumentTypeError):
        c.rhs("x")
    with pytest.raises(gc.ArgumentError):
        c.Q1(np.zeros(4))
    with pytest.raises(gc.ArgumentError):
        c.verify(n=10)
    assert c.in_region(np.zeros(4)) and c.Q1(np.zeros(2)) == 0.0


def test_Q_hessian_by_complex_step_matches_real_differences():
    """``gc.hessian`` of the Theorem-5 Lyapunov function ``Q`` (complex-step gradient) equals second central
    differences of ``Q`` on real points: ``Q`` accepts the complex points the complex step needs (regression: the
    argument checks refused them, which broke the roa_certification design's CTOL part)."""
    cert = ctol_lyapunov(VEH, LEVEL, *GAINS["moderate"])
    H = gc.hessian(cert.Q, np.zeros(4))
    h = 1e-3
    E = np.eye(4) * h
    Hfd = np.array([[(cert.Q(E[i] + E[j]) - cert.Q(E[i] - E[j]) - cert.Q(-E[i] + E[j]) + cert.Q(-E[i] - E[j]))
                     / (4 * h * h) for j in range(4)] for i in range(4)])
    np.testing.assert_allclose(H, Hfd, rtol=1e-5, atol=1e-6 * np.max(np.abs(H)))
    np.testing.assert_allclose(H, H.T, rtol=1e-12, atol=0)
    with pytest.raises(gc.ArgumentTypeError):
        cert.Q("a")
