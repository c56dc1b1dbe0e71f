"""Cases of the public-API probe (run them with ``python tests/probe/run.py``; see README.md beside this file).

Each case is a code snippet run in its own process after :data:`PRELUDE` (``np``, ``gc``, the five presets and a few
cheap results) with the helpers of :data:`HELPERS` in scope. The result is the value of the snippet when it is one
expression, else the variable ``r`` it assigns. ``expect`` says what is right:

- ``"error"``: the call must raise a :class:`glidectl.GlidectlError` subclass;
- ``"ok"``: the call must return, and ``check`` (a Python expression over ``r``, the prelude names and ``elapsed``,
  the snippet's wall time in seconds) must be True;
- ``"either"``: a GlidectlError is a right answer, and so is a returned value that passes ``check``.

``limit`` (seconds) bounds the snippet's own wall time: slower counts as a hang even if it finishes ("refused
quickly, before building"). ``timeout`` (seconds) raises the runner's wall-time cap for one expensive valid call
(the cap is then ``max(--timeout, timeout)``). This module imports nothing from glidectl at import time (the
runner imports it too).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["CASES", "GROUPS", "HELPERS", "PRELUDE", "STATE", "Case"]

VEH = "vehicles"
TRIM = "trims"
LIN = "linear analysis"
CTRL = "controllers"
STAB = "stability and certificates"
SIM = "simulation"
REP = "reports/CLI"
GROUPS = (VEH, TRIM, LIN, CTRL, STAB, SIM, REP)


@dataclass(frozen=True)
class Case:
    """One probe case (see the module docstring)."""

    id: str
    group: str
    code: str
    expect: str = "error"
    check: str | None = None
    limit: float | None = None
    note: str = ""
    timeout: float | None = None


# Shared setup, run in every child before its snippet: presets and cheap results only (a few milliseconds).
PRELUDE = """
import math
import pathlib
import tempfile
import numpy as np
import glidectl as gc
v = gc.load_vehicle("rogue")
sph = gc.load_vehicle("sphere_ch5")
slo = gc.load_vehicle("slocum_ch8")
dc8 = gc.load_vehicle("dc8_ctol")
ev = gc.load_vehicle("elevator_ch6")
g = gc.steady_glide(v, 0.3, -np.pi / 4, r_p3=0.05)
gl = gc.ctol_glide(dc8, 0.155, 0.1)
m = gc.LongitudinalGlider(v)
x0 = g.force_state()
vdp = gc.benchmarks.van_der_pol()
PRESETS = pathlib.Path(gc.__file__).resolve().parent / "vehicles"
DESIGNS = pathlib.Path(gc.__file__).resolve().parents[2] / "designs"
ROGUE_TOML = (PRESETS / "rogue.toml").read_text()
TMP = pathlib.Path(tempfile.mkdtemp(prefix="glidectl-probe-"))
"""


# ---------------------------------------------------------------------------------------------------- helpers
def finite(*xs: Any) -> bool:
    """True when every number in ``xs`` (scalars, arrays, nested tuples/lists/dicts) is finite."""
    import numpy as np

    for x in xs:
        if isinstance(x, dict):
            if not finite(*x.values()):
                return False
        elif isinstance(x, list | tuple):
            if not finite(*x):
                return False
        elif isinstance(x, bool | str) or x is None:
            continue
        else:
            a = np.asarray(x)
            if a.dtype.kind not in "biufc" or not np.all(np.isfinite(a)):
                return False
    return True


def glide_ok(r: Any, veh: Any, speed: float | None = None, gamma: float | None = None) -> bool:
    """A returned SteadyGlide is a true equilibrium of the force model of ``veh`` (relative residual < 1e-8), of the
    requested speed and gamma, with the provenance of ``veh``."""
    import numpy as np

    import glidectl as gc

    if r.provenance != veh.provenance:
        return False
    if speed is not None and not math.isclose(r.speed, speed, rel_tol=1e-12):
        return False
    if gamma is not None and not math.isclose(r.gamma, gamma, rel_tol=1e-12, abs_tol=1e-15):
        return False
    x = r.force_state()
    if not finite(x):
        return False
    f = gc.LongitudinalGlider(veh).rhs(x, np.zeros(3))
    mmin = min(veh.mass(1, r.m0), veh.mass(3, r.m0))
    acc = abs(r.m0) * veh.g / mmin
    rot = veh.mbar * veh.g * math.hypot(r.r_p1, r.r_p3) / veh.J2
    scale = max(acc, rot, veh.mbar * acc, r.speed, 1e-300)
    return finite(f) and float(np.max(np.abs(f[2:]))) <= 1e-8 * scale


def helix_ok(h: Any, veh: Any) -> bool:
    """A returned Helix is a true steady motion of :class:`glidectl.FixedMassGlider3D`: the body accelerations at
    its initial state are small relative to the forces that act (net weight for ``v'``, the moving-mass moment for
    ``Omega'``), with the provenance of ``veh``."""
    import numpy as np

    import glidectl as gc

    if h.provenance != veh.provenance or not finite(h.v, h.Omega, h.theta, h.phi, h.m0):
        return False
    masses = [veh.mass(i, h.m0) for i in (1, 2, 3)]
    if min(masses) <= 0 or veh.m + h.m0 - veh.mbar <= 0:
        return False
    model = gc.FixedMassGlider3D(veh, h.r_p, h.m0)
    d = model.rhs(h.initial_state())
    if not finite(d):
        return False
    V, W = float(np.linalg.norm(h.v)), float(np.linalg.norm(h.Omega))
    s_t = max(abs(h.m0) * veh.g / min(masses), V * W, 1e-300)
    s_r = max(veh.mbar * veh.g * float(np.linalg.norm(h.r_p)) / min(veh.J1, veh.J2, veh.J3), W * W, 1e-300)
    return float(np.max(np.abs(d[7:10]))) <= 1e-6 * s_t and float(np.max(np.abs(d[10:13]))) <= 1e-6 * s_r


#: set by the runner's child process to the case's temporary folder (``TMP`` of the prelude)
STATE: dict[str, Any] = {"tmp": None}


def write(name: str, data: str | bytes) -> Any:
    """Write ``data`` to ``TMP/name`` (a fresh temporary folder per case) and return the path."""
    import pathlib

    if STATE["tmp"] is None:
        raise RuntimeError("probe helper write() used outside a probe child")
    path = pathlib.Path(str(STATE["tmp"])) / name
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(data)
    return path


TINY_DESIGN = '''
import glidectl as gc
from glidectl.report import Report

TITLE = "probe tiny design"


def design(progress, quick=False):
    rep = Report(TITLE, vehicle=gc.load_vehicle("rogue"))
    rep.number("one", 1.0, "-", source="probe")
    return rep
'''


def design_file(name: str, body: str = TINY_DESIGN) -> Any:
    """A design file ``TMP/name`` (default: a tiny valid design that builds in a second)."""
    return write(name, body)


def cli(argv: list[Any]) -> int:
    """``glidectl.cli.main(argv)``; an argparse ``SystemExit`` becomes its exit code."""
    from glidectl.cli import main

    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else 2


def centre() -> Any:
    """``x1' = -x2, x2' = x1``: a marginally stable centre (no region of attraction to certify)."""
    from glidectl.roa import Poly, polynomial_system

    x1, x2 = Poly.variables(2)
    return polynomial_system("centre", ("x1", "x2"), [-x2, 1.0 * x1], box=((-1.0, -1.0), (1.0, 1.0)))


def unstable() -> Any:
    """``x1' = x1, x2' = -x2``: a saddle (unstable equilibrium)."""
    from glidectl.roa import Poly, polynomial_system

    x1, x2 = Poly.variables(2)
    return polynomial_system("saddle", ("x1", "x2"), [1.0 * x1, -1.0 * x2], box=((-1.0, -1.0), (1.0, 1.0)))


def torque_setup() -> tuple[Any, Any, Any]:
    """(TorqueControlledGlider(sph), its glide equilibrium, an LQR StateFeedback about it)."""
    import numpy as np

    import glidectl as gc

    sph = gc.load_vehicle("sphere_ch5")
    sp = gc.singular_perturbation(sph)
    model = gc.TorqueControlledGlider(sph)
    xe = np.array([sp.speed, sp.gamma, sp.alpha, 0.0])
    return model, xe, gc.lqr_state_feedback(model, xe, [0.0])


HELPERS = {"finite": finite, "glide_ok": glide_ok, "helix_ok": helix_ok, "write": write, "cli": cli,
           "centre": centre, "unstable": unstable, "design_file": design_file, "TINY_DESIGN": TINY_DESIGN,
           "torque_setup": torque_setup}

# ------------------------------------------------------------------------------------------------------ cases
CASES: list[Case] = []


def c(id: str, group: str, code: str, expect: str = "error", check: str | None = None, limit: float | None = None,
      note: str = "", timeout: float | None = None) -> None:
    CASES.append(Case(id, group, code.strip(), expect, check, limit, note, timeout))


# ---------------------------------------------------------------- vehicles
c("veh.load.none", VEH, "gc.load_vehicle(None)")
c("veh.load.int", VEH, "gc.load_vehicle(42)")
c("veh.load.unknown_name", VEH, "gc.load_vehicle('no_such_vehicle')")
c("veh.load.directory", VEH, "gc.load_vehicle(TMP)")
c("veh.override.str", VEH, "gc.load_vehicle('rogue', K_M='-36.5')")
c("veh.override.nan", VEH, "gc.load_vehicle('rogue', K_M=float('nan'))")
c("veh.override.negative_mass", VEH, "gc.load_vehicle('rogue', m1=-13.22)")
c("veh.override.unknown_key", VEH, "gc.load_vehicle('rogue', wingspan=1.0)")
c("veh.override.bool", VEH, "gc.load_vehicle('rogue', K_M=True)")
c("veh.override.complex", VEH, "gc.load_vehicle('rogue', K_M=1 + 2j)")
c("veh.override.array1", VEH, "gc.load_vehicle('rogue', K_M=np.array([-36.5]))")
c("veh.override.none", VEH, "gc.load_vehicle('rogue', K_M=None)")
c("veh.with_overrides.negative_mass", VEH, "v.with_overrides(m1=-1.0)")
c("veh.mass.bad_axis", VEH, "v.mass(7)")
c("veh.mass.ctol", VEH, "dc8.mass(1)")
c("veh.missing_param", VEH, "v.K_beta", note="rogue has no K_beta: ModelError naming the key")
c("veh.file.non_utf8", VEH, "gc.load_vehicle(write('latin1.toml', b'# caf\\xe9\\n' + ROGUE_TOML.encode()))",
  note="issue: a non-UTF-8 vehicle file")
c("veh.file.bad_toml", VEH, "gc.load_vehicle(write('bad.toml', '[vehicle\\nname = rogue'))")
c("veh.file.unknown_header_key", VEH,
  "gc.load_vehicle(write('hdr.toml', ROGUE_TOML.replace('[vehicle]', '[vehicle]\\ncolour = \"red\"')))")
c("veh.file.unknown_parameter", VEH,
  "gc.load_vehicle(write('par.toml', ROGUE_TOML + '\\nwingspan = { value = 1.0, unit = \"m\", source = \"x\" }\\n'))")
c("veh.file.nan_value", VEH, "gc.load_vehicle(write('nan.toml', ROGUE_TOML.replace('value = 13.22', 'value = nan')))")
c("veh.file.negative_mass", VEH,
  "gc.load_vehicle(write('neg.toml', ROGUE_TOML.replace('value = 13.22', 'value = -13.22')))")
c("veh.file.wrong_unit", VEH,
  "gc.load_vehicle(write('unit.toml', ROGUE_TOML.replace('value = 13.22,  unit = \"kg\"', "
  "'value = 13.22,  unit = \"lb\"')))")
c("veh.file.missing_required", VEH,
  "gc.load_vehicle(write('noJ2.toml', '\\n'.join(l for l in ROGUE_TOML.splitlines() if not l.startswith('J2'))))")
c("veh.file.valid_copy", VEH, "gc.load_vehicle(write('copy.toml', ROGUE_TOML))", "ok",
  "dict(r.params) == dict(v.params) and r.provenance == v.provenance")
c("veh.list_presets", VEH, "gc.list_presets()", "ok",
  "set(r) == {'rogue', 'sphere_ch5', 'elevator_ch6', 'slocum_ch8', 'dc8_ctol'}")
c("veh.load.preset", VEH, "gc.load_vehicle('rogue')", "ok",
  "r.m1 == 13.22 and r.K_M == -36.5 and r.provenance == v.provenance and r.kind == 'underwater_glider'")
c("veh.load.override", VEH, "gc.load_vehicle('rogue', K_M=-40.0)", "ok",
  "r.K_M == -40.0 and r.provenance != v.provenance")

# ---------------------------------------------------------------- trims
SG = "gc.steady_glide(v, {speed}, {gamma}, r_p3=0.05)"


def sg(speed: str = "0.3", gamma: str = "-np.pi / 4") -> str:
    return SG.format(speed=speed, gamma=gamma)


c("trim.steady_glide.speed_str", TRIM, "gc.steady_glide(v, '0.3', -0.785, r_p3=0.05)", note="issue, verbatim")
c("trim.steady_glide.speed_none", TRIM, "gc.steady_glide(v, speed=None, gamma=-0.785, r_p3=0.05)",
  note="issue: speed=None")
c("trim.steady_glide.speed_array1", TRIM, "gc.steady_glide(v, speed=np.array([.3]), gamma=-0.785, r_p3=0.05)",
  note="issue: speed=np.array([.3])")
c("trim.steady_glide.speed_bool", TRIM, sg("True"))
c("trim.steady_glide.speed_complex", TRIM, sg("0.3 + 0j"))
c("trim.steady_glide.speed_nan", TRIM, sg("float('nan')"))
c("trim.steady_glide.speed_negative", TRIM, sg("-0.3"))
c("trim.steady_glide.speed_huge", TRIM, sg("1e200"), "either", "glide_ok(r, v, 1e200, -np.pi / 4)")
c("trim.steady_glide.speed_tiny", TRIM, sg("1e-300"), "either", "glide_ok(r, v, 1e-300, -np.pi / 4) and r.m0 > 0",
  note="a downward glide needs m0 > 0; m0 underflowing to 0 is a wrong answer")
c("trim.steady_glide.gamma_nan", TRIM, sg(gamma="float('nan')"))
c("trim.steady_glide.gamma_zero", TRIM, sg(gamma="0.0"), note="outside the permissible set (2.26)")
c("trim.steady_glide.gamma_huge", TRIM, sg(gamma="1e200"))
c("trim.steady_glide.neither_family", TRIM, "gc.steady_glide(v, 0.3, -np.pi / 4)")
c("trim.steady_glide.r_p3_huge", TRIM, "gc.steady_glide(v, 0.3, -np.pi / 4, r_p3=1e200)", "either",
  "glide_ok(r, v, 0.3, -np.pi / 4)")
c("trim.steady_glide.ctol_vehicle", TRIM, "gc.steady_glide(dc8, 0.3, -np.pi / 4, r_p3=0.05)")
c("trim.steady_glide.vehicle_name", TRIM, "gc.steady_glide('rogue', 0.3, -np.pi / 4, r_p3=0.05)")
c("trim.steady_glide.no_moving_mass", TRIM, "gc.steady_glide(sph, 0.3, -np.pi / 4, r_p3=0.05)",
  note="sphere_ch5 has mbar = 0")
c("trim.steady_glide.valid", TRIM, sg(), "ok", "glide_ok(r, v, 0.3, -np.pi / 4) and r.m0 > 0")
c("trim.steady_glide.valid_up", TRIM, sg(gamma="np.pi / 4"), "ok", "glide_ok(r, v, 0.3, np.pi / 4) and r.m0 < 0")
c("trim.permissible.ctol", TRIM, "gc.permissible_gamma(dc8)")
c("trim.permissible.valid", TRIM, "gc.permissible_gamma(v)", "ok",
  "math.isclose(r[0], -math.atan(2 * math.sqrt(v.K_D0 * v.K_D) / v.K_L), rel_tol=1e-12) "
  "and math.isclose(r[1], -r[0], rel_tol=1e-12)")
# helix_trim
c("trim.helix.absurd_mass_position", TRIM, "gc.helix_trim(slo, r_p=(1e9, 1e9, 1e9), m0=1e6)", "either",
  "helix_ok(r, slo)", note="issue, verbatim")
c("trim.helix.zero_solid_mass", TRIM, "gc.helix_trim(slo, r_p=(.02, .02, .04), m0=-41.)",
  note="issue: m + m0 - mbar = 0")
c("trim.helix.tiny_m0", TRIM, "gc.helix_trim(slo, r_p=(.02, .02, .04), m0=1e-300)", "either", "helix_ok(r, slo)",
  note="issue: an error or a true equilibrium (residual relative to the force scale)")
c("trim.helix.r_p_short", TRIM, "gc.helix_trim(slo, r_p=(0.02, 0.02), m0=0.25)")
c("trim.helix.r_p_nan", TRIM, "gc.helix_trim(slo, r_p=(float('nan'), 0.02, 0.04), m0=0.25)")
c("trim.helix.m0_str", TRIM, "gc.helix_trim(slo, r_p=(.02, .02, .04), m0='0.25')")
c("trim.helix.m0_zero", TRIM, "gc.helix_trim(slo, r_p=(.02, .02, .04), m0=0.0)")
c("trim.helix.continuation_zero", TRIM, "gc.helix_trim(slo, continuation_steps=0)")
c("trim.helix.guess_shape", TRIM, "gc.helix_trim(slo, guess=np.zeros(3))")
c("trim.helix.ctol_vehicle", TRIM, "gc.helix_trim(dc8, r_p=(.02, .02, .04), m0=0.25)")
c("trim.helix.longitudinal_vehicle", TRIM, "gc.helix_trim(v, r_p=(.02, .02, .04), m0=0.25)",
  note="rogue has no 3D parameters")
c("trim.helix.valid_default", TRIM, "gc.helix_trim(slo)", "ok",
  "helix_ok(r, slo) and r.m0 == 0.25 and r.r_p == (0.02, 0.02, 0.04) and r.radius > 0")
# ctol_glide
c("trim.ctol_glide.speed_huge", TRIM, "gc.ctol_glide(dc8, 1e200, .1)", "either",
  "finite(r.alpha, r.k1, r.k2, r.thrust) and r.residual < 1e-9", note="issue, verbatim")
c("trim.ctol_glide.speed_str", TRIM, "gc.ctol_glide(dc8, '0.155', 0.1)")
c("trim.ctol_glide.speed_negative", TRIM, "gc.ctol_glide(dc8, -0.155, 0.1)")
c("trim.ctol_glide.gamma_nan", TRIM, "gc.ctol_glide(dc8, 0.155, float('nan'))")
c("trim.ctol_glide.gamma_absurd", TRIM, "gc.ctol_glide(dc8, 0.155, np.pi)")
c("trim.ctol_glide.alpha_max_negative", TRIM, "gc.ctol_glide(dc8, 0.155, 0.1, alpha_max=-0.35)")
c("trim.ctol_glide.glider_vehicle", TRIM, "gc.ctol_glide(v, 0.155, 0.1)")
c("trim.ctol_glide.valid", TRIM, "gc.ctol_glide(dc8, 0.155, 0.1)", "ok",
  "r.residual < 1e-9 and r.provenance == dc8.provenance and r.speed == 0.155 and finite(r.alpha, r.thrust)")
# elevator / buoyancy equilibria
c("trim.elevator.speed_nan", TRIM, "gc.elevator_equilibrium(ev, float('nan'), -np.pi / 4)")
c("trim.elevator.gamma_zero", TRIM, "gc.elevator_equilibrium(ev, 1.0, 0.0)")
c("trim.elevator.no_elevator", TRIM, "gc.elevator_equilibrium(v, 1.0, -np.pi / 4)", note="rogue has no delta")
c("trim.elevator.valid", TRIM, "gc.elevator_equilibrium(ev, 1.0, -np.pi / 4)", "ok",
  "r.residual < 1e-9 and r.provenance == ev.provenance and isinstance(r.certified, bool) and finite(r.m0e, r.u2e)")
c("trim.buoyancy.speed_nan", TRIM, "gc.buoyancy_equilibrium(sph, float('nan'))")
c("trim.buoyancy.speed_huge", TRIM, "gc.buoyancy_equilibrium(sph, 1e200)", "either", "finite(r.m0e, r.residual)")
c("trim.buoyancy.descending_str", TRIM, "gc.buoyancy_equilibrium(sph, 1.0, descending='no')")
c("trim.buoyancy.valid", TRIM, "gc.buoyancy_equilibrium(sph, 1.0)", "ok",
  "r.m0e > 0 and r.residual < 1e-9 and r.provenance == sph.provenance and r.speed == 1.0")
# design_helix
c("trim.design_helix.radius_negative", TRIM, "gc.design_helix(slo, radius=-50.0, pitch=150.0)")
c("trim.design_helix.radius_huge", TRIM, "gc.design_helix(slo, radius=1e200, pitch=150.0)", "either",
  "helix_ok(r.helix, slo) and abs(r.helix.radius - 1e200) < 1e-3 * 1e200")
c("trim.design_helix.no_second_target", TRIM, "gc.design_helix(slo, radius=50.0)")
c("trim.design_helix.bounds_shape", TRIM, "gc.design_helix(slo, radius=50.0, pitch=150.0, r_p_bounds=((0, 1),))")
c("trim.design_helix.valid", TRIM, "gc.design_helix(slo, radius=50.0, pitch=150.0)", "ok",
  "helix_ok(r.helix, slo) and abs(r.helix.radius - 50) < 0.05 and abs(r.helix.pitch - 150) < 0.15 "
  "and r.helix.stable")
c("trim.classify_motion.str", TRIM, "gc.classify_motion('v', (0, 0, 0))")
c("trim.classify_motion.valid", TRIM, "gc.classify_motion((1.0, 0, 0), (0, 0, 0))", "ok",
  "r['kind'] == 'straight line' and r['curvature'] == 0")

# ---------------------------------------------------------------- linear analysis
c("lin.linearize.glide_none", LIN, "gc.linearize_glide(v, None)", note="issue, verbatim")
c("lin.linearize.inputs_unknown", LIN, "gc.linearize_glide(v, g, inputs='torque')")
c("lin.linearize.other_vehicle", LIN, "gc.linearize_glide(v.with_overrides(K_M=-40.0), g)",
  note="provenance: a glide of rogue used with a changed rogue")
c("lin.linearize.ctol_vehicle", LIN, "gc.linearize_glide(dc8, g)")
c("lin.linearize.ctol_glide", LIN, "gc.linearize_glide(v, gl)")
c("lin.linearize.valid_force", LIN, "gc.linearize_glide(v, g)", "ok",
  "r.A.shape == (10, 10) and r.B.shape == (10, 3) and finite(r.A, r.B)")
c("lin.linearize.valid_acceleration", LIN, "gc.linearize_glide(v, g, inputs='acceleration')", "ok",
  "finite(r.A, r.B) and r.B.shape[1] == 3")
c("lin.glide_model.inputs_unknown", LIN, "gc.glide_model(v, g, inputs='bogus')")
c("lin.glide_model.other_vehicle", LIN, "gc.glide_model(v.with_overrides(mbar=3.0), g)")
c("lin.modes.none", LIN, "gc.modes(None)")
c("lin.modes.matrix", LIN, "gc.modes(np.eye(3))")
c("lin.modes.valid", LIN, "gc.modes(gc.linearize_glide(v, g))", "ok",
  "len(r.eigenvalues) == 10 and finite(r.eigenvalues, r.wn)")
c("lin.ctrb.unknown_input", LIN, "gc.controllability(gc.linearize_glide(v, g), inputs=['u9'])")
c("lin.ctrb.tol_negative", LIN, "gc.controllability(gc.linearize_glide(v, g), tol=-1.0)")
c("lin.ctrb.valid", LIN, "gc.controllability(gc.linearize_glide(v, g))", "ok", "r.n == 10 and 0 < r.rank <= 10")
c("lin.obsv.unknown", LIN, "gc.observability(gc.linearize_glide(v, g), ['nope'])")
c("lin.uncontrolled.no_family", LIN, "gc.uncontrolled_eigs(v, 0.3, -np.pi / 4)")
c("lin.uncontrolled.valid", LIN, "gc.uncontrolled_eigs(v, 0.3, -np.pi / 4, r_p3=0.05)", "ok",
  "len(r) > 0 and finite(r)")
c("lin.rbh_locus.empty", LIN, "gc.rbh_locus(v, 0.3, -np.pi / 4, [])")
c("lin.rbh_locus.valid", LIN, "gc.rbh_locus(v, 0.3, -np.pi / 4, np.linspace(0.005, 0.05, 5))", "ok",
  "r.branches.shape[0] == 5 and finite(r.branches)")
c("lin.mbar_locus.negative", LIN, "gc.mbar_locus(v, 0.3, -np.pi / 4, [-1.0, 1.0], r_p3=0.05)")
c("lin.parameter_locus.not_callable", LIN, "gc.parameter_locus(42, [1.0, 2.0], 'p', '-')")
c("lin.parameter_locus.empty", LIN, "gc.parameter_locus(lambda p: np.array([-p, -2 * p]), [], 'p', '-')")
c("lin.parameter_locus.ragged", LIN,
  "gc.parameter_locus(lambda p: np.array([-p]) if p < 1.5 else np.array([-p, -p]), [1.0, 2.0], 'p', '-')")
c("lin.parameter_locus.nan_eigs", LIN,
  "gc.parameter_locus(lambda p: np.array([np.nan, -p]), [1.0, 2.0], 'p', '-')")
c("lin.parameter_locus.valid", LIN,
  "gc.parameter_locus(lambda p: np.array([-p, -2 * p]), np.linspace(1, 2, 5), 'p', '-')", "ok",
  "r.branches.shape == (5, 2) and np.allclose(np.sort(r.branches.real, axis=1), "
  "np.sort(np.stack([-np.linspace(1, 2, 5), -2 * np.linspace(1, 2, 5)], 1), axis=1))")
c("lin.jacobians.not_callable", LIN, "gc.jacobians(42, [0.0], [0.0])")
c("lin.jacobians.nan_state", LIN, "gc.jacobians(lambda x, u: x ** 2 + u, [float('nan')], [0.0])")
c("lin.jacobians.valid", LIN,
  "M = np.array([[1.0, 2.0], [3.0, 4.0]]); N = np.array([[5.0], [6.0]])\n"
  "r = gc.jacobians(lambda x, u: x @ M.T + u @ N.T, np.array([0.3, -0.2]), np.array([0.1]))",
  "ok", "np.allclose(r[0], M) and np.allclose(r[1], N)")
c("lin.hessian.h_zero", LIN, "gc.hessian(lambda x: (x ** 2).sum(-1), [1.0, 2.0], h=0.0)")
c("lin.hessian.h_nan", LIN, "gc.hessian(lambda x: (x ** 2).sum(-1), [1.0, 2.0], h=float('nan'))")
c("lin.hessian.valid", LIN,
  "gc.hessian(lambda x: x[..., 0] ** 2 + 3 * x[..., 0] * x[..., 1], np.array([1.0, 2.0]))", "ok",
  "np.allclose(r, [[2.0, 3.0], [3.0, 0.0]], atol=1e-6)")
c("lin.helix_sweep.unknown_parameter", LIN, "gc.helix_sweep(slo, 'bogus', [0.01, 0.02])")
c("lin.helix_sweep.empty", LIN, "gc.helix_sweep(slo, 'r_P1', [])")
c("lin.helix_sweep.nan", LIN, "gc.helix_sweep(slo, 'r_P1', [0.01, float('nan')])")
c("lin.helix_sweep.longitudinal_vehicle", LIN, "gc.helix_sweep(v, 'r_P1', [0.01, 0.02])")
c("lin.helix_sweep.valid", LIN, "gc.helix_sweep(slo, 'r_P1', np.linspace(0.002, 0.06, 5))", "ok",
  "r.exists.all() and r.provenance == slo.provenance and finite(r.radius) and float(np.max(r.residual)) < 1e-9")
c("lin.straight_glides.not_sweep", LIN, "gc.straight_glides(slo, 'sweep')")
c("lin.straight_glides.other_vehicle", LIN,
  "sw = gc.helix_sweep(slo, 'r_P2', np.linspace(-0.01, 0.01, 5))\n"
  "r = gc.straight_glides(slo.with_overrides(K_M=-40.0), sw)")
c("lin.existence_scan.empty", LIN, "gc.existence_scan(slo, [], [0.25])")
NOM = "(0.02, -0.02, 0.04)"
c("lin.helix_rbh.empty", LIN, f"gc.helix_rbh_locus(slo, {NOM}, 0.25, [])")
c("lin.helix_rbh.valid", LIN, f"gc.helix_rbh_locus(slo, {NOM}, 0.25, np.linspace(0.0, 0.08, 5))", "ok",
  "r.locus.branches.shape[0] == 5 and finite(r.locus.branches)")
c("lin.resolved_crossing.step_zero", LIN, f"gc.resolved_crossing(slo, {NOM}, 0.25, step=0.0)")
c("lin.resolved_crossing.step_negative", LIN, f"gc.resolved_crossing(slo, {NOM}, 0.25, step=-5e-4)")
c("lin.resolved_crossing.stop_nan", LIN, f"gc.resolved_crossing(slo, {NOM}, 0.25, stop=float('nan'))")
c("lin.resolved_crossing.valid", LIN, f"gc.resolved_crossing(slo, {NOM}, 0.25)", "ok",
  "(r[0] is None or math.isfinite(r[0])) and helix_ok(r[1], slo)")

# ---------------------------------------------------------------- controllers
c("ctrl.lqr.glide_none", CTRL, "gc.lqr_glide(v, None)")
c("ctrl.lqr.Q_shape", CTRL, "gc.lqr_glide(v, g, Q=np.eye(3))")
c("ctrl.lqr.R_zero", CTRL, "gc.lqr_glide(v, g, R=np.zeros((3, 3)))")
c("ctrl.lqr.other_vehicle", CTRL, "gc.lqr_glide(v.with_overrides(K_M=-40.0), g)")
c("ctrl.lqr.max_deviation_unknown", CTRL, "gc.lqr_glide(v, g, max_deviation={'nope': 1.0})")
c("ctrl.lqr.valid", CTRL, "gc.lqr_glide(v, g)", "ok",
  "bool(np.all(np.real(r.closed_loop_poles) < 0)) and finite(r.K)")
c("ctrl.place.wrong_count", CTRL, "gc.place_glide(v, g, [-1.0, -2.0])")
c("ctrl.place.valid", CTRL, "gc.place_glide(v, g, -0.1 * np.arange(1, 11))", "ok",
  "np.allclose(np.sort(np.real(r.closed_loop_poles)), np.sort(-0.1 * np.arange(1, 11)), rtol=1e-3, atol=1e-4)")
c("ctrl.lqr_sf.x_e_shape", CTRL, "gc.lqr_state_feedback(gc.TorqueControlledGlider(sph), [1.0, 0.0], [0.0])")
c("ctrl.lqr_sf.not_equilibrium", CTRL, "gc.lqr_state_feedback(gc.TorqueControlledGlider(sph), [1.0, 0, 0, 0], [0.0])")
c("ctrl.lqr_sf.bounds_reversed", CTRL,
  "model, xe, _ = torque_setup()\nr = gc.lqr_state_feedback(model, xe, [0.0], u_min=[1.0], u_max=[-1.0])")
c("ctrl.decoupled.nan", CTRL, "gc.decoupled_gain_matrix(float('nan'), 1, 1, 1, 1)")
c("ctrl.closed_loop.none", CTRL, "gc.closed_loop(None)")
c("ctrl.closed_loop.valid", CTRL, "cl = gc.closed_loop(gc.lqr_glide(v, g))\nr = cl.rhs(cl.equilibrium)", "ok",
  "finite(r) and float(np.max(np.abs(r))) < 1e-9")
c("ctrl.ctol_eigs.glider_vehicle", CTRL, "gc.ctol_closed_loop_eigenvalues(v, gl, 10.0, 5.0)",
  note="issue: a glider vehicle")
c("ctrl.ctol_eigs.glider_glide", CTRL, "gc.ctol_closed_loop_eigenvalues(dc8, g, 10.0, 5.0)")
c("ctrl.ctol_eigs.other_vehicle", CTRL, "gc.ctol_closed_loop_eigenvalues(dc8.with_overrides(a_L=20.0), gl, 10.0, 5.0)")
c("ctrl.ctol_eigs.k3_nan", CTRL, "gc.ctol_closed_loop_eigenvalues(dc8, gl, float('nan'), 5.0)")
c("ctrl.ctol_eigs.T_zero", CTRL, "gc.ctol_closed_loop_eigenvalues(dc8, gl, 10.0, 5.0, T=0.0)")
c("ctrl.ctol_eigs.valid", CTRL, "gc.ctol_closed_loop_eigenvalues(dc8, gl, 10.0, 5.0)", "ok",
  "len(r) == 4 and finite(r) and bool(np.all(np.real(r) < 0))")
c("ctrl.climb.glider_vehicle", CTRL, "gc.climb_trajectory(v)")
c("ctrl.climb.valid", CTRL, "gc.climb_trajectory(dc8)", "ok", "math.isclose(r.speed, 0.85 / math.sqrt(dc8.a_L))")
c("ctrl.zero_dyn.negative", CTRL, "gc.zero_dynamics(dc8, -0.155)")
c("ctrl.zero_dyn.huge", CTRL, "gc.zero_dynamics(dc8, 1e200)", "either", "finite(r.eigenvalues, r.theta, r.thrust)")
c("ctrl.zero_dyn.glider_vehicle", CTRL, "gc.zero_dynamics(v, 0.155)")
c("ctrl.zero_dyn.valid", CTRL, "gc.zero_dynamics(dc8, 0.155)", "ok",
  "r.is_saddle and r.residual < 1e-9 and finite(r.eigenvalues)")
TWS = "gc.track_with_steady_glides(dc8, gc.climb_trajectory(dc8), dt=1.0, k3=1e3, k4=60.0, t_final=10.0)"
c("ctrl.track_glides.dt_zero", CTRL, TWS.replace("dt=1.0", "dt=0.0"))
c("ctrl.track_glides.t_final_str", CTRL, TWS.replace("t_final=10.0", "t_final='10'"))
c("ctrl.track_glides.glider_vehicle", CTRL,
  "gc.track_with_steady_glides(v, gc.climb_trajectory(dc8), dt=1.0, t_final=10.0)")
c("ctrl.track_glides.valid", CTRL, TWS, "ok", "r.completed and finite(r.max_error, r.peak_u1)")
c("ctrl.tracking_grid.empty", CTRL, "gc.tracking_grid(dc8, gc.climb_trajectory(dc8), [], [(1e3, 60.0)])")
c("ctrl.stable_inversion.reversed", CTRL, "gc.stable_inversion(dc8, t0=10.0, t1=0.0)")
c("ctrl.track_inversion.start_unknown", CTRL, "gc.track_stable_inversion(dc8, start='bogus')")
c("ctrl.track_inversion.t_final_negative", CTRL, "gc.track_stable_inversion(dc8, t_final=-1.0)")
c("ctrl.track_approx.pole_zero", CTRL, "gc.track_approximate_linearization(dc8, pole=0.0)")
c("ctrl.approx_eigs.nan", CTRL, "gc.approximate_linearization_eigenvalues(dc8, float('nan'))")
c("ctrl.approx_eigs.glider_vehicle", CTRL, "gc.approximate_linearization_eigenvalues(v, 0.155)")
c("ctrl.fl_blowup.dt_zero", CTRL, "gc.feedback_linearization_blowup(dc8, dt=0.0)")
EQ = "eq = gc.elevator_equilibrium(ev, 1.0, -np.pi / 4)\n"
c("ctrl.elev_eigs.other_vehicle", CTRL, EQ + "r = gc.elevator_closed_loop_eigenvalues(eq, ev.with_overrides(J2=0.2))")
c("ctrl.elev_eigs.K_nan", CTRL, EQ + "r = gc.elevator_closed_loop_eigenvalues(eq, ev, K=float('nan'))")
c("ctrl.elev_eigs.wrong_result", CTRL, "gc.elevator_closed_loop_eigenvalues(g, ev)")
c("ctrl.elev_eigs.valid", CTRL, EQ + "r = gc.elevator_closed_loop_eigenvalues(eq, ev)", "ok",
  "len(r) > 0 and finite(r)")
c("ctrl.elev_example.t_final_str", CTRL, "gc.elevator_example(ev, 1.0, -np.pi / 4, t_final='10')")
c("ctrl.elev_example.valid", CTRL, "gc.elevator_example(ev, 1.0, -np.pi / 4, t_final=5.0)", "ok",
  "finite(r.final_error, r.sim.x) and r.sim.t[-1] == 5.0")
c("ctrl.infer_J2.negative", CTRL, "gc.infer_J2(ev, -1.0, 1.0, -np.pi / 4)")
c("ctrl.torque_design.no_target", CTRL, "gc.design_torque_control(sph)")
c("ctrl.torque_design.speed_str", CTRL, "gc.design_torque_control(sph, speed='1.5')")
c("ctrl.torque_design.torque_max_zero", CTRL, "gc.design_torque_control(sph, speed=1.5, torque_max=0.0)")
c("ctrl.torque_design.valid", CTRL, "gc.design_torque_control(sph, speed=1.5)", "ok",
  "r.certified and r.mu < r.mu_d and r.provenance == sph.provenance and finite(r.peak_torque)")
c("ctrl.torque_family.nan", CTRL, "gc.torque_gain_family(sph, float('nan'))")
c("ctrl.torque_family.eps_ratio_negative", CTRL, "gc.torque_gain_family(sph, 0.02, eps_ratio=-1.0)")
c("ctrl.cl_formulas.law_str", CTRL, "gc.closed_loop_formulas(sph, 'law')")
BEQ = "beq = gc.buoyancy_equilibrium(sph, 1.0)\n"
c("ctrl.buoyancy_ctrl.other_vehicle", CTRL, BEQ + "r = gc.BuoyancyController(beq, sph.with_overrides(K_M=-60.0))")
c("ctrl.elevator_ctrl.K_zero", CTRL, EQ + "r = gc.ElevatorBuoyancyController(eq, ev, K=0.0)")
c("ctrl.steady_glide_ctrl.k3_nan", CTRL, "gc.SteadyGlideController(dc8, gl, k3=float('nan'), k4=5.0)")
TD = ("vm = sph.with_overrides(mbar=1.0, m1=27.0, m3=27.0)\nd = gc.design_torque_control(vm, speed=1.5)\n"
      "xe = np.array([d.speed, d.gamma, d.alpha, 0.0])\n")
c("ctrl.realized_torque.x0_shape", CTRL, TD + "r = gc.compare_realized_torque(vm, d.law, np.zeros(2), 1.0)")
c("ctrl.realized_torque.feedback_unknown", CTRL,
  TD + "r = gc.compare_realized_torque(vm, d.law, xe, 1.0, feedback='bogus')")
c("ctrl.pareto.empty", CTRL, "gc.pareto_front([])", "ok", "list(r) == []")
c("ctrl.pareto.nan", CTRL, "gc.pareto_front([(float('nan'), 1.0), (1.0, 2.0)])")
c("ctrl.pareto.valid", CTRL, "gc.pareto_front([(1, 3), (2, 2), (3, 1), (3, 3)])", "ok", "sorted(r) == [0, 1, 2]")

# ---------------------------------------------------------------- stability and certificates
c("stab.composite.Vbar_scalar", STAB, "gc.composite_lyapunov(sph, Vbar=0.4)", note="issue, verbatim")
c("stab.composite.Vbar_triple", STAB, "gc.composite_lyapunov(sph, Vbar=(-.4, 0, .4))", note="issue, verbatim")
c("stab.composite.tiny_domain", STAB,
  "gc.composite_lyapunov(sph, Vbar=(-1e-12, 1e-12), alphabar=(-1e-12, 1e-12))", "either",
  "r.d >= 0 and r.mu_d >= 0 and finite(r.d, r.mu_d, r.mu)", note="issue: must not return negative d / mu_d")
c("stab.composite.Vbar_reversed", STAB, "gc.composite_lyapunov(sph, Vbar=(0.4, -0.4))")
c("stab.composite.Vbar_nan", STAB, "gc.composite_lyapunov(sph, Vbar=(float('nan'), 0.4))")
c("stab.composite.Vbar_below_minus_one", STAB, "gc.composite_lyapunov(sph, Vbar=(-2.0, 0.4))",
  note="Vbar < -1 is a negative speed")
c("stab.composite.cw_unknown", STAB, "gc.composite_lyapunov(sph, cw='bogus')")
c("stab.composite.ctol_vehicle", STAB, "gc.composite_lyapunov(dc8)")
c("stab.composite.valid", STAB, "gc.composite_lyapunov(sph, Vbar=(-0.4, 0.4), alphabar=(-0.2, 0.2))", "ok",
  "finite(r.mu, r.mu_d, r.d) and r.d >= 0 and r.certified == (r.mu < r.mu_d) and r.provenance == sph.provenance")
c("stab.composite_verify.n_zero", STAB, "cert = gc.composite_lyapunov(sph)\nr = cert.verify(n=0)")
c("stab.sp.ctol_vehicle", STAB, "gc.singular_perturbation(dc8)")
c("stab.sp.vehicle_name", STAB, "gc.singular_perturbation('sphere_ch5')")
c("stab.sp.valid", STAB, "gc.singular_perturbation(sph)", "ok",
  "finite(r.speed, r.gamma, r.eps1, r.eps2, r.tau_s) and 0 < r.eps1 < 1 and r.provenance == sph.provenance")
c("stab.unequal.Vbar_reversed", STAB, "gc.unequal_mass_check(sph, Vbar=(0.4, -0.4))")
c("stab.unequal.valid", STAB, "gc.unequal_mass_check(sph.with_overrides(m3=30.0), n=2000)", "ok",
  "finite(r.kappa, r.delta_m) and r.n_samples > 0")
c("stab.delta_m.negative_kappa", STAB, "gc.allowable_delta_m_ratio(-1.0, -0.4)")
c("stab.delta_m.Vbar_below_minus_one", STAB, "gc.allowable_delta_m_ratio(0.5, -2.0)")
c("stab.delta_m.valid", STAB, "gc.allowable_delta_m_ratio(0.5, -0.4)", "ok", "finite(r) and r >= 0")
c("stab.buoyancy_check.other_vehicle", STAB, BEQ + "r = gc.buoyancy_lyapunov_check(beq, sph.with_overrides(K_q=-3.0))")
c("stab.buoyancy_check.valid", STAB, BEQ + "r = gc.buoyancy_lyapunov_check(beq, sph, n=2000, n_m0=3)", "ok",
  "r.n_samples > 0 and finite(r.mu, r.mu_d, r.max_dnu_b)")
c("stab.ctol_lyap.r_negative", STAB, "gc.ctol_lyapunov(dc8, gl, 10.0, 5.0, r=-1.0)")
c("stab.ctol_lyap.glider_vehicle", STAB, "gc.ctol_lyapunov(v, gl, 10.0, 5.0)")
c("stab.ctol_lyap.glider_glide", STAB, "gc.ctol_lyapunov(dc8, g, 10.0, 5.0)")
c("stab.ctol_lyap.valid", STAB, "gc.ctol_lyapunov(dc8, gl, 10.0, 5.0)", "ok",
  "isinstance(r.certified, bool) and finite(r.r_a, r.level, r.lam) and r.r_a >= 0")
# certify_roa
c("stab.roa.centre", STAB, "gc.certify_roa(centre(), degree=2)", note="issue: a marginally stable centre")
c("stab.roa.saddle", STAB, "gc.certify_roa(unstable(), degree=2)")
c("stab.roa.degree_nan", STAB, "gc.certify_roa(vdp, degree=float('nan'))", note="issue, verbatim")
c("stab.roa.backoff_negative", STAB, "gc.certify_roa(vdp, degree=2, backoff=-1.0)", note="issue, verbatim")
c("stab.roa.degree_100", STAB, "gc.certify_roa(vdp, degree=100)", limit=10.0,
  note="issue: must be refused quickly, before building")
c("stab.roa.degree_odd", STAB, "gc.certify_roa(vdp, degree=3)")
c("stab.roa.backoff_above_one", STAB, "gc.certify_roa(vdp, degree=2, backoff=2.0)")
c("stab.roa.solver_unknown", STAB, "gc.certify_roa(vdp, degree=2, solver='BOGUS')")
c("stab.roa.system_str", STAB, "gc.certify_roa('vdp')")
c("stab.roa.not_recastable", STAB, "gc.certify_roa(m, degree=2)", note="a model with inputs, no equilibrium")
c("stab.roa.valid_degree2", STAB, "gc.certify_roa(vdp, degree=2)", "ok",
  "r.certified and 0 < r.volume() < gc.benchmarks.VAN_DER_POL_AREA "
  "and r.contains(np.array([[0.0, 0.0], [2.9, 3.4]])).tolist() == [True, False]")
c("stab.roa.valid_degree4", STAB, "gc.certify_roa(vdp, degree=4)", "ok",
  "r.certified and 0 < r.volume() < gc.benchmarks.VAN_DER_POL_AREA and r.degree == 4", timeout=90.0)
c("stab.roa.valid_glider", STAB, "gc.certify_roa(gc.singular_perturbation(sph).reduced_model(), degree=2)", "ok",
  "r.certified and r.rho > 0 and bool(r.contains(np.zeros((1, 2)))[0])", timeout=120.0,
  note="SOS certificate of the chapter-5 glider: about 9 s on an idle core")
ROA = "cert = gc.certify_roa(vdp, degree=2)\n"
c("stab.roa_contains.n_path_zero", STAB, ROA + "r = cert.contains(np.array([[0.5, 0.5]]), n_path=0)",
  note="issue, verbatim (X a (1, 2) array)")
c("stab.roa_contains.shape", STAB, ROA + "r = cert.contains(np.zeros(3))")
c("stab.roa_contains.nan", STAB, ROA + "r = cert.contains(np.array([[np.nan, 0.0]]))", "either",
  "not bool(np.any(r))")
c("stab.roa_contains.valid", STAB, ROA + "r = cert.contains(np.array([[0.1, 0.1], [2.9, 3.4]]))", "ok",
  "r.tolist() == [True, False]")
c("stab.recast.speed_floor_zero", STAB, "gc.recast(gc.singular_perturbation(sph).reduced_model(), speed_floor=0.0)")
c("stab.taylor.order_zero", STAB, "gc.taylor_system(vdp, order=0)")
c("stab.lyap_matrix.centre", STAB, "gc.lyapunov_matrix(centre())", note="A^T P + P A = -I has no solution")
c("stab.lyap_matrix.valid", STAB, "gc.lyapunov_matrix(vdp)", "ok",
  "np.allclose(np.array([[0.0, 1.0], [-1.0, -1.0]]) @ r + r @ np.array([[0.0, -1.0], [1.0, -1.0]]), -np.eye(2)) "
  "and bool(np.all(np.linalg.eigvalsh(r) > 0))")
c("stab.max_level.rho_cap_negative", STAB, "gc.max_level(vdp, gc.lyapunov_quadratic(vdp), rho_cap=-1.0)")
c("stab.max_level.valid", STAB, "gc.max_level(vdp, gc.lyapunov_quadratic(vdp))", "ok",
  "math.isfinite(r.rho) and r.rho > 0")
c("stab.dVdt.shape", STAB, "gc.dVdt(gc.lyapunov_quadratic(vdp), vdp.lift, vdp.rhs, np.zeros(3))")

# ---------------------------------------------------------------- simulation (and the models it integrates)
c("sim.t_final_str", SIM, "gc.simulate(m, x0, '10')", note="issue, verbatim")
c("sim.x0_nan", SIM, "x = x0.copy()\nx[2] = np.nan\nr = gc.simulate(m, x, 10.0)", note="issue: x0 with NaN")
c("sim.controller_wrong_inputs", SIM, "gc.simulate(m, x0, 10.0, lambda t, x: np.zeros(2))",
  note="issue: a controller returning the wrong number of inputs")
c("sim.t_eval_beyond", SIM, "gc.simulate(m, x0, 1.0, t_eval=[0.0, 5.0])", note="issue: must not drop 5.0 silently")
c("sim.t_final_tiny", SIM, "gc.simulate(m, x0, 1e-200)", note="issue, verbatim")
c("sim.t_final_zero", SIM, "gc.simulate(m, x0, 0.0)")
c("sim.t_final_nan", SIM, "gc.simulate(m, x0, float('nan'))")
c("sim.t_final_array1", SIM, "gc.simulate(m, x0, np.array([10.0]))")
c("sim.t_final_huge", SIM, "gc.simulate(m, x0, 1e200)", "either", "finite(r.x) and r.t[-1] == 1e200")
c("sim.x0_shape", SIM, "gc.simulate(m, np.zeros(3), 10.0)")
c("sim.x0_complex", SIM, "gc.simulate(m, x0 + 1j, 10.0)")
c("sim.controller_not_callable", SIM, "gc.simulate(m, x0, 10.0, 42)")
c("sim.controller_nan", SIM, "gc.simulate(m, x0, 10.0, lambda t, x: np.full(3, np.nan))")
c("sim.method_unknown", SIM, "gc.simulate(m, x0, 10.0, method='bogus')")
c("sim.rtol_negative", SIM, "gc.simulate(m, x0, 10.0, rtol=-1.0)")
c("sim.t_eval_decreasing", SIM, "x = x0.copy()\nx[1] += 0.5\nr = gc.simulate(m, x, 1.0, t_eval=[0.5, 0.2])", "either",
  "np.allclose(r.x, gc.simulate(m, x, 1.0, t_eval=[0.2, 0.5]).x[::-1], rtol=1e-6, atol=1e-8)",
  note="either refused or the states at the requested times")
c("sim.stop_met_at_start", SIM, "gc.simulate(m, x0, 1.0, stop=lambda t, x: -1.0)")
c("sim.model_none", SIM, "gc.simulate(None, x0, 1.0)")
c("sim.tumbling_40s", SIM,
  "gt = gc.steady_glide(v, 0.3, -np.pi / 4, r_bh=-0.05)\nx = gt.force_state()\nx[2] += 0.3\n"
  "r = gc.simulate(gc.LongitudinalGlider(v), x, 40.0)", "either",
  "finite(r.x) and (r.t[-1] == 40.0 or r.stopped_at is not None)",
  note="top-heavy glide (r_bh < 0) tumbles: finish or stop with a BudgetError within the time cap")
c("sim.valid_equilibrium", SIM, "gc.simulate(m, x0, 10.0)", "ok",
  "finite(r.x) and float(np.max(np.abs(r.x[:, 2:] - x0[2:]))) < 1e-6 and r.t[-1] == 10.0")
c("sim.valid_lqr", SIM, "x = x0.copy()\nx[1] += 0.5\nr = gc.simulate(m, x, 120.0, gc.lqr_glide(v, g))", "ok",
  "finite(r.x, r.u) and abs(r.x[-1, 2] - g.theta) < 1e-2 and r.u.shape == (len(r.t), 3)")
c("sim.valid_ctol", SIM, "gc.simulate(gc.CTOLAircraft(dc8), gl.full_state(), 5.0, "
  "gc.SteadyGlideController(dc8, gl, 10.0, 5.0))", "ok",
  "finite(r.x) and np.allclose(r.x[-1, 2:], gl.full_state()[2:], atol=1e-6)")
c("sim.valid_phugoid_energy", SIM,
  "pm = gc.PhugoidModel(mass=14.0, m0=1.0, K=100.0)\nx = gc.initial_state_for_C(pm, 0.3)\n"
  "r = gc.simulate(pm, x, 6.0, rtol=1e-11, atol=1e-12)\nC = np.array([pm.lanchester_C(xi) for xi in r.x])", "ok",
  "float(np.max(np.abs(C - 0.3))) < 1e-6")
c("sim.state.unknown", SIM, "gc.simulate(m, x0, 1.0).state('nope')")
CL = "cl = gc.closed_loop(gc.lqr_glide(v, g))\nX0 = cl.equilibrium + 0.01 * np.eye(cl.n_states)[:3]\n"
c("sim.many.shape", SIM, CL + "r = gc.simulate_many(cl, np.zeros((3, cl.n_states + 1)), 5.0)")
c("sim.many.model_with_inputs", SIM, "gc.simulate_many(m, np.tile(x0, (2, 1)), 5.0)")
c("sim.many.valid", SIM, CL + "r = gc.simulate_many(cl, X0, 5.0)", "ok",
  "r.x_final.shape == X0.shape and finite(r.x_final)")
c("sim.batch.t_eval_beyond", SIM, "gc.integrate_batch(lambda X: -X, np.ones((3, 2)), 1.0, t_eval=[0.5, 2.0])")
c("sim.batch.f_wrong_shape", SIM, "gc.integrate_batch(lambda X: X[:, :1], np.ones((3, 2)), 1.0)")
c("sim.batch.valid", SIM, "gc.integrate_batch(lambda X: -X, np.ones((3, 2)), 1.0, rtol=1e-8, atol=1e-10)", "ok",
  "r.all_finished and np.allclose(r.x_final, np.exp(-1.0), rtol=1e-6)")
c("sim.batch.valid_blowup", SIM, "gc.integrate_batch(lambda X: X ** 2, np.ones((2, 1)), 2.0, bound=1e6)", "ok",
  "bool(np.all(r.diverged))")
TS = "model, xe, lqr = torque_setup()\nX = xe + np.array([[0.05, 0.0, 0.0, 0.0], [0.0, 0.05, 0.0, 0.0]])\n"
c("sim.compare.controller_str", SIM, TS + "r = gc.compare_controllers(model, {'lqr': 'x'}, X, xe, [0.0], 5.0)")
c("sim.compare.valid", SIM, TS + "r = gc.compare_controllers(model, {'lqr': lqr}, X, xe, [0.0], 20.0)", "ok",
  "bool(np.all(r.records['lqr'].converged))")
c("sim.plot.unknown_state", SIM, "gc.simulate(m, x0, 1.0).plot(names=('nope',))")
# models
c("sim.model.longitudinal_ctol", SIM, "gc.LongitudinalGlider(dc8)")
c("sim.model.longitudinal_no_moving_mass", SIM, "gc.LongitudinalGlider(sph)")
c("sim.model.rhs_state_shape", SIM, "m.rhs(np.zeros(3), np.zeros(3))")
c("sim.model.glider3d_longitudinal_vehicle", SIM, "gc.Glider3D(v)")
c("sim.model.fixed_mass_r_p_short", SIM, "gc.FixedMassGlider3D(slo, (0.02, 0.02), 0.25)")
c("sim.model.fixed_mass_zero_solid_mass", SIM, "gc.FixedMassGlider3D(slo, (0.02, 0.02, 0.04), -41.0)")
c("sim.model.ctol_glider_vehicle", SIM, "gc.CTOLAircraft(v)")
c("sim.model.closed_loop_ctol_glider_glide", SIM, "gc.ClosedLoopCTOL(dc8, g, 10.0, 5.0)")
c("sim.model.closed_loop_ctol_valid", SIM, "gc.ClosedLoopCTOL(dc8, gl, 10.0, 5.0)", "ok",
  "float(np.max(np.abs(r.rhs(np.zeros(4))))) < 1e-12 and bool(np.all(np.linalg.eigvals(r.jacobian()).real < 0))")
c("sim.model.glide_path_nan", SIM, "gc.GlidePathModel(m, float('nan'))")
c("sim.phugoid.negative_mass", SIM, "gc.PhugoidModel(mass=-14.0, m0=1.0, K=100.0)")
c("sim.phugoid.classify_nan", SIM, "gc.classify_C(float('nan'))")
c("sim.phugoid.classify_above", SIM, "gc.classify_C(1.0)")
c("sim.phugoid.classify_valid", SIM, "gc.classify_C(0.3)", "ok", "r == gc.PhugoidClass.WAVY")
c("sim.phugoid.period_valid", SIM,
  "pm = gc.PhugoidModel(mass=14.0, m0=1.0, K=100.0)\nr = gc.orbit_period(pm, gc.C_STEADY)",
  "ok", "math.isclose(r, pm.linear_period, rel_tol=1e-9)")
c("sim.phugoid.branch_unknown", SIM,
  "gc.initial_state_for_C(gc.PhugoidModel(mass=14.0, m0=1.0, K=100.0), 0.3, branch='medium')")
c("sim.rotation.quat_zero", SIM, "gc.quat_to_R([0.0, 0.0, 0.0, 0.0])")
c("sim.rotation.quat_nan", SIM, "gc.quat_to_R([float('nan'), 0.0, 0.0, 0.0])")
c("sim.rotation.quat_valid", SIM, "gc.quat_to_R([2.0, 0.0, 0.0, 0.0])", "ok", "np.allclose(r, np.eye(3))")
c("sim.rotation.R_not_rotation", SIM, "gc.R_to_ypr(np.ones((3, 3)))")
c("sim.rotation.roundtrip", SIM, "gc.R_to_ypr(gc.ypr_to_R(0.1, 0.2, 0.3))", "ok", "np.allclose(r, [0.1, 0.2, 0.3])")

# ---------------------------------------------------------------- reports and the command line
RP = "from glidectl.report import Report\n"
c("rep.report.title_int", REP, RP + "r = Report(123)")
c("rep.report.vehicle_name", REP, RP + "r = Report('t', vehicle='rogue')")
c("rep.report.vehicle_list_bad", REP, RP + "r = Report('t', vehicle=[v, 'x'])")
c("rep.report.reference_int", REP, RP + "r = Report('t', reference=5)")
c("rep.report.table_row_length", REP, RP + "rep = Report('t')\nr = rep.table('c', ['a', 'b'], [[1]])")
c("rep.report.number_duplicate", REP,
  RP + "rep = Report('t')\nrep.number('x', 1.0, 'm')\nr = rep.number('x', 2.0, 'm')")
c("rep.report.figure_not_figure", REP, RP + "rep = Report('t')\nr = rep.figure('f', 'not a figure', 'cap')")
c("rep.report.figure_duplicate", REP,
  RP + "from matplotlib.figure import Figure\nrep = Report('t')\nrep.figure('f', Figure(), 'a')\n"
  "r = rep.figure('f', Figure(), 'b')")
c("rep.report.text_heading_none", REP, RP + "rep = Report('t')\nr = rep.text(None, 'body')")
c("rep.report.write_bad_folder", REP, RP + "rep = Report('t')\nrep.number('x', 1.0, 'm')\nr = rep.write('/dev/null/x')")
c("rep.report.valid_write", REP,
  RP + "from matplotlib.figure import Figure\nrep = Report('probe', vehicle=[v, sph])\n"
  "rep.number('speed', g.speed, 'm/s', source='gc.steady_glide', published=0.3, tolerance=1e-9)\n"
  "rep.table('t', ['a', 'b'], [[1, 2]])\nfig = Figure()\nfig.add_subplot().plot([0, 1])\n"
  "rep.figure('line', fig, 'a line')\nr = rep.write(TMP / 'out')",
  "ok", "r.exists() and (TMP / 'out' / 'line.png').exists() and "
  "__import__('json').loads((TMP / 'out' / 'numbers.json').read_text())[0]['reproduced'] is True")
c("rep.design.unknown_name", REP, "from glidectl.report import load_design\nr = load_design('no_such_design', DESIGNS)")
c("rep.design.syntax_error", REP,
  "from glidectl.report import load_design\nr = load_design(design_file('bad_syntax.py', 'def design(:\\n'))")
c("rep.design.no_title", REP,
  "from glidectl.report import load_design\n"
  "r = load_design(design_file('no_title.py', 'def design(progress, quick=False):\\n    return None\\n'))")
c("rep.design.returns_none", REP,
  "from glidectl.report import build_design\n"
  "r = build_design(design_file('returns_none.py', 'TITLE = \"x\"\\ndef design(progress, quick=False):\\n"
  "    return None\\n'), TMP / 'out')")
c("rep.design.bad_out", REP,
  "from glidectl.report import build_design\nr = build_design(design_file('tiny.py'), '/dev/null/x')", limit=20.0)
c("rep.design.valid_build", REP,
  "from glidectl.report import build_design\nr = build_design(design_file('tiny.py'), TMP / 'out')", "ok",
  "r.exists() and (TMP / 'out' / 'tiny' / 'numbers.json').exists()")
c("rep.design.run_script_bad", REP,
  "from glidectl.report import run_script\nr = run_script(design_file('bad_syntax.py', 'def design(:\\n'), [str(TMP)])")
c("rep.cli.unknown_design", REP, "cli(['report', 'no_such_design', '--designs', DESIGNS, '--out', TMP])", "ok",
  "r == 2")
c("rep.cli.out_dev_null", REP,
  "cli(['report', 'ch2_longitudinal', '--designs', DESIGNS, '--out', '/dev/null/x'])", "ok", "r == 2 and elapsed < 20",
  limit=20.0, note="the output folder must be refused before anything is computed")
c("rep.cli.out_dev_null_all", REP, "cli(['report', 'all', '--designs', DESIGNS, '--out', '/dev/null/x'])", "ok",
  "r == 2 and elapsed < 30", limit=30.0)
c("rep.cli.unknown_command", REP, "cli(['bogus'])", "ok", "r == 2")
c("rep.cli.designs_missing", REP, "cli(['report', 'all', '--designs', TMP / 'nowhere', '--out', TMP])", "ok",
  "r == 2")
c("rep.cli.syntax_error", REP, "cli(['report', design_file('bad_syntax.py', 'def design(:\\n'), '--out', TMP])",
  "ok", "r == 2")
c("rep.cli.returns_none", REP,
  "cli(['report', design_file('returns_none.py', 'TITLE = \"x\"\\ndef design(progress, quick=False):\\n"
  "    return None\\n'), '--out', TMP])", "ok", "r == 2")
c("rep.cli.design_raises", REP,
  "cli(['report', design_file('raises.py', 'TITLE = \"x\"\\ndef design(progress, quick=False):\\n"
  "    return 1 / 0\\n'), '--out', TMP])", "ok", "r == 2",
  note="README: every error exits with status 2 and one line")
c("rep.cli.valid_report", REP, "cli(['report', design_file('tiny.py'), '--out', TMP])", "ok",
  "r == 0 and (TMP / 'tiny' / 'report.pdf').exists()")
c("rep.cli.valid_list", REP, "cli(['list', '--designs', DESIGNS])", "ok", "r == 0")


def _check_unique() -> None:
    seen: set[str] = set()
    for case in CASES:
        if case.id in seen:
            raise ValueError(f"duplicate case id {case.id}")
        if case.group not in GROUPS or case.expect not in ("error", "ok", "either"):
            raise ValueError(f"case {case.id}: bad group or expect")
        if case.expect != "error" and case.check is None:
            raise ValueError(f"case {case.id}: expect={case.expect!r} needs a check")
        seen.add(case.id)


_check_unique()
