"""Fig. 3 of the paper: the landing conditions in 3-D, split by slip/roll, with the separating plane."""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.core import published
from bouncelab.core.errors import DataError
from bouncelab.core.slip_roll import classify_slip_roll
from bouncelab.core.units import landing_from_speed_angle_spin
from bouncelab.laws.base import BounceModel
from bouncelab.laws.piecewise import PiecewiseAffine
from bouncelab.laws.plane_fitting import PlaneFit
from bouncelab.plots import _common as c

__all__ = ["driver_landing", "plane_polygon", "plot_landing_space"]


def driver_landing() -> np.ndarray:
    """The paper's typical driver landing (93.6 ft/s, 37.3 deg, 34.9 rev/s backspin) in scaled units."""
    d = published.DRIVER_LANDING
    return landing_from_speed_angle_spin(
        d["speed"], d["angle_deg"], d["spin"], speed_unit=d["speed_unit"], spin_unit=d["spin_unit"]
    )


def plot_landing_space(
    data: Any,
    law: Any = None,
    support: Any = None,
    *,
    ax: Any = None,
    title: str | None = None,
    elev: float | None = None,
    azim: float | None = None,
    driver: bool = True,
    units: Any = None,
):
    """Fig. 3: landing conditions ``(xdot0, ydot0, omega0)`` coloured by measured slip/roll class.

    Parameters
    ----------
    data
        A campaign Dataset (or a ``(landing, liftoff)`` pair).
    law
        Optional fitted :class:`~bouncelab.PiecewiseAffine` (or a fit result holding
        one in ``.model``, or the :class:`~bouncelab.laws.plane_fitting.PlaneFit` of
        :func:`~bouncelab.laws.plane_fitting.fit_svm`): its separating plane is drawn as a translucent surface
        clipped to the box spanned by the data.
    support
        Optional support vectors to circle: indices of bounces, a boolean mask, or
        the object returned by ``bouncelab.laws.plane_fitting.fit_svm`` (its
        ``.svm_support``). When ``law`` is such an object its support vectors are
        circled too.
    ax
        A 3-D axes to draw in (``fig.add_subplot(projection="3d")``); a new figure
        otherwise.
    title
        Figure title; default names the campaign.
    elev, azim
        Viewing angles of the 3-D axes, in degrees. By default a view near matplotlib's
        (18, -60) is chosen from which the plane is seen obliquely, never edge-on.
    driver
        Mark the paper's typical driver landing with a black asterisk.
    units
        Units of the axes (see :func:`bouncelab.plots.figure_units`); default scaled. The
        plane and its equation are drawn in the same units.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    TypeError
        ``law`` is not a piecewise-affine law (only it has a plane).
    NotFittedError
        ``law`` has no parameters yet.
    DataError
        Bad data or support indices.
    """
    p0, pf, attrs = c.campaign_data(data)
    fu = c.figure_units(units)
    if support is None and hasattr(law, "svm_support"):
        support = law.svm_support
    model = _plane_law(law)
    sv = _support_mask(support, len(p0))
    own = ax is None
    fig, ax = c.single_axes(ax, figsize=(10.0, 7.0), projection="3d")
    from matplotlib import patheffects
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    # Legend proxies: opaque, equal-sized markers whatever the scatter's alpha and sizes.
    handles = []
    # mplot3d orders whole collections by mean depth, which is not true occlusion; instead the
    # translucent plane is drawn first and every marker on top of it, so no class is hidden.
    ax.computed_zorder = False
    classes = classify_slip_roll(p0, pf)
    alpha = c.scatter_alpha(len(p0))
    p0 = fu.convert(p0)  # from here on everything drawn is in the figure's units
    scale = fu.factors
    for name, style in c.CLASS_STYLE.items():
        m = classes == name
        label = f"{style['label']} ({int(m.sum())})"
        ax.scatter(
            p0[m, 0], p0[m, 1], p0[m, 2], marker=style["marker"], color=style["color"], s=16, alpha=alpha,
            depthshade=False, label=label, gid=f"class-{name}", zorder=2,
        )
        handles.append(Line2D([], [], marker=style["marker"], color=style["color"], linestyle="none", label=label))
    lo, hi = _data_box(p0)
    if model is not None:
        # normal . p = offset in scaled units is (normal / scale) . (scale p) = offset in the figure's.
        shown_normal = np.asarray(model.normal, dtype=float) / scale
        poly = plane_polygon(shown_normal, model.offset, lo, hi)
        eq = _plane_mathtext(model, scale)
        if poly is None:
            handles.append(Patch(facecolor="none", edgecolor="none", label=f"plane {eq}: outside the data box"))
        else:
            from mpl_toolkits.mplot3d.art3d import Poly3DCollection

            style = {"facecolor": "0.45", "edgecolor": "0.1", "alpha": 0.22}
            surf = Poly3DCollection([poly], linewidth=1.2, gid="separating-plane", zorder=1, **style)
            ax.add_collection3d(surf)
            handles.append(Patch(label=f"separating plane\n{eq}", **style))
    if sv is not None:
        label = f"support vectors ({int(sv.sum())})"
        ax.scatter(
            p0[sv, 0], p0[sv, 1], p0[sv, 2], marker="o", s=70, facecolors="none", edgecolors="black",
            linewidths=0.9, depthshade=False, label=label, gid="support-vectors", zorder=3,
        )
        handles.append(Line2D([], [], marker="o", markersize=9, markerfacecolor="none", markeredgecolor="black",
                              linestyle="none", label=label))
    if driver:
        d = fu.convert(driver_landing())
        ax.scatter(
            [d[0]], [d[1]], [d[2]], marker=(6, 2, 0), s=260, color="black", linewidths=2.2, depthshade=False,
            label="typical driver landing", gid="driver-landing", zorder=4,
            path_effects=[patheffects.withStroke(linewidth=4.5, foreground="white")],
        )
        handles.append(Line2D([], [], marker=(6, 2, 0), markersize=11, markeredgewidth=1.8, color="black",
                              linestyle="none", label="typical driver landing\n(93.6 ft/s, 37.3°, 34.9 rev/s)"))
        lo, hi = np.minimum(lo, d), np.maximum(hi, d)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_xlabel(c.label("xdot", fu=fu), labelpad=8)
    ax.set_ylabel(c.label("ydot", fu=fu), labelpad=8)
    ax.set_zlabel(c.label("omega", fu=fu), labelpad=8)
    if elev is None or azim is None:
        e, a = _oblique_view(shown_normal, hi - lo, ax.get_box_aspect()) if model is not None else (18.0, -60.0)
        elev, azim = (e if elev is None else elev), (a if azim is None else azim)
    ax.view_init(elev=elev, azim=azim)
    ax.tick_params(labelsize="small")
    if own:
        fig.legend(handles=handles, loc="outside right upper", fontsize="small", borderaxespad=1.0)
    else:
        ax.legend(handles=handles, loc="upper left", fontsize="small", framealpha=0.85)
    if title is None:
        title = f"{c.campaign_name(attrs)}: landing conditions by measured slip/roll class"
    return c.finish(fig, attrs, title, ax=None if own else ax)


