"""Chapter 4 design: phugoid-mode model, Lanchester's classes of motion (Fig 4.1), Hamiltonian formulations.

The Fig 4.1 analogue (four classes of the Lanchester constant C), conservation and orbit periods (the cusp
case C = 0 has a finite period), and the vector fields of every formulation of the chapter (canonical 2-D,
2-form, charged particle, Euler-Lagrange, Legendre, pendulum with a driven base) compared with the one
right-hand side ``gc.PhugoidModel.rhs``, with the thesis corrections they expose.

Run ``glidectl report ch4_phugoid`` or ``python designs/ch4_phugoid.py [OUTDIR] [--quick]``;
writes ``OUTDIR/ch4_phugoid/``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import glidectl as gc
from glidectl.report import BHATTA_2006, Report, new_figure, run_script

ph = gc.phugoid_hamiltonian

TITLE = "Chapter 4: phugoid-mode model, Lanchester's classes of motion and Hamiltonian formulations"
#: build times on a 2-core machine (s): order a first cold `glidectl report all` longest first
EXPECTED_SECONDS = {"quick": 5.0, "full": 8.0}

# ------------------------------------------------------------------------------- thesis values (chapter 4)
MASS, M0, K_LIFT = 14.0, 1.0, 100.0  # kg, kg, kg/m: Fig 4.1 (m1 + mbar, m0, K)
G = 9.81  # m/s^2: chapter 4 does not state g; standard gravity assumed (nothing printed in chapter 4 depends on it)
C_STEADY = gc.C_STEADY  # 2/3: the relative equilibrium (steady level flight) of §4.1
THESIS_CLASS = {"2_3": gc.PhugoidClass.STEADY_LEVEL, "0_4": gc.PhugoidClass.WAVY, "0": gc.PhugoidClass.CUSP,
                "m0_5": gc.PhugoidClass.LOOPS}  # from the text of §4.1


@dataclass(frozen=True)
class Settings:
    """Every setting of the design (FULL: the values of the published report)."""

    t_final: float = 6.0  # s, Fig 4.1
    #: Lanchester constants of the four runs of the Fig 4.1 analogue (our choice: the thesis does not print its C's)
    c_runs: tuple[tuple[str, float], ...] = (("2_3", C_STEADY), ("0_4", 0.4), ("0", 0.0), ("m0_5", -0.5))
    n_t: int = 6001  # output samples per run (1 ms)
    rtol: float = 1e-10
    atol: float = 1e-12
    n_samples: int = 2000  # random states per vector-field comparison
    seed: int = 2006
    v_box: float = 3.0  # velocity samples in [-v_box, v_box] xdot_e per component
    exact_tol: float = 1e-12  # relative: values that are exact in theory (C of steady flight)
    mismatch_tol: float = 1e-10  # relative: a formulation "generates the phugoid field" when its mismatch is below
    period_grid: tuple[float, float, int] = (-2.0, C_STEADY, 241)  # linspace of C for the period curve
    n_pendulum: int = 500  # pendulum states for the circle-departure and canonical-pendulum checks


FULL = Settings()
QUICK = Settings(n_t=1201, n_samples=200, period_grid=(-2.0, C_STEADY, 25), n_pendulum=100)

_CLAIM_NOTE = {
    "thesis": "The thesis (with the corrections noted) claims equality; reproduced when below 1e-10.",
    "printed": "The formula exactly as printed, which the thesis claims equal: not reproduced (typo, see notes).",
    "contrast": "Shown for contrast: equality is not claimed.",
    "finding": "Our finding (no thesis claim): the printed matrix generates the mirror image x -> -x of the "
               "phugoid, i.e. the phugoid with the lift reversed (K -> -K).",
}

@dataclass(frozen=True)
class Mismatch:
    """Max difference between a formulation's vector field and ``gc.PhugoidModel.rhs`` over a sample of states."""

    key: str
    formulation: str
    equations: str
    samples: str
    n: int
    max_abs: float  # SI (m/s and m/s^2 mixed; kg m/s^2 for the momentum rows)
    rel: float  # max_abs / max |reference field| over the sample
    claim: str  # "thesis": equality claimed, formula as coded here; "printed": a formula exactly as printed,
    #             claimed equal by the thesis; "contrast": equality not claimed; "finding": our own observation


@dataclass(frozen=True)
class Run:
    """One simulation of the Fig 4.1 analogue and what was measured on it."""

    tag: str
    C: float
    x0: np.ndarray
    sim: gc.Simulation
    C0: float  # C of the initial state (round trip of initial_state_for_C)
    cls: gc.PhugoidClass
    drift_E: np.ndarray  # |E(t) - E(0)| / |E(0)|
    drift_C: np.ndarray  # |C(t) - C(0)|
    xdot_top: float  # xdot / xdot_e at the slowest sampled point
    bottoms: np.ndarray  # times (s) of the lowest points (zdot crossing + -> -), t = 0 included
    period_measured: float | None  # mean spacing of bottoms (s)
    period_predicted: float | None  # orbit_period (s)


