"""Areas and volumes of the thesis's region-of-attraction estimates (CompositeCertificate.phi_area and
.estimate_volume)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc

CC = gc.CompositeCertificate


def test_phi_area_closed_form_and_in_a_box():
    # sqrt(3) int_{-pi/2}^{pi/2} sqrt(cos g) dg = sqrt(3) sqrt(pi) Gamma(3/4) / Gamma(5/4)
    exact = math.sqrt(3 * math.pi) * math.gamma(0.75) / math.gamma(1.25)
    assert CC.phi_area() == pytest.approx(exact, rel=1e-10)
    # a box around the whole set {-1 < Vbar < sqrt(3 cos g) - 1, |g| < pi/2} measures the same area (QMC error)
    whole = CC.phi_area(([-1.0, -math.pi / 2], [math.sqrt(3) - 1, math.pi / 2]), n=2**14)
    assert whole == pytest.approx(exact, rel=5e-3)
    # half the box in gammabar: half the area (the set is symmetric in gammabar)
    half = CC.phi_area(([-1.0, 0.0], [math.sqrt(3) - 1, math.pi / 2]), n=2**14)
    assert half == pytest.approx(exact / 2, rel=5e-3)
    # a box inside the set: its whole area
    assert CC.phi_area(([-0.1, -0.1], [0.1, 0.1]), n=64) == pytest.approx(0.04, rel=1e-12)
    assert CC.phi_area(([-1.0, -math.pi / 2], [math.sqrt(3) - 1, math.pi / 2]), level=1e-9, n=256) == 0.0


def test_phi_area_bad_arguments():
    with pytest.raises(gc.ArgumentError, match="pass a box"):
        CC.phi_area(level=0.5)
    with pytest.raises(gc.ArgumentError, match="lo < hi"):
        CC.phi_area(([0.0, 0.0], [0.0, 1.0]))
    with pytest.raises(gc.ArgumentTypeError, match="pair"):
        CC.phi_area(np.zeros((2, 2)))
    with pytest.raises(gc.ArgumentError):
        CC.phi_area(([0.0, 0.0], [1.0, 1.0]), n=0)


def test_estimate_volume_counts_the_estimate():
    veh = gc.load_vehicle("sphere_ch5", K_M=-100.0)
    cert = gc.composite_lyapunov(veh, Vbar=(-0.5, 0.5), gammabar=(-0.5, 0.5), alphabar=(-0.3, 0.3),
                                 Omegabar=(-1.0, 1.0))
    v = cert.estimate_volume(n=2**12)
    assert 0.0 < v < 0.6  # inside the domain box of volume 1 x 1 x 0.6 x 2 = 1.2
    # L* lies in the domain: a twice larger box finds the same volume up to the QMC error
    big = cert.estimate_volume(([-1.0 + 1e-9, -1.0, -0.6, -2.0], [1.0, 1.0, 0.6, 2.0]), n=2**16)
    assert big == pytest.approx(cert.estimate_volume(n=2**14), rel=0.05)
    # the default box is the domain itself
    assert v == cert.estimate_volume(([-0.5, -0.5, -0.3, -1.0], [0.5, 0.5, 0.3, 1.0]), n=2**12)
    with pytest.raises(gc.ArgumentError, match="4"):
        cert.estimate_volume(([0.0, 0.0], [1.0, 1.0]))


def test_box_measure_exact_cases_and_errors():
    # a half plane cuts the unit square in half; its Sobol points are balanced, so 2^k points give 1/2 exactly
    assert gc.box_measure(lambda X: X[:, 0] < 0.5, ([0.0, 0.0], [1.0, 1.0]), n=2**10) == 0.5
    # a disc of radius 1 in [-1, 1]^2: pi, to the QMC error
    assert gc.box_measure(lambda X: np.sum(X**2, axis=1) <= 1, ([-1.0, -1.0], [1.0, 1.0]), n=2**14) == \
        pytest.approx(math.pi, rel=2e-3)
    vol, X = gc.box_points(([1.0, -2.0, 0.0], [3.0, 2.0, 0.5]), n=16, seed=3)
    assert vol == 4.0 and X.shape == (16, 3) and np.all((X >= [1, -2, 0]) & (X < [3, 2, 0.5]))
    np.testing.assert_array_equal(X, gc.box_points(([1.0, -2.0, 0.0], [3.0, 2.0, 0.5]), n=16, seed=3)[1])
    with pytest.raises(gc.ArgumentError, match=r"shape \(3,\)"):
        gc.box_points(([0.0, 0.0], [1.0, 1.0]), dim=3)
    with pytest.raises(gc.ArgumentError, match="lo < hi"):
        gc.box_points(([0.0, 1.0], [1.0, 1.0]))
    with pytest.raises(gc.ArgumentTypeError, match="pair"):
        gc.box_measure(lambda X: X[:, 0] > 0, "box")
    with pytest.raises(gc.ArgumentTypeError, match="indicator"):
        gc.box_measure(None, ([0.0], [1.0]))
    with pytest.raises(gc.ModelError, match="booleans"):
        gc.box_measure(lambda X: X[:, 0], ([0.0], [1.0]), n=8)
