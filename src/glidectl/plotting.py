"""Drawing glidectl results: one plot style and the drawing code behind the results' ``.plot()`` methods.

Results are computed elsewhere and draw themselves, as in python-control's ``ctrlplot``: a compute function
returns a frozen result object, and its ``.plot(ax=None, **kw)`` draws it and returns what it drew (an axes or an
array of axes)::

    locus = gc.rbh_locus(veh, 0.3, -math.pi / 4, np.linspace(0.0, 0.1, 201))
    ax = locus.plot()                 # root locus in the complex plane
    ax = locus.plot(kind="real")      # real parts versus r_bh

The methods import this module lazily, so computing never imports the drawing code, and they draw inside
:func:`style` (:data:`STYLE` through :func:`matplotlib.rc_context`), which restores the user's settings afterwards.
The functions below are what the methods call; they draw into the axes given or into a new figure
(:func:`new_figure`) and never compute dynamics (the region-of-attraction plots evaluate the certified set's
membership on a grid, nothing more). glidectl never calls :func:`matplotlib.use`: the backend is the user's.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from .analysis.continuation import COLUMN_UNITS
from .errors import GlidectlError
from .models.buoyancy_glider import BUOYANCY_UNITS
from .models.longitudinal import STATE_UNITS
from .models.reduced import REDUCED_UNITS

if TYPE_CHECKING:
    from .analysis.closed_loop import BatchComparison
    from .analysis.helix_existence import ExistenceScan
    from .analysis.helix_stability import HelixRbhLocus
    from .analysis.helix_sweeps import HelixSweep
    from .analysis.locus import ParameterLocus
    from .controllers.ctol_runs import TrackingRun
    from .controllers.ctol_tracking import ParetoStudy
    from .controllers.dive_cycle import DiveCycleRun
    from .roa.certificate import ROACertificate
    from .sim import Ensemble, Simulation
    from .stability.composite import CompositeCertificate

__all__ = [
    "STYLE",
    "label",
    "new_figure",
    "plot_batch_comparison",
    "plot_composite_certificate",
    "plot_dive_cycle",
    "plot_ensemble",
    "plot_existence_scan",
    "plot_glide_envelope",
    "plot_helix_rbh_locus",
    "plot_helix_sweep",
    "plot_locus",
    "plot_locus_real",
    "plot_pareto_study",
    "plot_roa_certificate",
    "plot_simulation",
    "plot_tracking_run",
    "style",
]

_LATEX = {"theta": r"$\theta$", "Omega2": r"$\Omega_2$", "v1": r"$v_1$", "v3": r"$v_3$", "r_P1": r"$r_{P1}$",
          "r_P3": r"$r_{P3}$", "P_P1": r"$P_{P1}$", "P_P3": r"$P_{P3}$", "m0": r"$m_0$", "z_prime": r"$z'$",
          "rdot_P1": r"$\dot r_{P1}$", "rdot_P3": r"$\dot r_{P3}$", "x": "$x$", "z": "$z$", "u1": "$u_1$",
          "u3": "$u_3$", "u4": "$u_4$", "w1": "$w_1$", "w3": "$w_3$", "w4": "$w_4$", "r_bh": r"$r_{bh}$",
          "mbar": r"$\bar m$", "r_P2": r"$r_{P2}$", "y": "$y$", "xdot": r"$\dot x$", "ydot": r"$\dot y$",
          "u2": "$u_2$", "V": "$V$", "gamma": r"$\gamma$", "alpha": r"$\alpha$", "Vbar": r"$\bar V$",
          "gammabar": r"$\bar\gamma$", "alphabar": r"$\bar\alpha$", "thetabar": r"$\bar\theta$",
          "Omegabar2": r"$\bar\Omega_2$", "Omega2bar": r"$\bar\Omega_2$", "x1": "$x_1$", "x2": "$x_2$"}

# units of names that are not in STATE_UNITS (names that mean one thing in every model)
_EXTRA_UNITS = {"V": "m/s", "gamma": "rad", "alpha": "rad", "beta": "rad", "phi": "rad", "psi": "rad", "y": "m",
                "xdot": "m/s", "ydot": "m/s", "v2": "m/s", "Omega1": "rad/s", "Omega3": "rad/s", "torque": "N m",
                "q0": "-", "q1": "-", "q2": "-", "q3": "-", "Vbar": "-", "gammabar": "rad", "alphabar": "rad",
                "thetabar": "rad"}
# states and inputs whose unit depends on the model (u1 is a force, a pump rate or a thrust), by model class name
_CTOL_UNITS = {"x": "m", "y": "m", "xdot": "m/s", "ydot": "m/s", "theta": "rad", "Omega2": "rad/s", "u1": "N",
               "u2": "N m"}
_MODEL_UNITS: dict[str, Mapping[str, str]] = {
    "ReducedLongitudinalGlider": REDUCED_UNITS, "TorqueControlledGlider": {**REDUCED_UNITS, "torque": "N m"},
    "BuoyancyGlider": BUOYANCY_UNITS, "ElevatorBuoyancyGlider": BUOYANCY_UNITS, "CTOLAircraft": _CTOL_UNITS,
    "ExtendedCTOL": {**_CTOL_UNITS, "u1dot": "N/s", "u1ddot": "N/s^2"},
}


def _model_units(model: str) -> Mapping[str, str]:
    """Units of a model's states and inputs from its name ``"Class(vehicle)"`` (``Simulation.model_name``; empty if
    unknown)."""
    return _MODEL_UNITS.get(model.split("(", 1)[0], {})


def label(name: str, unit: str | None = None) -> str:
    """Axis label ``symbol [unit]`` for a named state, input or parameter.

    Parameters
    ----------
    name : str
        A glidectl state, input or parameter name (``"theta"``, ``"r_P1"``, ``"Vbar"``, ...); known names are
        typeset as symbols.
    unit : str, optional
        Unit to print; default the unit of ``name`` in
        :data:`glidectl.models.longitudinal.STATE_UNITS` (or of a few other unambiguous names such as ``V``,
        ``gamma``, ``alpha``), none if unknown.

    Returns
    -------
    str
        ``"$\\theta$ [rad]"``, or the symbol alone when there is no unit.
    """
    u = unit if unit is not None else STATE_UNITS.get(name, _EXTRA_UNITS.get(name, ""))
    return f"{_LATEX.get(name, name)} [{u}]" if u else _LATEX.get(name, name)


#: the one plot style of glidectl figures (applied with :func:`style`)
STYLE: dict[str, Any] = {
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "figure.dpi": 100,
    "savefig.dpi": 130,
}


def style() -> Any:
    """Context manager applying glidectl's plot style (:data:`STYLE`) with :func:`matplotlib.rc_context`.

    Returns
    -------
    contextlib.AbstractContextManager
        ``with style(): ...`` draws with the glidectl style and restores the user's settings afterwards.
    """
    return matplotlib.rc_context(STYLE)


def new_figure(nrows: int = 1, ncols: int = 1, *, width: float = 7.0, height: float = 4.2, **kw: Any) -> Any:
    """A figure and its axes, with constrained layout, sized for a report page.

    Parameters
    ----------
    nrows, ncols : int
        Grid of axes.
    width, height : float
        Figure size in inches.
    **kw
        Passed to :func:`matplotlib.pyplot.subplots` (``sharex``, ``gridspec_kw``, ...).

    Returns
    -------
    tuple
        ``(fig, ax)`` as returned by :func:`matplotlib.pyplot.subplots`.
    """
    return plt.subplots(nrows, ncols, figsize=(width, height), layout="constrained", **kw)


def _axes(ax: Any, count: int, what: str, **fig_kw: Any) -> np.ndarray:
    """``count`` axes: a new figure when ``ax`` is None, else ``ax`` (an axes or array of axes) checked."""
    if ax is None:
        _, ax = new_figure(count, 1, **fig_kw)
    axes = np.atleast_1d(np.asarray(ax, dtype=object)).ravel()
    if axes.size != count:
        raise GlidectlError(f"{what} draws into {count} axes; got {axes.size}")
    return axes


# ------------------------------------------------------------------------------------------------ loci
def _param_label(locus: ParameterLocus) -> str:
    return label(locus.parameter, locus.unit)


def plot_locus(locus: ParameterLocus, ax: Any = None, *,
               zoom: tuple[float, float, float, float] | None = None) -> Any:
    """Root locus: every eigenvalue branch in the complex plane, coloured by the parameter.

    Crossings of the imaginary axis (x) and break points (o, lettered) are marked and listed; arrows show the
    direction of increasing parameter.

    Parameters
    ----------
    locus : ParameterLocus
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.
    zoom : (x0, x1, y0, y1), optional
        Adds an inset showing this window of the complex plane (1/s).

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        _, ax = new_figure()
    vals = locus.values
    norm = matplotlib.colors.Normalize(vals.min(), vals.max())
    for j in range(locus.branches.shape[1]):
        b = locus.branches[:, j]
        pts = np.column_stack([b.real, b.imag])
        segs = np.stack([pts[:-1], pts[1:]], axis=1)
        lc = LineCollection(segs, cmap="viridis", norm=norm, linewidths=2)
        lc.set_array(0.5 * (vals[:-1] + vals[1:]))
        ax.add_collection(lc)
        k = len(b) // 2
        ax.annotate("", xy=(b[k + 1].real, b[k + 1].imag), xytext=(b[k].real, b[k].imag),
                    arrowprops={"arrowstyle": "->", "color": "k", "lw": 1})
    ax.autoscale()
    cb = ax.figure.colorbar(lc, ax=ax)
    cb.set_label(_param_label(locus))
    ax.axvline(0, color="0.4", lw=0.8, ls="--")
    ax.axhline(0, color="0.8", lw=0.6)
    lines = []
    for k, bp in enumerate(locus.breakpoints):
        tag = chr(ord("A") + k)
        ax.plot(bp.eigenvalue, 0, "o", mfc="none", mec="C3", ms=9)
        ax.annotate(tag, (bp.eigenvalue, 0), textcoords="offset points", xytext=(-4, 9 if k % 2 else -17),
                    fontsize=10, color="C3", weight="bold")
        lines.append(f"{tag}: {bp.kind} at {locus.parameter} = {bp.parameter:.4g} {locus.unit}, "
                     f"$\\lambda$ = {bp.eigenvalue:.3f}")
    for c in locus.crossings:
        ax.plot(0, 0, "x", color="C1", ms=10, mew=2)
        lines.append(f"x: Re $\\lambda$ = 0 at {locus.parameter} = {c:.4g} {locus.unit}")
    if lines:
        ax.text(0.02, 0.02, "\n".join(lines), transform=ax.transAxes, fontsize=7.5, va="bottom",
                bbox={"fc": "white", "ec": "0.7", "alpha": 0.9})
    if zoom is not None:
        ins = ax.inset_axes((0.58, 0.62, 0.4, 0.35))
        for j in range(locus.branches.shape[1]):
            b = locus.branches[:, j]
            ins.scatter(b.real, b.imag, c=vals, cmap="viridis", norm=norm, s=3)
        for bp in locus.breakpoints:
            ins.plot(bp.eigenvalue, 0, "o", mfc="none", mec="C3", ms=7)
        ins.set_xlim(zoom[0], zoom[1])
        ins.set_ylim(zoom[2], zoom[3])
        ins.tick_params(labelsize=6)
        ins.grid(True, alpha=0.3)
        ax.indicate_inset_zoom(ins, edgecolor="0.5")
    ax.set_xlabel(r"Re $\lambda$ [1/s]")
    ax.set_ylabel(r"Im $\lambda$ [1/s]")
    ax.set_title(f"root locus: eigenvalues versus {_LATEX.get(locus.parameter, locus.parameter)}")
    ax.grid(True, alpha=0.3)
    return ax