@dataclass(frozen=True)
class Ch4Results:
    """Everything :func:`compute` produces (immutable)."""

    settings: Settings
    model: gc.PhugoidModel
    runs: tuple[Run, ...]
    linear_eigs: np.ndarray
    mismatches: tuple[Mismatch, ...]
    period_curve: tuple[np.ndarray, np.ndarray]  # (C, T(C) in s)
    cusp_period: float
    pendulum: ph.PendulumAnalogue
    circle_departure: float  # max |d^2(|r|^2/2)/dt^2 - g_p z| along the phugoid at pendulum states (m^2/s^2)
    hamilton_pendulum_mismatch: float  # corrected (4.24)-(4.25) vs (4.23), relative
    timings: dict[str, float] = field(default_factory=dict)


def _bottoms(sim: gc.Simulation) -> np.ndarray:
    """Times where zdot crosses zero from + to - (lowest points), linearly interpolated; t = 0 included."""
    t, zd = sim.t, sim.state("zdot")
    k = np.nonzero((zd[:-1] > 0) & (zd[1:] <= 0))[0]
    tc = t[k] + (t[k + 1] - t[k]) * zd[k] / (zd[k] - zd[k + 1])
    return np.concatenate([[0.0], tc])


def _run(s: Settings, model: gc.PhugoidModel, tag: str, C: float) -> Run:
    x0 = gc.initial_state_for_C(model, C)
    sim = gc.simulate(model, x0, s.t_final, t_eval=np.linspace(0.0, s.t_final, s.n_t), rtol=s.rtol, atol=s.atol)
    E, Cs = model.energy(sim.x), model.lanchester_C(sim.x)
    V = np.hypot(sim.state("xdot"), sim.state("zdot"))
    cls = gc.classify_C(float(Cs[0]))
    if cls is gc.PhugoidClass.STEADY_LEVEL:
        bottoms, pm, pp = np.array([0.0]), None, None
    else:
        bottoms = _bottoms(sim)
        pm = float(np.mean(np.diff(bottoms))) if bottoms.size > 1 else None
        pp = gc.orbit_period(model, C)
    return Run(tag, C, x0, sim, float(Cs[0]), cls, np.abs(E - E[0]) / abs(E[0]), np.abs(Cs - Cs[0]),
               float(sim.state("xdot")[np.argmin(V)] / model.xdot_e), bottoms, pm, pp)


def _mismatch(key: str, formulation: str, eqs: str, samples: str, got: np.ndarray, ref: np.ndarray,
              claim: str) -> Mismatch:
    d = float(np.max(np.abs(got - ref)))
    return Mismatch(key, formulation, eqs, samples, int(ref.shape[0]), d, d / float(np.max(np.abs(ref))), claim)


