"""Composite Lyapunov function and region-of-attraction estimate of §5.2-§5.3, :func:`glidectl.composite_lyapunov`.

Checked: every bound of Propositions 1-2 and Theorem 2 on samples (``verify``) for the §5.3.1 designs and for
random domains; the algebra of (5.54) and mu*; the boundary-layer Lyapunov function with the corrected and the
printed ``C_W``; the eigenvalue bounds ``k3, k4`` and the levels ``v0, w0`` recomputed here; the estimate ``L*``
(5.85) against simulations of the full nondimensional model; bad inputs.

Thesis typos established here:

* ``C_W`` of (5.31) (and the same matrix inside (5.83)): with ``c2 = 1 + r1/(r2 a)``, ``c3 = 1``, the cross term
  of ``dW/dtau`` vanishes only for ``c1 = 1 + 2 r2 a / r1``; the printed ``c1 = r1 + r1 a + r2 a`` leaves
  ``(r1^2 + r1^2 a + r1 r2 a - 2 r2 a - r1) alphabar Omegabar2`` and does not give ``dW/dtau = -r2 sigma^2``.
  With the corrected ``c1``, ``dW/dtau = -r2 sigma^2`` exactly.
* §5.3.1 says ``J2 = 0.01`` alone (K_M = -50) gives ``mu < mu_d``; it does not (see
  :func:`test_section_5_3_1_verdicts`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import glidectl as gc
from glidectl import (
    CompositeCertificate,
    Domain,
    GlidectlError,
    ModelError,
    composite_lyapunov,
    load_vehicle,
    singular_perturbation,
)

VARIANTS = {
    "baseline": load_vehicle("sphere_ch5"),
    "K_M=-100": load_vehicle("sphere_ch5", K_M=-100.0),
    "K_M=-100,J2=0.01": load_vehicle("sphere_ch5", K_M=-100.0, J2=0.01),
    "J2=0.01": load_vehicle("sphere_ch5", J2=0.01),
}
CERT = {k: composite_lyapunov(v) for k, v in VARIANTS.items()}
THESIS_BASE = composite_lyapunov(VARIANTS["baseline"], cw="thesis")
N = 20_000


def _u(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


def _cw_by_hand(r1: float, r2: float, a: np.ndarray, kind: str = "corrected") -> np.ndarray:
    """C_W(a) with the corrected c1 = 1 + 2 r2 a / r1, or the printed c1 = r1 + r1 a + r2 a (5.31)."""
    a = np.asarray(a, dtype=float)
    c1 = 1 + 2 * r2 * a / r1 if kind == "corrected" else r1 + r1 * a + r2 * a
    c2 = 1 + r1 / (r2 * a)
    C = np.empty((*a.shape, 2, 2))
    C[..., 0, 0], C[..., 1, 1], C[..., 0, 1], C[..., 1, 0] = c1, c2, 1.0, 1.0
    return C


# ------------------------------------------------------------------------------- 6. sampled validity, verdicts
@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_every_bound_holds_on_samples(name: str) -> None:
    cert = CERT[name]
    ver = cert.verify(n=N, seed=0)
    assert ver.n_samples == N and ver.seed == 0
    assert ver.passed, ver.failing()
    assert ver.failing() == {}
    # every inequality of Propositions 1-2 and Theorem 2 was checked, and the lower/upper bounds are not vacuous
    for key in ("Prop2.1 lower", "Prop2.1 upper", "Prop2.2: dPhi", "Prop1.1 lower", "Prop1.1 upper",
                "Prop1.2: dW", "Thm2.1", "Thm2.2", "Thm2.3", "F1"):
        assert any(k.startswith(key) for k in ver.margins), key
    r = ver.margins
    assert r["Prop1.1 lower: k3|q|^2 <= W"] < 1 / 0.9  # k3, k4 are tight (eigenvalue bounds)
    assert r["Prop1.1 upper: W <= k4|q|^2"] < 1 / 0.9
    assert r["Prop2.2: dPhi/dt_n <= -a1 psi^2"] == pytest.approx(1.0, rel=1e-9)  # (5.44): equality
    if cert.certified:
        assert "Thm2: dnu/dt_n <= 0 on B_p x B_q" in r


def test_section_5_3_1_verdicts() -> None:
    """Measured verdicts for |Vbar| <= 0.4, |alphabar| <= 0.2 (and |gammabar| <= pi, Omegabar unbounded).

    The thesis says baseline: not certified (mu_d = 3.635e-3 < mu = 4.784e-3); K_M = -100 and/or J2 = 0.01:
    certified. We reproduce the first three. J2 = 0.01 alone is NOT certified: J2 enters only eps2 (5.17), and
    mu = max(eps1, eps2) = eps1 = 4.784e-3 is unchanged (K_q, K_M, tau_s unchanged), while mu_d only rises from
    2.67e-3 to 2.83e-3 (lower eps2 -> larger r2 = mu/eps2 -> larger a2 = r2, but also larger beta2', gamma2'').
    Even the thesis's own baseline mu_d = 3.635e-3 is below 4.784e-3, so J2 = 0.01 alone would need mu_d to grow
    by a third over the thesis's baseline value; the thesis's "and/or" holds only for K_M = -100 (with or without
    J2 = 0.01). Our baseline mu_d = 2.666e-3 (d = 0.4635) differs from the printed 3.635e-3 (d = 0.4423) because
    of the corrected constants listed in glidectl.stability.composite (C_W, k3/k4, beta2', gamma2'')."""
    expected = {"baseline": False, "K_M=-100": True, "K_M=-100,J2=0.01": True, "J2=0.01": False}
    for name, verdict in expected.items():
        cert = CERT[name]
        assert cert.certified is verdict, (name, cert.mu, cert.mu_d)
        assert cert.certified == (cert.mu < cert.mu_d)
    base, j2 = CERT["baseline"], CERT["J2=0.01"]
    assert j2.mu == base.mu                       # J2 does not change eps1 = mu
    assert j2.sp.eps2 < base.sp.eps2 < base.mu    # only eps2 moves
    assert base.mu_d < j2.mu_d < j2.mu
    assert round(base.mu_d * 1e3, 3) == 2.666 and round(base.d, 4) == 0.4635


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_mu_d_and_mu_star(name: str) -> None:
    """(5.54) by hand; max over d of mu_d(d) is mu* = a1 a2 / (a1 gamma2 + a2 gamma1 + beta1 beta2) (gamma1 = 0),
    attained at d = beta1 / (beta1 + beta2) (AM-GM); mu_d <= mu*."""
    c = CERT[name]
    assert c.gamma1 == 0.0 and c.a1 == 1.0 and c.beta2pp == 0.0
    assert c.beta2 == c.beta2p + c.beta2pp and c.gamma2 == c.gamma2p + c.gamma2pp

    def mu_d(d: np.ndarray) -> np.ndarray:
        return c.a1 * c.a2 / (c.a1 * c.gamma2 + c.a2 * c.gamma1
                              + ((1 - d) * c.beta1 + d * c.beta2) ** 2 / (4 * (1 - d) * d))

    mu_star = c.a1 * c.a2 / (c.a1 * c.gamma2 + c.a2 * c.gamma1 + c.beta1 * c.beta2)
    assert c.mu_star == pytest.approx(mu_star, rel=1e-14)
    assert c.mu_d_best == pytest.approx(mu_star, rel=1e-9)
    assert c.d_best == pytest.approx(c.beta1 / (c.beta1 + c.beta2), rel=1e-4)
    assert c.mu_d == pytest.approx(float(mu_d(np.array(c.d))), rel=1e-13)
    assert float(c.mu_d_of(c.d)) == pytest.approx(c.mu_d, rel=1e-14)
    d = np.linspace(1e-4, 1 - 1e-4, 20001)
    grid = c.mu_d_of(d)
    np.testing.assert_allclose(grid, mu_d(d), rtol=1e-13)
    assert np.all(grid <= mu_star * (1 + 1e-12))
    assert np.max(grid) == pytest.approx(mu_star, rel=1e-7)
    assert c.mu_d <= c.mu_star
    # the certificate uses d of (5.84) = v0/(v0 + w0) and level v0 w0/(v0 + w0) of (5.85)
    assert c.d == pytest.approx(c.v0 / (c.v0 + c.w0), rel=1e-15)
    assert c.level == pytest.approx(c.v0 * c.w0 / (c.v0 + c.w0), rel=1e-15)


domains = st.fixed_dictionaries({
    "name": st.sampled_from(sorted(VARIANTS)),
    "Vlo": _u(-0.7, -0.05), "Vhi": _u(0.05, 0.7), "amax": _u(0.02, 0.5), "gmax": _u(0.2, math.pi)})


@given(dom=domains)
@settings(max_examples=20, deadline=None)
def test_bounds_hold_on_random_domains(dom: dict) -> None:
    cert = composite_lyapunov(VARIANTS[dom["name"]], Vbar=(dom["Vlo"], dom["Vhi"]),
                              alphabar=(-dom["amax"], dom["amax"]), gammabar=(-dom["gmax"], dom["gmax"]))
    assert cert.domain.Vbar == (dom["Vlo"], dom["Vhi"])
    ver = cert.verify(n=N, seed=1)
    assert ver.passed, (dom, ver.failing())
    assert cert.certified == (cert.mu < cert.mu_d)
    assert cert.mu_d <= cert.mu_star * (1 + 1e-12)
    assert cert.mu_d_best == pytest.approx(cert.mu_star, rel=1e-8)
    # (5.38), (5.41), (5.46) and b1, b2 with the domain's bounds
    gm = dom["gmax"]
    assert cert.k1 == pytest.approx(min(1 + dom["Vlo"] / 3, (1 + dom["Vlo"]) / 2 * (1 - gm**2 / 12)), rel=1e-14)
    assert cert.k2 == pytest.approx(max(1 + dom["Vhi"] / 3, (1 + dom["Vhi"]) / 2), rel=1e-14)
    assert cert.e == pytest.approx(1 - gm**2 / 24, rel=1e-14)
    assert cert.b1 == pytest.approx(cert.e**2 * (1 + dom["Vlo"]) ** 2, rel=1e-14)
    assert cert.b2 == pytest.approx(cert.a2 * (1 + dom["Vlo"]) ** 2, rel=1e-14)


def test_smaller_domain_is_easier() -> None:
    """Shrinking B_p x B_q can only enlarge mu* (all constants are monotone in the domain)."""
    big = CERT["baseline"]
    small = composite_lyapunov(VARIANTS["baseline"], Vbar=(-0.1, 0.1), alphabar=(-0.05, 0.05))
    assert small.mu_star > big.mu_star
    assert small.beta1 <= big.beta1 and small.gamma2 <= big.gamma2


# ----------------------------------------------------------------------------------- boundary layer, C_W
@pytest.mark.parametrize("name", ["baseline", "K_M=-100,J2=0.01"])
@given(V=_u(-0.7, 0.7), gb=_u(-math.pi, math.pi), ab=_u(-0.5, 0.5), Ob=_u(-3.0, 3.0))
@settings(max_examples=40, deadline=None)
def test_boundary_layer_lyapunov_derivative(name: str, V: float, gb: float, ab: float, Ob: float) -> None:
    """Corrected C_W: dW/dtau = -r2 sigma^2 exactly (Proposition 1 with a2 = r2). Printed C_W: the same plus the
    cross term (r1^2 + r1^2 a + r1 r2 a - 2 r2 a - r1) alphabar Omegabar2."""
    cert = CERT[name]
    sp = cert.sp
    r1, r2 = sp.r1, sp.r2
    p, q = np.array([V, gb]), np.array([ab, Ob])
    a = (1 + V) ** 2
    sigma2 = a * (ab * ab + Ob * Ob)                                                  # (5.32)
    assert CompositeCertificate.sigma(np.array([V, gb, ab, Ob])) ** 2 == pytest.approx(sigma2, rel=1e-13)
    bl = sp.boundary_layer_rhs(p, q)
    np.testing.assert_allclose(bl, [r1 * Ob, -r2 * a * (ab + Ob)], rtol=1e-12, atol=1e-12 * r2 * (1 + a))
    # relative error on the quadratic terms, plus a term linear in |q|: the model's g2 at q = 0 is a rounding
    # residual of K_M0 + K_M alpha_e (~1e-16), multiplied by dW/dq ~ |q|
    scale = r2 * a * (1 + r1 + r2) * (ab * ab + Ob * Ob) * (1 + a) + 1e-2 * r2 * (1 + a) * (abs(ab) + abs(Ob))
    C = _cw_by_hand(r1, r2, a)
    assert cert.W(p, q) == pytest.approx(0.5 * q @ C @ q, rel=1e-12, abs=1e-300)
    assert (C @ q) @ bl == pytest.approx(-r2 * sigma2, rel=0, abs=1e-12 * scale)
    thesis = composite_lyapunov(VARIANTS[name], cw="thesis") if name != "baseline" else THESIS_BASE
    Ct = _cw_by_hand(r1, r2, a, "thesis")
    assert thesis.W(p, q) == pytest.approx(0.5 * q @ Ct @ q, rel=1e-12, abs=1e-300)
    cross = r1**2 + r1**2 * a + r1 * r2 * a - 2 * r2 * a - r1
    assert (Ct @ q) @ bl == pytest.approx(-r2 * sigma2 + cross * ab * Ob, rel=0, abs=1e-12 * scale * (1 + r2))



@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_printed_C_W_does_not_give_a2_equal_r2(name: str) -> None:
    """With the printed C_W and the printed a2 = r2, Proposition 1 condition 2 fails on samples (margin < 1); with
    the a2 the code derives for that matrix (smaller than r2) every bound holds; the corrected C_W has a2 = r2."""
    thesis = composite_lyapunov(VARIANTS[name], cw="thesis")
    assert thesis.cw == "thesis" and CERT[name].cw == "corrected"
    assert CERT[name].a2 == pytest.approx(CERT[name].sp.r2, rel=1e-9)
    forced = dataclasses.replace(thesis, a2=thesis.sp.r2)
    forced_ver = forced.verify(n=N, seed=2)
    margin = forced_ver.margins["Prop1.2: dW/dtau <= -a2 sigma^2"]
    assert margin < 1 / 1.2
    assert not forced_ver.passed and forced_ver.failing()["Prop1.2: dW/dtau <= -a2 sigma^2"] == margin
    assert 0 < thesis.a2 < thesis.sp.r2
    ver = thesis.verify(n=N, seed=2)
    assert ver.passed, ver.failing()


@pytest.mark.parametrize("name", ["baseline", "K_M=-100"])
def test_k3_k4_are_half_the_eigenvalues_of_C_W(name: str) -> None:
    """Proposition 1 condition 1 with W = q^T C_W q / 2: k3, k4 are half the extreme eigenvalues of C_W over the
    Vbar range (the thesis says 'the eigenvalues', which is off by the factor 1/2)."""
    c = CERT[name]
    V = np.linspace(*c.domain.Vbar, 4001)
    lam = np.linalg.eigvalsh(_cw_by_hand(c.sp.r1, c.sp.r2, (1 + V) ** 2))
    assert c.k3 <= 0.5 * lam[:, 0].min() * (1 + 1e-12)
    assert c.k3 == pytest.approx(0.5 * lam[:, 0].min(), rel=1e-6)
    assert c.k4 >= 0.5 * lam[:, 1].max() * (1 - 1e-12)
    assert c.k4 == pytest.approx(0.5 * lam[:, 1].max(), rel=1e-6)


# --------------------------------------------------------------------------------------------- levels and L*
@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_v0_w0_levels(name: str) -> None:
    """v0 = min of Phi on the faces of B_p; w0 = largest level whose ellipse {W <= w0} fits the alphabar range at
    every Vbar (Omegabar unbounded): recomputed here on grids."""
    c = CERT[name]
    (Vlo, Vhi), (glo, ghi) = c.domain.Vbar, c.domain.gammabar
    t = np.linspace(0, 1, 4001)
    faces = np.concatenate([np.column_stack([np.full_like(t, Vlo), glo + (ghi - glo) * t]),
                            np.column_stack([np.full_like(t, Vhi), glo + (ghi - glo) * t]),
                            np.column_stack([Vlo + (Vhi - Vlo) * t, np.full_like(t, glo)]),
                            np.column_stack([Vlo + (Vhi - Vlo) * t, np.full_like(t, ghi)])])
    phi_min = float(np.min(CompositeCertificate.Phi(faces)))
    assert c.v0 <= phi_min + 1e-12
    assert c.v0 == pytest.approx(phi_min, rel=1e-6)
    V = np.linspace(Vlo, Vhi, 4001)
    Cinv = np.linalg.inv(_cw_by_hand(c.sp.r1, c.sp.r2, (1 + V) ** 2))
    amax = min(-c.domain.alphabar[0], c.domain.alphabar[1])
    extent = np.sqrt(2 * c.w0 * Cinv[:, 0, 0])  # largest |alphabar| on {W <= w0} at each Vbar
    assert np.all(extent <= amax * (1 + 1e-9))
    assert np.max(extent) == pytest.approx(amax, rel=1e-6)


@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_estimate_lies_inside_the_box(name: str) -> None:
    """Points of {nu <= level}, sampled in a region much larger than B_p x B_q, all lie in the box; in_estimate is
    exactly 'in the box and nu <= level'; on L*, Phi <= v0 and W <= w0."""
    c = CERT[name]
    rng = np.random.default_rng(5)
    n = 100_000
    ext = 2 * c.omega_extent
    lo = np.array([-0.95, -math.pi, -0.4, -ext])
    hi = np.array([1.0, math.pi, 0.4, ext])
    z = lo + (hi - lo) * rng.random((n, 4))
    sub = c.nu(z) <= c.level
    assert sub.sum() > 200  # the test has teeth
    box = ((z[:, 0] >= c.domain.Vbar[0]) & (z[:, 0] <= c.domain.Vbar[1]) & (np.abs(z[:, 2]) <= 0.2))
    assert np.all(box[sub])
    ins = c.in_estimate(z)
    np.testing.assert_array_equal(ins, sub & box)
    p, q = z[ins, :2], z[ins, 2:]
    assert np.all(CompositeCertificate.Phi(p) <= c.v0 * (1 + 1e-12))
    assert np.all(c.W(p, q) <= c.w0 * (1 + 1e-12))


def _grad_nu(c: CompositeCertificate, z: np.ndarray) -> np.ndarray:
    """Gradient of nu by complex step (nu is analytic), independent of the certificate's internals."""
    h = 1e-30
    g = np.empty_like(z)
    for j in range(4):
        zc = z.astype(complex)
        zc[:, j] += 1j * h
        g[:, j] = np.imag(c.nu(zc)) / h
    return g


def test_nu_decreases_on_the_box_for_the_certified_design() -> None:
    """Theorem 2 for K_M = -100: dnu/dt_n = grad(nu) . (f, A g / mu) <= 0 on B_p x B_q (Omegabar sampled up to
    the extent of L*), evaluated with the model's full nondimensional vector field."""
    c = CERT["K_M=-100"]
    assert c.certified
    rng = np.random.default_rng(9)
    z = c.domain.sample(30_000, rng, omega_extent=c.omega_extent)
    dnu = np.sum(_grad_nu(c, z) * c.sp.full_rhs_nondimensional(z), axis=1)
    assert np.all(dnu <= 1e-12)
    # strictly negative away from the origin: dnu <= -c |z|^2 with some c > 0 (5.55)
    assert np.max(dnu / np.sum(z * z, axis=1)) < 0


def test_nu_decreases_along_simulated_trajectories() -> None:
    """L* is a region of attraction estimate: trajectories of the full nondimensional model (5.28)-(5.29) started
    in L* (near its boundary) keep nu non-increasing and converge to the steady glide (K_M = -100, certified)."""
    c = CERT["K_M=-100"]
    sp = c.sp
    rng = np.random.default_rng(1)
    lo = np.array([c.domain.Vbar[0], -math.pi, c.domain.alphabar[0], -c.omega_extent])
    z = lo + (-2 * lo) * rng.random((100_000, 4))
    z = z[c.in_estimate(z)]
    nu0 = c.nu(z)
    starts = z[np.argsort(nu0)[-3:]]                     # the three sampled points closest to the level set
    starts = np.vstack([starts, z[np.argmax(np.abs(z[:, 3]))]])  # and the fastest pitch rate
    assert np.all(c.nu(starts) > 0.9 * c.level)
    t = np.linspace(0.0, 10.0, 2001)
    for z0 in starts:
        sol = solve_ivp(lambda _, y: sp.full_rhs_nondimensional(y), (0.0, 10.0), z0, method="LSODA",
                        rtol=1e-10, atol=1e-12, t_eval=t)
        assert sol.success, sol.message
        Y = sol.y.T
        nu = c.nu(Y)
        assert np.max(np.diff(nu)) <= 1e-9
        assert np.all(c.in_estimate(Y))                 # L* is positively invariant
        assert nu[-1] < 1e-8 * nu[0]
        assert np.max(np.abs(Y[-1])) < 1e-4


# ------------------------------------------------------------------------------------------------ bad inputs
@pytest.mark.parametrize("kwargs", [
    {"Vbar": (0.1, 0.4)},                       # lo >= 0
    {"Vbar": (0.0, 0.4)},
    {"alphabar": (-0.2, -0.1)},                 # hi <= 0
    {"gammabar": (-math.pi, 0.0)},
    {"Vbar": (-1.0, 0.4)},                      # V = 0 not allowed
    {"Vbar": (-1.5, 0.4)},
    {"gammabar": (-3.2, 3.0)},                  # |gammabar| > pi
    {"gammabar": (-1.0, 3.2)},
    {"alphabar": (-7.0, 0.2)},                  # |alphabar| > 2 pi
    {"Vbar": (-math.inf, 0.4)},
    {"Vbar": (math.nan, 0.4)},
    {"Omegabar": (math.nan, 1.0)},
])
def test_bad_domain_raises(kwargs: dict) -> None:
    with pytest.raises(GlidectlError):
        Domain(**kwargs)
    with pytest.raises(GlidectlError):
        composite_lyapunov(VARIANTS["K_M=-100"], **kwargs)


def test_good_domain_accepted() -> None:
    d = Domain(Vbar=(-0.999, 0.1), gammabar=(-math.pi, math.pi), alphabar=(-6.0, 6.0), Omegabar=(-1.0, math.inf))
    assert d.Vbar == (-0.999, 0.1)


def test_unequal_masses_refused() -> None:
    with pytest.raises(GlidectlError, match="equal added masses"):
        composite_lyapunov(load_vehicle("sphere_ch5", m3=31.0))


def test_bad_cw_refused() -> None:
    with pytest.raises(GlidectlError, match="cw"):
        composite_lyapunov(VARIANTS["baseline"], cw="printed")


def test_positive_K_q_refused() -> None:
    with pytest.raises(ModelError):
        singular_perturbation(load_vehicle("sphere_ch5", K_q=2.0))
    with pytest.raises(ModelError):
        composite_lyapunov(load_vehicle("sphere_ch5", K_q=2.0))


def test_m0_zero() -> None:
    """The loader accepts m0 = 0 ('any'-signed parameter); the chapter-5 model refuses it with a ModelError."""
    veh = load_vehicle("sphere_ch5", m0=0.0)
    with pytest.raises(ModelError, match="m0 = 0"):
        composite_lyapunov(veh)


def test_finite_omega_bound_limits_w0() -> None:
    """With a finite Omegabar range the level w0 can only shrink, and the Omegabar extent of {W <= w0} fits it."""
    c_inf = CERT["K_M=-100"]
    c_fin = composite_lyapunov(VARIANTS["K_M=-100"], Omegabar=(-0.05, 0.05))
    assert c_fin.w0 < c_inf.w0
    V = np.linspace(*c_fin.domain.Vbar, 2001)
    Cinv = np.linalg.inv(_cw_by_hand(c_fin.sp.r1, c_fin.sp.r2, (1 + V) ** 2))
    assert np.all(np.sqrt(2 * c_fin.w0 * Cinv[:, 1, 1]) <= 0.05 * (1 + 1e-9))
    assert c_fin.verify(n=N).passed


# ------------------------------------------------------------------------------- argument checks (issue 15)
@pytest.mark.parametrize(("kwargs", "exc"), [
    ({"Vbar": 0.4}, gc.ArgumentTypeError),              # issue 15: was a TypeError from unpacking
    ({"Vbar": (-0.4, 0, 0.4)}, gc.ArgumentError),       # issue 15: was an unpacking ValueError
    ({"Vbar": "(-0.4, 0.4)"}, gc.ArgumentTypeError),
    ({"alphabar": (-0.2, None)}, gc.ArgumentTypeError),
    ({"gammabar": (True, 1.0)}, gc.ArgumentTypeError),
    ({"Omegabar": (1.0, -1.0)}, gc.ArgumentError),
    ({"cw": "bogus"}, gc.ArgumentError),
])
def test_domain_arguments_get_precise_errors(kwargs: dict, exc: type) -> None:
    with pytest.raises(exc):
        composite_lyapunov(VARIANTS["baseline"], **kwargs)
    with pytest.raises(TypeError if exc is gc.ArgumentTypeError else ValueError):
        composite_lyapunov(VARIANTS["baseline"], **kwargs)


def test_vehicle_checks() -> None:
    with pytest.raises(gc.ArgumentTypeError):
        composite_lyapunov("sphere_ch5")  # type: ignore[arg-type]
    with pytest.raises(ModelError):
        composite_lyapunov(load_vehicle("dc8_ctol"))
    with pytest.raises(ModelError, match="equal added masses"):
        composite_lyapunov(load_vehicle("sphere_ch5", m3=31.0))


def test_tiny_domain_has_no_cancellation() -> None:
    """Issue 15: Vbar = alphabar = (-1e-12, 1e-12) gave negative d and mu_d (2/3 - (1 + V) + (1 + V)^3/3 cancels).
    Phi is now evaluated as V^2 (1 + V/3) + 2 (1 + V) sin^2(g/2): the levels are right, d and mu_d positive."""
    c = composite_lyapunov(VARIANTS["baseline"], Vbar=(-1e-12, 1e-12), alphabar=(-1e-12, 1e-12))
    assert c.v0 == pytest.approx(1e-24 * (1 - 1e-12 / 3), rel=1e-12)  # Phi(-1e-12, 0), the smallest face value
    assert 0 < c.d < 1 and c.mu_d > 0 and c.level > 0 and c.mu_d_best >= c.mu_d
    assert CompositeCertificate.Phi(np.array([1e-12, 0.0])) == pytest.approx(1e-24, rel=1e-11)
    # sampling cannot resolve such a domain (dimensional round trip): verify refuses instead of failing bounds
    with pytest.raises(gc.ArgumentError, match="too small to verify"):
        c.verify(n=1000)


@pytest.mark.parametrize("kwargs", [{"Vbar": (-1e-200, 1e-200)},
                                    {"Vbar": (-1e-160, 1e-160), "alphabar": (-1e-160, 1e-160)}])
def test_underflowing_domain_raises(kwargs: dict) -> None:
    with pytest.raises(gc.ArgumentError, match="too small"):
        composite_lyapunov(VARIANTS["baseline"], **kwargs)


def test_certificate_methods_check_their_arguments() -> None:
    c = CERT["baseline"]
    with pytest.raises(gc.ArgumentError):
        c.verify(n=0)
    with pytest.raises(gc.ArgumentTypeError):
        c.verify(n="100")  # type: ignore[arg-type]
    with pytest.raises(gc.ArgumentError):
        c.mu_d_of(1.5)
    with pytest.raises(gc.ArgumentError):
        c.nu(np.zeros(3))
    with pytest.raises(gc.ArgumentError):
        c.W(np.array([-1.0, 0.0]), np.zeros(2))  # V = 0: C_W is singular
    with pytest.raises(gc.ArgumentTypeError):
        CompositeCertificate.Phi("p")
    with pytest.raises(gc.ArgumentError):
        c.in_estimate(np.full(4, np.nan))
    with pytest.raises(gc.ArgumentTypeError):
        c.domain.sample(10, 0)  # type: ignore[arg-type]
    # points outside the box (even with Vbar <= -1) are simply outside the estimate
    assert not c.in_estimate(np.array([-2.0, 0.0, 0.0, 0.0])) and c.in_estimate(np.zeros(4))
    # complex points stay accepted by nu (complex-step gradients of the buoyancy controller)
    h = 1e-30
    g = np.imag(c.nu(np.array([1j * h, 0.1, 0.05, 0.0]))) / h
    assert np.isfinite(g)


@settings(max_examples=10, deadline=None)
@given(st.floats(-0.9, 1.5), st.floats(-math.pi, math.pi), st.floats(-0.5, 0.5), st.floats(-3.0, 3.0),
       st.sampled_from([{}, {"K_M": -100.0}, {"J2": 0.01}]))
def test_f_and_g_equal_the_separate_fields_exactly(Vb, gb, ab, ob, ov):
    """verify() takes f, g and g(eps = 0) from one right-hand-side evaluation: the same numbers, bit for bit, as the
    three separate calls (and the boundary layer as g(eps = 0) times diag(r1, r2))."""
    sp = gc.singular_perturbation(gc.load_vehicle("sphere_ch5", **ov))
    p = np.array([[Vb, gb], [0.5 * Vb, -gb]])
    q = np.array([[ab, ob], [-ab, 0.1 * ob]])
    f, g_eps, g_0 = sp.scaling.f_and_g(p, q)
    assert np.array_equal(f, sp.f(p, q))
    assert np.array_equal(g_eps, sp.g(p, q))
    assert np.array_equal(g_0, sp.g(p, q, eps=False))
    assert np.array_equal(g_0 * np.array([sp.scaling.r1, sp.scaling.r2]), sp.boundary_layer_rhs(p, q))
    assert not np.array_equal(g_eps, g_0) or gb == 0  # eps1 f2 is a real term: the two g differ off gamma = 0
