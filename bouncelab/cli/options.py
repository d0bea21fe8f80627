"""Argument types shared by the subcommands.

Each is an ``argparse`` ``type=``: it turns the option's text into a value or
raises :class:`argparse.ArgumentTypeError`, which argparse prints after the
option's name (``argument --fps: not a number: 'x'``) and exits with status 2.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

from bouncelab.core import checks
from bouncelab.core.errors import ParameterError

__all__ = ["finite", "positive", "whole"]


def finite(text: str) -> float:
    """A finite number (the text parsed, then :func:`bouncelab.core.checks.finite`'s rule)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    try:
        return checks.finite(value, "value")
    except ParameterError:
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}") from None


def positive(text: str) -> float:
    """A finite number > 0 (:func:`bouncelab.core.checks.positive`'s rule)."""
    value = finite(text)
    try:
        return checks.positive(value, "value")
    except ParameterError:
        raise argparse.ArgumentTypeError(f"must be positive: {text!r}") from None


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
