"""Input checks shared by the public functions: one wording for every "must be a positive number" error."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .errors import ModelError

__all__ = ["positive_number"]


def positive_number(name: str, value: Any, *, allow_inf: bool = False) -> float:
    """``float(value)`` when it is a real number > 0 (finite unless ``allow_inf``); :class:`ModelError` otherwise.

    Booleans, strings, ``None`` and NaN are rejected with a message naming ``name``.
    """
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ModelError(f"{name} must be a number, got {value!r}")
    v = float(value)
    if not (v > 0 and (allow_inf or math.isfinite(v))):
        kind = "positive number" if allow_inf else "positive finite number"
        raise ModelError(f"{name} must be a {kind}, got {v!r}")
    return v
