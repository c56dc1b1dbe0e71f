"""Reduced longitudinal glider of chapter 5, :class:`glidectl.ReducedLongitudinalGlider`, state
(V, gamma, alpha, Omega2).

What is checked, and against what independent oracle:

* the foundation model :class:`glidectl.AccelerationControlledGlider` with ``w = 0`` and ``r_P = rdot_P = 0``,
  converted by (5.1)-(5.3), gives the same vector field (``m1 != m3`` and ``m1 = m3``, several sign cases);
* for ``m1 = m3`` the right-hand side equals the printed (5.4)-(5.7) (written out below), and for ``m1 != m3`` the
  printed (5.86)-(5.89) (also written out below). Both print correctly once ``m_i`` is read as the effective mass
  ``M_i = m_i + mbar`` (the moving mass rides with the hull): no typo was found in (5.4)-(5.7) or (5.86)-(5.89);
* the energy balance ``d/dt (T - m0 g z) = -D V + Omega2 M_DL2`` (exact physics, any masses);
* without drag, at ``alpha = alpha_e`` and ``Omega2 = 0``, the (V, gamma) equations are the phugoid model
  (4.3)-(4.4) in ``(xdot, zdot) = (V cos gamma, -V sin gamma)`` coordinates (printed formulas and
  :class:`glidectl.models.phugoid.PhugoidModel`);
* the equilibrium angle of attack solves (5.90) (checked with an independent bracketing root finder), exact
  complex-step Jacobians agree with central differences, batches equal point-wise evaluation, bad vehicles raise.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

import glidectl
from glidectl import (
    AccelerationControlledGlider,
    GlidectlError,
    ModelError,
    ReducedLongitudinalGlider,
    load_vehicle,
)
from glidectl.derivatives import central_difference_jacobians, jacobians

# --------------------------------------------------------------------------------------------------- vehicles
ROGUE = load_vehicle("rogue", m0=0.3)                                    # m1 = 13.22 != m3 = 25.22, mbar = 2
ROGUE_FULL = load_vehicle("rogue", m0=0.3, K_q=-1.5, K_L0=20.0, K_M0=0.5)  # every term of (2.9)-(2.13) on
ROGUE_RISING = load_vehicle("rogue", m0=-0.25, K_q=-1.5, K_M0=-0.3)      # buoyant (m0 < 0)
ROGUE_EQ = load_vehicle("rogue", m0=0.3, m3=13.22, K_q=-1.5, K_L0=20.0, K_M0=0.5)  # m1 = m3, mbar = 2
SPHERE = load_vehicle("sphere_ch5")                                      # m1 = m3 = 28, mbar = 0
SPHERE_UNEQ = load_vehicle("sphere_ch5", m3=31.0)

UNEQUAL = {"rogue": ROGUE, "rogue_full": ROGUE_FULL, "rogue_rising": ROGUE_RISING, "sphere_m3_31": SPHERE_UNEQ}
EQUAL = {"sphere": SPHERE, "sphere_KM100": load_vehicle("sphere_ch5", K_M=-100.0), "rogue_m3_eq_m1": ROGUE_EQ,
         "rogue_eq_rising": load_vehicle("rogue", m0=-0.4, m3=13.22, K_q=-0.8)}
ALL = {**UNEQUAL, **EQUAL}

FAST = settings(max_examples=60, deadline=None)


def _u(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


# V > 0 (the reduced model is defined for V > 0), |alpha| < pi/2 so that atan2(v3, v1) of the foundation model
# returns the same alpha, gamma anywhere, moderate pitch rates.
reduced_states = st.tuples(_u(0.05, 3.0), _u(-math.pi, math.pi), _u(-0.7, 0.7), _u(-1.5, 1.5)).map(np.array)


def _close(got: np.ndarray, ref: np.ndarray, rel: float = 1e-12, scale: float | None = None) -> None:
    """``|got - ref| <= rel * scale`` component-wise, ``scale`` = the size of the terms that were summed."""
    scale = float(np.max(np.abs(ref))) if scale is None else scale
    np.testing.assert_allclose(got, ref, rtol=0, atol=rel * max(scale, 1e-300))


def _loads(veh: glidectl.Vehicle, V: float, al: float, Om: float) -> tuple[float, float, float]:
    """(2.11), (2.9), (2.13) written out: lift, drag, pitching moment."""
    L = (veh.K_L0 + veh.K_L * al) * V**2
    D = (veh.K_D0 + veh.K_D * al**2) * V**2
    M = (veh.K_M0 + veh.K_M * al + veh.K_q * Om) * V**2
    return L, D, M


def _effective_masses(veh: glidectl.Vehicle) -> tuple[float, float]:
    return veh.m1 + veh.mbar, veh.m3 + veh.mbar


# ------------------------------------------------------------------------------- 1. equals the foundation model
def _foundation_in_reduced_coordinates(veh: glidectl.Vehicle, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(V', gamma', alpha', Omega2') from AccelerationControlledGlider with w = 0, r_P = rdot_P = 0, via (5.1)-(5.3).

    Also returns the foundation derivative itself (to check that r_P, rdot_P, m0 stay put)."""
    V, gam, al, Om = x
    v1, v3 = V * math.cos(al), V * math.sin(al)
    theta = gam + al                                             # (5.3)
    xa = np.array([0.0, 0.0, theta, Om, v1, v3, 0.0, 0.0, 0.0, 0.0, veh.m0])
    d = AccelerationControlledGlider(veh).rhs(xa, np.zeros(3))
    thd, Omd, v1d, v3d = d[2], d[3], d[4], d[5]
    Vd = (v1 * v1d + v3 * v3d) / V                               # d/dt of (5.1)
    ald = (v1 * v3d - v3 * v1d) / V**2                           # d/dt of (5.2)
    return np.array([Vd, thd - ald, ald, Omd]), d


