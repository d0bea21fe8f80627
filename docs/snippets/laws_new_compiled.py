"""A new compiled law with array parameters and its own fitting method: one affine map for all bounces."""

import numpy as np
from numba import njit

import bouncelab as bl
from bouncelab.laws import CompiledLaw, FitOutcome, Parameter, fit_method


@njit
def affine_kernel(xd, yd, w, theta):
    """theta = [A (3x3, row-major), b (3)]: pF = A p0 + b, one regime."""
    return (theta[0] * xd + theta[1] * yd + theta[2] * w + theta[9],
            theta[3] * xd + theta[4] * yd + theta[5] * w + theta[10],
            theta[6] * xd + theta[7] * yd + theta[8] * w + theta[11], 0)


class AffineMap(CompiledLaw):
    """pF = A p0 + b: the piecewise law without its plane (a baseline with 12 numbers)."""

    parameter_specs = (
        Parameter("A", (-3.0, 3.0), (-1e6, 1e6), "1", "linear map, rows xdotF ydotF omegaF", shape=(3, 3)),
        Parameter("b", (-1000.0, 1000.0), (-1e12, 1e12), "radius/s, radius/s, rad/s", "offset", shape=(3,)),
    )
    regimes = ("affine",)
    kernel = affine_kernel
    default_fit_method = "lstsq"

    def __init__(self, A=None, b=None):
        self.A = A
        self.b = b
        super().__init__()

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
        value = problem.objective(law)(law._theta())
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