def _mismatches(s: Settings, model: gc.PhugoidModel, rng: np.random.Generator) -> list[Mismatch]:
    n, xe, vb = s.n_samples, model.xdot_e, s.v_box
    X = np.column_stack([rng.uniform(-10, 10, n), rng.uniform(-10, 10, n),
                         rng.uniform(-vb, vb, n) * xe, rng.uniform(-vb, vb, n) * xe])
    f = model.rhs(X)
    Z = ph.zero_energy_shift(model, X)  # E = 0
    fz = model.rhs(Z)
    off = Z.copy()
    off[:, 1] = rng.uniform(0.0, 2.0, n) * Z[:, 1] + rng.uniform(0.0, 0.05, n)  # z >= 0, E != 0
    pend = ph.PendulumAnalogue.from_model(model)
    th = rng.uniform(-math.pi, math.pi, n)
    w = rng.uniform(0.0, vb * xe / pend.length, n)
    P, Pn = pend.state(th, w), pend.state(th, -w)
    gen, zero = f"uniform, |pos| <= 10 m, |vel| <= {vb:g} xdot_e", "E = 0 (z = m V^2 / 2 m0 g)"
    q = 1.0  # C: the charge cancels out of K/q * q

    def b_field(s6: np.ndarray) -> np.ndarray:
        V = np.sqrt(s6[..., 3] ** 2 + s6[..., 4] ** 2 + s6[..., 5] ** 2)
        return np.stack([np.zeros_like(V), -(model.K / q) * V, np.zeros_like(V)], axis=-1)

    S6 = np.column_stack([X[:, 0], np.zeros(n), X[:, 1], X[:, 2], np.zeros(n), X[:, 3]])
    cp = ph.charged_particle_field(S6, model.mass, q, b_field, model.m0 * model.g / model.mass)
    y = ph.to_canonical(model, Z)
    pdot = ph.legendre_field(model, y)[:, 2:]
    # the phugoid with K -> -K is the mirror image x -> -x of the phugoid: f_{-K}(X) = R f(R X), R = diag(-1, 1, -1, 1)
    R = np.array([-1.0, 1.0, -1.0, 1.0])
    fr = R * model.rhs(R * X)
    return [
        _mismatch("canonical_2d", "(a) canonical 2-D, q = xdot, p = zdot", "(4.6)-(4.8)", gen,
                  ph.canonical_vector_field(model, X), f, "thesis"),
        _mismatch("omega_B", "(b) Omega_B from the 2-form, i_X Omega = dE", "(4.31)-(4.35)", gen,
                  ph.symplectic_field(model, X), f, "thesis"),
        _mismatch("omega_B_printed", "(b) Omega_B matrix as printed", "(4.31) matrix", gen,
                  ph.symplectic_field(model, X, printed=True), f, "printed"),
        _mismatch("omega_B_printed_mirror", "(b) printed matrix vs phugoid with K -> -K",
                  "(4.31) matrix", gen, ph.symplectic_field(model, X, printed=True), fr, "finding"),
        _mismatch("charged_particle", "charged particle (4.13), B_y = -(K/q)V, g -> m0 g/m", "(4.11)-(4.18)",
                  gen, cp[:, [0, 2, 3, 5]], f, "thesis"),
        _mismatch("euler_lagrange_E0", "(c) Euler-Lagrange of L with vector potential", "(4.37)-(4.42)", zero,
                  ph.euler_lagrange_field(model, Z), fz, "thesis"),
        _mismatch("euler_lagrange_offE0", "(c) Euler-Lagrange, E != 0 (not claimed equal)", "(4.41)-(4.42)",
                  "z >= 0, E != 0", ph.euler_lagrange_field(model, off), model.rhs(off), "contrast"),
        _mismatch("legendre_E0", "(d) canonical Hamiltonian |p - KA|^2/2m - m0 g z", "(4.44)-(4.48)", zero,
                  ph.legendre_vector_field(model, Z), fz, "thesis"),
        _mismatch("legendre_vs_EL_offE0", "(d) vs (c) off E = 0 (same system)", "(4.44)-(4.46)", "z >= 0, E != 0",
                  ph.legendre_vector_field(model, off), ph.euler_lagrange_field(model, off), "thesis"),
        _mismatch("pdot_printed_line1", "(d) pdot of (4.46) line 1 as printed vs -dH/dq", "(4.46)", zero,
                  ph.pdot_as_printed(model, y, 1), pdot, "printed"),
        _mismatch("pdot_printed_line2", "(d) pdot of (4.46) line 2 as printed vs -dH/dq", "(4.46)", zero,
                  ph.pdot_as_printed(model, y, 2), pdot, "printed"),
        _mismatch("pendulum_driven_base", "(e) pendulum + driven base, l = m/K, g_p = m0 g/m",
                  "(4.51)-(4.58) corr.", "pendulum states, thetadot > 0", pend.relative_field(P), model.rhs(P),
                  "thesis"),
        _mismatch("pendulum_driven_base_neg", "(e) same, thetadot < 0 (not claimed)", "(4.51)-(4.58) corr.",
                  "pendulum states, thetadot < 0", pend.relative_field(Pn), model.rhs(Pn), "contrast"),
    ]


