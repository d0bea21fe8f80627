"""Shared fixtures."""

from __future__ import annotations

import numpy as np
import pytest

try:  # hypothesis profiles of the fuzz tests: small and repeatable by default (CI gives the same verdict on the
    # same code), `--hypothesis-profile=fuzz` for 20x more examples, drawn afresh each run
    from hypothesis import HealthCheck, settings

    settings.register_profile("bouncelab", max_examples=60, deadline=None, derandomize=True,
                              suppress_health_check=[HealthCheck.too_slow])
    settings.register_profile("fuzz", max_examples=1200, deadline=None,
                              suppress_health_check=[HealthCheck.too_slow])
    settings.load_profile("bouncelab")
except ImportError:  # the test extra is not installed: tests/test_fuzz.py skips itself
    pass


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


def random_landings(rng: np.random.Generator, n: int = 2000, *, both_directions: bool = True) -> np.ndarray:
    """Landings spanning the paper's Table 1 ranges (scaled units), optionally in both directions."""
    xd = rng.uniform(1.0, 2300.0, n)
    if both_directions:
        xd *= rng.choice([-1.0, 1.0], n)
    yd = -rng.uniform(90.0, 1900.0, n)
    w = rng.uniform(-1700.0, 1700.0, n)
    return np.column_stack([xd, yd, w])


def contact_landings(n: int, seed: int = 0) -> np.ndarray:
    """Landings for the contact laws' property tests: forward and backward, backspin and topspin."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-300, 1300, n), rng.uniform(-950, -50, n), rng.uniform(-400, 1000, n)])


def kinetic_energy(p: np.ndarray) -> np.ndarray:
    """Kinetic energy per m R^2 of (..., 3) states: (xdot^2 + ydot^2)/2 + I omega^2 / 2 with I = 2/5 m R^2."""
    return 0.5 * (p[..., 0] ** 2 + p[..., 1] ** 2) + 0.2 * p[..., 2] ** 2


@pytest.fixture
def landings(rng: np.random.Generator) -> np.ndarray:
    return random_landings(rng)
