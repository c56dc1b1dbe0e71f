"""Issue 17 part 3: one default box (glidectl.validity_box) for gc.certify_roa and gc.saturated_loop: actuator
ranges and rates of the vehicle file, a narrow band about a fixed actuator, the documented half-widths of the glider
states; unknown states refused in both; box= overrides; cert.box and cert.scale report what was used."""

from __future__ import annotations

import math

import numpy as np
import pytest

import glidectl as gc
from glidectl.errors import ArgumentError, ArgumentTypeError
from glidectl.roa.scaling import DEFAULT_HALF_WIDTH, box_scale, resolve_box
from glidectl.roa.surrogate import surrogate_system

SHRINK = 1 - 1e-3


def _slocum_lqr_loop(reduce_fixed: bool = True):
    veh = gc.load_vehicle("slocum_shallow")
    glide = gc.steady_glide(veh, 0.35, math.radians(-25.0), r_p3=veh.actuators["r_P3"].fixed)
    return gc.closed_loop(gc.lqr_glide(veh, glide, inputs="acceleration", reduce_fixed=reduce_fixed))


def _buoyancy_loop():
    sph = gc.load_vehicle("sphere_ch5")
    return gc.closed_loop(gc.BuoyancyController(gc.buoyancy_equilibrium(sph, 1.5), sph, 5.0))


def _shrunk(lo, hi):
    c = 0.5 * (lo + hi)
    return c + SHRINK * (lo - c), c + SHRINK * (hi - c)


@pytest.mark.parametrize("make", [_slocum_lqr_loop, _buoyancy_loop], ids=["slocum LQR", "ch6 buoyancy"])
def test_certify_roa_and_saturated_loop_default_to_the_same_box(make):
    loop = make()
    lo, hi = gc.validity_box(loop)
    sl = gc.saturated_loop(loop)
    rlo, rhi = resolve_box(loop)                       # what certify_roa uses without box=
    assert np.array_equal(rlo, lo) and np.array_equal(rhi, hi)
    assert np.array_equal(sl.box[0], lo) and np.array_equal(sl.box[1], hi)


def test_validity_box_values_of_the_slocum_loop():
    assert "r_P3" not in _slocum_lqr_loop().state_names       # the design model drops the fixed actuator
    loop = _slocum_lqr_loop(reduce_fixed=False)
    acts = loop.vehicle.actuators
    xe = loop.equilibrium
    lo, hi = gc.validity_box(loop)
    box = {k: (lo[i], hi[i]) for i, k in enumerate(loop.state_names)}
    assert box["m0"] == pytest.approx(_shrunk(acts["m0"].min, acts["m0"].max), rel=1e-15)
    assert box["r_P1"] == pytest.approx(_shrunk(acts["r_P1"].min, acts["r_P1"].max), rel=1e-15)
    assert box["rdot_P1"] == pytest.approx((-SHRINK * acts["r_P1"].rate, SHRINK * acts["r_P1"].rate), rel=1e-15)
    # r_P3 is fixed by the vehicle file: a 1e-3 band about its value (and its zero rate), not a generic width
    assert box["r_P3"] == pytest.approx((0.05 - SHRINK * 1e-3, 0.05 + SHRINK * 1e-3), rel=1e-12)
    assert box["rdot_P3"] == pytest.approx((-SHRINK * 1e-3, SHRINK * 1e-3), rel=1e-12)
    for k in ("z_prime", "theta", "Omega2", "v1", "v3"):
        w, kind = DEFAULT_HALF_WIDTH[k]
        x = xe[loop.state_names.index(k)]
        w = w * abs(x) if kind == "rel" else w
        assert box[k] == pytest.approx((x - SHRINK * w, x + SHRINK * w), rel=1e-12, abs=1e-15), k
    assert np.all(lo < xe) and np.all(xe < hi)


def test_box_argument_overrides_the_default():
    loop = _slocum_lqr_loop()
    lo0, hi0 = gc.validity_box(loop)
    i = loop.state_names.index("theta")
    lo, hi = resolve_box(loop, {"theta": (-0.6, -0.2)})
    assert (lo[i], hi[i]) == (-0.6, -0.2)
    keep = np.arange(len(lo)) != i
    assert np.array_equal(lo[keep], lo0[keep]) and np.array_equal(hi[keep], hi0[keep])
    xe = loop.equilibrium
    lo, hi = resolve_box(loop, (xe - 0.01, xe + 0.01))
    assert np.array_equal(lo, xe - 0.01) and np.array_equal(hi, xe + 0.01)
    sl = gc.saturated_loop(loop, box=(lo, hi))
    assert np.array_equal(sl.box[0], lo) and np.array_equal(sl.box[1], hi)
    with pytest.raises(ArgumentError, match="not strictly inside"):
        resolve_box(loop, {"theta": (0.0, 0.2)})
    with pytest.raises(ArgumentError, match="not a state"):
        resolve_box(loop, {"alpha": (0.0, 0.2)})