@pytest.mark.parametrize("name", ["rogue", "rogue_full", "rogue_rising", "rogue_m3_eq_m1", "rogue_eq_rising"])
@given(x=reduced_states)
@FAST
def test_reduced_equals_foundation_model(name: str, x: np.ndarray) -> None:
    veh = ALL[name]  # rogue variants: the foundation model needs a moving mass (mbar = 2 kg)
    ref, full = _foundation_in_reduced_coordinates(veh, x)
    # the moving mass and the buoyancy really are frozen under w = 0
    np.testing.assert_array_equal(full[6:], np.zeros(5))
    got = ReducedLongitudinalGlider(veh).rhs(x)
    # scale: the largest force term divided by the smallest mass, so near-cancelling components are judged fairly
    V = x[0]
    L, D, M = _loads(veh, V, x[2], x[3])
    M1, M3 = _effective_masses(veh)
    scale = (abs(L) + abs(D) + abs(veh.m0) * veh.g + (M1 + M3) * V * abs(x[3])) / min(M1, M3) / V \
        + abs(x[3]) + (abs(M) + abs(M3 - M1) * V**2) / veh.J2
    _close(got, ref, 1e-12, scale)


def test_reduced_equals_foundation_model_batch() -> None:
    """Batched evaluation equals point-wise evaluation and the foundation model (100 random states, rogue)."""
    rng = np.random.default_rng(7)
    X = np.column_stack([rng.uniform(0.05, 3, 100), rng.uniform(-np.pi, np.pi, 100), rng.uniform(-0.7, 0.7, 100),
                         rng.uniform(-1.5, 1.5, 100)])
    model = ReducedLongitudinalGlider(ROGUE_FULL)
    batch = model.rhs(X)
    assert batch.shape == (100, 4)
    for x, b in zip(X, batch, strict=True):
        np.testing.assert_array_equal(b, model.rhs(x))
        ref, _ = _foundation_in_reduced_coordinates(ROGUE_FULL, x)
        np.testing.assert_allclose(b, ref, rtol=1e-11, atol=1e-11 * np.max(np.abs(ref)))


def test_effective_masses_include_moving_mass() -> None:
    assert ReducedLongitudinalGlider(ROGUE).masses == (13.22 + 2.0, 25.22 + 2.0)
    assert ReducedLongitudinalGlider(ROGUE).delta_m == pytest.approx(12.0, abs=1e-12)
    assert ReducedLongitudinalGlider(SPHERE).masses == (28.0, 28.0)
    assert ReducedLongitudinalGlider(SPHERE).delta_m == 0.0


# ------------------------------------------------------------------------ 2. the printed equations as oracles
def printed_5_4_to_5_7(veh: glidectl.Vehicle, x: np.ndarray) -> np.ndarray:
    """(5.4)-(5.7) exactly as printed (``m1`` = the effective mass ``m1 + mbar``)."""
    V, gam, al, Om = x
    m1 = veh.m1 + veh.mbar
    L, D, M = _loads(veh, V, al, Om)
    m0g = veh.m0 * veh.g
    Vd = -(m0g * math.sin(gam) + D) / m1                          # (5.4)
    gd = (L - m0g * math.cos(gam)) / (m1 * V)                     # (5.5)
    ad = Om - (L - m0g * math.cos(gam)) / (m1 * V)                # (5.6)
    Od = M / veh.J2                                               # (5.7)
    return np.array([Vd, gd, ad, Od])


