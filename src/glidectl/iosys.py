"""python-control interop: any glidectl model as a :class:`control.NonlinearIOSystem` (:func:`to_iosys`).

A glidectl model has ``state_names``, ``input_names`` and a batch-capable ``rhs(x, u)``; :func:`to_iosys` wraps it,
with the same names, so that :func:`control.input_output_response`, :func:`control.find_operating_point`,
:func:`control.linearize` and interconnections work on it. The right-hand side is the model's own (never coded twice).

A :class:`control.StateSpace` pickles here through its matrices, time base and signal names
(:func:`copyreg.pickle`): python-control keeps a lambda in it, which the standard pickler refuses, and controllers
that carry their design plant (:class:`~glidectl.controllers.linear.LinearGlideController`) must cross a process
pool (:func:`glidectl.robust_stability`, :func:`glidectl.monte_carlo`).
"""

from __future__ import annotations

import copyreg
from collections.abc import Sequence
from typing import Any

import control
import numpy as np

from .errors import ArgumentError, ArgumentTypeError

__all__ = ["IOSysExport", "to_iosys"]


def _rebuilt_statespace(A: Any, B: Any, C: Any, D: Any, dt: Any, inputs: Any, outputs: Any, states: Any,
                        name: str) -> control.StateSpace:
    return control.ss(A, B, C, D, dt, inputs=inputs, outputs=outputs, states=states, name=name)


def _reduce_statespace(sys: control.StateSpace) -> tuple[Any, tuple[Any, ...]]:
    return _rebuilt_statespace, (sys.A, sys.B, sys.C, sys.D, sys.dt, sys.input_labels, sys.output_labels,
                                 sys.state_labels, sys.name)


copyreg.pickle(control.StateSpace, _reduce_statespace)


def to_iosys(model: Any, *, name: str | None = None) -> control.NonlinearIOSystem:
    """A glidectl model as a continuous-time :class:`control.NonlinearIOSystem` with named signals.

    Parameters
    ----------
    model : model
        Any glidectl model: ``state_names``, ``input_names`` (may be empty, e.g. a
        :class:`~glidectl.models.closed_loop.ClosedLoop`) and ``rhs(x, u)`` (state and input units of the model; time
        in s, or the model's nondimensional time).
    name : str, optional
        System name; default the model's ``name`` attribute, else its class name.

    Returns
    -------
    control.NonlinearIOSystem
        ``dx/dt = model.rhs(x, u)``; states and inputs named as the model's; outputs are the states (same names).

    Raises
    ------
    ArgumentTypeError
        If ``model`` is not a glidectl model (no ``state_names``, ``input_names`` or callable ``rhs``) or ``name`` is
        not a string.
    ArgumentError
        If the model has no states.
    """
    states = getattr(model, "state_names", None)
    inputs = getattr(model, "input_names", None)
    if not (isinstance(states, Sequence) and isinstance(inputs, Sequence) and callable(getattr(model, "rhs", None))):
        raise ArgumentTypeError(f"to_iosys needs a glidectl model (state_names, input_names and rhs(x, u)), got "
                                f"{type(model).__name__}")
    if not states:
        raise ArgumentError(f"model {type(model).__name__} has no states")
    if name is None:
        name = getattr(model, "name", None)
        name = name if isinstance(name, str) else type(model).__name__
    elif not isinstance(name, str):
        raise ArgumentTypeError(f"name must be a string, got {type(name).__name__}")
    m = len(inputs)

    def update(t: float, x: Any, u: Any, params: Any = None) -> np.ndarray:
        return np.asarray(model.rhs(np.asarray(x, dtype=float), np.asarray(u, dtype=float).reshape(m)), dtype=float)

    return control.NonlinearIOSystem(update, None, states=list(states), inputs=list(inputs) if m else 0,
                                     outputs=list(states), name=name)


class IOSysExport:
    """Mixin giving a glidectl model a ``to_iosys()`` method (the one :func:`to_iosys`, bound to the model)."""

    def to_iosys(self, name: str | None = None) -> control.NonlinearIOSystem:
        """This model as a :class:`control.NonlinearIOSystem` with named states and inputs (outputs = states), so
        that :func:`control.input_output_response` and interconnections work on it (see :func:`to_iosys`).

        Parameters
        ----------
        name : str, optional
            System name; default the model's ``name`` attribute, else its class name.

        Returns
        -------
        control.NonlinearIOSystem

        Raises
        ------
        ArgumentTypeError
            If ``name`` is not a string.
        """
        return to_iosys(self, name=name)