def plot_locus_real(locus: ParameterLocus, ax: Any = None) -> Any:
    """Real parts of the eigenvalue branches versus the parameter, with the stability boundary marked.

    Parameters
    ----------
    locus : ParameterLocus
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.

    Returns
    -------
    matplotlib.axes.Axes
        One line per branch; crossings of ``Re lambda = 0`` as vertical lines, break points as circles.
    """
    if ax is None:
        _, ax = new_figure()
    for j in range(locus.branches.shape[1]):
        ax.plot(locus.values, locus.branches[:, j].real, lw=1.8)
    ax.axhline(0, color="0.3", lw=0.8, ls="--")
    for k, c in enumerate(locus.crossings):
        ax.axvline(c, color="C3", lw=1, label="stability boundary" if k == 0 else None)
        ax.annotate(f"{c:.4g} {locus.unit}", (c, 0), textcoords="offset points", xytext=(4, 6), color="C3",
                    fontsize=8)
    for k, bp in enumerate(locus.breakpoints):
        ax.plot(bp.parameter, bp.eigenvalue, "o", mfc="none", mec="k", ms=7,
                label="break point (real pair meets)" if k == 0 else None)
    if locus.crossings or locus.breakpoints:
        ax.legend(loc="best", fontsize=7)
    ax.set_xlabel(_param_label(locus))
    ax.set_ylabel(r"Re $\lambda$ [1/s]")
    ax.set_title(f"real parts of the eigenvalues versus {_LATEX.get(locus.parameter, locus.parameter)} "
                 "(a complex pair shares one curve)")
    ax.grid(True, alpha=0.3)
    return ax


def plot_helix_rbh_locus(hl: HelixRbhLocus, ax: Any = None, *, kind: str = "real", **kw: Any) -> Any:
    """Eigenvalues of the reduced helix linearization versus ``r_bh`` (Fig 8.13-8.14), nominal ``r_bh`` marked.

    Parameters
    ----------
    hl : HelixRbhLocus
    ax : matplotlib.axes.Axes, optional
    kind : {"real", "complex"}
        Real parts versus ``r_bh`` (Fig 8.13, default) or the root locus in the complex plane (Fig 8.14).
    **kw
        Passed to :func:`plot_locus` (``zoom``) for ``kind="complex"``.

    Returns
    -------
    matplotlib.axes.Axes
    """
    how = "frozen at the nominal helix" if hl.frozen else "re-solved at every r_bh"
    if kind == "real":
        loc = hl.locus
        ax = plot_locus_real(loc, ax, **kw)
        ax.axvline(hl.nominal.r_bh, color="k", ls=":", lw=0.8)
        ax.annotate("nominal", (hl.nominal.r_bh, 1.0), xycoords=("data", "axes fraction"),
                    textcoords="offset points", xytext=(3, -10), fontsize=7)
        ax.set_title(f"helix eigenvalues versus $r_{{bh}}$ (equilibrium {how}): real parts")
        re = loc.branches.real
        top = np.max(re, axis=1)  # the slowest eigenvalue decides stability: zoom on it when it is hard to see
        y0, y1 = min(float(top.min()), 0.0), max(float(top.max()), 0.0)
        pad = 0.2 * (y1 - y0) + 1e-12
        if np.ptp(re) > 8 * (y1 - y0 + 2 * pad):
            ins = ax.inset_axes((0.52, 0.3, 0.45, 0.36))
            for j in range(re.shape[1]):
                ins.plot(loc.values, re[:, j], lw=1.2)
            ins.axhline(0, color="0.3", lw=0.8, ls="--")
            for c in loc.crossings:
                ins.axvline(c, color="C3", lw=1)
            ins.axvline(hl.nominal.r_bh, color="k", ls=":", lw=0.8)
            ins.set_ylim(y0 - pad, y1 + pad)
            ins.set_title(r"zoom on the slowest eigenvalues [1/s]", fontsize=7)
            ins.tick_params(labelsize=6)
            ins.grid(True, alpha=0.3)
            if ax.get_legend() is not None:
                ax.legend(loc="lower left", fontsize=7)
    elif kind == "complex":
        ax = plot_locus(hl.locus, ax, **kw)
        ax.set_title(f"helix root locus versus $r_{{bh}}$ (equilibrium {how})")
    else:
        raise GlidectlError(f"kind must be 'real' or 'complex', got {kind!r}")
    return ax


# ------------------------------------------------------------------------------------------------ simulations
def plot_simulation(sim: Simulation, names: Sequence[str] | None = None, ax: Any = None, *,
                    scale: dict[str, tuple[float, str]] | None = None, **line: Any) -> Any:
    """One axis per named state or input versus time.

    Parameters
    ----------
    sim : Simulation
    names : sequence of str, optional
        States and inputs to draw; default every state.
    ax : axes or array of axes, optional
        One axes per name; default a new figure.
    scale : dict, optional
        ``scale[name] = (factor, unit)`` converts units for display (e.g. ``{"x": (1e-3, "km")}``); by default
        angles and angular rates are drawn in degrees (:func:`display_unit`), other quantities in their units.
    **line
        Passed to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    ndarray of matplotlib.axes.Axes
        The run's end is marked (dotted) when it was stopped early.
    """
    names = list(names) if names is not None else list(sim.state_names)
    axes = _axes(ax, len(names), "Simulation.plot", height=1.6 * len(names) + 0.6, sharex=True)
    scale = scale or {}
    units = _model_units(sim.model_name)
    for a, n in zip(axes, names, strict=True):
        shown, factor = display_unit(units.get(n))
        f, u = scale.get(n, (factor, shown))
        a.plot(sim.t, f * sim.state(n), **line)
        if sim.stopped_at is not None:
            a.axvline(sim.stopped_at, color="C3", ls=":", lw=1)
        a.set_ylabel(label(n, u))
        a.grid(True, alpha=0.3)
    axes[-1].set_xlabel("t [s]")
    stop = f", stopped at {sim.stopped_at:.4g} s (dotted)" if sim.stopped_at is not None else ""
    axes[0].set_title(f"simulation of {sim.model_name}, {sim.t[-1] - sim.t[0]:.4g} s{stop}")
    return axes


def _index(key: Any, names: Sequence[str], n: int) -> int:
    """A state index from a name or an index."""
    if isinstance(key, str):
        if key not in names:
            raise GlidectlError(f"no state {key!r}; have {tuple(names)}")
        return list(names).index(key)
    k = int(key)
    if not -n <= k < n:
        raise GlidectlError(f"state index {k} out of range for {n} states")
    return k % n


def _pair(dims: Sequence[Any], names: Sequence[str], n: int) -> tuple[int, int]:
    """Two distinct state indices from indices or names."""
    if isinstance(dims, str) or len(dims) != 2:
        raise GlidectlError(f"choose two states to draw, got {dims!r}")
    out = [_index(d, names, n) for d in dims]
    if out[0] == out[1]:
        raise GlidectlError(f"choose two different states, got {dims!r}")
    return out[0], out[1]


