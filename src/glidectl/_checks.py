"""Compatibility shim: :func:`positive_number` is :func:`glidectl.checks.positive`."""

from __future__ import annotations

from typing import Any

from .checks import positive

__all__ = ["positive_number"]


def positive_number(name: str, value: Any, *, allow_inf: bool = False) -> float:
    """``float(value)`` when it is a real number > 0 (finite unless ``allow_inf``).

    See :func:`glidectl.checks.positive`.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a real number.
    ArgumentError
        If it is not > 0 or not finite.
    """
    return positive(name, value, allow_inf=allow_inf)