def printed_5_86_to_5_89(veh: glidectl.Vehicle, x: np.ndarray) -> np.ndarray:
    """(5.86)-(5.89) exactly as printed (``m_i`` = effective masses ``m_i + mbar``, ``Delta m = m3 - m1``)."""
    V, gam, al, Om = x
    m1, m3 = veh.m1 + veh.mbar, veh.m3 + veh.mbar
    dm = m3 - m1
    L, D, _ = _loads(veh, V, al, Om)
    m0g = veh.m0 * veh.g
    th = gam + al
    sa, ca = math.sin(al), math.cos(al)
    P = m0g * math.sin(th) - L * sa + D * ca
    Vd = (-dm * ca / (m1 * m3) * (P + (m1 + m3) * V * Om * sa)
          - (m0g * math.sin(gam) + D) / m3)                                                       # (5.86)
    E2 = (-dm / (m1 * m3 * V) * (P * sa + (m3 * sa**2 - m1 * ca**2) * V * Om)
          + (-m0g * math.cos(gam) + L) / (m3 * V))                                                # (5.87)
    ad = Om - E2                                                                                  # (5.88)
    Od = ((veh.K_M0 + veh.K_M * al + veh.K_q * Om) * V**2 + dm * V**2 * sa * ca) / veh.J2         # (5.89)
    return np.array([Vd, E2, ad, Od])


def _scale(veh: glidectl.Vehicle, x: np.ndarray) -> float:
    V, _, al, Om = x
    L, D, M = _loads(veh, V, al, Om)
    M1, M3 = _effective_masses(veh)
    return ((abs(L) + abs(D) + abs(veh.m0) * veh.g + (M1 + M3) * V * abs(Om)) / min(M1, M3) / V + abs(Om)
            + (abs(M) + abs(M3 - M1) * V**2) / veh.J2)


@pytest.mark.parametrize("name", sorted(EQUAL))
@given(x=reduced_states)
@FAST
def test_equal_masses_match_printed_5_4_to_5_7(name: str, x: np.ndarray) -> None:
    veh = EQUAL[name]
    got = ReducedLongitudinalGlider(veh).rhs(x)
    _close(got, printed_5_4_to_5_7(veh, x), 1e-12, _scale(veh, x))


@pytest.mark.parametrize("name", sorted(ALL))
@given(x=reduced_states)
@FAST
def test_rhs_matches_printed_5_86_to_5_89(name: str, x: np.ndarray) -> None:
    """(5.86)-(5.89) hold as printed (no typo) for m1 != m3, and reduce to (5.4)-(5.7) for m1 = m3."""
    veh = ALL[name]
    got = ReducedLongitudinalGlider(veh).rhs(x)
    _close(got, printed_5_86_to_5_89(veh, x), 1e-12, _scale(veh, x))


@given(x=reduced_states)
@FAST
def test_unequal_masses_differ_from_equal_mass_formulas(x: np.ndarray) -> None:
    """Guard against a model that ignores Delta m: (5.4)-(5.7) must NOT describe rogue (m3 - m1 = 12 kg)."""
    got = ReducedLongitudinalGlider(ROGUE_FULL).rhs(x)
    # Omega2' differs by Delta m V^2 sin(alpha) cos(alpha) / J2 exactly
    V, _, al, _ = x
    eq = printed_5_4_to_5_7(ROGUE_FULL, x)
    assert got[3] - eq[3] == pytest.approx(12.0 * V**2 * math.sin(al) * math.cos(al) / ROGUE_FULL.J2,
                                           rel=1e-9, abs=1e-9 * _scale(ROGUE_FULL, x))


# ------------------------------------------------------------------------------------- energy balance (physics)
@pytest.mark.parametrize("name", sorted(ALL))
@given(x=reduced_states)
@FAST
def test_energy_balance(name: str, x: np.ndarray) -> None:
    """``T = (M1 v1^2 + M3 v3^2 + J2 Omega2^2)/2``; gyroscopic terms do no work, so along the flow
    ``dT/dt = -m0 g V sin(gamma) - D V + Omega2 M_DL2`` (gravity, drag, hydrodynamic moment). Lift does no work."""
    veh = ALL[name]
    V, gam, al, Om = x
    Vd, _, ad, Od = ReducedLongitudinalGlider(veh).rhs(x)
    M1, M3 = _effective_masses(veh)
    sa, ca = math.sin(al), math.cos(al)
    dT = ((M1 * ca**2 + M3 * sa**2) * V * Vd + (M3 - M1) * V**2 * sa * ca * ad + veh.J2 * Om * Od)
    _, D, M = _loads(veh, V, al, Om)
    power = -veh.m0 * veh.g * V * math.sin(gam) - D * V + Om * M
    scale = (M1 + M3) * V * _scale(veh, x) * (1 + V) + abs(M * Om) + abs(power)
    assert dT == pytest.approx(power, rel=0, abs=1e-12 * scale)


