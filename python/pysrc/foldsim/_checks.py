"""Argument checks shared by the package's functions: errors name the argument."""

from __future__ import annotations

import os
from typing import Any


def path_arg(value: Any, name: str) -> str:
    """A str or path-like argument as str; TypeError naming the argument otherwise."""
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    raise TypeError(f"{name} must be a str or a path, not {type(value).__name__}")


def count(value: Any, name: str, minimum: int = 1) -> int | None:
    """An optional whole-number argument of at least `minimum` (None stays None); TypeError
    or ValueError naming it."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{name} must be a whole number, not {type(value).__name__}")
    if value < minimum:
        raise ValueError(f"{name} must be a whole number ≥ {minimum}; got {value}")
    return value