def compute(s: Settings, progress: Callable[[str], None] = lambda msg: None) -> Ch4Results:
    """Run every computation of the chapter-4 study (Fig 4.1 vehicle: m = 14 kg, m0 = 1 kg, K = 100 kg/m)."""
    tm: dict[str, float] = {}
    t0 = time.perf_counter()
    model = gc.PhugoidModel(MASS, M0, K_LIFT, G)
    progress(f"Fig 4.1 analogue: four classes of C, {s.t_final:g} s each (rtol {s.rtol:g})")
    runs = tuple(_run(s, model, tag, C) for tag, C in s.c_runs)
    tm["simulations"] = time.perf_counter() - t0

    progress("linearization at steady level flight (complex-step Jacobian)")
    A, _ = gc.jacobians(model.rhs, gc.initial_state_for_C(model, C_STEADY), np.zeros(0))
    eigs = np.linalg.eigvals(A)

    progress(f"vector fields of the Hamiltonian formulations vs PhugoidModel.rhs ({s.n_samples} states each)")
    t1 = time.perf_counter()
    mism = tuple(_mismatches(s, model, np.random.default_rng(s.seed)))
    tm["mismatches"] = time.perf_counter() - t1

    progress("orbit period versus C (quadrature)")
    period_c = np.linspace(*s.period_grid)
    periods = np.array([gc.orbit_period(model, float(c)) for c in period_c])

    progress("pendulum analogue: departure from the circle, canonical pendulum equations")
    pend = ph.PendulumAnalogue.from_model(model)
    rng = np.random.default_rng(s.seed + 1)
    npd = s.n_pendulum
    P = pend.state(rng.uniform(-math.pi, math.pi, npd), rng.uniform(0.1, 20.0, npd))
    f = model.rhs(P)
    dd = np.sum(P[:, 2:] ** 2, axis=1) + np.sum(P[:, :2] * f[:, 2:], axis=1)  # d^2(|r|^2/2)/dt^2 on the phugoid
    departure = float(np.max(np.abs(dd - pend.gravity * P[:, 1])))
    th = rng.uniform(-math.pi, math.pi, npd)
    p = rng.uniform(-5.0, 5.0, npd)
    thd, pd = pend.hamilton_field(th, p)
    ml2 = pend.mass * pend.length**2
    ham = float(max(np.max(np.abs(thd - p / ml2)) / np.max(np.abs(p / ml2)),
                    np.max(np.abs(pd / ml2 - pend.theta_ddot(th))) / np.max(np.abs(pend.theta_ddot(th)))))
    tm["total"] = time.perf_counter() - t0
    return Ch4Results(s, model, runs, eigs, mism, (period_c, periods), gc.orbit_period(model, 0.0), pend,
                      departure, ham, tm)


# ---------------------------------------------------------------------------------------------- figures
def _label(run: Run) -> str:
    c = "2/3" if run.tag == "2_3" else f"{run.C:g}"
    return f"C = {c}: {run.cls.value}"


