"""Issue 17: ``ROACertificate.volume(method=...)``, the directed (angular central Gaussian) volume of a certified set.

A thin set in many states holds no Sobol point of its box, so the Sobol estimate is 0; the directed estimate
integrates the boundary radius ``R(u)`` along rays from the equilibrium,
``vol = prod(w) |B^nf| / sqrt(det H) E_ACG[(R(u)^2 u'Hu)^(nf/2)]``, which is exact for an ellipsoid. Checked against
closed-form volumes of ellipsoids (rotated, thin, cut by the box) and against the Sobol estimate on a fat
non-ellipsoidal set; ``"auto"`` keeps the Sobol number whenever enough of its points are inside. The LMI
certificate's ``EllipsoidCertificate.volume`` in an explicit box gets the same three methods (exact ray integral of
the ellipsoid cut by the box)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.stats import qmc

import glidectl as gc
from glidectl.analysis.measure import MIN_SOBOL_HITS, unit_sobol
from glidectl.errors import ArgumentError
from glidectl.roa import Poly, polynomial_system
from glidectl.roa.certificate import PathPoints, ROACertificate, ROAVerification, _volume_directed, step_volume


def _system(n: int, lo, hi):
    Z = Poly.variables(n)
    return polynomial_system(f"linear{n}", tuple(f"x{i}" for i in range(n)), [-z for z in Z], box=(lo, hi))


def _certificate(ps, V: Poly, rho: float) -> ROACertificate:
    """A certificate of ``{V <= rho}`` without solving anything (volume only reads system, V and rho)."""
    ver = ROAVerification((), 1.0, -1.0, 0, -1.0, 0, 0, 1.0)
    return ROACertificate(ps, V, rho, rho, V.degree, (), ver, 0.0, 0.0)


def _ball(n: int) -> float:
    return math.pi ** (n / 2) / math.gamma(n / 2 + 1)


def _ellipsoid_volume(P: np.ndarray, rho: float) -> float:
    """Volume of ``{x' P x <= rho}``."""
    n = P.shape[0]
    return _ball(n) * rho ** (n / 2) / math.sqrt(np.linalg.det(P))


def _rotated_P(axes, seed: int) -> np.ndarray:
    Q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((len(axes), len(axes))))
    return Q @ np.diag(1.0 / np.asarray(axes) ** 2) @ Q.T


@pytest.mark.parametrize(("nf", "axes"), [(2, (1.5, 0.4)), (8, (0.9, 0.6, 0.5, 0.4, 0.3, 0.3, 0.2, 0.15))])
def test_directed_volume_of_a_rotated_ellipsoid_is_exact(nf, axes):
    P = _rotated_P(axes, nf)
    rho = 2.0                     # semi-axes sqrt(2) * axes: inside the box [-2, 3]^nf (off-centre box: w = 3)
    ps = _system(nf, [-2.0] * nf, [3.0] * nf)
    cert = _certificate(ps, Poly.quadratic(P), rho)
    exact = _ellipsoid_volume(P, rho)
    lo, hi = ps.box
    vol, err = _volume_directed(ps, cert.V, rho, lo, hi, 512, 0)
    # W(u) is constant on an ellipsoid: the estimate is exact up to the bisection (2^-40 of the box)
    assert vol == pytest.approx(exact, rel=1e-9) and err <= 1e-9 * exact
    assert cert.volume(method="directed", n=2**10) == pytest.approx(exact, rel=1e-9)


def test_thin_8d_ellipsoid_sobol_is_zero_and_auto_is_exact():
    axes = np.array([1.0] + [0.05] * 7)
    P = _rotated_P(axes, 3)
    ps = _system(8, [-1.5] * 8, [1.5] * 8)
    cert = _certificate(ps, Poly.quadratic(P), 1.0)
    exact = _ellipsoid_volume(P, 1.0)           # 4.06 * 0.05^7 = 3.2e-9 in a box of 3^8 = 6561
    assert cert.volume(method="sobol") == 0.0   # no Sobol point falls inside (today's answer)
    auto = cert.volume(n=2**14)
    assert auto == pytest.approx(exact, rel=1e-9)
    assert cert.volume(n=2**14, method="directed") == auto
    assert cert.volume(n=2**12, seed=4) == pytest.approx(exact, rel=1e-9)


