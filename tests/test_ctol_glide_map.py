"""Theorem 4 over a grid (ctol_glide_map): the same glides as ctol_glide point by point, NaN where none exists."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc

DC8 = gc.load_vehicle("dc8_ctol")


def test_map_equals_point_by_point_theorem4():
    speeds, gammas = np.array([0.1, 0.3]), np.radians([-60.0, 0.0, 60.0])
    m = gc.ctol_glide_map(DC8, speeds, gammas, [(10.0, 5.0)])
    assert m.alpha.shape == m.thrust.shape == (2, 3) and m.provenance == DC8.provenance
    worst, res = -math.inf, 0.0
    for i, v in enumerate(speeds):
        for j, g in enumerate(gammas):
            try:
                gl = gc.ctol_glide(DC8, float(v), float(g))
            except gc.InfeasibleGlideError:
                assert math.isnan(m.alpha[i, j]) and math.isnan(m.thrust[i, j])
                continue
            assert m.alpha[i, j] == gl.alpha and m.thrust[i, j] == gl.thrust
            res = max(res, gl.residual)
            worst = max(worst, float(np.max(gc.ctol_closed_loop_eigenvalues(DC8, gl, 10.0, 5.0).real)))
    assert m.feasible.any() and m.max_residual == res and m.max_real_eig == {(10.0, 5.0): worst}
    assert worst < 0  # Theorem 5: every steady glide is exponentially stable for k3, k4 > 0
    assert m.negative_thrust_fraction == np.sum(m.thrust < 0) / np.sum(m.feasible)
    assert "Theorem 4 map: 2 speeds x 3" in m.summary()
    with pytest.raises(ValueError):
        m.alpha[0, 0] = 1.0  # read-only


@pytest.mark.parametrize(("args", "exc"), [
    ((gc.load_vehicle("rogue"), [0.1], [0.0]), gc.ModelError),
    ((DC8, [], [0.0]), gc.ArgumentError),
    ((DC8, [-0.1], [0.0]), gc.ArgumentError),
    ((DC8, [0.1], [4.0]), gc.ArgumentError),
    ((DC8, [0.1], [0.0], [(1.0,)]), gc.ArgumentError),
    ((DC8, [0.1], [0.0], [(1.0, -1.0)]), gc.ArgumentError),
    ((DC8, [0.1], [0.0], "k3"), gc.ArgumentTypeError),
    ((DC8, np.linspace(0.1, 0.5, 1000), np.linspace(-1, 1, 1000)), gc.BudgetError),
])
def test_bad_arguments(args, exc):
    with pytest.raises(exc):
        gc.ctol_glide_map(*args)
