"""A plant model closed by a static state feedback: the input-free vector field ``x' = f(x, law(x))``.

:class:`ClosedLoop` turns any glidectl model (``rhs(x, u)``, ``state_names``, ``input_names``, batch-capable over
leading dimensions) and any state feedback ``u = law(x)`` (batch-capable: ``x`` of shape ``(..., n)`` gives ``u`` of
shape ``(..., m)``) into an input-free model for :func:`glidectl.sim.simulate`, :func:`glidectl.sim.simulate_many`,
:func:`glidectl.derivatives.jacobians` and the region-of-attraction tools. The right-hand side is the plant's
own, so a closed loop is never coded twice. :func:`glidectl.closed_loop` builds it from a controller of this package
(the plant and the equilibrium the controller was designed for).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ArgumentTypeError
from ..iosys import IOSysExport
from ..params import Vehicle
from ._validate import numeric_array, trailing_array

__all__ = ["ClosedLoop"]


@dataclass(frozen=True, eq=False)
class ClosedLoop(IOSysExport):
    """Input-free closed loop ``x' = plant.rhs(x, law(x))``.

    Parameters
    ----------
    plant : model
        A glidectl model with ``rhs(x, u)``, ``state_names``, ``input_names`` and ``vehicle``; its right-hand side
        must accept a batch of states ``(..., n)`` with inputs ``(..., m)``.
    law : callable
        State feedback ``u = law(x)``: ``x`` of shape ``(..., n)`` (the plant's state units) to ``u`` of shape
        ``(..., m)`` (the plant's input units). Time-invariant; for a controller ``c(t, x)`` of this package use
        :func:`glidectl.closed_loop`.
    equilibrium : array_like, shape (n,), optional
        The closed-loop equilibrium (plant state units), e.g. the steady glide the law regulates to; ``None`` when
        not known.
    description : str
        What the law is (for :attr:`name`); default the law's type.

    Attributes
    ----------
    state_names : tuple of str
        The plant's states.
    input_names : tuple
        ``()`` (input-free).
    n_states : int
    equilibrium : ndarray, shape (n,), or None
        Read-only.
    vehicle : Vehicle
        The plant's vehicle.
    name : str
        Plant, vehicle and law, for tables and plots.
    provenance : str
        The vehicle's parameter hash (as every glidectl model and result).

    Raises
    ------
    ArgumentTypeError
        If ``plant`` is not a glidectl model, ``law`` is not callable or ``description`` is not a string.
    ArgumentError
        If ``equilibrium`` is not ``n`` finite numbers.
    """

    plant: Any
    law: Callable[[Any], Any]
    equilibrium: np.ndarray | None = None
    description: str = ""
    input_names: tuple[str, ...] = field(default=(), init=False)

    def __post_init__(self) -> None:
        for attr in ("rhs", "state_names", "input_names"):
            if not hasattr(self.plant, attr):
                raise ArgumentTypeError(f"plant {type(self.plant).__name__} is not a glidectl model: it has no "
                                        f"'{attr}' (need rhs(x, u), state_names, input_names)")
        if not callable(self.plant.rhs):
            raise ArgumentTypeError(f"plant {type(self.plant).__name__} is not a glidectl model: rhs is not callable")
        if not callable(self.law):
            raise ArgumentTypeError(f"law must be a callable u = law(x), got {type(self.law).__name__}")
        if not isinstance(self.description, str):
            raise ArgumentTypeError(f"description must be a string, got {type(self.description).__name__}")
        if self.equilibrium is not None:
            try:
                xe = checks.array("equilibrium", self.equilibrium, shape=(self.n_states,)).copy()
            except ArgumentError as exc:
                raise ArgumentError(f"equilibrium must be {self.n_states} finite numbers for states "
                                    f"{tuple(self.plant.state_names)}, got {self.equilibrium!r} ({exc})") from None
            xe.setflags(write=False)
            object.__setattr__(self, "equilibrium", xe)

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(self.plant.state_names)

    @property
    def n_states(self) -> int:
        return len(self.plant.state_names)

    @property
    def vehicle(self) -> Vehicle:
        return self.plant.vehicle

    @property
    def name(self) -> str:
        veh = getattr(self.plant, "vehicle", None)
        what = self.description or type(self.law).__name__
        return f"{type(self.plant).__name__}({getattr(veh, 'name', '?')}) closed by {what}"

    @property
    def provenance(self) -> str:
        return str(getattr(getattr(self.plant, "vehicle", None), "provenance", ""))

    def rhs(self, x: Any, u: Any = None) -> np.ndarray:
        """Closed-loop ``x'`` for states ``x`` of shape ``(..., n)`` (``u`` is ignored: the loop is input-free).

        ``x`` may be complex (complex-step Jacobians) when the plant and the law are. Exceptions raised by the law
        reach the caller unchanged.

        Raises
        ------
        ArgumentTypeError
            If ``x`` is not an array of numbers, or the law returns something else.
        ArgumentError
            If ``x`` does not have the trailing dimension ``n``, or the law's output not the plant's ``m``.
        """
        x = trailing_array("state", x, self.n_states, self.state_names)
        u = self.law(x)
        m = len(self.plant.input_names)
        if m:
            ua = numeric_array("the law's output u = law(x)", u)
            if ua.shape[-1:] != (m,):
                raise ArgumentError(f"the law returned shape {ua.shape} for states of shape {x.shape}; it must return "
                                    f"(..., {m}), one value per input {tuple(self.plant.input_names)}")
            u = ua
        return np.asarray(self.plant.rhs(x, u))
