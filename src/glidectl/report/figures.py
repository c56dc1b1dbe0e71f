"""Figure helpers: they draw results computed elsewhere and never compute dynamics themselves."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection

from ..models.longitudinal import STATE_UNITS

if TYPE_CHECKING:
    from ..analysis.locus import ParameterLocus
    from ..sim import Simulation

__all__ = ["label", "new_figure", "plot_locus", "plot_locus_real", "plot_simulation"]

_LATEX = {"theta": r"$\theta$", "Omega2": r"$\Omega_2$", "v1": r"$v_1$", "v3": r"$v_3$", "r_P1": r"$r_{P1}$",
          "r_P3": r"$r_{P3}$", "P_P1": r"$P_{P1}$", "P_P3": r"$P_{P3}$", "m0": r"$m_0$", "z_prime": r"$z'$",
          "rdot_P1": r"$\dot r_{P1}$", "rdot_P3": r"$\dot r_{P3}$", "x": "$x$", "z": "$z$", "u1": "$u_1$",
          "u3": "$u_3$", "u4": "$u_4$", "w1": "$w_1$", "w3": "$w_3$", "w4": "$w_4$", "r_bh": r"$r_{bh}$",
          "mbar": r"$\bar m$"}


def label(name: str, unit: str | None = None) -> str:
    """Axis label ``symbol [unit]`` for a named state/input/parameter."""
    u = unit if unit is not None else STATE_UNITS.get(name, "")
    return f"{_LATEX.get(name, name)} [{u}]" if u else _LATEX.get(name, name)


def new_figure(nrows: int = 1, ncols: int = 1, *, width: float = 7.0, height: float = 4.2, **kw: Any) -> Any:
    """A figure with constrained layout sized for a report page."""
    return plt.subplots(nrows, ncols, figsize=(width, height), layout="constrained", **kw)


def _param_label(locus: ParameterLocus) -> str:
    return label(locus.parameter, locus.unit)


def plot_locus(locus: ParameterLocus, ax: Any = None, *,
               zoom: tuple[float, float, float, float] | None = None) -> Any:
    """Root locus: every branch in the complex plane, coloured by the parameter; crossings (x) and break points
    (o, lettered) marked; arrows show the direction of increasing parameter; ``zoom = (x0, x1, y0, y1)`` adds
    an inset."""
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
    ax.grid(True, alpha=0.3)
    return ax


def plot_locus_real(locus: ParameterLocus, ax: Any = None) -> Any:
    """Real parts of the eigenvalue branches versus the parameter, with the stability boundary marked."""
    if ax is None:
        _, ax = new_figure()
    for j in range(locus.branches.shape[1]):
        ax.plot(locus.values, locus.branches[:, j].real, lw=1.8)
    ax.axhline(0, color="0.3", lw=0.8, ls="--")
    for c in locus.crossings:
        ax.axvline(c, color="C3", lw=1)
        ax.annotate(f"{c:.4g} {locus.unit}", (c, 0), textcoords="offset points", xytext=(4, 6), color="C3",
                    fontsize=8)
    for bp in locus.breakpoints:
        ax.plot(bp.parameter, bp.eigenvalue, "o", mfc="none", mec="k", ms=7)
    ax.set_xlabel(_param_label(locus))
    ax.set_ylabel(r"Re $\lambda$ [1/s]")
    ax.grid(True, alpha=0.3)
    return ax


def plot_simulation(sim: Simulation, names: Sequence[str] | None = None, ax: Any = None, *,
                    scale: dict[str, tuple[float, str]] | None = None, **line: Any) -> Any:
    """One axis per named state/input versus time. ``scale[name] = (factor, unit)`` converts units for display."""
    names = list(names) if names is not None else list(sim.state_names)
    if ax is None:
        _, ax = new_figure(len(names), 1, height=1.6 * len(names) + 0.6, sharex=True)
    axes = np.atleast_1d(ax)
    scale = scale or {}
    for a, n in zip(axes, names, strict=True):
        f, u = scale.get(n, (1.0, None))
        a.plot(sim.t, f * sim.state(n), **line)
        a.set_ylabel(label(n, u), fontsize=9)
        a.grid(True, alpha=0.3)
    axes[-1].set_xlabel("t [s]")
    return axes
