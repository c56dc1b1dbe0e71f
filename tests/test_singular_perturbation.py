"""Singular-perturbation form of the chapter-5 glider (§5.1, §5.4): :func:`glidectl.singular_perturbation` and
:func:`glidectl.unequal_mass_check`.

Independent oracles: the printed equations (5.8)-(5.10), (5.16)-(5.18), (5.20)-(5.25), (5.44), (5.50),
(5.91)-(5.92), (5.103)-(5.105), (5.107)-(5.110) written out in this file, a bracketing root finder for (5.90), and
the characteristic polynomials of the linearizations.

Thesis typos and false statements established here (each test says which):

* (5.103): the sign of the Delta m term is wrong. With ``f`` as printed in (5.105) the reduced subsystem is
  ``dVbar/dt_n = -tau_s/(m3 V_e) [m0 g sin(gammabar + gamma_e) + K_De V_e^2 (1 + Vbar)^2 - (Delta m cos(alpha_e)
  / m1) f]`` (minus, not plus). (5.104), (5.105) and (5.108) are right as printed, and (5.108) is in fact only
  consistent with the corrected (5.103).
* (5.92): ``sin(alphabar + 2 alpha_e) cos(alphabar)`` must read ``sin(alphabar) cos(alphabar + 2 alpha_e)``
  (``= (sin 2alpha - sin 2alpha_e)/2``); as printed the boundary layer would not vanish at ``q = 0``. The gradient
  (5.94) of (5.93) already uses the correct difference ``sin 2(alphabar + alpha_e) - sin 2 alpha_e``.
* §5.1: "the sum of the reciprocals of the eigenvalues of the linearization of (5.4)-(5.5) is exactly 3 tau_s" is
  false: the trace gives ``lambda1 + lambda2 = -3/tau_s`` exactly, while ``1/lambda1 + 1/lambda2 =
  -3 tau_s / (2 (1 + (K_Le/K_De)^2))`` (negative; -0.971 tau_s for the §5.3.1 sphere).
* (5.109): the factor ``2 Delta m |m0 g|`` must be ``2 |Delta m m0 g|`` (as in (5.110)); for ``Delta m < 0``
  the printed right side is negative while ``R`` is not.
* §5.3.1 prints ``V_e = 1.684`` m/s; (5.8) with the printed parameters gives 1.648 m/s (digit transposition:
  tau_s = m1/(K_De V_e) = 8.361 s, also printed, needs 1.648).
* §5.1.3's boundary-layer eigenvalues -84.582 and -363.796 are not reproduced: the boundary layer (5.30) on the
  t_n scale has characteristic polynomial ``s^2 + s/eps2 + 1/(eps1 eps2)`` and, with the printed eps1 = 4.784e-3,
  eps2 = 4.403e-4, roots -232.9 and -2038.0 (their sum must be -1/eps2 = -2271; the printed pair sums to -448).
  Tested here: the roots of that polynomial; the printed pair is only reported.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from glidectl import (
    CompositeCertificate,
    GlidectlError,
    ModelError,
    SingularPerturbation,
    SlowModel,
    Vehicle,
    allowable_delta_m_ratio,
    load_vehicle,
    singular_perturbation,
    unequal_mass_check,
)
from glidectl.derivatives import jacobians

SPHERE = load_vehicle("sphere_ch5")
VARIANTS = {
    "baseline": SPHERE,
    "K_M=-100": load_vehicle("sphere_ch5", K_M=-100.0),
    "K_M=-100,J2=0.01": load_vehicle("sphere_ch5", K_M=-100.0, J2=0.01),
    "J2=0.01": load_vehicle("sphere_ch5", J2=0.01),
    "K_L0,K_M0": load_vehicle("sphere_ch5", K_L0=0.7, K_M0=-0.5, m0=0.4),  # every coefficient nonzero
}
UNEQUAL = {"m3=31": load_vehicle("sphere_ch5", m3=31.0), "m3=25": load_vehicle("sphere_ch5", m3=25.0),
           "m3=33,K_M=-100": load_vehicle("sphere_ch5", m3=33.0, K_M=-100.0)}
SP = {k: singular_perturbation(v) for k, v in {**VARIANTS, **UNEQUAL}.items()}

FAST = settings(max_examples=50, deadline=None)


def _u(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


# nondimensional points inside a generous B_p x B_q
p_points = st.tuples(_u(-0.8, 1.0), _u(-math.pi, math.pi)).map(np.array)
q_points = st.tuples(_u(-0.6, 0.6), _u(-2.0, 2.0)).map(np.array)


def _srt(lam: np.ndarray) -> np.ndarray:
    """Eigenvalues in a rounding-proof order (by real part, then imaginary part, both rounded)."""
    lam = np.asarray(lam, dtype=complex)
    return lam[np.lexsort((np.round(lam.imag, 8), np.round(lam.real, 8)))]


# ------------------------------------------------------------------------------- independent equilibrium
def equilibrium(veh: Vehicle) -> dict[str, float]:
    """(5.8)-(5.10)/(5.90), (5.16)-(5.18) computed here from the printed formulas (``m_i`` effective masses)."""
    m1, m3 = veh.m1 + veh.mbar, veh.m3 + veh.mbar
    dm = m3 - m1
    if dm == 0:
        a = -veh.K_M0 / veh.K_M                                                              # (5.10)
    else:
        a = brentq(lambda x: veh.K_M0 + veh.K_M * x + dm * math.sin(x) * math.cos(x),      # (5.90)
                   -math.pi / 4, math.pi / 4, xtol=1e-15, rtol=1e-15)
    KDe, KLe = veh.K_D0 + veh.K_D * a * a, veh.K_L0 + veh.K_L * a
    Ve = math.sqrt(abs(veh.m0) * veh.g / math.sqrt(KDe**2 + KLe**2))                         # (5.8)
    ge = math.atan2(-KDe / veh.m0, KLe / veh.m0)                                              # (5.9)
    tau = m3 / (KDe * Ve)                                                                     # (5.18), m1 = m3
    eps1 = (veh.K_q / veh.K_M) / tau                                                          # (5.16)
    eps2 = -(veh.J2 / (veh.K_q * Ve**2)) / tau                                                # (5.17)
    return {"alpha_e": a, "K_De": KDe, "K_Le": KLe, "V_e": Ve, "gamma_e": ge, "tau_s": tau, "eps1": eps1,
            "eps2": eps2, "m1": m1, "m3": m3, "dm": dm}


@pytest.mark.parametrize("name", sorted(SP))
def test_equilibrium_and_small_parameters_match_printed_formulas(name: str) -> None:
    sp, e = SP[name], equilibrium({**VARIANTS, **UNEQUAL}[name])
    for attr, key in (("alpha", "alpha_e"), ("K_De", "K_De"), ("K_Le", "K_Le"), ("speed", "V_e"), ("gamma", "gamma_e"),
                      ("tau_s", "tau_s"), ("eps1", "eps1"), ("eps2", "eps2")):
        assert getattr(sp, attr) == pytest.approx(e[key], rel=1e-13, abs=1e-15), key
    assert sp.mu == max(sp.eps1, sp.eps2)                                                     # (5.26)
    assert sp.r1 == pytest.approx(sp.mu / sp.eps1, rel=1e-15)                                 # (5.27)
    assert sp.r2 == pytest.approx(sp.mu / sp.eps2, rel=1e-15)
    assert min(sp.r1, sp.r2) == pytest.approx(1.0, rel=1e-15)
    # the steady glide is an equilibrium of the dimensional model
    np.testing.assert_allclose(sp.model.rhs(sp.equilibrium), 0.0, atol=1e-12)
    # equilibrium relations used throughout §5.1.2: m0 g sin(gamma_e) = -K_De V_e^2, m0 g cos(gamma_e) = K_Le V_e^2
    m0g = sp.model.vehicle.m0 * sp.model.vehicle.g
    assert m0g * math.sin(sp.gamma) == pytest.approx(-sp.K_De * sp.speed**2, rel=1e-13)
    assert m0g * math.cos(sp.gamma) == pytest.approx(sp.K_Le * sp.speed**2, rel=1e-13)


def test_section_5_3_1_numbers() -> None:
    """§5.1.3/§5.3.1 numbers for the sphere (g = 9.8 m/s^2 as in the vehicle file), to the printed digits."""
    sp = SP["baseline"]
    assert round(sp.tau_s, 3) == 8.361
    assert round(sp.eps1 * 1e3, 3) == 4.784
    assert round(sp.eps2 * 1e4, 3) == 4.403
    assert round(sp.mu * 1e3, 3) == 4.784
    assert round(math.degrees(sp.gamma), 3) == -53.566
    # the thesis prints V_e = 1.684 m/s: a digit transposition of the 1.648 m/s that (5.8) gives (and that its own
    # tau_s = 8.361 s requires: 28 / (2.032 * 1.684) = 8.183 s)
    assert round(sp.speed, 3) == 1.648
    assert round(sp.model.masses[0] / (sp.K_De * 1.684), 3) != 8.361
    lam = sp.reduced_eigenvalues
    assert lam.shape == (2,)
    np.testing.assert_array_equal(np.round(lam.real, 3), [-1.5, -1.5])
    np.testing.assert_array_equal(np.round(np.sort(lam.imag), 3), [-0.916, 0.916])


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_reduced_eigenvalues_closed_form(name: str) -> None:
    """Linearizing (5.20)-(5.21) at q = 0 gives [[-2, -c], [2c, -1]], c = K_Le/K_De (using the equilibrium
    relations), so lambda = -3/2 +- sqrt(1/4 - 2 c^2) for every equal-mass glider."""
    sp = SP[name]
    c = sp.K_Le / sp.K_De
    disc = complex(0.25 - 2 * c * c) ** 0.5
    ref = np.array([-1.5 - disc, -1.5 + disc])
    got = sp.reduced_eigenvalues
    np.testing.assert_allclose(_srt(got), _srt(ref), rtol=0, atol=1e-12)
    A, _ = jacobians(lambda p, u: sp.reduced_rhs(p), np.zeros(2), np.zeros(0))
    np.testing.assert_allclose(A, [[-2.0, -c], [2 * c, -1.0]], rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_sum_of_reciprocal_eigenvalues_is_not_3_tau_s(name: str) -> None:
    """§5.1 claims that the reciprocals of the eigenvalues of the dimensional linearization of (5.4)-(5.5) (at
    alpha_e, Omega2 = 0) sum to exactly 3 tau_s. What is exactly true is lambda1 + lambda2 = -3/tau_s (trace); the
    sum of reciprocals is trace/det = -3 tau_s / (2 (1 + c^2)), c = K_Le/K_De, which is negative and never 3 tau_s."""
    sp = SP[name]
    slow = sp.slow_model()
    A, _ = jacobians(slow.rhs, np.array([sp.speed, sp.gamma]), np.zeros(0))
    lam = np.linalg.eigvals(A)
    np.testing.assert_allclose(_srt(lam * sp.tau_s), _srt(sp.reduced_eigenvalues), rtol=1e-11, atol=1e-12)
    assert np.sum(lam).real == pytest.approx(-3.0 / sp.tau_s, rel=1e-12)
    assert abs(np.sum(lam).imag) < 1e-12
    recip = np.sum(1.0 / lam)
    c = sp.K_Le / sp.K_De
    assert recip.real == pytest.approx(-3.0 * sp.tau_s / (2 * (1 + c * c)), rel=1e-12)
    assert abs(recip.imag) < 1e-12 * sp.tau_s
    assert recip.real < 0 and abs(recip.real - 3 * sp.tau_s) > sp.tau_s
    if name == "baseline":
        assert round(recip.real / sp.tau_s, 3) == -0.971


def test_boundary_layer_eigenvalues_are_roots_of_characteristic_polynomial() -> None:
    """(5.30) rescaled to t_n for m1 = m3 at p = 0: d(alphabar)/dt_n = Omegabar/eps1,
    d(Omegabar)/dt_n = -(alphabar + Omegabar)/eps2, i.e. s^2 + s/eps2 + 1/(eps1 eps2) = 0."""
    for name in VARIANTS:
        sp = SP[name]
        roots = np.roots([1.0, 1.0 / sp.eps2, 1.0 / (sp.eps1 * sp.eps2)])
        got = sp.boundary_layer_eigenvalues
        np.testing.assert_allclose(np.sort(got.real), np.sort(roots.real), rtol=1e-11)
        assert np.all(np.abs(got.imag) < 1e-9 * np.abs(got.real))
    # baseline: -232.915 and -2038.037 (the thesis prints -84.582 and -363.796, which sum to -448.4, not -1/eps2)
    bl = SP["baseline"].boundary_layer_eigenvalues.real
    np.testing.assert_allclose(np.sort(bl), [-2038.037, -232.915], atol=1e-3)
    assert np.sum(bl) == pytest.approx(-1 / SP["baseline"].eps2, rel=1e-12)


def test_time_scale_separation() -> None:
    """The full linearization has two slow (|lambda| < 5) and two fast (|lambda| > 100 = O(1/mu)) eigenvalues,
    all stable, for every §5.3.1 variant."""
    for name in VARIANTS:
        lam = np.sort(np.abs(SP[name].full_eigenvalues))
        assert np.all(SP[name].full_eigenvalues.real < 0)
        assert lam[1] < 5 and lam[2] > 100, (name, lam)


def test_negative_buoyancy_equilibrium_is_the_mirror_glide() -> None:
    """m0 < 0 (buoyant): same speed, gamma_e + pi (the glide of the heavy vehicle, reversed; alpha_e is fixed by
    the moment balance, so the rising steady glide is the inverted one); it is an equilibrium of the model."""
    up = singular_perturbation(load_vehicle("sphere_ch5", m0=-0.7))
    down = SP["baseline"]
    assert up.speed == pytest.approx(down.speed, rel=1e-14)
    assert up.gamma == pytest.approx(down.gamma + math.pi, rel=1e-14)
    np.testing.assert_allclose(up.model.rhs(up.equilibrium), 0.0, atol=1e-12)


# ------------------------------------------------------------------------------------------ coordinates
@pytest.mark.parametrize("name", ["baseline", "m3=31"])
@given(V=_u(0.05, 4.0), gam=_u(-4.0, 4.0), al=_u(-1.0, 1.0), Om=_u(-5.0, 5.0))
@FAST
def test_nondimensional_round_trip(name: str, V: float, gam: float, al: float, Om: float) -> None:
    sp = SP[name]
    x = np.array([V, gam, al, Om])
    z = sp.to_nondimensional(x)
    # (5.12)-(5.15) by hand
    v = sp.model.vehicle
    np.testing.assert_allclose(z, [(V - sp.speed) / sp.speed, gam - sp.gamma, al - sp.alpha, v.K_q / v.K_M * Om],
                               rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(sp.to_dimensional(z), x, rtol=1e-13, atol=1e-13)
    # batches too
    X = np.stack([x, 2 * x])
    np.testing.assert_allclose(sp.to_dimensional(sp.to_nondimensional(X)), X, rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("name", sorted(SP))
def test_f_and_g_vanish_at_origin(name: str) -> None:
    sp = SP[name]
    z = np.zeros(2)
    np.testing.assert_allclose(sp.f(z, z), 0.0, atol=1e-13)
    np.testing.assert_allclose(sp.g(z, z), 0.0, atol=1e-13)
    np.testing.assert_allclose(sp.g(z, z, eps=False), 0.0, atol=1e-13)
    np.testing.assert_allclose(sp.full_rhs_nondimensional(np.zeros(4)), 0.0, atol=1e-10)
    np.testing.assert_allclose(sp.reduced_rhs(z), 0.0, atol=1e-13)
    np.testing.assert_allclose(sp.boundary_layer_rhs(z, z), 0.0, atol=1e-13)


def printed_5_20_to_5_25(sp: SingularPerturbation, p: np.ndarray,
                         q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """f, g(eps), g(0) of (5.20)-(5.25) / (5.28)-(5.29) exactly as printed, from the independent equilibrium."""
    veh = sp.model.vehicle
    e = equilibrium(veh)
    Vb, gb = p
    ab, Ob = q
    m0g = veh.m0 * veh.g
    D = (veh.K_D0 + veh.K_D * (ab + e["alpha_e"]) ** 2) * e["V_e"] ** 2 * (1 + Vb) ** 2            # (5.24)
    L = (veh.K_L0 + veh.K_L * (ab + e["alpha_e"])) * e["V_e"] ** 2 * (1 + Vb) ** 2                 # (5.25)
    f1 = -(m0g * math.sin(gb + e["gamma_e"]) + D) / (e["K_De"] * e["V_e"] ** 2)                    # (5.20)
    E2 = (-m0g * math.cos(gb + e["gamma_e"]) + L) / (e["K_De"] * e["V_e"] ** 2 * (1 + Vb))         # (5.21)
    g1 = Ob - e["eps1"] * E2                                                                       # (5.22)
    g2 = -(ab + Ob) * (1 + Vb) ** 2                                                                # (5.23)
    return np.array([f1, E2]), np.array([g1, g2]), np.array([Ob, g2])


@pytest.mark.parametrize("name", sorted(VARIANTS))
@given(p=p_points, q=q_points)
@FAST
def test_f_g_equal_printed_5_20_to_5_25(name: str, p: np.ndarray, q: np.ndarray) -> None:
    sp = SP[name]
    f_ref, g_ref, g0_ref = printed_5_20_to_5_25(sp, p, q)
    scale = 10.0 * (1 + abs(p[0])) ** 2 + np.max(np.abs(q))  # size of the terms summed (all O(1) coefficients)
    np.testing.assert_allclose(sp.f(p, q), f_ref, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(sp.g(p, q), g_ref, rtol=0, atol=1e-12 * scale)
    # g(p, q, 0) = (Omegabar2, -(alphabar + Omegabar2)(1 + Vbar)^2)
    np.testing.assert_allclose(sp.g(p, q, eps=False), g0_ref, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(sp.g(p, q, eps=False),
                               [q[1], -(q[0] + q[1]) * (1 + p[0]) ** 2], rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("name", ["baseline", "K_M=-100", "m3=31"])
@given(p=p_points, q=q_points)
@FAST
def test_compact_form_is_the_dimensional_model_in_new_variables(name: str, p: np.ndarray, q: np.ndarray) -> None:
    """(5.28)-(5.29): dz/dt_n = tau_s * d/dt (affine map (5.12)-(5.15)) of the dimensional vector field, and
    mu dq/dt_n = A g (so A g / mu = g / eps, component-wise)."""
    sp = SP[name]
    z = np.concatenate([p, q])
    x = sp.to_dimensional(z)
    d = sp.model.rhs(x)
    v = sp.model.vehicle
    ref = sp.tau_s * np.array([d[0] / sp.speed, d[1], d[2], v.K_q / v.K_M * d[3]])
    got = sp.full_rhs_nondimensional(z)
    scale = np.max(np.abs(ref)) + 1.0
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(got[2:], sp.g(p, q) / np.array([sp.eps1, sp.eps2]), rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(got[:2], sp.f(p, q), rtol=0, atol=1e-12 * scale)
    # one evaluation of the right-hand side serves f and g: exactly the values of the two separate calls
    sc = sp.scaling
    assert np.array_equal(got, np.concatenate([sc.f(p, q), sc.g(p, q) * np.array([sc.r1, sc.r2]) / sc.mu]))
    assert sc.glider is sc.glider       # the dimensional model is built once per scaling
    # g1 = Omegabar2 - eps1 f2 (5.22) holds for unequal masses too, because alpha' = Omega2 - gamma' exactly
    assert sp.g(p, q)[0] == pytest.approx(q[1] - sp.eps1 * sp.f(p, q)[1], abs=1e-12 * scale)


def test_slow_model_is_the_reduced_subsystem_in_dimensional_form() -> None:
    sp = SP["K_M=-100"]
    slow = SlowModel(sp.model.vehicle, sp.alpha)   # plain numbers; SingularPerturbation.slow_model() builds the same
    assert slow == sp.slow_model()
    assert slow.state_names == ("V", "gamma") and slow.input_names == ()
    assert slow.vehicle is sp.model.vehicle
    rng = np.random.default_rng(11)
    P = np.column_stack([rng.uniform(-0.6, 0.8, 50), rng.uniform(-3, 3, 50)])
    X = np.column_stack([sp.speed * (1 + P[:, 0]), P[:, 1] + sp.gamma])
    d = slow.rhs(X)
    np.testing.assert_allclose(sp.reduced_rhs(P), sp.tau_s * np.column_stack([d[:, 0] / sp.speed, d[:, 1]]),
                               rtol=1e-12, atol=1e-12)
    # equal to the full model at alpha = alpha_e, Omega2 = 0
    full = sp.model.rhs(np.column_stack([X, np.full(50, sp.alpha), np.zeros(50)]))
    np.testing.assert_array_equal(d, full[:, :2])


# ------------------------------------------------------------------------------------ 5. Phi along the reduced
@pytest.mark.parametrize("name", sorted(VARIANTS))
@given(p=st.tuples(_u(-0.95, 2.0), _u(-math.pi, math.pi)).map(np.array))
@FAST
def test_dPhi_dtn_equals_minus_psi_squared(name: str, p: np.ndarray) -> None:
    """(5.44): along the reduced subsystem (5.33), dPhi/dt_n = -psi^2 exactly (equal masses), psi of (5.50)."""
    sp = SP[name]
    Vb, gb = p
    grad = np.array([-math.cos(gb) + (1 + Vb) ** 2, (1 + Vb) * math.sin(gb)])  # of (5.35)
    dPhi = grad @ sp.reduced_rhs(p)
    psi2 = (Vb * Vb + 2 * Vb) ** 2 + 4 * (1 + Vb) ** 2 * math.sin(gb / 2) ** 2  # (5.50)
    assert CompositeCertificate.psi(p) ** 2 == pytest.approx(psi2, rel=1e-13, abs=1e-300)
    assert dPhi == pytest.approx(-psi2, rel=0, abs=1e-12 * (1 + (1 + Vb) ** 4))
    # and Phi is positive definite: (5.35) > 0 away from p = 0
    Phi = CompositeCertificate.Phi(p)
    assert Phi == pytest.approx(2 / 3 - (1 + Vb) * math.cos(gb) + (1 + Vb) ** 3 / 3, rel=1e-14, abs=1e-15)
    if psi2 > 1e-12:
        assert Phi > 0


# --------------------------------------------------------------------------------- §5.4, unequal added masses
def _f_5_105(sp: SingularPerturbation, p: np.ndarray) -> float:
    veh = sp.model.vehicle
    th_e = sp.gamma + sp.alpha
    return veh.m0 * veh.g * (math.sin(th_e) * (1 + p[0]) ** 2 - math.sin(p[1] + th_e))


def reduced_5_103_5_104(sp: SingularPerturbation, p: np.ndarray, printed_sign: bool = False) -> np.ndarray:
    """(5.103)-(5.104) with f of (5.105). ``printed_sign=True``: '+ Delta m cos(alpha_e) f / m1' in (5.103) as
    printed; otherwise the corrected '-'."""
    veh = sp.model.vehicle
    m1, m3 = sp.model.masses
    dm = m3 - m1
    Vb, gb = p
    f = _f_5_105(sp, p)
    m0g = veh.m0 * veh.g
    s = 1.0 if printed_sign else -1.0
    dV = -sp.tau_s / (m3 * sp.speed) * (m0g * math.sin(gb + sp.gamma) + sp.K_De * sp.speed**2 * (1 + Vb) ** 2
                                      + s * dm * math.cos(sp.alpha) / m1 * f)
    dg = sp.tau_s / (m3 * sp.speed * (1 + Vb)) * (sp.K_Le * sp.speed**2 * (1 + Vb) ** 2
                                                 - m0g * math.cos(gb + sp.gamma)
                                                 + dm * math.sin(sp.alpha) / m1 * f)
    return np.array([dV, dg])


@pytest.mark.parametrize("name", sorted(UNEQUAL))
@given(p=p_points)
@FAST
def test_unequal_reduced_subsystem_matches_corrected_5_103_5_104(name: str, p: np.ndarray) -> None:
    """The reduced subsystem for m1 != m3 equals (5.103)-(5.105) with the sign of the Delta m term of (5.103)
    flipped (thesis typo: '+ Delta m cos(alpha_e) f / m1' must be '- ...'); (5.104) is right as printed."""
    sp = SP[name]
    got = sp.reduced_rhs(p)
    ref = reduced_5_103_5_104(sp, p)
    scale = 10 * (1 + abs(p[0])) ** 2 / (1 + p[0])
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * scale)
    # the printed sign is measurably wrong away from p = 0 (where f != 0)
    if abs(_f_5_105(sp, p)) > 1e-3:
        printed = reduced_5_103_5_104(sp, p, printed_sign=True)
        assert abs(printed[0] - got[0]) > 1e-6
    # tau_s = m3 / (K_De V_e) is the choice that makes (5.103)-(5.107) hold as printed
    assert sp.tau_s == pytest.approx(sp.model.masses[1] / (sp.K_De * sp.speed), rel=1e-15)


@pytest.mark.parametrize("name", sorted(UNEQUAL))
@given(p=p_points)
@FAST
def test_unequal_dPhi_is_minus_psi_squared_plus_R(name: str, p: np.ndarray) -> None:
    """(5.107)-(5.108) as printed hold along the model's reduced subsystem (consistent only with the corrected
    (5.103))."""
    sp = SP[name]
    m1, m3 = sp.model.masses
    Vb, gb = p
    grad = np.array([-math.cos(gb) + (1 + Vb) ** 2, (1 + Vb) * math.sin(gb)])
    dPhi = grad @ sp.reduced_rhs(p)
    psi2 = (Vb * Vb + 2 * Vb) ** 2 + 4 * (1 + Vb) ** 2 * math.sin(gb / 2) ** 2
    R = ((m3 - m1) / (m1 * sp.K_De * sp.speed**2)
         * (2 * math.sin((gb + 2 * sp.alpha) / 2) * math.sin(gb / 2) + math.cos(sp.alpha) * (Vb * Vb + 2 * Vb))
         * _f_5_105(sp, p))                                                                    # (5.108)
    assert dPhi == pytest.approx(-psi2 + R, rel=0, abs=1e-12 * (1 + (1 + Vb) ** 4))


@pytest.mark.parametrize("name", sorted(UNEQUAL))
@given(p=p_points, q=q_points)
@FAST
def test_unequal_boundary_layer_matches_corrected_5_91_5_92(name: str, p: np.ndarray, q: np.ndarray) -> None:
    """(5.91)-(5.92) with the typo fixed: dOmegabar/dtau = -r2 {alphabar + (Delta m/K_M) sin(alphabar)
    cos(alphabar + 2 alpha_e) + Omegabar} (1 + Vbar)^2. The printed sin(alphabar + 2 alpha_e) cos(alphabar) does
    not vanish at q = 0."""
    sp = SP[name]
    veh = sp.model.vehicle
    dm = sp.model.delta_m
    ab, Ob = q
    a = (1 + p[0]) ** 2
    ref = np.array([sp.r1 * Ob,                                                                 # (5.91)
                    -sp.r2 * (ab + dm / veh.K_M * math.sin(ab) * math.cos(ab + 2 * sp.alpha) + Ob) * a])
    got = sp.boundary_layer_rhs(p, q)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * sp.r2 * (1 + a) * (1 + np.max(np.abs(q))))
    printed_at_0 = -sp.r2 * (dm / veh.K_M * math.sin(2 * sp.alpha)) * a
    assert abs(printed_at_0) > 1e-4 and np.max(np.abs(sp.boundary_layer_rhs(p, np.zeros(2)))) < 1e-12


# ----------------------------------------------------------------------------------------- 7. (5.109)-(5.110)
def _kappa_by_hand(veh: Vehicle) -> float:
    e = equilibrium(veh)
    return abs(veh.m0) * veh.g / (e["K_De"] * e["V_e"] ** 2)


@pytest.mark.parametrize("ratio", [-0.1, 0.02, 0.05, 0.12, 0.3])
def test_unequal_mass_bound_5_109_holds_and_5_110_by_hand(ratio: float) -> None:
    veh = load_vehicle("sphere_ch5", m3=28.0 * (1 + ratio))
    Vbar = (-0.4, 0.4)
    chk = unequal_mass_check(veh, Vbar=Vbar, n=20_000, seed=1)
    kappa = _kappa_by_hand(veh)
    assert chk.delta_m == pytest.approx(28.0 * ratio, rel=1e-12)
    assert chk.kappa == pytest.approx(kappa, rel=1e-12)
    lhs = 2 * abs(28.0 * ratio * veh.m0 * veh.g) / (28.0 * equilibrium(veh)["K_De"] * equilibrium(veh)["V_e"] ** 2
                                                    * (1 + Vbar[0]) ** 2)                       # (5.110)
    assert chk.condition_lhs == pytest.approx(lhs, rel=1e-12)
    assert chk.certified == (lhs < 1)
    assert 1.0 <= chk.bound_margin < math.inf    # (5.109) holds on the samples
    # consistency with Fig 5.3's trade-off curve: lhs * allowable ratio = |Delta m| / m1 exactly
    assert chk.condition_lhs * allowable_delta_m_ratio(chk.kappa, Vbar[0]) == pytest.approx(abs(ratio), rel=1e-12)
    # when (5.110) holds, Phi decreases along the reduced subsystem on the samples
    if chk.certified:
        assert chk.max_dPhi < 0
        assert chk.max_dPhi <= -(1 - chk.condition_lhs) + 1e-12
        assert chk.passed and chk.failing() == {}
    else:
        assert not chk.passed and "(5.110) kappa_dm < 1" in chk.failing()


def test_5_109_needs_absolute_delta_m() -> None:
    """(5.109) prints the factor as 2 Delta m |m0 g| / (...) (signed); for Delta m < 0 that right side is negative
    while R takes positive values, so the bound needs |Delta m| (as (5.110) has). The code uses |Delta m|."""
    veh = load_vehicle("sphere_ch5", m3=25.2)  # Delta m / m1 = -0.1
    sp = singular_perturbation(veh)
    m1, m3 = sp.model.masses
    rng = np.random.default_rng(4)
    P = np.column_stack([rng.uniform(-0.4, 0.4, 20_000), rng.uniform(-math.pi, math.pi, 20_000)])
    Vb, gb = P[:, 0], P[:, 1]
    dPhi = np.sum(np.column_stack([-np.cos(gb) + (1 + Vb) ** 2, (1 + Vb) * np.sin(gb)]) * sp.reduced_rhs(P), axis=1)
    psi2 = (Vb * Vb + 2 * Vb) ** 2 + 4 * (1 + Vb) ** 2 * np.sin(gb / 2) ** 2
    R = dPhi + psi2
    k = 2 * (m3 - m1) * abs(veh.m0 * veh.g) / (m1 * sp.K_De * sp.speed**2 * (1 - 0.4) ** 2)
    assert k < 0 and np.max(R) > 0                        # the signed bound R <= k psi^2 fails ...
    assert np.all(R <= abs(k) * psi2 + 1e-12)             # ... the |Delta m| bound holds
    assert unequal_mass_check(veh, n=20_000, seed=4).bound_margin >= 1


def test_equal_masses_have_no_remainder() -> None:
    """Delta m = 0: R = 0 (dPhi/dt_n = -psi^2 exactly) and kappa = 1.243 (the value quoted for Fig 5.3)."""
    chk = unequal_mass_check(SPHERE, n=5000)
    assert chk.delta_m == 0.0 and chk.condition_lhs == 0.0 and chk.certified
    assert chk.bound_margin > 1e12                  # 1 / max |R| with lhs = 0
    assert chk.margins["(5.110) kappa_dm < 1"] == math.inf and chk.passed
    assert chk.max_dPhi == pytest.approx(-1.0, abs=1e-10)
    assert round(chk.kappa, 3) == 1.243


def test_allowable_delta_m_ratio() -> None:
    kappa = 1.243
    assert allowable_delta_m_ratio(kappa, 0.0) == pytest.approx(1 / (2 * kappa), rel=1e-15)
    V = np.linspace(-0.9, 0.0, 10)
    got = allowable_delta_m_ratio(kappa, V)
    np.testing.assert_allclose(got, (1 + V) ** 2 / (2 * kappa), rtol=1e-15)
    assert np.all(np.diff(got) > 0)  # larger domains (lower Vbar_min) allow less Delta m


def test_unequal_mass_check_bad_domain() -> None:
    for Vbar in [(0.1, 0.4), (-1.0, 0.4), (-0.4, -0.1)]:
        with pytest.raises(GlidectlError):
            unequal_mass_check(UNEQUAL["m3=31"], Vbar=Vbar, n=100)


# ------------------------------------------------------------------------------------------------ bad inputs
def test_positive_pitch_damping_coefficient_is_refused() -> None:
    with pytest.raises(ModelError, match="K_q"):
        singular_perturbation(load_vehicle("sphere_ch5", K_q=2.0))


def test_positive_pitch_stiffness_is_refused() -> None:
    with pytest.raises(ModelError, match="K_M < 0"):
        singular_perturbation(load_vehicle("sphere_ch5", K_M=50.0))


def test_no_drag_is_refused() -> None:
    with pytest.raises(ModelError, match="drag"):
        singular_perturbation(load_vehicle("sphere_ch5", K_D0=0.0, K_D=0.0))


def test_m0_zero_is_refused_by_the_model_not_the_loader() -> None:
    veh = load_vehicle("sphere_ch5", m0=0.0)  # the loader accepts m0 = 0 (an 'any'-signed parameter)
    with pytest.raises(ModelError, match="m0 = 0"):
        singular_perturbation(veh)


def test_no_pitch_damping_is_refused() -> None:
    """rogue has K_q = 0: eps1 = 0 and eps2 = J2/(0 ...): a ModelError, not a ZeroDivisionError from (5.17)."""
    with pytest.raises(ModelError, match="K_q"):
        singular_perturbation(load_vehicle("rogue", m0=0.3))


# ---------------------------------------------------------------------------------- argument checks (issue 15)
def test_vehicle_argument_is_checked() -> None:
    import glidectl as gc

    with pytest.raises(gc.ArgumentTypeError):
        singular_perturbation("sphere_ch5")  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentTypeError):
        singular_perturbation(None)  # type: ignore[arg-type]
    with pytest.raises(ModelError):
        singular_perturbation(load_vehicle("dc8_ctol"))


def test_underflowing_glide_is_refused() -> None:
    """m0 = 1e-300 kg gives V_e ~ 2e-150 m/s: the complex-step derivatives underflow and the eigenvalues came out as
    exact zeros. The implausible glide speed is refused."""
    with pytest.raises(ModelError, match="plausible range"):
        singular_perturbation(load_vehicle("sphere_ch5", m0=1e-300))
    with pytest.raises(ModelError):
        singular_perturbation(load_vehicle("sphere_ch5", K_q=-1e-300))  # eps overflows


def test_equal_masses_margin_is_not_reported_holding_when_R_is_positive() -> None:
    """With Delta m = 0, (5.109) reads R <= 0. The margin used to be 1 / max|R| (huge, 'holds') whatever the sign
    of R. Now it is inf only when R <= 0 (within rounding of its terms) on every sample, else 0."""
    r = unequal_mass_check(SPHERE, n=5000)
    assert r.delta_m == 0.0 and r.condition_lhs == 0.0
    assert r.bound_margin == math.inf and r.passed  # R = 0 up to rounding for equal masses


def test_equal_masses_with_positive_R_fail(monkeypatch: pytest.MonkeyPatch) -> None:
    """A reduced field that makes R > 0 (the drag halved: dPhi = -psi^2/2 + ...) must fail (5.109) at Delta m = 0."""
    sp = singular_perturbation(SPHERE)
    monkeypatch.setattr(SingularPerturbation, "reduced_rhs", lambda self, p: 0.5 * sp.scaling.reduced_rhs(p))
    r = unequal_mass_check(SPHERE, n=2000)
    assert r.bound_margin == 0.0 and not r.passed and "(5.109) R <= kappa_dm psi^2" in r.failing()


@pytest.mark.parametrize(("kw", "exc"), [({"n": 0}, "ArgumentError"), ({"n": 2.5}, "ArgumentTypeError"),
                                         ({"seed": "a"}, "ArgumentTypeError"), ({"Vbar": 0.4}, "ArgumentTypeError"),
                                         ({"Vbar": (0.4, -0.4)}, "ArgumentError"),
                                         ({"gammabar": (-4.0, 1.0)}, "ArgumentError")])
def test_unequal_mass_check_bad_arguments(kw: dict, exc: str) -> None:
    import glidectl as gc

    with pytest.raises(getattr(gc, exc)):
        unequal_mass_check(SPHERE, **kw)


@pytest.mark.parametrize(("args", "exc"), [((math.nan, -0.4), "ArgumentError"), ((-1.0, -0.4), "ArgumentError"),
                                           ((0.0, -0.4), "ArgumentError"), ((0.5, "-0.4"), "ArgumentTypeError"),
                                           ((0.5, -2.0), "ArgumentError"), ((0.5, [-0.4, 0.3]), "ArgumentError")])
def test_allowable_delta_m_ratio_bad_arguments(args: tuple, exc: str) -> None:
    import glidectl as gc

    with pytest.raises(getattr(gc, exc)):
        allowable_delta_m_ratio(*args)