def test_unknown_states_are_refused_by_both_paths():
    # rogue has no [actuators] table: the pump and battery states (and their momenta, force inputs) have no limit,
    # and no generic width is invented; the glider states are known
    veh = gc.load_vehicle("rogue")
    loop = gc.closed_loop(gc.lqr_glide(veh, gc.steady_glide(veh, 0.3, math.radians(-25), r_p3=0.005)))
    msg = r"no limits known for states \['r_P1', 'r_P3', 'P_P1', 'P_P3', 'm0'\].*'z_prime': \(-1.998, 1.998\).*box="
    with pytest.raises(ArgumentError, match=msg):
        gc.validity_box(loop)
    with pytest.raises(ArgumentError, match=msg):
        gc.saturated_loop(loop)
    with pytest.raises(ArgumentError, match=msg):
        gc.certify_roa(loop, degree=2)
    # the glider half-widths apply to models of a vehicle only; a name outside the table is refused
    with pytest.raises(ArgumentError, match=r"no limits known for states \['theta', 'omega'\]"):
        gc.validity_box(("theta", "omega"), [0.0, 0.0])
    with pytest.raises(ArgumentError, match=r"states \['q'\]"):
        gc.validity_box(("theta", "q"), [0.0, 0.0], gc.load_vehicle("slocum_shallow"))
    lo, hi = gc.validity_box(("theta",), [0.1], gc.load_vehicle("slocum_shallow"))
    assert (lo[0], hi[0]) == pytest.approx((0.1 - SHRINK * 0.5, 0.1 + SHRINK * 0.5))
    with pytest.raises(ArgumentError, match="equilibrium"):
        gc.validity_box(("theta",), None, gc.load_vehicle("slocum_shallow"))
    with pytest.raises(ArgumentTypeError):
        gc.validity_box("theta", [0.0])


class PitchLoop:
    """A 2-state pitch loop of the slocum_shallow glider (theta, Omega2; not polynomial: sin theta), with its vehicle:
    every state is in the validity table, so certify_roa needs no box."""

    state_names = ("theta", "Omega2")
    input_names = ()
    name = "pitch loop"
    provenance = "test"

    def __init__(self) -> None:
        self.vehicle = gc.load_vehicle("slocum_shallow")
        self.equilibrium = np.array([-0.4, 0.0])

    def rhs(self, X, u=None):
        X = np.asarray(X)
        th, om = X[..., 0], X[..., 1]
        return np.stack([om, -2.0 * (np.sin(th) - math.sin(-0.4)) - 1.5 * om], axis=-1)


def test_certificate_reports_the_default_box_and_its_scale():
    m = PitchLoop()
    lo, hi = gc.validity_box(m)
    assert (lo[0], hi[0], lo[1], hi[1]) == pytest.approx((-0.4 - SHRINK * 0.5, -0.4 + SHRINK * 0.5,
                                                          -SHRINK * 0.3, SHRINK * 0.3), rel=1e-15)
    ps = surrogate_system(m)
    assert np.array_equal(ps.box[0], lo) and np.array_equal(ps.box[1], hi)
    np.testing.assert_allclose(ps.scale, box_scale((lo, hi), ps.equilibrium), rtol=1e-15)
    cert = gc.certify_roa(m, degree=2, method="surrogate", iterations=1, sampling=dict(n_truth=256, n_verify=2000,
                                                                                       n_simulate=16))
    assert cert.certified and cert.method == "surrogate+remainder"
    assert np.array_equal(cert.box[0], lo) and np.array_equal(cert.box[1], hi)
    # cert.scale = the state scale s of (x - x_e) / s times the internal rescaling of the programs (<= 1)
    s = box_scale((lo, hi), cert.system.equilibrium)
    assert cert.scale.shape == (2,) and np.all(cert.scale > 0) and np.all(cert.scale <= s * (1 + 1e-12))
    X = cert.sample(200, seed=3)
    assert np.all((X >= lo) & (X <= hi))
    # an explicit box is what the certified system (cert.system, whose box cert.box reports) then holds
    box = ([-0.7, -0.2], [-0.1, 0.2])
    p2 = surrogate_system(m, box)
    assert np.array_equal(p2.box[0], box[0]) and np.array_equal(p2.box[1], box[1])
    np.testing.assert_allclose(p2.scale, box_scale(box, p2.equilibrium), rtol=1e-15)