def figures(res: Ch4Results) -> dict[str, tuple[Any, str]]:
    """Figures of the study: ``{stem: (figure, caption)}``."""
    out: dict[str, tuple[Any, str]] = {}
    model, s = res.model, res.settings
    xe = model.xdot_e

    fig, ax = new_figure(1, 2, width=11, height=4.6, gridspec_kw={"width_ratios": [1.55, 1]})
    for k, run in enumerate(res.runs):
        ax[0].plot(run.sim.state("x"), run.sim.state("z"), color=f"C{k}", lw=1.6, label=_label(run))
    ax[0].plot(0, 0, "ko", ms=4)
    ax[0].invert_yaxis()
    ax[0].set_aspect("equal", adjustable="datalim")
    ax[0].set_xlabel("horizontal position x [m]")
    ax[0].set_ylabel("depth z [m] (down)")
    ax[0].set_title(f"trajectories, {s.t_final:g} s from x = z = 0", fontsize=9)
    ax[0].legend(fontsize=8, loc="lower left")
    u = np.linspace(-2.3, 2.3, 401)
    U, W = np.meshgrid(u, u)
    Cg = model.lanchester_C(np.stack([0 * U, 0 * U, U * xe, W * xe], axis=-1))
    cs = ax[1].contour(U, W, Cg, levels=[-2, -1.5, -1, -0.5, 0, 0.2, 0.4, 0.6], colors="0.6", linewidths=0.7)
    ax[1].clabel(cs, fontsize=6, fmt="%g")
    for k, run in enumerate(res.runs):
        ax[1].plot(run.sim.state("xdot") / xe, run.sim.state("zdot") / xe, color=f"C{k}", lw=1.6)
    ax[1].plot(1, 0, "o", color="C0", ms=5)
    ax[1].plot(0, 0, "k+", ms=8)
    ax[1].set_aspect("equal")
    ax[1].invert_yaxis()
    ax[1].set_xlabel(r"$\dot x / \dot x_e$ [-]")
    ax[1].set_ylabel(r"$\dot z / \dot x_e$ [-] (down)")
    ax[1].set_title(r"velocity plane: level sets of C (4.5), $\dot x_e$ = " + f"{xe:.4f} m/s", fontsize=9)
    ax[1].grid(True, alpha=0.3)
    ax[0].grid(True, alpha=0.3)
    ics = "; ".join(f"C = {'2/3' if r.tag == '2_3' else f'{r.C:g}'}: xdot0 = {r.x0[2]:.5f} m/s" for r in res.runs)
    out["fig4_1_trajectories"] = (fig, (
        f"Analogue of Fig 4.1: phugoid-mode trajectories (4.1)-(4.4) for m1 + mbar = {MASS:g} kg, m0 = {M0:g} kg, "
        f"K = {K_LIFT:g} kg/m, g = {G} m/s^2 (assumed), {s.t_final:g} s. Each run starts at x = z = 0 in level "
        f"flight (zdot0 = 0) on the fast branch of initial_state_for_C (the lowest, fastest point of its orbit): "
        f"{ics}. Left: path in the vertical plane, depth down. Right: the same runs in the velocity plane with "
        "level sets of C; the cusp orbit C = 0 passes through zero velocity (+)."))

    fig, ax = new_figure(1, 2, width=10, height=3.8, sharex=True)
    floor = 1e-18
    for k, run in enumerate(res.runs):
        t = run.sim.t[1:]
        ax[0].semilogy(t, np.maximum(run.drift_E[1:], floor), color=f"C{k}", lw=1, label=_label(run))
        ax[1].semilogy(t, np.maximum(run.drift_C[1:], floor), color=f"C{k}", lw=1)
    ax[0].set_ylabel(r"$|E(t) - E(0)| / |E(0)|$ [-]")
    ax[1].set_ylabel(r"$|C(t) - C(0)|$ [-]")
    for a in ax:
        a.set_xlabel("t [s]")
        a.grid(True, alpha=0.3, which="both")
        a.set_ylim(floor, 1e-6)
    ax[0].legend(fontsize=7, loc="upper left")
    out["conservation"] = (fig, (
        f"Conservation along the Fig 4.1 runs (LSODA, rtol = {s.rtol:g}, atol = {s.atol:g}): relative drift of the "
        "energy "
        "E (4.32)/(4.43) (left; E(0) = m V0^2/2 since z0 = 0) and absolute drift of the dimensionless Lanchester "
        f"constant C (4.5) (right). Values below {floor:g} are drawn at {floor:g}. No thesis figure."))

    fig, ax = new_figure(1, 1, width=7, height=3.8)
    Cc, Tc = res.period_curve
    ax.plot(Cc, Tc, "k", lw=1.5, label="orbit_period (quadrature)")
    for k, run in enumerate(res.runs):
        if run.period_measured is not None:
            ax.plot(run.C, run.period_measured, "o", color=f"C{k}", ms=7, mfc="none", mew=1.5,
                    label=f"simulated, {_label(run)}")
    ax.plot(C_STEADY, model.linear_period, "s", color="C0", ms=6, label="linear period at C = 2/3")
    ax.axvline(0.0, color="0.5", ls="--", lw=0.8)
    ax.set_xlabel("Lanchester constant C [-]")
    ax.set_ylabel("period T [s]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    out["period_vs_C"] = (fig, (
        "Period of the phugoid orbits versus C for the Fig 4.1 vehicle: time between successive lowest points "
        "(wavy, C > 0), between cusps (C = 0) or per loop (C < 0). Quadrature of dt = m xdot_e dv / (m0 g "
        "|sin gamma|) along the level set of C (line) and from the simulations (circles). The cusp case C = 0 has "
        f"a finite period, {res.cusp_period:.4f} s, contrary to the 'infinite time interval' of §4.1. "
        "No thesis figure."))
    return out