def _state_names(names: Sequence[str], n: int) -> list[str]:
    return list(names) if len(names) == n else [f"x[{k}]" for k in range(n)]


def plot_ensemble(ens: Ensemble, ax: Any = None, *, dims: Sequence[Any] = (0, 1), x_e: Any = None,
                  tol: float = 1e-3, scale: Any = None) -> Any:
    """Initial states of an ensemble in the plane of two states, marked by outcome.

    Parameters
    ----------
    ens : Ensemble
    ax : matplotlib.axes.Axes, optional
    dims : two state names or indices
        The plane to draw (the other states are projected out).
    x_e : array_like, optional
        Equilibrium. When given, a run converged if ``max_i |x_final,i - x_e,i| / scale_i <= tol`` and it was not
        frozen; without it, runs are split into frozen and not frozen only.
    tol : float
        Convergence tolerance (scaled state units).
    scale : array_like, optional
        Per-state scale of the convergence test (default ones).

    Returns
    -------
    matplotlib.axes.Axes
        One line of markers per non-empty outcome (converged ``o``, not converged ``x``, frozen ``^``).
    """
    n = ens.x0.shape[1]
    sn = _state_names(ens.state_names, n)
    i, j = _pair(dims, sn, n)
    if ax is None:
        _, ax = new_figure(width=6.5, height=4.8)
    frozen = np.asarray(ens.frozen, dtype=bool)
    groups: list[tuple[np.ndarray, str, dict[str, Any]]] = []
    if x_e is not None:
        sc = np.ones(n) if scale is None else np.asarray(scale, dtype=float)
        err = np.max(np.abs(ens.x_final - np.asarray(x_e, dtype=float)) / sc, axis=1)
        conv = (err <= tol) & ~frozen
        groups += [(conv, "converges", {"marker": "o", "color": "C2", "ms": 3.5}),
                   (~conv & ~frozen, "does not converge", {"marker": "x", "color": "C3", "ms": 5})]
    else:
        groups.append((~frozen, f"runs to t = {ens.t_final:g} s", {"marker": "o", "color": "C0", "ms": 3.5}))
    groups.append((frozen, "frozen (left the model's domain)", {"marker": "^", "color": "C1", "ms": 4}))
    units = _model_units(ens.model_name)
    (ux, fx), (uy, fy) = display_unit(units.get(sn[i])), display_unit(units.get(sn[j]))     # angles in degrees
    for mask, what, kw in groups:
        if np.any(mask):
            ax.plot(fx * ens.x0[mask, i], fy * ens.x0[mask, j], ls="", label=f"{what} ({np.sum(mask)})", **kw)
    if x_e is not None:
        xe = np.asarray(x_e, dtype=float)
        ax.plot(fx * xe[i], fy * xe[j], "k+", ms=11, mew=2, label="equilibrium")
    ax.set_xlabel(label(sn[i], ux))
    ax.set_ylabel(label(sn[j], uy))
    ax.set_title(f"{ens.model_name}: outcome of {ens.x0.shape[0]} runs of {ens.t_final:g} s\nby initial state"
                 + (" (projection on two states)" if n > 2 else ""))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=7)
    ax.grid(True, alpha=0.3)
    return ax


def plot_batch_comparison(cmp: BatchComparison, ax: Any = None, *, dims: Sequence[Any] = (0, 1)) -> Any:
    """Initial states of a controller comparison in the plane of two states, marked by outcome per controller.

    Parameters
    ----------
    cmp : BatchComparison
    ax : matplotlib.axes.Axes, optional
    dims : two state names or indices
        The plane to draw (the initial box projected on it).

    Returns
    -------
    matplotlib.axes.Axes
        Two lines of markers per controller (converges, does not), the equilibrium as ``+``.
    """
    n = cmp.x0.shape[1]
    sn = _state_names(cmp.state_names, n)
    i, j = _pair(dims, sn, n)
    if ax is None:
        _, ax = new_figure(width=6.5, height=4.8)
    nc = len(cmp.records)
    (xl, fx), (yl, fy) = state_axis(sn, i), state_axis(sn, j)                    # angles in degrees
    for k, (name, rec) in enumerate(cmp.records.items()):
        ok = np.asarray(rec.converged, dtype=bool)
        big = k == 0  # the first controller as large open circles, the others filled on top of them
        ax.plot(fx * cmp.x0[ok, i], fy * cmp.x0[ok, j], "o", ms=6 if big else 3,
                mfc="none" if big else f"C{k % 10}", color=f"C{k % 10}",
                label=f"{name}: converges ({rec.fraction:.0%})")
        ax.plot(fx * cmp.x0[~ok, i], fy * cmp.x0[~ok, j], "x", ms=6, mew=1.5, color=f"C{(nc + k) % 10}",
                label=f"{name}: does not ({np.sum(~ok)})")
    ax.plot(fx * cmp.x_e[i], fy * cmp.x_e[j], "k*", ms=11, label="equilibrium")
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    ax.set_title(f"simulated region of attraction: {cmp.x0.shape[0]} initial states, {cmp.t_final:g} s"
                 + (" (projection on two states)" if n > 2 else ""))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=7)
    ax.grid(True, alpha=0.3)
    return ax


# ------------------------------------------------------------------------------------------------ helices
def _broken(values: np.ndarray, y: np.ndarray, cut: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Insert NaN after the points in ``cut`` so that a line is broken there."""
    at = np.flatnonzero(cut) + 1
    return np.insert(np.asarray(values, float), at, np.nan), np.insert(np.asarray(y, float), at, np.nan)


def plot_helix_sweep(sw: HelixSweep, ax: Any = None, *, column: str = "radius", **line: Any) -> Any:
    """One helix quantity versus the swept control parameter (one panel of Fig 8.5-8.12).

    The curve is broken where the continuation jumps between branches (:attr:`HelixSweep.branch_jumps`);
    unstable steady motions are marked ``x``; radius and period go on a log scale when they span more than a factor
    20 (they are infinite at a straight glide).

    Parameters
    ----------
    sw : HelixSweep
    ax : matplotlib.axes.Axes, optional
    column : str
        A column of :attr:`HelixSweep.columns` (units in
        :data:`glidectl.analysis.continuation.COLUMN_UNITS`).
    **line
        Passed to :meth:`matplotlib.axes.Axes.plot` for the curve.

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        _, ax = new_figure()
    y = np.asarray(sw.column(column), dtype=float)
    xs, ys = _broken(sw.values, y, np.isin(sw.values, sw.branch_jumps))
    ax.plot(xs, ys, **{"color": "C0", "label": "steady motion", **line})
    uns = sw.exists & ~sw.stable
    if np.any(uns):
        ax.plot(sw.values[uns], y[uns], "x", color="C3", ms=5, label="unstable")
    pos = y[np.isfinite(y) & (y > 0)]
    if column in ("radius", "period") and pos.size and pos.max() > 20 * pos.min():
        ax.set_yscale("log")
    ax.set_xlabel(label(sw.parameter, sw.unit))
    ax.set_ylabel(f"{column} [{COLUMN_UNITS[column]}]")
    missing = int(np.sum(~np.asarray(sw.exists)))
    fixed = [f"{k} = {v:g} {u}" for k, v, u in zip(("r_P1", "r_P2", "r_P3", "m0"), (*sw.r_p, sw.m0),
                                                     ("m", "m", "m", "kg"), strict=True) if k != sw.parameter]
    ax.set_title(f"steady helices: {column} versus {_LATEX.get(sw.parameter, sw.parameter)} "
                 f"({', '.join(fixed)})"
                 + (f"\n{missing} of {sw.values.size} points without a steady motion" if missing else ""))
    ax.legend(loc="best")
    ax.grid(True, alpha=0.3)
    return ax


def plot_existence_scan(scan: ExistenceScan, ax: Any = None) -> Any:
    """Where steady motions were found on the ``(r_P1, m0)`` grid, with the claim region of §8.2.2 shaded.

    Parameters
    ----------
    scan : ExistenceScan
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
        Markers: a stable upright motion found (``o``), motions but none stable upright (``^``), none (``x``);
        numbers: distinct motions found at the point. ``r_P1`` is drawn in cm.
    """
    if ax is None:
        _, ax = new_figure(width=7, height=5.2)
    R, M = np.meshgrid(scan.r_P1 * 100, scan.m0)
    rmin, rmax = min(float(R.min()), 0.0) * 1.05, max(float(R.max()), 0.0) * 1.05
    mmin, mmax = min(float(M.min()), 0.0) * 1.1, max(float(M.max()), 0.0) * 1.1
    # the claim region: m0 > 0 with r_P1 < 0 (upper left) and m0 < 0 with r_P1 > 0 (lower right)
    ax.fill_between([rmin, 0], 0, mmax, color="C3", alpha=0.1, lw=0, label="§8.2.2: no equilibria here")
    ax.fill_between([0, rmax], mmin, 0, color="C3", alpha=0.1, lw=0)
    su = scan.n_stable_upright > 0
    other = scan.exists & ~su
    for mask, mk, col, what in ((su, "o", "C2", "stable upright motion found"),
                                (other, "^", "C1", "motions found, none stable upright"),
                                (~scan.exists, "x", "k", "no motion found")):
        if np.any(mask):
            ax.plot(R[mask], M[mask], mk, color=col, ls="", label=what)
    for i, j in zip(*np.nonzero(scan.exists), strict=True):
        ax.annotate(str(int(scan.n_solutions[i, j])), (R[i, j], M[i, j]), textcoords="offset points",
                    xytext=(5, 4), fontsize=7)
    ax.axhline(0, color="k", lw=0.6)
    ax.axvline(0, color="k", lw=0.6)
    ax.set_xlabel(r"$r_{P1}$ [cm]")
    ax.set_ylabel(r"$m_0$ [kg]")
    n_in = int(np.sum(scan.exists & scan.claim_region))
    ax.set_title(f"steady motions found (numbers: how many) at $r_{{P2}}$ = {scan.r_P2 * 100:g} cm, "
                 f"$r_{{P3}}$ = {scan.r_P3 * 100:g} cm;\nmotions at {n_in} of {int(np.sum(scan.claim_region))} "
                 "points of the claim region")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, fontsize=7)
    ax.grid(True, alpha=0.3)
    return ax