# ------------------------------------------------------------------------ 3. without drag: the phugoid model
def printed_4_3_4_4(mass: float, m0: float, K: float, g: float, xd: float, zd: float) -> np.ndarray:
    """(4.3)-(4.4) as printed: xddot = K V zdot / m, zddot = (m0 g - K V xdot) / m."""
    V = math.hypot(xd, zd)
    return np.array([K * V * zd / mass, (m0 * g - K * V * xd) / mass])


def _phugoid_model(mass: float, m0: float, K: float, g: float) -> Any:
    """glidectl's chapter-4 model if present (it is the other model of the pair), else None."""
    try:
        from glidectl.models.phugoid import PhugoidModel
    except ImportError:
        return None
    return PhugoidModel(mass=mass, m0=m0, K=K, g=g)


@pytest.mark.parametrize("overrides", [{}, {"K_M": -100.0}, {"m0": 0.35, "K_L0": 0.8}],
                         ids=["sphere", "sphere_KM100", "sphere_KL0"])
@given(V=_u(0.05, 3.0), gam=_u(-math.pi, math.pi))
@settings(max_examples=40, deadline=None)
def test_no_drag_reduces_to_phugoid_model(overrides: dict[str, float], V: float, gam: float) -> None:
    """K_D0 = K_D = 0, alpha = alpha_e, Omega2 = 0: (xdot, zdot) = (V cos gamma, -V sin gamma) (z down) obeys
    (4.3)-(4.4) with mass M1 = m1 + mbar and K = K_L0 + K_L alpha_e. (singular_perturbation() refuses a vehicle
    without drag, so the model's own rhs is used.)"""
    veh = load_vehicle("sphere_ch5", K_D0=0.0, K_D=0.0, **overrides)
    model = ReducedLongitudinalGlider(veh)
    a_e = model.trim_alpha()
    assert a_e == pytest.approx(-veh.K_M0 / veh.K_M, abs=1e-15)  # (5.10)
    Vd, gd, ad, Od = model.rhs(np.array([V, gam, a_e, 0.0]))
    assert Od == pytest.approx(0.0, abs=1e-12)                  # no moment at alpha_e, so alpha_e stays put ...
    assert gd + ad == pytest.approx(0.0, abs=1e-12 * (1 + abs(gd)))  # ... and theta' = Omega2 = 0
    xd, zd = V * math.cos(gam), -V * math.sin(gam)
    xdd = Vd * math.cos(gam) - V * math.sin(gam) * gd
    zdd = -Vd * math.sin(gam) - V * math.cos(gam) * gd
    M1, _ = model.masses
    K = veh.K_L0 + veh.K_L * a_e
    ref = printed_4_3_4_4(M1, veh.m0, K, veh.g, xd, zd)
    scale = (K * V * V + veh.m0 * veh.g) / M1
    _close(np.array([xdd, zdd]), ref, 1e-12, scale)
    pm = _phugoid_model(M1, veh.m0, K, veh.g)
    if pm is not None:  # the chapter-4 model of glidectl (state (x, z, xdot, zdot)) is the same vector field
        d = pm.rhs(np.array([0.0, 0.0, xd, zd]))
        _close(np.asarray(d)[2:], np.array([xdd, zdd]), 1e-12, scale)
        np.testing.assert_allclose(np.asarray(d)[:2], [xd, zd], rtol=1e-15)