# ---------------------------------------------------------------------------------------------- report
TYPOS: tuple[tuple[str, str, str, str, str], ...] = (
    # (name, equation, printed, corrected, explanation)
    ("typo_4_10_lorentz", "(4.10)", "dV/dt = (q/m) B x V", "(q/m) V x B + g e_z",
     "(4.13) with i_X Omega = dH and (4.14)/(4.18) generates dV/dt = (q/m) V x B + g e_z (checked on random "
     "states); only V x B makes B_y = -(K/q)V of 4.3.1 give the phugoid lift, and the gravity of H (4.14) is "
     "missing from (4.10)."),
    ("typo_4_11_form", "(4.11)", "m(dx^dp_x+...), p = mV", "m(dx^dV_x+...)",
     "With p = mV, m dx^dp_x = m^2 dx^dV_x; the matrix (4.13) (entries m) and dH (4.18) (entries m xdot) are in "
     "the coordinates (r, V)."),
    ("typo_4_21_22_pendulum", "(4.21)-(4.22)", "dx/dt = -T cos th", "m xddot = -T sin th",
     "Left sides are m dxdot/dt, m dzdot/dt (not dx/dt, dz/dt) and sin/cos are swapped for sin th = x/l, "
     "cos th = z/l: m xddot = -T sin th, m zddot = m g - T cos th (checked against the kinematics of (4.23))."),
    ("typo_4_24_25_pendulum", "(4.24)-(4.25)", "p = m l thd, H = p^2/2m", "p = m l^2 thd, H = p^2/(2ml^2)",
     "With p_theta = m l thetadot the pair (theta, p_theta) is not canonical (dH/dp = l thetadot). Canonical: "
     "thetadot = p/(m l^2), pdot = -m g l sin theta, which reproduces (4.23)."),
    ("typo_4_31_matrix", "(4.31) matrix", "Omega[x,z] = +K V", "Omega[x,z] = -K V",
     "The matrix printed under (4.31) disagrees with the 2-form on the same line (footnote-2 convention, order "
     "x, z, xdot, zdot) and with (4.13) for B_y = -(K/q)V; it generates the phugoid with the lift reversed "
     "(K -> -K)."),
    ("typo_4_34_interior", "(4.34)", "(-KV - m X3, KV - m X4, ..)", "(KV X2 - m X3, -KV X1 - m X4, ..)",
     "Entries 1-2 of X^T Omega_B lack the factors X_H2, X_H1 (with the printed matrix they would be "
     "-KV X_H2 - m X_H3 and KV X_H1 - m X_H4; with the corrected matrix the signs flip as shown)."),
    ("typo_4_46_pdot", "(4.46)", "-(1/m) J_A^T (p - KA)", "+(K/m) J_A^T (p - KA)",
     "pdot = -dH/dq of (4.44) is +(K/m) [dA/dq]^T (p - KA) + (0, m0 g); the second line of (4.46) lacks the "
     "factor K/m: -(K/m) sqrt(2 m0 g z/m)(p1 - K A1) + m0 g."),
    ("claim_4_3_2_shift", "4.3.2", "all E-L trajectories -> E = 0", "phugoid traj. -> E = 0 E-L",
     "z -> z + E/(m0 g) maps every phugoid trajectory (any E) onto a zero-energy Euler-Lagrange trajectory, but "
     "E-L trajectories with E != 0 (lift K sqrt(V^2 - 2E/m)) are not mapped onto solutions: the E-L equations "
     "depend on z. The map is one-to-one only modulo vertical translation: the new depth m V^2/(2 m0 g) depends "
     "on the velocity alone."),
    ("typo_4_51_58_pendulum", "(4.51)-(4.58)", "xddot = (m V/l) zdot", "xddot = (V/l) zdot",
     "Every right-hand term carries a spurious mass factor (accelerations). Corrected, (4.57)-(4.58) match "
     "(4.3)-(4.4) with l = m/K and pendulum gravity g_p = m0 g/m, at pendulum states with thetadot > 0 only; "
     "along the phugoid flow d^2(|r|^2/2)/dt^2 = g_p z != 0, so the base-frame motion leaves the circle |r| = l "
     "(an identity of vector fields, not of motions)."),
)


def _cname(run: Run) -> str:
    return "2/3" if run.tag == "2_3" else f"{run.C:g}"