# ------------------------------------------------------------------------------------------------ certificates
#: units shown in figures in place of a state's own unit (the conventions page: degrees in plots), with the factor
DISPLAY_UNITS: dict[str, tuple[str, float]] = {"rad": ("deg", 180.0 / math.pi), "rad/s": ("deg/s", 180.0 / math.pi)}


def display_unit(unit: str | None) -> tuple[str | None, float]:
    """The unit a figure shows for a state of unit ``unit`` and the factor from state units to it: degrees for
    radians (:data:`DISPLAY_UNITS`), the unit itself otherwise."""
    return DISPLAY_UNITS.get(unit, (unit, 1.0)) if unit is not None else (None, 1.0)


def state_axis(names: Sequence[str], k: int, time_unit: str = "s", angles: Sequence[int] = ()) -> tuple[str, float]:
    """Axis label and factor (state units to the shown unit) of state ``k`` of a model with states ``names``:
    angles (the known angle states, and the indices ``angles``) in degrees, states of a nondimensional model
    (``time_unit`` not ``"s"``) ``[-]``."""
    name = names[k]
    unit = "rad" if k in tuple(angles) else STATE_UNITS.get(name, _EXTRA_UNITS.get(name))
    if unit is None and time_unit != "s":
        unit = "-"
    shown, factor = display_unit(unit)
    return label(name, shown), factor


def _roa_axis(ps: Any, k: int) -> tuple[str, float]:
    """:func:`state_axis` of state ``k`` of a :class:`~glidectl.roa.systems.PolySystem` (its lifted angles)."""
    return state_axis(ps.state_names, k, ps.time_unit, tuple(ps.angle_states) + tuple(ps.mixed_states))


def _slice_base(ps: Any, fixed: Any) -> np.ndarray:
    """The state the slice goes through: the equilibrium, with the values of ``fixed``."""
    base = np.array(ps.equilibrium, dtype=float)
    if fixed is None:
        return base
    if isinstance(fixed, Mapping):
        for key, v in fixed.items():
            base[_index(key, ps.state_names, ps.n)] = float(v)
        return base
    f = np.asarray(fixed, dtype=float)
    if f.shape != (ps.n,):
        raise GlidectlError(f"fixed must give all {ps.n} states {tuple(ps.state_names)} (or be a mapping name -> "
                            f"value), got shape {f.shape}")
    return f.copy()


def plot_roa_certificate(cert: ROACertificate, ax: Any = None, *, dims: Sequence[Any] = (0, 1), fixed: Any = None,
                         n: int = 201, samples: bool = True, seed: int = 0) -> Any:
    """A 2-D slice of a certified region of attraction through the equilibrium.

    Parameters
    ----------
    cert : ROACertificate
    ax : matplotlib.axes.Axes, optional
    dims : two state names or indices
        The plane of the slice.
    fixed : array_like (n,) or mapping, optional
        Values of the other states on the slice (a full state, whose ``dims`` entries are ignored, or
        ``{name: value}``); default the equilibrium.
    n : int
        Grid points per axis over the system's box (the set is :meth:`ROACertificate.contains` on the grid), and
        the number of random points of the slice in the set drawn when ``samples``.
    samples : bool
        Draw points of the set. The certificate's :class:`~glidectl.roa.certificate.ROAVerification` keeps counts, not
        the sampled points, so ``n`` points of the slice in the set are drawn here (rejection from the box, seeded
        with ``seed``).

    Returns
    -------
    matplotlib.axes.Axes
        The set as a filled contour with its boundary, the equilibrium as ``+``, the samples as dots; angles in
        degrees.
    """
    ps = cert.system
    i, j = _pair(dims, ps.state_names, ps.n)
    base = _slice_base(ps, fixed)
    if n < 2:
        raise GlidectlError(f"n must be at least 2, got {n}")
    lo, hi = (np.asarray(b, dtype=float) for b in ps.box)
    if ax is None:
        _, ax = new_figure(width=6.5, height=5.2)
    drawn = ax.get_legend_handles_labels()[0]       # what the axes already show (e.g. a convergent slice)
    (xlabel, fx), (ylabel, fy) = _roa_axis(ps, i), _roa_axis(ps, j)
    A, B = np.meshgrid(np.linspace(lo[i], hi[i], n), np.linspace(lo[j], hi[j], n))
    X = np.tile(base, (A.size, 1))
    X[:, i], X[:, j] = A.ravel(), B.ravel()
    ins = cert.contains(X).reshape(A.shape)
    # V itself inside the set and V above the level outside it: its rho contour is the smooth boundary of the set
    Vv = np.nan_to_num(cert.value(X).reshape(A.shape), nan=np.inf)
    F = np.where(ins, np.minimum(Vv, cert.rho), np.maximum(Vv, cert.rho * (1 + 1e-9) + 1e-300))
    handles: list[Any] = [Patch(color="C0", alpha=0.35, label=f"certified: V ≤ {cert.rho:.4g} (degree {cert.degree})")]
    if ins.any():
        F = np.minimum(F, 2 * cert.rho + 1.0)
        ax.contourf(fx * A, fy * B, F, levels=[float(F.min()) - 1.0, cert.rho], colors=["C0"], alpha=0.35)
        ax.contour(fx * A, fy * B, F, levels=[cert.rho], colors="C0", linewidths=1.2)
    if samples:
        rng = np.random.default_rng(seed)
        pts = np.empty((0, 2))
        for _ in range(20):
            P = np.tile(base, (4 * n, 1))
            P[:, i] = lo[i] + (hi[i] - lo[i]) * rng.random(4 * n)
            P[:, j] = lo[j] + (hi[j] - lo[j]) * rng.random(4 * n)
            pts = np.concatenate([pts, P[cert.contains(P)][:, [i, j]]])[:n]
            if len(pts) >= n:
                break
        if len(pts):
            (h,) = ax.plot(fx * pts[:, 0], fy * pts[:, 1], ".", color="C2", ms=2.5,
                           label=f"{len(pts)} random points of the set")
            handles.append(h)
    if samples and ps.n == 2 and hasattr(cert, "sample"):
        # the verification's simulation starts: the outermost points of the set
        try:
            out = cert.sample(min(n, 64), seed=seed, boundary=True)
        except GlidectlError:
            out = np.empty((0, 2))
        if len(out):
            (h,) = ax.plot(fx * out[:, i], fy * out[:, j], "x", color="C3", ms=4,
                           label=f"{len(out)} outermost points (simulation starts)")
            handles.append(h)
    eq = np.asarray(ps.equilibrium, dtype=float)
    (h,) = ax.plot(fx * eq[i], fy * eq[j], "k+", ms=12, mew=2, label="equilibrium")
    handles.append(h)
    ax.set_xlim(fx * lo[i], fx * hi[i])
    ax.set_ylim(fy * lo[j], fy * hi[j])
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    rest = [f"{lab} = {fk * base[k]:.3g}" for k in range(ps.n) if k not in (i, j)
            for lab, fk in [_roa_axis(ps, k)]]                    # the slice's other states, angles in degrees
    status = "verified" if cert.verification.passed else "NOT verified"
    route = f", {cert.method}" if getattr(cert, "method", "exact recast") != "exact recast" else ""
    width = max(40, int(14 * ax.figure.get_figwidth()))     # a long loop name wraps to the figure's width
    ax.set_title(textwrap.fill(f"{ps.name}: certified region of attraction ({status}{route})", width=width)
                 + (f"\n{textwrap.fill('slice ' + ', '.join(rest), width=width)}" if rest else ""), fontsize=8)
    ax.legend(handles=drawn + handles, loc="lower right", fontsize=7)
    ax.grid(True, alpha=0.3)
    return ax


