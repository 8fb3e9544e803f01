"""Checks of the arguments the package's functions take, each raising ValueError that names the argument."""
from __future__ import annotations

import numbers
from typing import Sequence


def rgb(value, what: str):
    try:
        c = tuple(float(x) for x in value)
    except TypeError:
        raise ValueError(f"{what} must be three numbers, got {value!r}") from None
    if len(c) != 3:
        raise ValueError(f"{what} must be three numbers, got {value!r}")
    return c


def one_of(names: Sequence[str], quote: bool = True) -> str:
    """'a', 'b' or 'c': the allowed values, for error messages."""
    shown = [repr(n) if quote else n for n in names]
    return " or ".join([", ".join(shown[:-1]), shown[-1]] if len(shown) > 1 else shown)


def int_argument(name: str, value, lo: int, hi: int = 2 ** 31 - 1) -> int:
    """An integer argument in lo..hi (by default: one the native side's int holds), else ValueError."""
    if not isinstance(value, numbers.Integral) or isinstance(value, bool) or not lo <= value <= hi:
        raise ValueError(f"{name} must be an integer in {lo}..{hi}, got {value!r}")
    return int(value)
