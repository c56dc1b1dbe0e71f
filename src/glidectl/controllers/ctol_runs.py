"""Common result of every CTOL tracking method (steady gliding, feedback linearization, stable inversion,
approximate linearization): time histories and the metrics compared in the §7.3.3 baseline table, and the
simulation window the exact-tracking baselines run in."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError
from ..sim import MAX_STEPS, simulate

__all__ = ["MAX_OUTPUT_POINTS", "TrackingRun", "simulate_window"]


@dataclass(frozen=True, eq=False)
class TrackingRun:
    """A tracking run of the CTOL aircraft, common to every tracking method (exact, approximate, steady gliding).

    Attributes
    ----------
    method : str
        Method name and settings.
    t : ndarray (N,)
        Times (s).
    x : ndarray (N, 6)
        States ``(x, y, xdot, ydot, theta, Omega2)`` (m, m, m/s, m/s, rad, rad/s).
    u : ndarray (N, 2)
        Inputs ``(u1, u2)`` (N, N m).
    error : ndarray (N, 2)
        Position error ``p - p_d`` (m).
    peak_u1, peak_u2 : float
        ``max |u1|`` (N), ``max |u2|`` (N m).
    rms_u1, rms_u2 : float
        Time-weighted RMS (trapezoid over ``t``) of ``u1`` (N) and ``u2`` (N m).
    max_error : float
        ``max ||p - p_d||`` (m).
    effort : float
        Time-RMS of ``||u|| = sqrt(u1^2 + u2^2)`` (the effort axis of the Pareto study; ``u1`` in N and ``u2`` in
        N m are both O(1) in the normalized units of §7.1).
    note : str
        What happened (settings, start, why it stopped).
    stopped_at : float or None
        Time (s) at which the run was ended early (divergence), None if it ran to the end.
    """

    method: str
    t: np.ndarray = field(repr=False)
    x: np.ndarray = field(repr=False)
    u: np.ndarray = field(repr=False)
    error: np.ndarray = field(repr=False)
    peak_u1: float
    peak_u2: float
    rms_u1: float
    rms_u2: float
    max_error: float
    effort: float
    note: str = ""
    stopped_at: float | None = None

    @classmethod
    def from_arrays(cls, method: str, t: Any, x: Any, u: Any, error: Any, *, note: str = "",
                    stopped_at: float | None = None,
                    mean_squares: tuple[float, float, float] | None = None) -> TrackingRun:
        """Build a run and compute its metrics from the time histories (arrays as in the class docstring).

        ``mean_squares``: exact time means of ``(u1^2, u2^2, |u|^2)`` when the caller integrated them (quadrature
        states); otherwise they are the trapezoid rule over ``t``.

        Raises
        ------
        ArgumentTypeError
            If ``method`` or ``note`` is not a string, or an array is not real numbers.
        ArgumentError
            If the arrays are not finite or their shapes are inconsistent (``t (N,)`` nondecreasing, ``x (N, 6)``,
            ``u (N, 2)``, ``error (N, 2)``), ``stopped_at`` is not finite, or ``mean_squares`` is not three
            finite numbers (negative rounding errors of a quadrature are clipped to 0).
        """
        if not isinstance(method, str) or not isinstance(note, str):
            raise ArgumentTypeError("method and note must be strings")
        t = checks.array("t", t, ndim=1, min_size=1)
        x, u, error = (checks.array(n, a, ndim=2) for n, a in (("x", x), ("u", u), ("error", error)))
        if u.shape != (t.size, 2) or error.shape != (t.size, 2) or x.shape[0] != t.size:
            raise ArgumentError(f"inconsistent run arrays: t {t.shape}, x {x.shape}, u {u.shape}, "
                                f"error {error.shape}")
        if np.any(np.diff(t) < 0):
            raise ArgumentError("run times t must be nondecreasing")
        if stopped_at is not None:
            stopped_at = checks.real("stopped_at", stopped_at, unit="s")
        if mean_squares is not None:
            checks.array("mean_squares", mean_squares, shape=(3,))  # tiny negative quadrature errors clip to 0

        def rms(a: np.ndarray) -> float:
            if t[-1] <= t[0]:
                return float(np.sqrt(np.mean(a**2)))
            return float(np.sqrt(np.trapezoid(a**2, t) / (t[-1] - t[0])))

        if mean_squares is None:
            r1, r2, re = rms(u[:, 0]), rms(u[:, 1]), rms(np.hypot(u[:, 0], u[:, 1]))
        else:
            r1, r2, re = (math.sqrt(max(float(v), 0.0)) for v in mean_squares)
        return cls(method, t, x, u, error, float(np.max(np.abs(u[:, 0]))), float(np.max(np.abs(u[:, 1]))),
                   r1, r2, float(np.max(np.hypot(error[:, 0], error[:, 1]))), re, note,
                   None if stopped_at is None else float(stopped_at))

    @property
    def completed(self) -> bool:
        """True when the run reached its final time."""
        return self.stopped_at is None

    def plot(self, ax: Any = None, *, input_scale: str = "linear") -> Any:
        """Draw the position error and the inputs versus time (Fig 7.3-7.4) in the glidectl style.

        Parameters
        ----------
        ax : array of 3 axes, optional
            Position error, thrust ``u1``, pitching moment ``u2``; default a new figure.
        input_scale : {"linear", "symlog"}
            Scale of the input axes; ``"symlog"`` shows input spikes together with the rest of the run.

        Returns
        -------
        ndarray of 3 matplotlib.axes.Axes
            See :func:`glidectl.plotting.plot_tracking_run`.
        """
        from ..plotting import plot_tracking_run, style

        with style():
            return plot_tracking_run(self, ax, input_scale=input_scale)

    TABLE_HEADER: ClassVar[tuple[str, ...]] = ("method", "max |e| [m]", "peak |u1|", "RMS u1", "peak |u2|",
                                                "RMS u2", "status")
    """Column names of :meth:`table_row` (u1 in N, u2 in N m)."""

    def table_row(self, label: str | None = None) -> list[str]:
        """One row of text for a table comparing tracking runs (the §7.3.3 baseline table), as :data:`TABLE_HEADER`.

        Parameters
        ----------
        label : str, optional
            Text of the first column; default :attr:`method`.

        Returns
        -------
        list of str
            ``[label, max |e| (m), peak |u1| (N), RMS u1 (N), peak |u2| (N m), RMS u2 (N m), status]``, numbers to
            3 significant digits; status is ``"completed"`` or ``"stopped at <t> s"``.

        Raises
        ------
        ArgumentTypeError
            If ``label`` is not a string.
        """
        if label is not None and not isinstance(label, str):
            raise ArgumentTypeError(f"label must be a string (the table's first column), got {type(label).__name__}")
        status = "completed" if self.completed else f"stopped at {self.stopped_at:.2f} s"
        return [self.method if label is None else label, f"{self.max_error:.3g}", f"{self.peak_u1:.3g}",
                f"{self.rms_u1:.3g}", f"{self.peak_u2:.3g}", f"{self.rms_u2:.3g}", status]

    def as_dict(self) -> dict[str, Any]:
        """The metrics as a plain dict (for tables and ``numbers.json``)."""
        return {"method": self.method, "max_error": self.max_error, "peak_u1": self.peak_u1,
                "peak_u2": self.peak_u2, "rms_u1": self.rms_u1, "rms_u2": self.rms_u2, "effort": self.effort,
                "completed": self.completed, "stopped_at": self.stopped_at, "note": self.note}

    def summary(self) -> str:
        """A few lines of text: the method, how the run ended, the error and the inputs."""
        end = "ran to the end" if self.completed else f"stopped at t = {self.stopped_at:.4g} s"
        lines = [f"{self.method}: {end}, t = {self.t[0]:.4g} .. {self.t[-1]:.4g} s",
                 f"  max position error {self.max_error:.4g} m, effort (RMS |u|) {self.effort:.4g}",
                 f"  peak |u1| {self.peak_u1:.4g} N, |u2| {self.peak_u2:.4g} N m; RMS u1 {self.rms_u1:.4g} N, "
                 f"u2 {self.rms_u2:.4g} N m"]
        if self.note:
            lines.append(f"  {self.note}")
        return "\n".join(lines)


#: Largest number of output points of :func:`simulate_window` (``(t_final - t_start) / dt``).
MAX_OUTPUT_POINTS = 10_000_000


def simulate_window(model: Any, x0: np.ndarray, t_start: float, t_final: float,
                    controller: Callable[[float, Any], Any], dt: float,
                    stop: Callable[[float, np.ndarray], float] | None = None, method: str = "LSODA",
                    rtol: float = 1e-9, atol: float = 1e-11, max_steps: int = MAX_STEPS,
                    time_limit: float | None = None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float | None]:
    """:func:`glidectl.sim.simulate` on ``[t_start, t_final]`` s (time shifted to start at 0 for the integrator).

    Parameters
    ----------
    model : Model
        Plant (``rhs``, ``state_names``, ``input_names``).
    x0 : ndarray
        State at ``t_start``.
    t_start, t_final : float
        Window (s); ``t_start`` may be negative (the pre-action of a stable inversion).
    controller : callable
        ``(t, x) -> u`` in the original time ``t`` (s).
    dt : float
        Output spacing (s), ``0 < dt <= t_final - t_start``; at most :data:`MAX_OUTPUT_POINTS` outputs.
    stop : callable, optional
        ``(t, x) -> float`` in the original time; the run ends where it falls through zero.
    method, rtol, atol
        Integrator settings of :func:`glidectl.sim.simulate`.
    max_steps, time_limit
        Budgets of :func:`glidectl.sim.simulate` (integrator steps; wall time in s, default none).

    Returns
    -------
    t, x, u : ndarray
        Output times (s, original time), states and inputs.
    stopped_at : float or None
        Time (s, original time) at which ``stop`` ended the run.

    Raises
    ------
    ArgumentTypeError
        If an argument has the wrong type (see :func:`glidectl.sim.simulate`).
    ArgumentError
        If ``t_start``/``t_final`` are not finite with ``t_start < t_final``, ``dt`` is not in
        ``(0, t_final - t_start]`` or gives more than :data:`MAX_OUTPUT_POINTS` points, or
        :func:`glidectl.sim.simulate` refuses an argument.
    BudgetError
        If the run hits a budget of :func:`glidectl.sim.simulate`.
    SolverError
        If the integration fails.
    """
    t_start = checks.real("t_start", t_start, unit="s")
    t_final = checks.real("t_final", t_final, unit="s")
    if not t_final > t_start:
        raise ArgumentError(f"need t_start < t_final, got [{t_start:g}, {t_final:g}] s")
    span = t_final - t_start
    dt = checks.real("dt", dt, lo=0.0, hi=span, lo_open=True, unit="s")
    if span / dt > MAX_OUTPUT_POINTS:
        raise ArgumentError(f"dt = {dt:g} s gives {span / dt:.3g} output points on [{t_start:g}, {t_final:g}] s; at "
                            f"most {MAX_OUTPUT_POINTS} are allowed (raise dt)")
    checks.function("controller", controller)
    if stop is not None:
        checks.function("stop", stop)
    n = max(1, round(span / dt))
    te = np.linspace(0.0, span, n + 1)

    def ctrl(s: float, x: Any) -> Any:
        return controller(s + t_start, x)

    st = None if stop is None else (lambda s, x: stop(s + t_start, x))
    sim = simulate(model, x0, span, ctrl, t_eval=te, method=method, rtol=rtol, atol=atol, stop=st, max_steps=max_steps,
                   time_limit=time_limit)
    stopped = None if sim.stopped_at is None else sim.stopped_at + t_start
    return sim.t + t_start, sim.x, sim.u, stopped