def plot_composite_certificate(cert: CompositeCertificate, ax: Any = None, *, n: int = 201) -> Any:
    """The composite-Lyapunov estimate ``L*`` (5.85) in the ``(Vbar, gammabar)`` plane at ``alphabar = Omegabar2 =
    0``, with the reduced level set ``{Phi <= v0}`` (5.35) and the box ``B_p`` it lies in.

    Parameters
    ----------
    cert : CompositeCertificate
    ax : matplotlib.axes.Axes, optional
    n : int
        Grid points per axis.

    Returns
    -------
    matplotlib.axes.Axes
        ``L*`` filled (it is a region-of-attraction estimate only when ``cert.certified``, said in the title),
        ``Phi = v0`` as a dashed line, ``B_p`` as a dotted rectangle.
    """
    dom = cert.domain
    deg = 180.0 / math.pi                                      # gammabar (rad) is drawn in degrees
    (vlo, vhi), (glo, ghi) = dom.Vbar, dom.gammabar
    pad = 0.25 * (vhi - vlo)
    V = np.linspace(max(vlo - pad, -0.99), vhi + pad, n)
    G = np.linspace(max(glo - 0.1 * (ghi - glo), -math.pi), min(ghi + 0.1 * (ghi - glo), math.pi), n)
    VV, GG = np.meshgrid(V, G)
    z = np.stack([VV, GG, np.zeros_like(VV), np.zeros_like(VV)], axis=-1)
    ins = np.asarray(cert.in_estimate(z), dtype=float)
    if ax is None:
        _, ax = new_figure(width=6.5, height=4.8)
    handles: list[Any] = []
    if ins.any():
        ax.contourf(VV, deg * GG, ins, levels=[0.5, 1.5], colors=["C0"], alpha=0.4)
        ax.contour(VV, deg * GG, ins, levels=[0.5], colors="C0", linewidths=1.2)
    handles.append(Patch(color="C0", alpha=0.4,
                         label=f"$L^*$ (5.85): $\\nu \\leq$ {cert.level:.3g} (d = {cert.d:.3g})"))
    ax.contour(VV, deg * GG, cert.Phi(np.stack([VV, GG], axis=-1)), levels=[cert.v0], colors="C3",
               linestyles="--")
    handles.append(Line2D([], [], color="C3", ls="--",
                          label=f"$\\Phi$ = $v_0$ = {cert.v0:.3g} (5.35); at q = 0, $L^*$ = {{$\\Phi \\leq v_0$}}"))
    ax.plot([vlo, vhi, vhi, vlo, vlo], [deg * glo, deg * glo, deg * ghi, deg * ghi, deg * glo], "k:", lw=1)
    handles.append(Line2D([], [], color="k", ls=":", label="domain $B_p$"))
    (h,) = ax.plot(0.0, 0.0, "k+", ms=12, mew=2, label="steady glide")
    handles.append(h)
    ax.set_xlabel(r"$\bar V$ [-]")
    ax.set_ylabel(r"$\bar\gamma$ [deg]")
    verdict = (f"certified: $\\mu$ = {cert.mu:.3g} < $\\mu_d$ = {cert.mu_d:.3g}" if cert.certified
               else f"NOT certified: $\\mu$ = {cert.mu:.3g} ≥ $\\mu_d$ = {cert.mu_d:.3g}")
    ax.set_title(f"{cert.vehicle.name}: composite Lyapunov estimate, slice $\\bar\\alpha$ = $\\bar\\Omega_2$ = 0\n"
                 f"{verdict}")
    ax.legend(handles=handles, loc="lower right", fontsize=7)
    ax.grid(True, alpha=0.3)
    return ax


# ------------------------------------------------------------------------------------------------ CTOL tracking
def plot_tracking_run(run: TrackingRun, ax: Any = None, *, input_scale: str = "linear") -> Any:
    """Position error and inputs of a CTOL tracking run versus time (Fig 7.3-7.4).

    Parameters
    ----------
    run : TrackingRun
    ax : array of 3 axes, optional
        Error, thrust, pitching moment; default a new figure.
    input_scale : {"linear", "symlog"}
        Scale of the input axes. ``"symlog"`` shows spikes and the rest of a run together: an input whose peak
        exceeds 100 times its median magnitude is drawn on a symmetric log scale, linear up to 10 times the median.

    Returns
    -------
    ndarray of 3 matplotlib.axes.Axes
    """
    axes = _axes(ax, 3, "TrackingRun.plot", width=7.5, height=6.0, sharex=True)
    axes[0].plot(run.t, run.error[:, 0], "C0", lw=1, label="$e_x = x - x_d$")
    axes[0].plot(run.t, run.error[:, 1], "C1", lw=1, label="$e_y = y - y_d$")
    axes[0].set_ylabel("position error [m]")
    axes[0].legend(loc="best", fontsize=7)
    axes[1].plot(run.t, run.u[:, 0], "C2", lw=0.8)
    axes[1].set_ylabel("thrust $u_1$ [N]")
    axes[2].plot(run.t, run.u[:, 1], "C4", lw=0.8)
    axes[2].set_ylabel("moment $u_2$ [N m]")
    if input_scale not in ("linear", "symlog"):
        raise GlidectlError(f"input_scale must be 'linear' or 'symlog', got {input_scale!r}")
    for a, u in zip(axes[1:], np.abs(run.u).T, strict=True):
        med = float(np.median(u[u > 0])) if np.any(u > 0) else 0.0
        if input_scale == "symlog" and med > 0 and u.max() > 100 * med:  # spikes: linear up to 10 x the median
            a.set_yscale("symlog", linthresh=10 * med)
    for a in axes:
        if run.stopped_at is not None:
            a.axvline(run.stopped_at, color="C3", ls=":", lw=1)
        a.grid(True, alpha=0.3)
    axes[-1].set_xlabel("t [s]")
    end = "completed" if run.completed else f"stopped at {run.stopped_at:.4g} s (dotted)"
    axes[0].set_title(f"{run.method}\nmax |e| = {run.max_error:.3g} m, peak |u1| = {run.peak_u1:.3g} N, "
                      f"peak |u2| = {run.peak_u2:.3g} N m, {end}")
    return axes


def plot_pareto_study(study: ParetoStudy, ax: Any = None) -> Any:
    """Max position error against control effort over the tracking grid, with the Pareto front.

    Parameters
    ----------
    study : ParetoStudy
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
        One marker per completed run, coloured by ``(k3, k4)`` and shaped by ``dt``, filled on the front; the front
        joined by a black line. An axis is logarithmic when its values are positive and span more than a decade.
    """
    if ax is None:
        _, ax = new_figure(width=8.0, height=5.0)
    recs = study.records
    done = [k for k, r in enumerate(recs) if r["completed"]]
    gains = list(dict.fromkeys((r["k3"], r["k4"]) for r in recs))
    dts = list(dict.fromkeys(r["dt"] for r in recs))
    shapes = "os^Dv<>ph"
    front = set(study.front)
    for k in done:
        r = recs[k]
        c = f"C{gains.index((r['k3'], r['k4'])) % 10}"
        ax.plot(r["effort"], r["max_error"], shapes[dts.index(r["dt"]) % len(shapes)], color=c, ms=7,
                mfc=c if k in front else "none")
    fr = study.front_records()
    (hf,) = ax.plot([r["effort"] for r in fr], [r["max_error"] for r in fr], "k-", lw=0.8,
                    label="Pareto front (filled)")
    vals = np.array([[recs[k]["effort"], recs[k]["max_error"]] for k in done]) if done else np.ones((1, 2))
    for col, set_scale in ((vals[:, 0], ax.set_xscale), (vals[:, 1], ax.set_yscale)):
        if np.all(col > 0) and col.max() > 10 * col.min():  # log axes for values over more than a decade
            set_scale("log")
    ax.set_xlabel(r"control effort: time-RMS of $\|u\|$ [-]")
    ax.set_ylabel("max position error [m]")
    handles = [Line2D([], [], color=f"C{k % 10}", lw=4, label=f"k3 = {g[0]:g}, k4 = {g[1]:g}")
               for k, g in enumerate(gains)]
    handles += [Line2D([], [], marker=shapes[k % len(shapes)], color="grey", ls="", label=f"dt = {dt:g} s")
                for k, dt in enumerate(dts)]
    ax.legend(handles=[*handles, hf], loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0, fontsize=7)
    nstop = len(recs) - len(done)
    ax.set_title(f"tracking by steady gliding over {study.t_final:g} s: {len(done)} completed runs"
                 + (f" ({nstop} stopped, not shown)" if nstop else ""))
    ax.grid(True, which="both", alpha=0.3)
    return ax


# ------------------------------------------------------------------------------------------------ glide envelope
#: colours of the binding limits of a glide envelope (codes 0 and 2-5; codes 1 and 6 have no glide to draw)
_BINDING_COLOURS = {0: "tab:green", 2: "tab:blue", 3: "tab:purple", 4: "tab:orange", 5: "tab:red"}


def _range_text(bounds: tuple[float, float], scale: float, unit: str) -> str:
    lo, hi = bounds
    if lo == -math.inf and hi == math.inf:
        return "not limited"
    return f"in [{lo * scale:g}, {hi * scale:g}] {unit}"


