"""A plant model closed by a static state feedback: the input-free vector field ``x' = f(x, law(x))``.

:class:`ClosedLoop` turns any glidectl model (``rhs(x, u)``, ``state_names``, ``input_names``, batch-capable over
leading dimensions) and any state feedback ``u = law(x)`` (batch-capable: ``x`` of shape ``(..., n)`` gives ``u`` of
shape ``(..., m)``) into an input-free model for :func:`glidectl.sim.simulate`, :func:`glidectl.sim.simulate_many`,
:func:`glidectl.analysis.jacobian.jacobians` and the region-of-attraction tools. The right-hand side is the plant's
own, so a closed loop is never coded twice. :func:`glidectl.closed_loop` builds it from a controller of this package
(the plant and the equilibrium the controller was designed for).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ModelError
from ..params import Vehicle

__all__ = ["ClosedLoop"]


@dataclass(frozen=True, eq=False)
class ClosedLoop:
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
    """

    plant: Any
    law: Callable[[Any], Any]
    equilibrium: np.ndarray | None = None
    description: str = ""
    input_names: tuple[str, ...] = field(default=(), init=False)

    def __post_init__(self) -> None:
        for attr in ("rhs", "state_names", "input_names"):
            if not hasattr(self.plant, attr):
                raise ModelError(f"plant {type(self.plant).__name__} is not a glidectl model: it has no '{attr}' "
                                 "(need rhs(x, u), state_names, input_names)")
        if not callable(self.law):
            raise ModelError(f"law must be a callable u = law(x), got {type(self.law).__name__}")
        if self.equilibrium is not None:
            xe = np.array(self.equilibrium, dtype=float)
            if xe.shape != (self.n_states,) or not np.all(np.isfinite(xe)):
                raise ModelError(f"equilibrium must be {self.n_states} finite numbers for states "
                                 f"{tuple(self.plant.state_names)}, got {self.equilibrium!r}")
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

        ``x`` may be complex (complex-step Jacobians) when the plant and the law are.
        """
        x = np.asarray(x)
        if x.shape[-1:] != (self.n_states,):
            raise ModelError(f"state must have a trailing dimension {self.n_states} {self.state_names}, got shape "
                             f"{x.shape}")
        return np.asarray(self.plant.rhs(x, self.law(x)))
