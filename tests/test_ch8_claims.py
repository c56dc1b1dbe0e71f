"""The §8.2.2 statements about the helix maps, tested as properties of the model (symmetry, sign rules, straight
glides out of the plane, coexisting helices) and through the claim checks of the ch8 design (designs/ch8_helix.py)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from glidectl import (
    FixedMassGlider3D,
    classify_motion,
    existence_scan,
    helix_sweep,
    helix_trim,
    load_vehicle,
    straight_glides,
)
from glidectl.report import load_design
from glidectl.trim.helix import helix_equations

ROOT = Path(__file__).resolve().parents[1]
ch8_claims = load_design(ROOT / "designs" / "ch8_helix.py").module  # the claim checks live in the design file
SLOCUM = load_vehicle("slocum_ch8")
SETTINGS = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _mirror(y: np.ndarray) -> np.ndarray:
    """Reflection y -> -y of the trim unknowns (v1, v2, v3, psidot, theta, phi)."""
    return np.array([y[0], -y[1], y[2], -y[3], y[4], -y[5]])


@SETTINGS
@given(r1=st.floats(0.005, 0.03), r2=st.floats(0.003, 0.04), r3=st.floats(0.02, 0.08), m0=st.floats(0.1, 0.5),
       light=st.booleans())
@example(r1=0.005, r2=0.005859375, r3=0.032355798787735895, m0=0.46875, light=True)  # two coexisting helices
def test_reflected_helix_is_a_helix_of_the_reflected_mass_position(r1, r2, r3, m0, light):
    """§8.2.2: equilibria are symmetric about r_P2 = 0. The reflection (v2, psidot, phi) -> -(v2, psidot, phi) of a
    helix at r_P2 solves the trim equations at -r_P2 exactly, with the same radius and opposite sideslip."""
    if light:
        r1, m0 = -r1, -m0
    h = helix_trim(SLOCUM, (r1, r2, r3), m0)
    mirrored = FixedMassGlider3D(SLOCUM, (r1, -r2, r3), m0)
    res = np.max(np.abs(helix_equations(mirrored, _mirror(h.unknowns))))
    assert res < 1e-10
    # the solver started from the mirrored helix converges to it (a cold solve may find another helix: several
    # coexist, e.g. r_P = (-0.5, 0.59, 3.2) cm, m0 = -0.469 kg has helices of radius 20.7 m and 4.45 m)
    hm = helix_trim(SLOCUM, (r1, -r2, r3), m0, guess=_mirror(h.unknowns))
    np.testing.assert_allclose(hm.unknowns, _mirror(h.unknowns), atol=1e-8)
    assert hm.radius == pytest.approx(h.radius, rel=1e-8)
    assert hm.beta == pytest.approx(-h.beta, abs=1e-10)


@SETTINGS
@given(r2=st.floats(0.002, 0.04), m0=st.floats(0.1, 0.5), s2=st.sampled_from([-1, 1]), light=st.booleans())
def test_sideslip_has_the_sign_of_m0_times_r_p2(r2, m0, s2, light):
    """The thesis's rule "beta > 0 when m0 and r_P2 have opposite signs" is reversed in the model: on the maps of
    Fig 8.7-8.8 (r_P1 = 2 sign(m0) cm, r_P3 = 4 cm) sign(beta) = sign(m0 r_P2)."""
    m0 = -m0 if light else m0
    h = helix_trim(SLOCUM, (math.copysign(0.02, m0), s2 * r2, 0.04), m0)
    assert np.sign(h.beta) == np.sign(m0 * s2 * r2)


def test_printed_initial_condition_has_the_sideslip_sign_of_our_helix():
    """§8.2.2's own example (r_P2 = +2 cm, m0 = +0.25 kg) starts from v2 = +0.014 m/s: beta > 0 with m0, r_P2 of the
    same sign, as our model gives and against the printed rule."""
    h = helix_trim(SLOCUM, (0.02, 0.02, 0.04), 0.25)
    assert h.beta > 0 and math.copysign(1, 0.014) == math.copysign(1, h.v[1])


def test_critical_r_p3_is_a_straight_glide_out_of_the_plane():
    """Fig 8.9: a critical r_P3 gives Omega = 0 with beta != 0 (m0 > 0)."""
    sw = helix_sweep(SLOCUM, "r_P3", np.linspace(0.019, 0.025, 7), r_p=(0.02, 0.02, 0.04), m0=0.25)
    (h,) = straight_glides(SLOCUM, sw)
    assert abs(h.psidot) < 1e-9 and 0.019 < h.r_p[2] < 0.025
    assert classify_motion(h.v, np.zeros(3))["kind"] == "straight line"
    assert math.degrees(h.beta) > 1.0  # not in the longitudinal plane
    assert h.residual < 1e-10 and h.stable


def test_straight_glides_none_without_sign_change():
    sw = helix_sweep(SLOCUM, "r_P1", np.linspace(0.01, 0.02, 5), r_p=(0.02, 0.02, 0.04), m0=0.25)
    assert straight_glides(SLOCUM, sw) == ()


def test_two_stable_helices_coexist_between_the_folds_of_fig8_9():
    """Near r_P3 = 1.54 cm (m0 = 0.25 kg) the branch continued from small r_P3 and the branch of the nominal helix
    overlap: two distinct stable helices at the same control parameters."""
    x = 0.0154
    lo = helix_trim(SLOCUM, (0.02, 0.02, 0.014), 0.25)
    for r3 in np.linspace(0.014, x, 15)[1:]:
        lo = helix_trim(SLOCUM, (0.02, 0.02, r3), 0.25, guess=lo, n_random=0)
    hi = helix_trim(SLOCUM, (0.02, 0.02, 0.02), 0.25)
    for r3 in np.linspace(0.02, x, 47)[1:]:
        hi = helix_trim(SLOCUM, (0.02, 0.02, r3), 0.25, guess=hi, n_random=0)
    assert lo.r_p == hi.r_p
    assert max(lo.residual, hi.residual) < 1e-10
    assert lo.stable and hi.stable
    assert np.linalg.norm(lo.unknowns - hi.unknowns) > 1e-2
    assert abs(lo.psidot - hi.psidot) > 0.01  # rad/s: distinct turn rates, far above the trim tolerance


def test_existence_claim_is_refuted_with_stable_upright_motions():
    scan = existence_scan(SLOCUM, [-0.02, 0.02], [-0.25, 0.25], n_starts=4, continuation=False)
    c = ch8_claims.existence_claim(scan)
    assert c.reproduced is False and c.value == 2
    for ce in scan.counterexamples(stable_only=True, upright_only=True):
        h = helix_trim(SLOCUM, (ce["r_P1"], 0.02, 0.04), ce["m0"], guess=ce["unknowns"], n_random=0)
        assert h.residual < 1e-10 and h.stable and abs(h.phi) < math.pi / 2
        assert np.sign(ce["r_P1"]) == -np.sign(ce["m0"])


def test_speed_scales_like_the_square_root_of_buoyancy():
    """Fig 8.11-8.12: V ~ |m0|^n with n near 1/2 (force balance |m0| g ~ V^2), not linear as 8.2.2 says."""
    vals = np.linspace(0.05, 0.6, 8)
    heavy = helix_sweep(SLOCUM, "m0", vals, r_p=(0.02, 0.02, 0.04))
    light = helix_sweep(SLOCUM, "m0", -vals[::-1], r_p=(-0.02, 0.02, 0.04))
    speed, radius = ch8_claims.m0_claims(heavy, light)
    assert speed.reproduced is False
    assert all(0.4 < n < 0.6 for n in speed.value)
    assert radius.reproduced is True


def test_r_p2_claims_on_a_coarse_map():
    vals = np.linspace(-0.04, 0.04, 9)
    heavy = helix_sweep(SLOCUM, "r_P2", vals, r_p=(0.02, 0.02, 0.04), m0=0.25)
    light = helix_sweep(SLOCUM, "r_P2", vals, r_p=(-0.02, 0.02, 0.04), m0=-0.25)
    claims = {c.name: c for c in ch8_claims.r_p2_claims(heavy, light)}
    assert claims["claim_beta_sign_rule"].reproduced is False
    assert claims["claim_beta_sign_rule"].value == "0/16"
    assert claims["claim_fig8_7_8_symmetry"].reproduced is True
    assert claims["claim_fig8_7_8_symmetry"].value < 1e-8
    assert claims["claim_fig8_7_8_roll_range"].reproduced is True