def plot_glide_envelope(env: Any, ax: Any = None) -> Any:
    """The glide envelope in the glide polar: horizontal speed against sink rate, coloured by binding limit.

    Parameters
    ----------
    env : GlideEnvelope
        From :func:`glidectl.glide_envelope`.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
        One marker per grid point where the steady glide exists: green where it is feasible, else coloured by the
        actuator limit that binds (``m0`` or ``r_P1``, min or max). The vertical axis is the sink rate (m/s,
        positive downwards) and points down, so down glides lie below the axis and climbs above it. Dashed rays:
        the shallowest down and up glides of the permissible set (2.26); between them no glide exists.
    """
    from .trim.envelope import BINDING_LABELS

    if ax is None:
        _, ax = new_figure(width=7.5, height=5.2)
    n = env.binding.size
    size = float(np.clip(6000.0 / max(n, 1), 2.0, 40.0))
    for code, colour in _BINDING_COLOURS.items():
        mask = env.binding == code
        if np.any(mask):
            what = "feasible" if code == 0 else f"{BINDING_LABELS[code]} binds"
            ax.scatter(env.horizontal_speed[mask], env.vertical_speed[mask], s=size, marker="s", color=colour,
                       lw=0, label=f"{what} ({int(mask.sum())})")
    lo, hi = env.gamma_bounds
    reach = float(np.nanmax(env.speeds)) * 1.05
    for g, what in ((lo, "down"), (hi, "up")):
        ax.plot([0.0, reach * math.cos(g)], [0.0, -reach * math.sin(g)], "k--", lw=0.8,
                label=f"shallowest {what} glide (2.26): {math.degrees(g):+.2f} deg")
    ax.axhline(0.0, color="k", lw=0.6)
    if not ax.yaxis_inverted():
        ax.invert_yaxis()
    ax.set_xlabel("horizontal speed $V\\cos\\gamma$ [m/s]")
    ax.set_ylabel("sink rate $-V\\sin\\gamma$ [m/s] (positive down)")
    none_n = int(np.sum(env.binding == 1))
    trim_n = int(np.sum(env.binding == 6))
    ax.set_title(f"glide envelope of '{env.vehicle.name}' at $r_{{P3}}$ = {env.r_p3 * 100:g} cm: "
                 f"{int(env.feasible.sum())} of {n} grid points feasible\n"
                 f"$m_0$ {_range_text(env.m0_bounds, 1.0, 'kg')}, "
                 f"$r_{{P1}}$ {_range_text(env.r_p1_bounds, 100.0, 'cm')}; "
                 f"not drawn: {none_n} with no glide"
                 + (f", {trim_n} with no mass position" if trim_n else ""))
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0, fontsize=7, markerscale=2)
    ax.grid(True, alpha=0.3)
    return ax


def plot_dive_cycle(run: DiveCycleRun, ax: Any = None) -> Any:
    """Dive-cycle mission: depth with the depth limits and the inflections, pitch, and commanded versus achieved
    pump mass and battery position, versus time.

    Parameters
    ----------
    run : DiveCycleRun
    ax : array of 4 axes, optional
        Default a new figure.

    Returns
    -------
    ndarray of 4 matplotlib.axes.Axes
        Depth, pitch, pump mass and battery position (``axes[0].figure`` is the figure).

    Raises
    ------
    GlidectlError
        If ``ax`` is not 4 axes.
    """
    axes = _axes(ax, 4, "DiveCycleRun.plot", width=7.5, height=7.5, sharex=True)
    t = run.t
    top, bottom = run.depths
    a = axes[0]
    a.plot(t, run.depth, "C0", lw=1, label="depth")
    for d in (top, bottom):
        a.axhline(d, color="k", ls="--", lw=0.8)
    a.plot(run.switch_times, run.switch_depths, "v", color="C3", ms=5, label="inflections")
    a.invert_yaxis()
    a.set_ylabel("depth $z$ [m]")
    a.legend(loc="best", fontsize=7)
    axes[1].plot(t, np.degrees(run.state("theta")), "C1", lw=1)
    axes[1].set_ylabel(r"pitch $\theta$ [deg]")
    for a, name, unit in ((axes[2], "m0", "kg"), (axes[3], "r_P1", "m")):
        a.plot(t, run.actuator(name, commanded=True), "C7", lw=0.8, ls=":", label="commanded")
        a.plot(t, run.actuator(name), "C2", lw=1.2, label="achieved")
        i = run.actuator_names.index(name)
        for b in (run.lower[i], run.upper[i]):
            if np.isfinite(b):
                a.axhline(b, color="C3", ls="--", lw=0.7)
        lo, hi = run.lower[i], run.upper[i]
        if np.isfinite(lo) and np.isfinite(hi):
            pad = 0.3 * (hi - lo)
            a.set_ylim(lo - pad, hi + pad)
        a.set_ylabel(label(name, unit))
        a.legend(loc="best", fontsize=7)
    for a in axes:
        for ts in run.switch_times:
            a.axvline(ts, color="C3", lw=0.5, alpha=0.4)
    axes[-1].set_xlabel("t [s]")
    axes[0].set_title(f"{run.vehicle.name}: {len(run.cycles)} dive cycles, controller {run.controller}")
    return axes


def plot_ellipsoid_certificate(cert: Any, ax: Any = None, *, dims: Sequence[Any] = (0, 1), n: int = 200) -> Any:
    """Slice through the equilibrium of an LMI-certified ellipsoid
    (:class:`~glidectl.roa.lmi.EllipsoidCertificate`) in the plane of two free states, with the loop's box.

    Parameters
    ----------
    cert : EllipsoidCertificate
    ax : matplotlib.axes.Axes, optional
    dims : two state names or indices
        The plane (free states of the loop).
    n : int
        Points of the drawn boundary (>= 8).

    Returns
    -------
    matplotlib.axes.Axes
        The ellipse (other free states at equilibrium), the box, the equilibrium; angles in degrees.
    """
    loop = cert.system
    i, j = _pair(dims, loop.state_names, loop.n)
    free = list(loop.free)
    if i not in free or j not in free:
        raise GlidectlError(f"choose two free states of the certificate (held: "
                            f"{[loop.state_names[k] for k in loop.held]}), got {dims!r}")
    if n < 8:
        raise GlidectlError(f"n must be at least 8, got {n}")
    a, b = free.index(i), free.index(j)
    P2 = np.asarray(cert.P)[np.ix_([a, b], [a, b])]
    L = np.linalg.cholesky(np.linalg.inv(0.5 * (P2 + P2.T)))
    th = np.linspace(0.0, 2 * math.pi, n)
    E = (L @ np.vstack([np.cos(th), np.sin(th)])).T + loop.equilibrium[[i, j]]
    if ax is None:
        _, ax = new_figure(width=6.5, height=5.2)
    lo, hi = (np.asarray(v, dtype=float) for v in cert.box)
    (xlabel, fx), (ylabel, fy) = state_axis(loop.state_names, i), state_axis(loop.state_names, j)
    E = E * [fx, fy]
    (xl, xh), (yl, yh) = (fx * lo[i], fx * hi[i]), (fy * lo[j], fy * hi[j])
    ax.fill(E[:, 0], E[:, 1], color="C0", alpha=0.35, label=f"certified ellipsoid (slice), {cert.method}")
    ax.plot(E[:, 0], E[:, 1], color="C0", lw=1.2)
    ax.plot([xl, xh, xh, xl, xl], [yl, yl, yh, yh, yl], "k--", lw=1, label="box")
    ax.plot(fx * loop.equilibrium[i], fy * loop.equilibrium[j], "k+", ms=12, mew=2, label="equilibrium")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    status = "verified" if cert.certified else "NOT verified"
    # a loop's name can be longer than the axes are wide: wrapped, as the figure's width allows
    ax.set_title(textwrap.fill(loop.name, width=max(40, int(14 * ax.figure.get_figwidth())))
                 + f"\nLMI region of attraction ({status}), {100 * cert.volume_fraction:.3g} % of the box", fontsize=8)
    ax.legend(loc="lower right", fontsize=7)
    ax.grid(True, alpha=0.3)
    return ax


def plot_extents(extent: Any, under: Any = None, ax: Any = None) -> Any:
    """Bar chart of a region's extent per state axis and direction (:class:`~glidectl.roa.extent.Extent`), as the
    fraction of the box's half-width on that side (the union of both extents' boxes), with a second extent (e.g.
    the convergent one) drawn under it.

    Parameters
    ----------
    extent : Extent
        Drawn in front (e.g. the certified extent).
    under : Extent, optional
        Drawn behind, wider and lighter (e.g. :func:`glidectl.convergent_extent`); the ratio of the two is printed
        on each bar.
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
        Bars below zero for ``x_e - lo``, above for ``hi - x_e``, per state (box half-width = 1); the ratio of
        ``extent`` to ``under`` per bar.
    """
    names = list(extent.names)
    lo_b, hi_b = (np.asarray(b, dtype=float) for b in extent.box)
    if under is not None:                   # one scale for both: the union of their boxes
        lo_b, hi_b = np.minimum(lo_b, under.box[0]), np.maximum(hi_b, under.box[1])
    xe = np.asarray(extent.equilibrium, dtype=float)
    below_box, above_box = xe - lo_b, hi_b - xe

    def fractions(e: Any) -> tuple[np.ndarray, np.ndarray]:
        with np.errstate(divide="ignore", invalid="ignore"):
            return (np.where(below_box > 0, e.below / below_box, 0.0),
                    np.where(above_box > 0, e.above / above_box, 0.0))

    if ax is None:
        _, ax = new_figure(width=7.0, height=4.0)
    x = np.arange(len(names))
    if under is not None:
        ub, ua = fractions(under)
        ax.bar(x, ua, 0.8, color="0.8", label=under.what)
        ax.bar(x, -ub, 0.8, color="0.8")
    eb, ea = fractions(extent)
    ax.bar(x, ea, 0.5, color="C0", label=extent.what + ("" if extent.rigorous in (None, True) else ", not rigorous"))
    ax.bar(x, -eb, 0.5, color="C0")
    if under is not None:
        rb, ra = extent.ratio(under)
        for k in range(len(names)):
            for r, y in ((ra[k], ea[k]), (rb[k], -eb[k])):
                if np.isfinite(r):
                    ax.annotate(f"{r:.2g}", (x[k], y), ha="center", va="bottom" if y >= 0 else "top", fontsize=6)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axhline(0.5, color="C3", lw=0.6, ls=":")
    ax.axhline(-0.5, color="C3", lw=0.6, ls=":")
    ax.set_xticks(x, [_LATEX.get(n, n) for n in names])
    ax.set_ylim(-1.1, 1.1)
    ax.set_ylabel("extent / box half-width [-]")
    ax.set_title("Extent per state axis through the equilibrium (below 0: towards lo, above: towards hi)", fontsize=8)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=2, fontsize=7, frameon=False)
    return ax


