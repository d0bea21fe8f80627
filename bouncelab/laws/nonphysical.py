r"""Non-physical lift-offs: a ball sent into the ground, or leaving with more energy than it landed with.

:meth:`BounceModel.predict(landing, return_flags=True) <bouncelab.BounceModel.predict>`
returns a :class:`LiftoffFlags` beside the lift-offs, computed in the same call
from the landings and lift-offs already in memory (no second prediction):

``into_ground``
    :math:`\dot y_F \le 0`: the ball does not leave the surface (y points up).
``energy_gain``
    :math:`E_F > E_0` with :math:`E \propto \dot x^2 + \dot y^2 + k\,\omega^2` in scaled
    units, :math:`k = I / (m R^2)` = :data:`~bouncelab.core.units.INERTIA_FACTOR` (0.4, a
    solid sphere, as the rigid bounce assumes); a relative tolerance of
    :data:`ENERGY_RTOL` absorbs rounding.

A law with the reference paper's published values (``Law.published("A")`` or
``"B"``) warns with :class:`~bouncelab.core.errors.NonphysicalLiftoffWarning` whenever
it predicts such lift-offs, since its users take it as given: e.g. the published
Penner laws of campaign B send landings within the paper's Table 1 ranges into
the ground (see ``docs/simulators.md``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from bouncelab.core._jit import jit
from bouncelab.core._parallel import run_chunked
from bouncelab.core.errors import NonphysicalLiftoffWarning, ParameterError
from bouncelab.core.units import INERTIA_FACTOR

__all__ = [
    "ENERGY_RTOL",
    "LiftoffFlags",
    "any_flagged",
    "flags_of",
    "liftoff_flags",
    "published_campaign",
    "warn_if_published_nonphysical",
]

#: Relative tolerance of the energy comparison (a rigid bounce with r = 1 and no friction keeps its energy).
ENERGY_RTOL = 1e-9


@dataclass(frozen=True)
class LiftoffFlags:
    """Which predicted lift-offs are non-physical (boolean arrays with the landings' leading shape).

    Attributes
    ----------
    into_ground
        ``ydotF <= 0``: the predicted lift-off does not leave the ground.
    energy_gain
        The lift-off's kinetic energy (translation and spin) exceeds the landing's.
    """

    into_ground: Any
    energy_gain: Any

    @property
    def nonphysical(self) -> Any:
        """Either flag."""
        return self.into_ground | self.energy_gain

    def counts(self) -> dict[str, int]:
        """Number of lift-offs flagged, per flag and in all."""
        return {"into_ground": int(np.sum(self.into_ground)), "energy_gain": int(np.sum(self.energy_gain)),
                "nonphysical": int(np.sum(self.nonphysical)), "n": int(np.size(self.into_ground))}

    def __repr__(self) -> str:
        c = self.counts()
        return (f"LiftoffFlags({c['nonphysical']} of {c['n']} non-physical: {c['into_ground']} into the ground "
                f"(ydotF <= 0), {c['energy_gain']} gaining energy)")


def _energy(p: np.ndarray) -> np.ndarray:
    return p[:, 0] * p[:, 0] + p[:, 1] * p[:, 1] + INERTIA_FACTOR * p[:, 2] * p[:, 2]


def liftoff_flags(landing: np.ndarray, liftoff: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(into_ground, energy_gain)`` boolean (n,) arrays of validated (n, 3) landings and predicted lift-offs."""
    into_ground = liftoff[:, 1] <= 0.0
    energy_gain = _energy(liftoff) > _energy(landing) * (1.0 + ENERGY_RTOL)
    return into_ground, energy_gain


def _any_flagged(landing: np.ndarray, liftoff: np.ndarray, inertia: float, rtol: float, start: int, stop: int
                 ) -> bool:
    """True when a lift-off in rows [start, stop) is flagged (the arithmetic of :func:`liftoff_flags`)."""
    for i in range(start, stop):
        if liftoff[i, 1] <= 0.0:
            return True
        e0 = landing[i, 0] * landing[i, 0] + landing[i, 1] * landing[i, 1] + inertia * landing[i, 2] * landing[i, 2]
        e1 = liftoff[i, 0] * liftoff[i, 0] + liftoff[i, 1] * liftoff[i, 1] + inertia * liftoff[i, 2] * liftoff[i, 2]
        if e1 > e0 * (1.0 + rtol):
            return True
    return False


_any_flagged_compiled = None


def any_flagged(landing: np.ndarray, liftoff: np.ndarray) -> bool:
    """Whether :func:`liftoff_flags` would flag any lift-off, in one compiled pass without temporaries: the
    check a published law makes on every ``predict`` costs a fraction of the prediction, not several times it."""
    global _any_flagged_compiled
    if _any_flagged_compiled is None:
        _any_flagged_compiled = jit(nogil=True)(_any_flagged)  # no fastmath: the same arithmetic as NumPy's
    p0, pf = np.ascontiguousarray(landing, dtype=np.float64), np.ascontiguousarray(liftoff, dtype=np.float64)
    return any(run_chunked(_any_flagged_compiled, len(p0), p0, pf, INERTIA_FACTOR, ENERGY_RTOL))


def published_campaign(law: Any) -> str | None:
    """The campaign ("A" or "B") whose published values ``law`` carries, or None (cached on the law)."""
    cached = law.__dict__.get("_published_as", False)
    if cached is not False:
        return cached
    found = None
    for campaign in ("A", "B"):
        try:
            ref = type(law).published(campaign)
        except (ParameterError, NotImplementedError):
            break
        if ref == law:
            found = campaign
            break
    object.__setattr__(law, "_published_as", found)  # laws are immutable values: the answer never changes
    return found


def warn_if_published_nonphysical(law: Any, landing: np.ndarray, liftoff: np.ndarray,
                                  flags: tuple[np.ndarray, np.ndarray] | None = None) -> None:
    """Warn (NonphysicalLiftoffWarning) when a law with published values predicts non-physical lift-offs."""
    campaign = published_campaign(law)
    if campaign is None:
        return
    into_ground, gain = flags if flags is not None else liftoff_flags(landing, liftoff)
    n_ground, n_gain = int(into_ground.sum()), int(gain.sum())
    if not (n_ground or n_gain):
        return
    n = len(landing)
    parts = []
    if n_ground:
        parts.append(f"{n_ground} of {n} ({n_ground / n:.1%}) into the ground (ydotF <= 0, first: landing row "
                     f"{int(np.argmax(into_ground)) + 1})")
    if n_gain:
        parts.append(f"{n_gain} of {n} ({n_gain / n:.1%}) with more kinetic energy than the landing (first: row "
                     f"{int(np.argmax(gain)) + 1})")
    warnings.warn(
        f"{type(law).__name__}.published({campaign!r}) predicts non-physical lift-offs: {'; '.join(parts)}. "
        "The paper fitted these values to its measured landings; predict(..., return_flags=True) marks each one "
        "(see the 'Simulators' page of the docs)",
        NonphysicalLiftoffWarning, stacklevel=4,  # the caller of predict (via flags_of)
    )


def flags_of(law: Any, landing: np.ndarray, liftoff: np.ndarray, *,
             always: bool) -> tuple[np.ndarray, np.ndarray] | None:
    """``predict``'s flag layer: the flags of the lift-offs when asked for (``always``), and the warning of a
    law with the paper's published values that predicts non-physical lift-offs (checked in one compiled pass
    first, so the usual call pays nothing more)."""
    if not always and (published_campaign(law) is None or not any_flagged(landing, liftoff)):
        return None
    flags = liftoff_flags(landing, liftoff)
    warn_if_published_nonphysical(law, landing, liftoff, flags)
    return flags
