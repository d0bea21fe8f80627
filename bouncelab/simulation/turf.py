"""The turf of a simulated campaign: a bounce law plus the spot-to-spot variation of its
parameters and the duration of contact (:class:`Turf`).

The paper moved the launcher between repeats, "so that the ball hit a
different, undamaged piece of the surface for each recorded impact", and found
the lift-off states of repeats scattered more than their landings: "the
behaviour of the turf was not fully deterministic". A :class:`Turf` models
that: each bounce hits its own spot, whose law parameters are drawn around the
nominal values of ``law``,

.. math::

    \\theta_{ik} = F_k(\\theta_k^{nom}, z_{ik}), \\qquad z_i \\sim N(0, C),

with ``F_k`` given per parameter by ``scatter``: :class:`LogNormal`
(``theta_nom * exp(sigma z)``: the median is the nominal value, ``sigma`` is
the standard deviation of ``ln theta``) or :class:`Normal`
(``theta_nom + sd z``), and ``C`` the ``correlation`` matrix of the standard
normal draws (identity by default; a soft spot can, say, lower restitution
and raise friction together). Draws are clipped to each parameter's physical
range. Parameters without an entry in ``scatter`` are the same everywhere.

The bounce itself is the law evaluated with the spot's parameters. Any
:class:`~bouncelab.BounceModel` with values can serve; a law that can take one
parameter vector per bounce in one call may define
``predict_per_bounce(landing, theta) -> (liftoff, regime_codes)`` with
``landing`` (n, 3) and ``theta`` (n, k) in ``parameter_specs`` order, which
:meth:`Turf.liftoff` then uses; a :class:`~bouncelab.CompiledLaw` (such as a
compiled contact law) needs nothing more: its scalar kernel is called in one
compiled loop with each bounce's own parameters. Other laws are called once
per bounce.

The duration of contact (:class:`ContactDuration`) decides how many camera
frames the turf hides the ball in; it scatters from spot to spot too.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bouncelab.core import checks
from bouncelab.core.errors import ParameterError
from bouncelab.laws.base import BounceModel

__all__ = ["ContactDuration", "LogNormal", "Normal", "Turf"]


def _check_nonneg(owner: str, name: str, value: Any) -> float:
    try:
        return checks.positive(value, name, allow_zero=True)
    except ParameterError as exc:
        raise ParameterError(f"{owner} {exc.message}", parameter=name, value=value) from None


@dataclass(frozen=True)
class LogNormal:
    """Spot value ``nominal * exp(sigma z)``: median the nominal value, ``sigma`` the sd of its logarithm."""

    sigma: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "sigma", _check_nonneg("LogNormal", "sigma", self.sigma))

    def apply(self, nominal: float, z: np.ndarray) -> np.ndarray:
        """Spot values for standard normal draws ``z``."""
        return nominal * np.exp(self.sigma * z)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description."""
        return {"kind": "lognormal", "sigma": self.sigma}