def _plane_law(law: Any) -> PiecewiseAffine | None:
    if law is None:
        return None
    if isinstance(law, PlaneFit):  # the paper's SVM procedure: its plane and maps
        return PiecewiseAffine(**law.parameters)
    model = getattr(law, "model", law)
    if not isinstance(model, PiecewiseAffine):
        kind = type(model).__name__ if isinstance(model, BounceModel) else type(law).__name__
        raise TypeError(
            f"the separating plane needs a PiecewiseAffine law (or a fit result of one); got {kind}. "
            "Fit one with bouncelab.fit(bouncelab.PiecewiseAffine, data)"
        )
    model._fitted_values()  # NotFittedError with the law's own message when it has no plane yet
    return model


def _support_mask(support: Any, n: int) -> np.ndarray | None:
    if support is None:
        return None
    if hasattr(support, "svm_support"):
        support = support.svm_support
        if support is None:
            return None
    s = np.asarray(support)
    if s.dtype == bool:
        if s.shape != (n,):
            raise DataError(f"a boolean support mask needs one entry per bounce ({n}); got shape {s.shape}",
                            option="support")
        return s
    if s.ndim != 1 or (s.size and s.dtype.kind not in "iu"):
        raise DataError("support must be bounce indices (integers) or a boolean mask", option="support")
    if s.size and (s.min() < -n or s.max() >= n):
        raise DataError(f"support indices must lie in [0, {n}); got {s.min()}..{s.max()}", option="support")
    mask = np.zeros(n, dtype=bool)
    mask[s.astype(np.int64)] = True
    return mask