def test_alternation_judges_a_thin_set_by_the_directed_estimate():
    # certify_roa keeps the V step whose set is largest; a thin set holds none of its 8192 Sobol points, so by the
    # Sobol fraction every step had volume 0 and none was ever kept (the user glider's unsaturated loop)
    axes = np.array([1.0] + [0.05] * 7)
    P = _rotated_P(axes, 3)
    ps = _system(8, [-1.5] * 8, [1.5] * 8)
    lo, hi = ps.box
    pts = PathPoints(ps, lo + (hi - lo) * unit_sobol(8, 2, 2**13))
    V = Poly.quadratic(P)
    assert not np.any(pts.contains(V, 1.0))
    assert step_volume(ps, pts, V, lo, hi, 0) == pytest.approx(_ellipsoid_volume(P, 1.0), rel=1e-9)
    # a larger thin set is judged larger (with the Sobol fraction both were 0)
    assert step_volume(ps, pts, V * (1 / 1.2), lo, hi, 0) == pytest.approx(1.2 ** 4 * _ellipsoid_volume(P, 1.0),
                                                                             rel=1e-9)
    # at another level (the history's final-margin rows): the same set
    assert step_volume(ps, pts, V, lo, hi, 0, rho=1.2) == pytest.approx(1.2 ** 4 * _ellipsoid_volume(P, 1.0),
                                                                          rel=1e-9)


def test_alternation_keeps_the_sobol_fraction_on_a_fat_set():
    cert = _fat_quartic()
    ps = cert.system
    lo, hi = ps.box
    pts = PathPoints(ps, lo + (hi - lo) * unit_sobol(2, 2, 2**13))
    V = cert.V * (1 / cert.rho)
    inside = pts.contains(V, 1.0)
    assert np.count_nonzero(inside) >= MIN_SOBOL_HITS
    assert step_volume(ps, pts, V, lo, hi, 0) == float(np.prod(hi - lo) * np.mean(inside))


def _cut_volume(ax: np.ndarray, clip: float) -> float:
    """Volume of the axis-aligned ellipsoid with semi-axes ``ax`` cut at ``|x0| <= clip``."""
    n = len(ax)
    f = lambda t: (1.0 - (t / ax[0]) ** 2) ** ((n - 1) / 2)     # noqa: E731
    return _ball(n - 1) * float(np.prod(ax[1:])) * quad(f, -clip, clip)[0]


@pytest.mark.parametrize("nf", [2, 8])
def test_rays_stop_at_the_requested_box(nf):
    ax = np.array([1.0] + [0.05 if nf == 8 else 0.5] * (nf - 1))
    ps = _system(nf, [-1.5] * nf, [1.5] * nf)
    cert = _certificate(ps, Poly.quadratic(np.diag(1.0 / ax ** 2)), 1.0)
    lo, hi = np.full(nf, -1.0), np.full(nf, 1.0)
    lo[0], hi[0] = -0.5, 0.4                     # cuts both ends of the long axis
    exact = _cut_volume(ax, 0.5) / 2 + _cut_volume(ax, 0.4) / 2
    vol, err = _volume_directed(ps, cert.V, 1.0, lo, hi, 2**12, 0)
    assert 0 < err < 0.05 * exact                # W(u) is no longer constant: a real standard error
    assert abs(vol - exact) <= 4 * err
    assert cert.volume((lo, hi), method="directed", n=2**16) == vol    # ceil(n / 16) directions
    # the uncut ellipsoid is larger: the box did cut the rays
    assert vol < 0.9 * _ellipsoid_volume(np.diag(1.0 / ax ** 2), 1.0)
    if nf == 2:                                  # fat: Sobol has thousands of points inside, auto keeps it
        sob = cert.volume((lo, hi), method="sobol")
        assert cert.volume((lo, hi)) == sob and sob == pytest.approx(exact, rel=0.01)


def _fat_quartic():
    """A fat 2-D set that is not an ellipsoid: ``V = x^2 + x y + y^2 + x^4 / 2 + x^2 y^2 / 3 <= 1.2`` in the Van der
    Pol box."""
    vdp = gc.benchmarks.van_der_pol()
    x, y = Poly.variables(2)
    V = x ** 2 + x * y + y ** 2 + 0.5 * x ** 4 + (1.0 / 3.0) * x ** 2 * y ** 2
    return _certificate(vdp, V, 1.2)