def report(res: Ch4Results) -> Report:
    """Assemble the report (numbers with thesis values, tables, figures, notes)."""
    rep = Report(TITLE, reference=BHATTA_2006)
    model, s = res.model, res.settings
    xe = model.xdot_e
    rep.number("xdot_e_mps", xe, "m/s", "4.1", note=f"sqrt(m0 g / K) for m1 + mbar = {MASS:g} kg, m0 = {M0:g} kg, "
               f"K = {K_LIFT:g} kg/m, g = {G} m/s^2 (g not stated in chapter 4). Not printed in the thesis.")
    steady = res.runs[0]
    rep.number("C_steady_level", float(steady.C0), "-", "(4.5), 4.1", published=C_STEADY, tolerance=s.exact_tol,
               note="C of the state (x, z, xdot_e, 0); the text says C = 2/3 is the relative equilibrium (steady "
                    "level flight). Its simulated velocity stays at xdot_e: max |V - xdot_e| = "
                    f"{float(np.max(np.abs(np.hypot(steady.sim.state('xdot'), steady.sim.state('zdot')) - xe))):.1e}"
                    f" m/s over {s.t_final:g} s.")
    for run in res.runs:
        pred_top = gc.initial_state_for_C(model, run.C, branch="slow")[2] / xe
        rep.number(f"class_C_{run.tag}", run.cls.value, "-", "4.1, Fig 4.1", published=THESIS_CLASS[run.tag].value,
                   verdict=run.cls is THESIS_CLASS[run.tag],
                   note=f"classify_C(C = {_cname(run)}). Observed on the simulation: at the slowest sampled point "
                        f"xdot/xdot_e = {run.xdot_top:+.4f} (predicted top of the orbit {pred_top:+.4f}: > 0 wavy, "
                        "0 cusp (the glider stops), < 0 loop, flying backwards inverted).")
        rep.number(f"xdot0_C_{run.tag}_mps", float(run.x0[2]), "m/s", "our choice (fast branch)",
                   note=f"initial_state_for_C(C = {_cname(run)}): level flight at the bottom of the orbit, "
                        f"xdot0/xdot_e = {run.x0[2] / xe:.6f}; C of the initial state - requested C = "
                        f"{run.C0 - run.C:.1e}.")
        rep.number(f"drift_E_rel_C_{run.tag}", float(np.max(run.drift_E)), "-", "(4.43)",
                   note=f"max |E(t) - E(0)|/|E(0)| over {s.t_final:g} s (rtol {s.rtol:g}, atol {s.atol:g}).")
        rep.number(f"drift_C_abs_C_{run.tag}", float(np.max(run.drift_C)), "-", "(4.5)",
                   note=f"max |C(t) - C(0)| over {s.t_final:g} s.")
        if run.period_measured is not None:
            rel = abs(run.period_measured - run.period_predicted) / run.period_predicted
            rep.number(f"period_C_{run.tag}_s", run.period_measured, "s", "our analysis",
                       note=f"Mean time between lowest points in the simulation ({run.bottoms.size - 1} periods); "
                            f"orbit_period quadrature gives {run.period_predicted:.6f} s (rel. diff {rel:.1e}).")
    rep.number("linear_period_s", model.linear_period, "s", "linearization of (4.3)-(4.4)",
               note="pi sqrt(2) m xdot_e/(m0 g) (Lanchester's pi sqrt(2) V/g for m = m0). The complex-step Jacobian "
                    "of PhugoidModel.rhs at steady level flight has eigenvalues "
                    + ", ".join(f"{z.real:.2g}{z.imag:+.6f}i" for z in sorted(res.linear_eigs, key=lambda z: z.imag))
                    + f" 1/s, i.e. period {2 * math.pi / np.max(res.linear_eigs.imag):.6f} s. Not printed.")
    rep.number("cusp_period_s", res.cusp_period, "s", "4.1 (C = 0)", published="infinite time interval", verdict=False,
               note="The thesis: 'C = 0 corresponds to a singular trajectory, a single flight with the flight path "
                    "angle varying between -90 deg and +90 deg over an infinite time interval'. Along C = 0 the "
                    "speed falls to zero at the finite rate m0 g/m (only gravity acts at V = 0), so each arch between "
                    "cusps takes 2 sqrt(3) B(1/4,1/2)/4 m xdot_e/(m0 g) = "
                    f"{res.cusp_period:.4f} s; the simulation gives {res.runs[2].period_measured:.4f} s. The C = 0 "
                    "motion is a periodic train of cusps (Lanchester's classical result), not reproduced as stated.")
    for m in res.mismatches:
        rep.number(f"mismatch_{m.key}", m.rel, "-", m.equations,
                   verdict=None if m.claim in ("contrast", "finding") else bool(m.rel < s.mismatch_tol),
                   note=f"{m.formulation}; {m.n} states ({m.samples}); max |dX| = {m.max_abs:.3e} SI, relative to "
                        "max |reference field|. " + _CLAIM_NOTE[m.claim])
    rep.number("pendulum_length_m", res.pendulum.length, "m", "4.3.4 corrected",
               note="l = (m1 + mbar)/K: then the centripetal tension m V^2/l equals the lift K V^2.")
    rep.number("pendulum_gravity_mps2", res.pendulum.gravity, "m/s^2", "4.3.4 corrected",
               note="g_p = m0 g/(m1 + mbar): the pendulum feels the net weight per unit mass of the glider.")
    rep.number("pendulum_circle_departure", res.circle_departure, "m^2/s^2", "4.3.4",
               note=f"max |d^2(|r|^2/2)/dt^2 - g_p z| of the phugoid field at {s.n_pendulum} pendulum states "
                    "(thetadot > 0): "
                    "the identity d^2(|r|^2/2)/dt^2 = g_p z != 0 holds, so the base-frame motion leaves |r| = l.")
    rep.number("pendulum_hamilton_mismatch", res.hamilton_pendulum_mismatch, "-", "(4.23)-(4.25) corrected",
               verdict=res.hamilton_pendulum_mismatch < s.exact_tol,
               note="Hamilton's equations of p^2/(2 m l^2) - m g l cos(theta) vs (4.23), relative.")
    for name, eq, printed, corrected, why in TYPOS:
        rep.number(name, corrected, "-", eq, published=printed, verdict=False, note=why)

    rep.table("Model (Fig 4.1 vehicle)", ["quantity", "value", "unit", "source"], [
        ["m = m1 + mbar", f"{MASS:g}", "kg", "4.1, Fig 4.1"],
        ["m0", f"{M0:g}", "kg", "4.1, Fig 4.1"],
        ["K = K_L0 + K_L alpha", f"{K_LIFT:g}", "kg/m", "4.1, Fig 4.1"],
        ["g", f"{G}", "m/s^2", "assumed (not stated in chapter 4)"],
        ["xdot_e = sqrt(m0 g/K)", f"{xe:.6f}", "m/s", "4.1"],
        ["T0 = m xdot_e/(m0 g)", f"{model.time_scale:.6f}", "s", "time unit of orbit_period"],
        ["pendulum l = m/K", f"{res.pendulum.length:.4f}", "m", "4.3.4 corrected"],
        ["pendulum g_p = m0 g/m", f"{res.pendulum.gravity:.6f}", "m/s^2", "4.3.4 corrected"],
    ])
    rows = []
    for run in res.runs:
        rows.append([_cname(run), run.cls.value, f"{run.x0[2]:.6f}", f"{run.x0[2] / xe:.6f}", f"{run.C0:.3e}",
                     f"{run.xdot_top:+.4f}",
                     "-" if run.period_predicted is None else f"{run.period_predicted:.6f}",
                     "-" if run.period_measured is None else f"{run.period_measured:.6f}",
                     f"{np.max(run.drift_E):.1e}", f"{np.max(run.drift_C):.1e}"])
    rep.table(f"Fig 4.1 runs (x0 = z0 = 0, zdot0 = 0, {s.t_final:g} s, rtol {s.rtol:g}, atol {s.atol:g})",
              ["C", "class", "xdot0 [m/s]", "xdot0/xdot_e", "C(0)", "top xdot/xdot_e", "T pred. [s]",
               "T sim. [s]", "max rel dE", "max |dC|"], rows)
    rep.table(f"Vector fields of the formulations vs PhugoidModel.rhs ({s.n_samples} random states each)",
              ["key", "formulation", "equations", "states", "max |dX| (SI)", "relative", "claim"],
              [[m.key, m.formulation, m.equations, m.samples, f"{m.max_abs:.2e}", f"{m.rel:.2e}",
                m.claim] for m in res.mismatches])
    rep.table("Thesis corrections (chapter 4)", ["ledger name", "equation", "printed", "corrected"],
              [[n, eq, p, c] for n, eq, p, c, _ in TYPOS])
    for stem, (fig, cap) in figures(res).items():
        rep.figure(stem, fig, cap)
    rep.text("Method", (
        "One right-hand side, glidectl.models.phugoid.PhugoidModel.rhs (4.1)-(4.4), is simulated and compared "
        "with every other formulation of the chapter, coded in glidectl.models.phugoid_hamiltonian from its "
        "generating object: (a) the canonical Hamiltonian (4.6) with q = xdot, p = zdot; (b) the 2-form (4.31) "
        "built literally from wedge products, with i_X Omega = dE solved by numpy.linalg.solve, and the charged "
        "particle (4.13) it comes from; (c) the Lagrangian (4.37) with vector potential A, whose Euler-Lagrange "
        "equations are solved for a magnetic-type Lagrangian (verified in the tests against central differences "
        "of L itself); (d) the Legendre-transformed Hamiltonian (4.44), Hamilton's equations pulled back through "
        "the transform; (e) the pendulum with a driven base. All gradients and Jacobians are exact (complex "
        "step), so the mismatches are at rounding level where the thesis (as corrected) claims equality.\n\n"
        "Fig 4.1 does not print its C values or initial conditions; we use C = 2/3, 0.4, 0, -0.5 and start each "
        "run in level flight at the fast root of C = s - |s|^3/3 (s = xdot0/xdot_e >= 1), i.e. at the bottom of "
        "the orbit. The other root (branch='slow') lies on the same orbit half a period later. g = 9.81 m/s^2 is "
        "assumed (chapters 5 and 8 are reproduced with 9.8; no chapter-4 statement depends on g, which only "
        "rescales xdot_e and the time unit m xdot_e/(m0 g)). Nothing was tuned to match the thesis; no number "
        "in chapter 4 is printed besides C = 2/3."))
    rep.text("Thesis corrections and remarks", "\n\n".join(f"{eq}: {why}" for _, eq, _, _, why in TYPOS) + (
        "\n\n4.1, C = 0: the 'infinite time interval' is not reproduced; the cusp period is finite (cusp_period_s)."
        "\n\n4.3.4, last sentence ('... observer travelling along the x-direction with a constant speed equal to "
        "the average speed of the glider'): with the corrected equations the base-frame motion is the phugoid "
        "motion itself, in the inertial frame; we could not give the travelling observer a precise meaning and "
        "did not test it."))
    return rep



def design(progress: Callable[[str], None] = lambda msg: None, quick: bool = False) -> Report:
    """The chapter-4 design: compute everything, then assemble the report (not written here)."""
    res = compute(QUICK if quick else FULL, progress)
    progress("figures and report")
    return report(res)


if __name__ == "__main__":
    run_script(__file__)
