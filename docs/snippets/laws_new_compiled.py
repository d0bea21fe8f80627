"""A new compiled law with array parameters and its own fitting method: one affine map for all bounces."""

import numpy as np
from numba import njit

import bouncelab as bl
from bouncelab.laws import CompiledLaw, FitOutcome, Parameter, fit_method


@njit
def affine_kernel(xd, yd, w, A, b):
    """pF = A p0 + b, one regime (the parameters by name: A a 3 x 3 array, b of length 3)."""
    return (A[0, 0] * xd + A[0, 1] * yd + A[0, 2] * w + b[0],
            A[1, 0] * xd + A[1, 1] * yd + A[1, 2] * w + b[1],
            A[2, 0] * xd + A[2, 1] * yd + A[2, 2] * w + b[2], 0)


class AffineMap(CompiledLaw):
    """pF = A p0 + b: the piecewise law without its plane (a baseline with 12 numbers)."""

    A = Parameter(bounds=(-3.0, 3.0), physical=(-1e6, 1e6), shape=(3, 3), unit="1",
                  doc="linear map, rows xdotF ydotF omegaF")
    b = Parameter(bounds=(-1000.0, 1000.0), physical=(-1e12, 1e12), shape=(3,), unit="radius/s, radius/s, rad/s",
                  doc="offset")
    regimes = ("affine",)
    kernel = affine_kernel
    default_fit_method = "lstsq"

    @fit_method("lstsq")
    def _fit_lstsq(self, problem, *, weighted: bool = False) -> FitOutcome:
        """Least squares on every lift-off component (weights 1 / ||p0||^2 with weighted=True), with stderr."""
        if problem.fixed:  # a closed form of all twelve numbers: it cannot hold some of them
            raise bl.FitError(f"method 'lstsq' cannot hold {sorted(problem.fixed)}; use method='global'")
        X = np.column_stack([problem.landing, np.ones(problem.n)])
        w = 1 / np.linalg.norm(problem.landing, axis=1) if weighted else np.ones(problem.n)
        if problem.sample_weight is not None:  # the caller's weights (bl.fit(..., sample_weight=...))
            w = w * np.sqrt(problem.sample_weight)
        coef, *_ = np.linalg.lstsq(X * w[:, None], problem.liftoff * w[:, None], rcond=None)
        resid = (problem.liftoff - X @ coef) * w[:, None]
        cov = np.linalg.inv((X * w[:, None]).T @ (X * w[:, None]))  # (X^T X)^-1, one per component
        se = np.sqrt(np.outer(np.diag(cov), (resid**2).sum(axis=0) / (problem.n - 4)))
        law = self.replace(A=coef[:3].T, b=coef[3])
        value = problem.value(law)
        return FitOutcome(model=law, objective_value=value, algorithm="linear least squares",
                          stderr={"A": se[:3].T, "b": se[3]}, notes=["closed form; delta not minimised"])


if __name__ == "__main__":
    ds = bl.load_campaign("B", surrogate="published")
    res = bl.fit(AffineMap, ds)                              # its own method, "lstsq"
    print(res)
    print(res.params)                                        # values with standard errors
    polished = bl.fit(res.model, ds, method="global", maxeval=2000)   # the generic search, from there
    print(f"delta: least squares {res.delta:.4f}, then minimising delta {polished.delta:.4f}")
    print(AffineMap.fit_methods().keys())