@dataclass(frozen=True)
class Normal:
    """Spot value ``nominal + sd z`` (absolute standard deviation, in the parameter's unit)."""

    sd: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "sd", _check_nonneg("Normal", "sd", self.sd))

    def apply(self, nominal: float, z: np.ndarray) -> np.ndarray:
        """Spot values for standard normal draws ``z``."""
        return nominal + self.sd * z

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description."""
        return {"kind": "normal", "sd": self.sd}


Scatter = LogNormal | Normal


@dataclass(frozen=True)
class ContactDuration:
    """Duration of the ball's contact with the turf, which hides it from the camera.

    .. math::

        t_c = t_{ref} \\left(\\frac{|\\dot y_0|}{v_{ref}}\\right)^{-a} e^{\\sigma z}

    Parameters
    ----------
    t_ref
        Contact time at a normal landing speed ``v_ref``, s (default 3 ms: a
        46 g ball on a bed of stiffness ~50 kN/m, which sinks ~1 cm at 10 m/s).
    v_ref
        Reference normal landing speed ``|ydot0|``, radii/s.
    exponent
        ``a``: 0 for a linear spring (duration independent of speed), 0.2
        for Hertzian contact.
    sigma
        Spot-to-spot scatter, standard deviation of ``ln t_c``.
    """

    t_ref: float = 3.0e-3
    v_ref: float = 500.0
    exponent: float = 0.0
    sigma: float = 0.1

    def __post_init__(self) -> None:
        for name in ("t_ref", "v_ref", "exponent", "sigma"):
            object.__setattr__(self, name, _check_nonneg("ContactDuration", name, getattr(self, name)))
        if self.t_ref <= 0 or self.v_ref <= 0:
            raise ParameterError(f"ContactDuration t_ref and v_ref must be > 0; got {self.t_ref!r}, {self.v_ref!r}",
                                 parameter="t_ref" if self.t_ref <= 0 else "v_ref")

    def duration(self, landing: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Contact times (s) of landings (n, 3) with standard normal draws ``z`` (n,)."""
        speed = np.abs(landing[:, 1]) / self.v_ref
        return self.t_ref * speed ** (-self.exponent) * np.exp(self.sigma * z)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description."""
        return {"t_ref_s": self.t_ref, "v_ref_radius_per_s": self.v_ref, "exponent": self.exponent,
                "sigma": self.sigma}


@dataclass(frozen=True)
class Turf:
    """A bounce law with spot-to-spot variation of its parameters, and a contact duration.

    Parameters
    ----------
    law
        The bounce at the nominal spot: any :class:`~bouncelab.BounceModel`
        with all its parameters set.
    scatter
        Parameter name -> :class:`LogNormal` or :class:`Normal`: how that
        parameter varies from spot to spot. Missing parameters do not vary.
    correlation
        Optional correlation matrix of the standard normal draws, one row and
        column per parameter of ``law`` (``parameter_specs`` order).
    contact
        Duration of contact.
    name
        A label stored with the campaign.

    Examples
    --------
    >>> import bouncelab as bl
    >>> turf = Turf(bl.Rigid(r=0.5, mu=0.4), {"r": LogNormal(0.1)})
    >>> turf.parameter_names
    ('r', 'mu')
    """

    law: BounceModel
    scatter: Mapping[str, Scatter] = field(default_factory=dict)
    correlation: Any = None
    contact: ContactDuration = field(default_factory=ContactDuration)
    name: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.law, BounceModel):
            raise ParameterError(f"Turf law must be a bouncelab BounceModel; got {type(self.law).__name__}",
                                 parameter="law")
        if not self.law.is_fitted:
            missing = [k for k, v in self.law.parameters.items() if v is None]
            raise ParameterError(f"Turf law {type(self.law).__name__} has no value for {missing}", parameter="law",
                                 law=type(self.law).__name__)
        if not isinstance(self.scatter, Mapping):
            raise ParameterError(f"Turf scatter must be a mapping name -> LogNormal/Normal; got {self.scatter!r}",
                                 parameter="scatter")
        names = self.parameter_names
        for key, value in self.scatter.items():
            if key not in names:
                raise ParameterError(
                    f"Turf scatter names {key!r}, which is not a parameter of {type(self.law).__name__} {names}",
                    parameter="scatter", value=key, law=type(self.law).__name__
                )
            if not isinstance(value, LogNormal | Normal):
                raise ParameterError(f"Turf scatter of {key!r} must be LogNormal or Normal; got {value!r}",
                                     parameter="scatter", value=value)
        object.__setattr__(self, "scatter", dict(self.scatter))
        if self.correlation is not None:
            c = np.asarray(self.correlation, dtype=float)
            k = len(names)
            if c.shape != (k, k) or not np.allclose(c, c.T) or not np.allclose(np.diag(c), 1.0):
                raise ParameterError(
                    f"Turf correlation must be a symmetric {k}x{k} matrix with unit diagonal; got {c.tolist()}",
                    parameter="correlation")
            try:
                np.linalg.cholesky(c)
            except np.linalg.LinAlgError:
                raise ParameterError("Turf correlation matrix is not positive definite") from None
            object.__setattr__(self, "correlation", tuple(map(tuple, c.tolist())))
        if not isinstance(self.contact, ContactDuration):
            raise ParameterError(f"Turf contact must be a ContactDuration; got {type(self.contact).__name__}",
                                 parameter="contact")

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Names of the columns of :meth:`spot_parameters`: the law's numbers in ``theta`` order
        (``name`` for a scalar parameter, ``name[i,j]`` for the elements of an array parameter)."""
        return tuple(n for spec in self.law.parameter_specs for n in spec.element_names())

    @property
    def nominal(self) -> np.ndarray:
        """Nominal parameter numbers (the law's values, in declaration order, arrays by element)."""
        return np.array(list(self.law.flat_parameters().values()), dtype=np.float64)

    def replace(self, **changes: Any) -> Turf:
        """A copy with some fields changed."""
        from dataclasses import replace

        return replace(self, **changes)

    def spot_parameters(self, z: np.ndarray) -> np.ndarray:
        """(n, k) law parameters of n spots from (n, k) independent standard normal draws ``z``.

        Each scattered number is clipped to its parameter's physical range.
        """
        z = np.asarray(z, dtype=float)
        if self.correlation is not None:
            z = z @ np.linalg.cholesky(np.asarray(self.correlation)).T
        nominal = self.nominal
        theta = np.tile(nominal, (z.shape[0], 1))
        col = 0
        for spec in self.law.parameter_specs:
            lo, hi = spec.physical_arrays()
            for k, name in enumerate(spec.element_names()):
                dist = self.scatter.get(name)
                if dist is not None:
                    theta[:, col] = np.clip(dist.apply(nominal[col], z[:, col]), lo[k], hi[k])
                col += 1
        return theta

    def liftoff(self, landing: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lift-off states (n, 3) and regime codes (n,) of landings (n, 3) on spots with parameters (n, k).

        The law's own ``predict_per_bounce(landing, theta)`` if it has one, else
        :func:`bouncelab.laws.predict_per_bounce` (for a compiled law one compiled loop calling its kernel
        with each row's parameters; otherwise one evaluation per distinct row).
        """
        landing = np.ascontiguousarray(landing, dtype=np.float64)
        theta = np.ascontiguousarray(theta, dtype=np.float64)
        if theta.shape != (len(landing), self.nominal.size):
            raise ParameterError(
                f"Turf.liftoff needs one parameter row per landing, shape {(len(landing), self.nominal.size)}; "
                f"got {theta.shape}"
            )
        law = self.law
        per_bounce = getattr(law, "predict_per_bounce", None)
        if per_bounce is not None:
            out, codes = per_bounce(landing, theta)
            return np.asarray(out, dtype=float), np.asarray(codes, dtype=np.int8)
        from bouncelab.laws.varying import predict_per_bounce

        return predict_per_bounce(law, landing, theta, codes=True)

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description: the nominal law, the scatter, the correlation and the contact duration."""
        return {
            "name": self.name,
            "law": self.law.to_dict(metadata=False),  # the law's value: units and conventions are the campaign's
            "scatter": {k: v.to_dict() for k, v in self.scatter.items()},
            "correlation": None if self.correlation is None else [list(r) for r in self.correlation],
            "contact_duration": self.contact.to_dict(),
        }

