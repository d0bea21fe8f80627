"""The piecewise-affine landing-to-lift-off map of the paper (eqs. disjointA/B)."""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.data import published as _published
from bouncelab.data.units import COMPONENTS
from bouncelab.errors import ParameterError
from bouncelab.laws._compiled import kernels
from bouncelab.laws.base import BounceModel

__all__ = ["PiecewiseAffine"]

_SHAPES = {"normal": (3,), "offset": (), "A1": (3, 3), "b1": (3,), "A2": (3, 3), "b2": (3,)}


class PiecewiseAffine(BounceModel):
    r"""Two affine maps either side of a plane in landing space.

    Eq. (piecewise_fit) with the split of eqs. (disjointA/B):

    .. math::

        \mathbf p_F = \begin{cases}
            A_1 \mathbf p_0 + \mathbf b_1 & \text{if } \mathbf n \cdot \mathbf p_0 < c
                \quad(\text{side 1, "roll"})\\
            A_2 \mathbf p_0 + \mathbf b_2 & \text{if } \mathbf n \cdot \mathbf p_0 \ge c
                \quad(\text{side 2, "slip"})
        \end{cases}

    with :math:`\mathbf p = [\dot x, \dot y, \omega]`. The paper prints the plane as
    :math:`a \dot x_0 + b \dot y_0 + \omega_0 = c`, i.e. :math:`\mathbf n = (a, b, 1)`.
    By convention side 1 holds the bounces that roll and side 2 those that slip
    throughout (the fitters orient the plane so); the law itself is just two maps.

    Parameters
    ----------
    normal : array_like (3,), optional
        Plane normal :math:`\mathbf n` (coefficients of xdot0 [1/radius·s], ydot0, omega0 [s]).
    offset : float, optional
        Plane offset :math:`c`, in the units of :math:`\mathbf n \cdot \mathbf p_0`.
    A1, A2 : array_like (3, 3), optional
        Linear parts, dimensionless (rows: xdotF, ydotF, omegaF; columns: xdot0, ydot0, omega0).
    b1, b2 : array_like (3,), optional
        Offsets in radii/s, radii/s, rad/s.

    Notes
    -----
    All six are given together or not at all (an unfitted law).

    Examples
    --------
    >>> law = PiecewiseAffine.published("A")
    >>> law.plane_equation()
    '0.891·xdot0 + 0.763·ydot0 + omega0 = 600'
    >>> law.regime([[1000.0, -800.0, 600.0], [1000.0, -800.0, 0.0]])
    array(['slip', 'roll'], dtype='<U4')
    """

    regimes = ("roll", "slip")

    def __init__(
        self,
        normal: Any = None,
        offset: float | None = None,
        A1: Any = None,
        b1: Any = None,
        A2: Any = None,
        b2: Any = None,
    ) -> None:
        self.normal = normal
        self.offset = offset
        self.A1 = A1
        self.b1 = b1
        self.A2 = A2
        self.b2 = b2
        super().__init__()

    def _validate_parameters(self) -> None:
        given = {k: getattr(self, k) for k in _SHAPES}
        missing = [k for k, v in given.items() if v is None]
        if len(missing) == len(_SHAPES):
            return
        if missing:
            raise ParameterError(f"PiecewiseAffine needs all of {list(_SHAPES)}; missing {missing}")
        for key, shape in _SHAPES.items():
            try:
                arr = np.array(given[key], dtype=np.float64)
            except (TypeError, ValueError):
                raise ParameterError(f"PiecewiseAffine parameter {key!r} must be numeric") from None
            if arr.shape != shape:
                raise ParameterError(f"PiecewiseAffine parameter {key!r} must have shape {shape}; got {arr.shape}")
            if not np.isfinite(arr).all():
                raise ParameterError(f"PiecewiseAffine parameter {key!r} must be finite; got {arr}")
            if key == "offset":
                object.__setattr__(self, key, float(arr))
                continue
            arr.setflags(write=False)
            object.__setattr__(self, key, arr)
        if not np.any(self.normal):
            raise ParameterError("PiecewiseAffine plane normal must not be zero")

    @property
    def parameters(self) -> dict[str, float | None]:
        """All 28 numbers as a flat name -> float mapping.

        Names: ``normal_xdot``, ``normal_ydot``, ``normal_omega``, ``offset``,
        ``A1_ij`` / ``A2_ij`` (row i = lift-off component, column j = landing
        component, 1-based) and ``b1_i`` / ``b2_i``.
        """
        names = self.parameter_names()
        if self.normal is None:
            return dict.fromkeys(names)
        return dict(zip(names, self._flat(), strict=True))

    @staticmethod
    def parameter_names() -> list[str]:
        """Names of :attr:`parameters`, in order."""
        names = [f"normal_{c}" for c in COMPONENTS] + ["offset"]
        for side in ("1", "2"):
            names += [f"A{side}_{i}{j}" for i in range(1, 4) for j in range(1, 4)]
            names += [f"b{side}_{i}" for i in range(1, 4)]
        return names

    def _flat(self) -> np.ndarray:
        return np.concatenate(
            [self.normal, [self.offset], self.A1.ravel(), self.b1, self.A2.ravel(), self.b2]
        )

    def _theta(self) -> np.ndarray:
        if self.normal is None:
            from bouncelab.errors import NotFittedError

            raise NotFittedError(
                "PiecewiseAffine has no plane or maps; pass them to the constructor "
                "or fit the law with bouncelab.fit(PiecewiseAffine(), data)"
            )
        return self._flat()

    def _predict(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        out = np.empty_like(p)
        kernels().affine_predict(p, self.normal, self.offset, self.A1, self.b1, self.A2, self.b2, out)
        return out

    def _regime(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        return (p @ self.normal >= self.offset).astype(np.int8)

    def printed_plane(self) -> tuple[float, float, float]:
        """The plane as the paper prints it, ``(a, b, c)`` in ``a xdot0 + b ydot0 + omega0 = c``.

        Raises ParameterError if the plane is parallel to the omega axis (no such form).
        """
        self._theta()
        if self.normal[2] == 0:
            raise ParameterError("the plane is parallel to the omega axis; it has no 'omega0 = ...' form")
        a, b, _ = self.normal / self.normal[2]
        c = self.offset / self.normal[2]
        return float(a), float(b), float(c)

    def plane_equation(self, digits: int = 3) -> str:
        """The plane as text, e.g. ``'0.891·xdot0 + 0.763·ydot0 + omega0 = 600'``."""
        a, b, c = self.printed_plane()
        side = "" if self.normal[2] > 0 else " (sides swapped: omega coefficient was negative)"
        return f"{a:.{digits}g}·xdot0 + {b:.{digits}g}·ydot0 + omega0 = {c:.{digits}g}{side}"

    @classmethod
    def published(cls, campaign: str) -> PiecewiseAffine:
        """Eq. (disjointA) for campaign "A" or eq. (disjointB) for "B"."""
        return cls(**_published.piecewise_parameters(campaign))