def plot_convergent_slice(sl: Any, ax: Any = None) -> Any:
    """The converging part of a 2-D slice (:class:`~glidectl.roa.extent.ConvergentSlice`) filled light grey, angles
    in degrees, with a legend entry; a certificate's slice plot drawn on the same axes lies over it.

    Parameters
    ----------
    sl : ConvergentSlice
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    if ax is None:
        _, ax = new_figure(width=6.5, height=5.2)
    (xlabel, fx), (ylabel, fy) = state_axis(sl.names, 0), state_axis(sl.names, 1)
    A, B = np.meshgrid(fx * sl.x, fy * sl.y)
    if sl.converged.any():
        ax.contourf(A, B, sl.converged.astype(float), levels=[0.5, 1.5], colors=["0.82"])
    ax.fill([], [], color="0.82", label=f"{sl.what}: {100 * sl.fraction:.0f} % of the slice")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    return ax


# ------------------------------------------------------------------------------------------------ dive records
def plot_dive_record(record: Any, ax: Any = None) -> Any:
    """A dive record: depth, pitch and pumped volume against time, the default fit mask's samples marked.

    Parameters
    ----------
    record : DiveRecord
    ax : array of 3 axes, optional
        Default a new figure.

    Returns
    -------
    ndarray of Axes

    Raises
    ------
    GlidectlError
        If ``ax`` is not 3 axes.
    """
    axes = _axes(ax, 3, "DiveRecord.plot", width=7.5, height=6.5, sharex=True)
    t = (record.time - record.time[0]) / 60.0
    used = record.mask()
    axes[0].plot(t, record.depth, "C0", lw=1, label="depth")
    axes[0].plot(t[used], record.depth[used], ".", color="C2", ms=2, label="used by a fit (default mask)")
    axes[0].invert_yaxis()
    axes[0].set_ylabel("depth [m]")
    axes[0].legend(loc="best", fontsize=7)
    axes[1].plot(t, np.degrees(record.pitch), "C1", lw=1)
    axes[1].set_ylabel(r"pitch $\theta$ [deg]")
    axes[2].plot(t, record.buoyancy_volume * 1e6, "C3", lw=1)
    axes[2].set_ylabel("pumped volume [cm$^3$]")
    axes[2].set_xlabel("time since start [min]")
    axes[0].set_title(f"dive record {textwrap.shorten(str(record.source).split('/')[-1], 60)}: {len(record)} "
                      f"samples, {int(used.sum())} used")
    return axes


def plot_flight_fit(fit: Any, ax: Any = None) -> Any:
    """A flight-model fit: measured and modelled vertical speed against time, and the residual against depth.

    Parameters
    ----------
    fit : FlightFit
    ax : array of 2 axes, optional
        Default a new figure.

    Returns
    -------
    ndarray of Axes

    Raises
    ------
    GlidectlError
        If ``ax`` is not 2 axes.
    """
    axes = _axes(ax, 2, "FlightFit.plot", width=7.5, height=6.0)
    rec, used = fit.record, fit.used
    t = (rec.time - rec.time[0]) / 60.0
    model = fit.predict()
    a = axes[0]
    a.plot(t, rec.vertical_speed, "C7", lw=0.8, label="measured $-dz/dt$")
    a.plot(t, model.vertical_speed, "C0", lw=1.2, label=f"modelled ({fit.law} law)")
    a.plot(t[~used], rec.vertical_speed[~used], "x", color="C3", ms=3, label="left out by the mask")
    a.set_xlabel("time since start [min]")
    a.set_ylabel("vertical speed [m/s]")
    a.legend(loc="best", fontsize=7)
    cv = "" if fit.cv_rms is None else f", cross-validated {fit.cv_rms:.4f} m/s"
    a.set_title(f"{fit.law} law: RMS {fit.rms:.4f} m/s{cv}")
    b = axes[1]
    b.plot(fit.residual, rec.depth[used], ".", ms=2, color="C0")
    b.axvline(0.0, color="k", lw=0.8)
    b.invert_yaxis()
    b.set_xlabel("modelled - measured vertical speed [m/s]")
    b.set_ylabel("depth [m]")
    return axes


def _current_arrows(ax: Any, run: Any, bounds: tuple[float, float, float, float]) -> None:
    """Arrows of the surface current on a coarse grid of the map (a quiver key gives the scale)."""
    e0, e1, n0, n1 = bounds
    E, N = np.meshgrid(np.linspace(e0, e1, 6), np.linspace(n0, n1, 6))
    pos = np.stack([E, N, np.zeros_like(E)], -1)
    c = run.current.at(0.0, pos)
    if not np.any(np.hypot(c[..., 0], c[..., 1]) > 0):
        return
    q = ax.quiver(E / 1000.0, N / 1000.0, c[..., 0], c[..., 1], color="0.6", width=0.003, zorder=0)
    ax.quiverkey(q, 0.97, 0.03, 0.1, "0.1 m/s surface current", labelpos="W", coordinates="axes",
                 fontproperties={"size": 7})


def plot_mission_run(run: Any, ax: Any = None) -> Any:
    """A flown mission: map view (track, dead reckoning, surfacings, waypoints with their arrival circles, current
    arrows), depth against time and the actuators against time.

    Parameters
    ----------
    run : MissionRun
    ax : array of 3 axes, optional
        Default a new figure.

    Returns
    -------
    ndarray of Axes
        Map, depth, actuators.

    Raises
    ------
    GlidectlError
        If ``ax`` is not 3 axes.
    """
    if ax is None:
        fig, _ = new_figure(width=11.0, height=7.0)
        fig.clf()
        grid = fig.add_gridspec(2, 2, width_ratios=(1.0, 1.3))
        axes = np.array([fig.add_subplot(grid[:, 0]), fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, 1])])
        axes[2].sharex(axes[1])
    else:
        axes = _axes(ax, 3, "MissionRun.plot")
    pos, t_h = run.position / 1000.0, run.t / 3600.0
    m = axes[0]
    m.plot(pos[:, 0], pos[:, 1], "C0", lw=1, label="track")
    dr = run.dead_reckoned / 1000.0
    under = run.phase != 0
    m.plot(np.where(under, dr[:, 0], np.nan), np.where(under, dr[:, 1], np.nan), "C1", lw=0.8, ls="--",
           label="dead reckoning")
    fixes = np.array([d.fix for d in run.dives]) / 1000.0
    if fixes.size:
        m.plot(fixes[:, 0], fixes[:, 1], "k.", ms=4, label="GPS fixes")
    wp = np.asarray(run.mission.waypoints) / 1000.0
    m.plot(wp[:, 0], wp[:, 1], "s", color="C3", ms=7, mfc="none", label="waypoints")
    r = run.mission.arrival_radius / 1000.0
    for k, (e, n) in enumerate(wp):
        m.add_patch(matplotlib.patches.Circle((e, n), r, fill=False, color="C3", lw=0.6, ls=":"))
        m.annotate(str(k), (e, n), textcoords="offset points", xytext=(5, 5), fontsize=8, color="C3")
    m.plot(*(np.asarray(run.mission.start) / 1000.0), "^", color="C2", ms=7, label="launch")
    m.set_aspect("equal", adjustable="datalim")
    lo = np.minimum(pos[:, :2].min(0), wp.min(0)) * 1000.0
    hi = np.maximum(pos[:, :2].max(0), wp.max(0)) * 1000.0
    pad = 0.1 * max(float(np.max(hi - lo)), 1.0)
    _current_arrows(m, run, (lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad))
    m.set_xlabel("east [km]")
    m.set_ylabel("north [km]")
    m.legend(loc="best", fontsize=7)
    m.set_title(textwrap.shorten(f"{run.vehicle.name}, {run.controller}: {sum(g.arrived for g in run.legs)}/"
                                 f"{len(run.legs)} waypoints, {run.energy_per_km:.0f} J/km", 70), fontsize=9)
    axes[1].plot(t_h, pos[:, 2] * 1000.0, "C0", lw=0.8)
    axes[1].axhline(run.mission.depths[1], color="0.5", lw=0.6, ls=":")
    axes[1].invert_yaxis()
    axes[1].set_ylabel("depth [m]")
    axes[1].set_title(f"{len(run.dives)} dives, {run.duration / 3600:.1f} h", fontsize=9)
    a = axes[2]
    a.plot(t_h, run.actuator("m0") * 1000.0, "C3", lw=0.8, label="pump $m_0$ [g]")
    a.plot(t_h, run.actuator("r_P1") * 1000.0, "C2", lw=0.8, label="battery $r_{P1}$ [mm]")
    for name, color in (("roll", "C4"), ("rudder", "C5")):
        if run.plant.rate_limit[run.plant.actuator_names.index(name)] > 0:
            a.plot(t_h, np.degrees(run.actuator(name)), color, lw=0.8, label=f"{name} [deg]")
    a.set_xlabel("mission time [h]")
    a.set_ylabel("actuator setting")
    a.legend(loc="best", fontsize=7, ncol=2)
    return axes


def plot_mission_3d(run: Any, ax: Any = None) -> Any:
    """The track of a flown mission in 3-D (east, north, depth increasing downwards) with the waypoints at the
    surface.

    Parameters
    ----------
    run : MissionRun
    ax : Axes3D, optional
        Default a new figure.

    Returns
    -------
    Axes3D
    """
    if ax is None:
        fig, _ = new_figure(width=7.5, height=6.0)
        fig.clf()
        ax = fig.add_subplot(projection="3d")
    pos = run.position
    ax.plot(pos[:, 0] / 1000.0, pos[:, 1] / 1000.0, -pos[:, 2], "C0", lw=0.6)
    wp = np.asarray(run.mission.waypoints) / 1000.0
    ax.scatter(wp[:, 0], wp[:, 1], np.zeros(len(wp)), marker="s", color="C3", label="waypoints")
    ax.set_xlabel("east [km]")
    ax.set_ylabel("north [km]")
    ax.set_zlabel("height [m] (0 = surface)")
    ax.set_title(f"{run.vehicle.name}: {len(run.dives)} dives", fontsize=9)
    ax.legend(loc="best", fontsize=7)
    return ax


def plot_fleet_run(run: Any, ax: Any = None, *, snapshots: int = 6) -> Any:
    """A fleet's run: the tracks with snapshots of the formation at evenly spaced times (Fig 3.2), and the mean
    spacing against the scheduled one (Fig 3.3).

    Parameters
    ----------
    run : FleetRun
    ax : array of 2 axes, optional
        Default a new figure.
    snapshots : int
        Formation snapshots drawn on the map.

    Returns
    -------
    ndarray of Axes
        Map, spacing.

    Raises
    ------
    GlidectlError
        If ``ax`` is not 2 axes.
    """
    if ax is None:
        _, a = new_figure(1, 2, width=11.0, height=5.0, gridspec_kw={"width_ratios": (1.0, 1.2)})
        axes = np.asarray(a)
    else:
        axes = _axes(ax, 2, "FleetRun.plot")
    m = axes[0]
    for i in range(run.size):
        p = run.position(i) / 1000.0
        m.plot(p[:, 0], p[:, 1], lw=0.8, color=f"C{i}", label=f"glider {i} ({run.vehicles[i].name})")
    times, spacing = run.mean_spacing()
    snap = np.linspace(0.0, times[-1], snapshots)
    P = run.positions_at(snap) / 1000.0
    for k, tk in enumerate(snap):
        poly = np.vstack([P[k], P[k][:1]])
        m.plot(poly[:, 0], poly[:, 1], "k-", lw=0.6, alpha=0.4 + 0.6 * k / max(snapshots - 1, 1))
        m.annotate(f"{tk / 3600:.0f} h", P[k].mean(0), fontsize=7, ha="center")
    lp = getattr(run.coordinator, "leader_path", None)
    if lp is not None:
        lp = np.asarray(lp) / 1000.0
        m.plot(lp[:, 0], lp[:, 1], ":", color="0.4", lw=1, label="virtual body's path")
    m.set_aspect("equal", adjustable="datalim")
    m.set_xlabel("east [km]")
    m.set_ylabel("north [km]")
    m.legend(loc="best", fontsize=7)
    m.set_title(f"{run.size} gliders, formation snapshots", fontsize=9)
    s = axes[1]
    s.plot(times / 3600.0, spacing / 1000.0, "C0", label="mean spacing")
    desired = run.desired_spacing(times)
    if np.all(np.isfinite(desired)):
        s.plot(times / 3600.0, desired / 1000.0, "k--", lw=1, label="desired")
    s.set_xlabel("time [h]")
    s.set_ylabel("spacing [km]")
    s.legend(loc="best", fontsize=7)
    return axes


# ------------------------------------------------------------------------------------------------ robustness
def plot_monte_carlo(mc: Any, names: Any = None, ax: Any = None) -> Any:
    """Histogram of each of a Monte Carlo study's numbers (5 %, median, 95 % marked), and its scatter against the
    sampled coefficient with the largest rank correlation (``MonteCarlo.influence``).

    Parameters
    ----------
    mc : MonteCarlo
    names : sequence of str, optional
        The numbers drawn (default all, at most 6).
    ax : array of Axes, shape (len(names), 2), optional

    Returns
    -------
    ndarray of Axes, shape (len(names), 2)

    Raises
    ------
    GlidectlError
        If ``ax`` has the wrong number of axes, or a name is not one of the study's numbers.
    """
    names = list(mc.names[:6] if names is None else names)
    if ax is None:
        _, a = new_figure(len(names), 2, width=10.0, height=2.8 * len(names) + 0.6, squeeze=False)
        axes = np.asarray(a)
    else:
        axes = _axes(ax, 2 * len(names), "MonteCarlo.plot").reshape(len(names), 2)
    for row, name in enumerate(names):
        y = mc.column(name)
        good = np.isfinite(y)
        h = axes[row, 0]
        h.hist(y[good], bins=min(40, max(5, int(np.sqrt(good.sum())))), color="C0", alpha=0.8)
        if good.any():
            for q, ls in zip(mc.quantiles(name), (":", "-", ":"), strict=True):
                h.axvline(q, color="k", ls=ls, lw=1)
        h.set(xlabel=label(name, mc.unit(name) or None), ylabel="samples",
              title=f"{name}: {int(good.sum())} of {mc.n} samples (median, 5-95 %)")
        h.title.set_fontsize(9)
        s = axes[row, 1]
        infl = mc.influence(name) if good.sum() >= 3 else {}
        key = next(iter(infl), None)
        if key is None:
            s.set_axis_off()
            continue
        x = mc.column(key)
        s.plot(x[good], y[good], ".", ms=3, alpha=0.6)
        s.set(xlabel=f"{label(key, mc.unit(key) or None)} (sampled)", ylabel=label(name, mc.unit(name) or None),
              title=f"most influential: {key} (rank correlation {infl[key]:+.2f})")
        s.title.set_fontsize(9)
    axes[0, 0].figure.suptitle(textwrap.fill(f"Monte Carlo of {mc.study} over {', '.join(mc.keys)} "
                                             f"({mc.vehicle.name}, seed {mc.seed})", 110), fontsize=9)
    return axes


def plot_robust_stability(rs: Any, ax: Any = None) -> Any:
    """Three panels of a :class:`~glidectl.robustness.stability.RobustStability`: the histogram of the largest
    closed-loop real part over the samples (0 and the worst case marked), the dominant pole's change per half-range
    of each coefficient, and the largest real part against the most sensitive coefficient.

    Parameters
    ----------
    rs : RobustStability
    ax : three Axes, optional

    Returns
    -------
    ndarray of 3 Axes

    Raises
    ------
    GlidectlError
        If ``ax`` is not 3 axes.
    """
    if ax is None:
        _, a = new_figure(1, 3, width=14.0, height=4.4)
        axes = np.asarray(a)
    else:
        axes = _axes(ax, 3, "RobustStability.plot")
    mr = rs.max_real[np.isfinite(rs.max_real)]
    h = axes[0]
    h.hist(mr, bins=min(40, max(5, int(np.sqrt(mr.size)))), color="C0", alpha=0.8)
    h.axvline(0.0, color="C3", lw=1.2, label="stability boundary")
    if rs.worst_case is not None and math.isfinite(rs.worst_case.max_real):
        h.axvline(rs.worst_case.max_real, color="k", ls="--", lw=1, label=f"worst case {rs.worst_case.max_real:.3g}")
    h.set(xlabel="largest closed-loop real part [1/s]", ylabel="samples",
          title=f"stable in {rs.probability:.1%} of {int(rs.valid.sum())} samples")
    h.legend(fontsize=7)
    keys = list(rs.sensitivities)
    sv = np.array([rs.sensitivities[k] for k in keys])
    b = axes[1]
    y = np.arange(len(keys))
    b.barh(y - 0.2, sv.real, 0.4, color="C0", label="real part")
    b.barh(y + 0.2, sv.imag, 0.4, color="C1", label="imaginary part")
    b.set_yticks(y, keys, fontsize=7)
    b.axvline(0.0, color="k", lw=0.6)
    b.set(xlabel="dominant pole change per half-range [1/s]", title="sensitivities at the nominal coefficients")
    b.legend(fontsize=7)
    s = axes[2]
    if keys:
        top = max(keys, key=lambda k: abs(rs.sensitivities[k].real))
        j = rs.keys.index(top)
        ok = np.isfinite(rs.max_real)
        s.plot(rs.values[ok, j], rs.max_real[ok], ".", ms=3, alpha=0.6)
        s.axhline(0.0, color="C3", lw=1.2)
        unit = str(getattr(getattr(rs, "vehicle", None), "units", {}).get(top, "")) or None
        s.set(xlabel=f"{label(top, unit)} (sampled)", ylabel="largest real part [1/s]", title=f"against {top}")
    margin = ("" if rs.margin is None else
              f"; margin {'' if rs.margin_bounded else '>= '}{rs.margin:.3g} x the box")
    axes[0].figure.suptitle(textwrap.shorten(f"{rs.loop}{margin}", 160), fontsize=9)
    for a_ in axes:
        a_.title.set_fontsize(9)
    return axes