# ----------------------------------------------------------------------------------- equilibrium (5.8)-(5.11)
@pytest.mark.parametrize("m3", [20.0, 25.0, 28.0, 31.0, 40.0])
def test_trim_alpha_solves_5_90(m3: float) -> None:
    veh = load_vehicle("sphere_ch5", m3=m3)
    model = ReducedLongitudinalGlider(veh)
    dm = m3 - 28.0

    def F(a: float) -> float:
        return veh.K_M0 + veh.K_M * a + dm * math.sin(a) * math.cos(a)

    ref = brentq(F, -math.pi / 4, math.pi / 4, xtol=1e-15, rtol=1e-15)
    a = model.trim_alpha()
    assert a == pytest.approx(ref, abs=1e-13)
    # at (V_e, gamma_e) of (5.8)-(5.9) with this alpha_e, every component of the vector field vanishes
    KDe, KLe = veh.K_D0 + veh.K_D * a * a, veh.K_L0 + veh.K_L * a
    Ve = math.sqrt(abs(veh.m0) * veh.g / math.hypot(KDe, KLe))
    ge = math.atan2(-KDe / veh.m0, KLe / veh.m0)
    np.testing.assert_allclose(model.rhs(np.array([Ve, ge, a, 0.0])), 0.0, atol=1e-12)


def test_trim_alpha_equal_masses_is_5_10() -> None:
    for veh in (SPHERE, load_vehicle("sphere_ch5", K_M=-100.0, K_M0=-3.0)):
        assert ReducedLongitudinalGlider(veh).trim_alpha() == -veh.K_M0 / veh.K_M


def test_steady_glide_is_not_trivially_zero_elsewhere() -> None:
    """The equilibrium is isolated in (V, gamma): off it, the slow equations do not vanish."""
    model = ReducedLongitudinalGlider(SPHERE)
    a = model.trim_alpha()
    d = model.rhs(np.array([1.0, -0.5, a, 0.0]))
    assert np.max(np.abs(d[:2])) > 1e-2


# -------------------------------------------------------------------------------------------- Jacobians, units
@pytest.mark.parametrize("name", sorted(ALL))
def test_complex_step_jacobian_matches_central_differences(name: str) -> None:
    model = ReducedLongitudinalGlider(ALL[name])
    rng = np.random.default_rng(3)
    for _ in range(5):
        x = np.array([rng.uniform(0.2, 2.5), rng.uniform(-3, 3), rng.uniform(-0.6, 0.6), rng.uniform(-1, 1)])
        A, B = jacobians(lambda x_, u_: model.rhs(x_, u_), x, np.zeros(0))
        Ac, _ = central_difference_jacobians(lambda x_, u_: model.rhs(x_, u_), x, np.zeros(0))
        assert B.shape == (4, 0)
        np.testing.assert_allclose(A, Ac, rtol=1e-6, atol=1e-6 * np.max(np.abs(A)))


def test_state_names_and_units() -> None:
    model = ReducedLongitudinalGlider(SPHERE)
    assert model.state_names == ("V", "gamma", "alpha", "Omega2")
    assert model.input_names == ()
    from glidectl.models.reduced import REDUCED_UNITS
    assert REDUCED_UNITS == {"V": "m/s", "gamma": "rad", "alpha": "rad", "Omega2": "rad/s"}


# ------------------------------------------------------------------------------------------------ bad inputs
def test_m0_zero_accepted_by_loader_refused_by_model() -> None:
    """m0 is an 'any'-signed optional parameter, so the loader accepts 0; the chapter-5 model refuses it
    (assumption 2 of §5.1: constant nonzero buoyancy)."""
    veh = load_vehicle("sphere_ch5", m0=0.0)
    assert veh.m0 == 0.0
    with pytest.raises(ModelError, match="m0 = 0"):
        ReducedLongitudinalGlider(veh)
    with pytest.raises(ModelError):
        glidectl.singular_perturbation(veh)


def test_missing_m0_raises_model_error() -> None:
    """rogue.toml has no nominal m0: the model cannot be built without an override."""
    with pytest.raises(ModelError, match="m0"):
        ReducedLongitudinalGlider(load_vehicle("rogue"))


def test_not_an_underwater_glider() -> None:
    with pytest.raises(ModelError, match="not an underwater glider"):
        ReducedLongitudinalGlider(load_vehicle("dc8_ctol"))


def test_no_pitch_stiffness_raises() -> None:
    with pytest.raises(ModelError, match="K_M = 0"):
        ReducedLongitudinalGlider(load_vehicle("sphere_ch5", K_M=0.0)).trim_alpha()


def test_no_admissible_trim_raises() -> None:
    """(5.90) with |alpha_e| < pi/4 has no root here (K_M0/K_M ~ 0.9 rad, Delta m = 1 kg): a ModelError, not a
    silently returned non-root."""
    veh = load_vehicle("sphere_ch5", K_M0=45.0, m3=29.0)
    with pytest.raises(ModelError, match=r"\(5.90\)"):
        ReducedLongitudinalGlider(veh).trim_alpha()


def test_errors_are_glidectl_errors() -> None:
    assert issubclass(ModelError, GlidectlError)