def test_fat_non_ellipsoidal_set_sobol_and_directed_agree():
    cert = _fat_quartic()
    ps = cert.system
    lo, hi = ps.box
    box = float(np.prod(hi - lo))
    n = 2**14
    sob = cert.volume(n=n, method="sobol")
    p = sob / box
    assert p * n > 1000                                          # fat: Sobol is the right tool here
    sob_err = box * math.sqrt(p * (1 - p) / n)                   # random-point error (scrambled Sobol is smaller)
    vol, err = _volume_directed(ps, cert.V, cert.rho, lo, hi, n // 16, 1)
    assert err > 1e-4 * vol                                      # not an ellipsoid: W varies
    assert abs(vol - sob) <= 4 * math.hypot(err, sob_err)
    assert cert.volume(n=n, seed=1, method="directed") == vol
    # auto keeps today's number bitwise: the plain box_measure of contains
    assert cert.volume(n=n) == sob == gc.box_measure(cert.contains, ps.box, n, 0, dim=2)


def test_auto_switches_below_the_hit_threshold():
    # a disc whose Sobol count straddles the threshold as n grows: auto is Sobol exactly when it has enough hits
    ps = _system(2, [-4.0, -4.0], [4.0, 4.0])
    r = 0.5
    cert = _certificate(ps, Poly.quadratic(np.eye(2)), r * r)
    exact = math.pi * r * r
    for n in (2**10, 2**16):
        sob = cert.volume(n=n, method="sobol")
        hits = round(sob / 64.0 * n)
        auto = cert.volume(n=n)
        if hits >= MIN_SOBOL_HITS:
            assert auto == sob
        else:
            assert auto == pytest.approx(exact, rel=1e-9) and auto != sob
    assert round(cert.volume(n=2**10, method="sobol") / 64.0 * 2**10) < MIN_SOBOL_HITS      # both branches ran
    assert round(cert.volume(n=2**16, method="sobol") / 64.0 * 2**16) >= MIN_SOBOL_HITS


def _held(ps2, box3):
    """``ps2`` (free states x1, x2) embedded in three states with ``x3`` held at 1 (as certify_roa's embed_held)."""
    lift0 = ps2.lift
    return dataclasses.replace(ps2, state_names=("x1", "x2", "x3"), lift=lambda X: lift0(np.asarray(X)[..., :2]),
                               equilibrium=np.array([0.0, 0.0, 1.0]), box=box3, held=(2,))


def test_held_states_volume_in_the_free_states():
    P = _rotated_P((1.2, 0.3), 5)
    ps2 = _system(2, [-2.0, -2.0], [2.0, 2.0])
    ps = _held(ps2, (np.array([-2.0, -2.0, 0.5]), np.array([2.0, 2.0, 1.5])))
    cert = _certificate(ps, Poly.quadratic(P), 1.0)
    exact = _ellipsoid_volume(P, 1.0)
    assert cert.volume(method="directed") == pytest.approx(exact, rel=1e-9)
    sob = cert.volume(method="sobol")
    assert cert.volume() == sob and sob == pytest.approx(exact, rel=0.01)
    # the held state's box range does not enter (even one that does not contain its value, as for Sobol)
    other = (np.array([-2.0, -2.0, 3.0]), np.array([2.0, 2.0, 4.0]))
    assert cert.volume(other, method="directed") == pytest.approx(exact, rel=1e-9)
    assert cert.volume(other, method="sobol") == sob


def test_held_states_thin_set_auto_is_directed():
    nf = 8
    P = _rotated_P([0.8] + [0.04] * (nf - 1), 6)
    Z = Poly.variables(nf)
    ps0 = polynomial_system("thin", tuple(f"x{i}" for i in range(nf)), [-z for z in Z],
                            box=([-1.0] * nf, [1.0] * nf))
    lift0 = ps0.lift
    ps = dataclasses.replace(ps0, state_names=(*ps0.state_names, "h"), lift=lambda X: lift0(np.asarray(X)[..., :nf]),
                             equilibrium=np.append(np.zeros(nf), 2.0),
                             box=(np.append(-np.ones(nf), 1.0), np.append(np.ones(nf), 3.0)), held=(nf,))
    cert = _certificate(ps, Poly.quadratic(P), 1.0)
    assert cert.volume(method="sobol") == 0.0
    assert cert.volume() == pytest.approx(_ellipsoid_volume(P, 1.0), rel=1e-9)


def test_bad_method_and_box_refused():
    cert = _fat_quartic()
    for bad in ("Sobol", "mc", None, 3):
        with pytest.raises(ArgumentError, match="method"):
            cert.volume(method=bad)
    off = (np.array([1.0, 1.0]), np.array([2.0, 2.0]))          # the equilibrium (0, 0) is not in this box
    with pytest.raises(ArgumentError, match="equilibrium"):
        cert.volume(off, method="directed")
    assert cert.volume(off) == cert.volume(off, method="sobol")  # auto falls back to Sobol there
    with pytest.raises(ArgumentError):
        cert.volume(((1.0, 1.0), (0.0, 0.0)), method="directed")
    with pytest.raises(ArgumentError):
        cert.volume(n=0, method="directed")
    # an empty set (level below V(x_e) = 0): every radius is 0, the volume is 0 (not an error, as Sobol)
    empty = _certificate(cert.system, cert.V, -1.0)
    assert empty.volume(method="directed", n=64) == 0.0 and empty.volume(n=64) == 0.0


# --------------------------------------------------------------------------------------------- LMI ellipsoids
def _ellipsoid_certificate(P: np.ndarray, box: float, held: bool = False):
    """An :class:`EllipsoidCertificate` of ``{dX' P dX <= 1}`` for a linear saturated loop (no SDP solved); with
    ``held``, one more state held at 2."""
    from glidectl.roa.lmi import EllipsoidCertificate

    nf = P.shape[0]
    n = nf + held
    K = np.zeros((1, n))
    K[0, 0] = -1.0
    xe = np.zeros(n)
    lo, hi = -np.full(n, box), np.full(n, box)
    if held:
        xe[-1], lo[-1], hi[-1] = 2.0, 1.0, 3.0
    loop = gc.SaturatedLoop("lin", tuple(f"x{i}" for i in range(n)), ("u",), lambda X, W: -(X - xe) + 0 * W[:, :1],
                            xe, K, np.array([-1.0]), np.array([1.0]), (lo, hi), held=(n - 1,) if held else ())
    return EllipsoidCertificate(loop, P, np.zeros((1, nf)), np.zeros((nf, nf, nf)), np.full(nf, box),
                                np.full(nf, box), (lo, hi), None, (), 0.0, 0.0, 0.0)


@pytest.mark.parametrize("held", [False, True])
def test_lmi_thin_ellipsoid_in_a_box_is_not_zero(held):
    P = _rotated_P([0.8] + [0.03] * 7, 8)
    cert = _ellipsoid_certificate(P, 1.0, held)
    exact = cert.volume()                                        # closed form (box None)
    assert exact == pytest.approx(_ellipsoid_volume(P, 1.0), rel=1e-12)
    assert cert.volume(cert.box, method="sobol") == 0.0          # today's answer in an explicit box
    assert cert.volume(cert.box) == pytest.approx(exact, rel=1e-12)   # the box does not cut it: exact
    assert cert.volume(cert.box, n=16, method="directed") == pytest.approx(exact, rel=1e-12)


def test_lmi_ellipsoid_cut_by_a_box():
    from glidectl.roa.lmi import _ellipsoid_box_weights

    ax = np.array([1.0, 0.5])
    P = np.diag(1.0 / ax ** 2)
    cert = _ellipsoid_certificate(P, 2.0)
    lo, hi = np.array([-0.5, -1.0]), np.array([0.4, 1.0])
    exact = _cut_volume(ax, 0.5) / 2 + _cut_volume(ax, 0.4) / 2
    n = 2**14
    Wt = _ellipsoid_box_weights(P, lo, hi, n, 0)
    err = math.pi * 0.5 * float(np.std(Wt, ddof=1)) / math.sqrt(n)
    vol = cert.volume((lo, hi), n=n, method="directed")
    assert vol == pytest.approx(math.pi * 0.5 * float(np.mean(Wt)), rel=1e-12)
    assert 0 < err < 0.01 * exact and abs(vol - exact) <= 4 * err
    sob = cert.volume((lo, hi), n=n, method="sobol")
    assert cert.volume((lo, hi), n=n) == sob and sob == pytest.approx(exact, rel=0.01)   # fat: auto is Sobol
    # today's Sobol number, bit for bit
    X = lo + (hi - lo) * qmc.Sobol(2, seed=0).random(n)
    assert sob == float(np.prod(hi - lo) * np.mean(cert.contains(X)))


def test_lmi_bad_method_refused():
    cert = _ellipsoid_certificate(np.eye(2), 2.0)
    with pytest.raises(ArgumentError, match="method"):
        cert.volume(method="quasi")
    off = (np.array([0.5, 0.5]), np.array([1.0, 1.0]))
    with pytest.raises(ArgumentError, match="equilibrium"):
        cert.volume(off, method="directed")
    assert cert.volume(off) == cert.volume(off, method="sobol")