def _oblique_view(normal: np.ndarray, span: np.ndarray, box_aspect: Any) -> tuple[float, float]:
    """(elev, azim) nearest the default (18, -60) that sees the plane obliquely.

    Edge-on the plane would shrink to a line; face-on the two sides would overlap in the
    picture. Between about 10 and 27 degrees from edge-on both the plane and the split of
    the points are visible.
    """
    aspect = np.ones(3) if box_aspect is None else np.asarray(box_aspect, dtype=float)
    n = np.asarray(normal, dtype=float) * span / aspect  # the normal in displayed coordinates
    n /= np.linalg.norm(n)
    best, best_score = (18.0, -60.0), np.inf
    for elev in np.arange(10.0, 36.0, 4.0):
        for azim in np.arange(-150.0, -14.0, 5.0):
            e, a = np.deg2rad(elev), np.deg2rad(azim)
            eye = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
            cos = abs(eye @ n)  # sine of the angle from edge-on
            score = 10.0 * (max(0.0, 0.18 - cos) + max(0.0, cos - 0.45))
            score += 0.002 * abs(azim + 60.0) + 0.004 * abs(elev - 18.0)
            if score < best_score:
                best, best_score = (float(elev), float(azim)), score
    return best


def _data_box(p0: np.ndarray, pad: float = 0.03) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = p0.min(axis=0), p0.max(axis=0)
    span = np.where(hi > lo, hi - lo, 1.0)
    return lo - pad * span, hi + pad * span


def plane_polygon(normal: Any, offset: float, lo: Any, hi: Any) -> np.ndarray | None:
    """Corners (k, 3) of the plane ``normal . p = offset`` clipped to the box ``[lo, hi]``, in order.

    ``None`` when the plane misses the box (or only touches it at an edge or corner).
    """
    n = np.asarray(normal, dtype=float)
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    span = hi - lo
    # Work in the unit cube, where the three axes are comparable; the polygon maps back affinely.
    nu = n * span
    cu = float(offset) - float(n @ lo)
    pts = []
    for k in range(3):
        i, j = [a for a in range(3) if a != k]
        for a in (0.0, 1.0):
            for b in (0.0, 1.0):
                if nu[k] == 0:
                    continue
                t = (cu - nu[i] * a - nu[j] * b) / nu[k]
                if -1e-12 <= t <= 1 + 1e-12:
                    q = np.empty(3)
                    q[i], q[j], q[k] = a, b, min(max(t, 0.0), 1.0)
                    pts.append(q)
    if not pts:
        return None
    pts = np.unique(np.round(np.array(pts), 12), axis=0)
    if len(pts) < 3:
        return None
    centre = pts.mean(axis=0)
    unit = nu / np.linalg.norm(nu)
    e1 = pts[0] - centre
    e1 -= (e1 @ unit) * unit
    if np.linalg.norm(e1) == 0:
        return None
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(unit, e1)
    d = pts - centre
    order = np.argsort(np.arctan2(d @ e2, d @ e1))
    return lo + pts[order] * span


def _plane_mathtext(model: PiecewiseAffine, scale: np.ndarray | None = None) -> str:
    """``$1.07\\dot{x}_0 + 0.887\\dot{y}_0 + \\omega_0 = 596$`` (the paper's printed form when possible).

    With ``scale`` (the figure's unit factors) the equation is of the plane in those units.
    """
    scale = np.ones(3) if scale is None else np.asarray(scale, dtype=float)
    if model.has_paper_form():
        a, b, off = model.printed_plane()  # a xdot + b ydot + omega = off, scaled units
        coefs = tuple(np.array([a, b, 1.0]) / scale * scale[2])
        off = off * scale[2]
    else:  # (nearly) parallel to the omega axis: the unit normal's form, which always exists
        u, d = model.plane_unit_form()
        coefs, off = tuple(u / scale), d
    terms = []
    for coef, sym in zip(coefs, (r"\dot{x}_0", r"\dot{y}_0", r"\omega_0"), strict=True):
        if coef == 0:
            continue
        mag = f"{abs(coef):.3g}"
        mag = "" if mag == "1" else mag + "\\,"
        sign = "-" if coef < 0 else "+"
        terms.append((sign, f"{mag}{sym}"))
    text = ("-" if terms[0][0] == "-" else "") + terms[0][1]
    text += "".join(f" {s} {t}" for s, t in terms[1:])
    return f"${text} = {off:.3g}$"
