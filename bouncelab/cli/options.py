"""Argument types shared by the subcommands.

Each is an ``argparse`` ``type=``: it turns the option's text into a value or
raises :class:`argparse.ArgumentTypeError`, which argparse prints after the
option's name (``argument --fps: not a number: 'x'``) and exits with status 2.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

__all__ = ["finite", "positive", "whole"]


def finite(text: str) -> float:
    """A finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def positive(text: str) -> float:
    """A finite number > 0."""
    value = finite(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive: {text!r}")
    return value


def whole(minimum: int, what: str = "") -> Callable[[str], int]:
    """The type of a whole number >= ``minimum``; ``what`` says what it counts (e.g. "processes")."""
    counts = f" {what}" if what else ""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a whole number{counts}: {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{minimum} or more{counts}: {text!r}")
        return value

    parse.__name__ = f"whole_from_{minimum}"
    return parse
