"""Video tracking on rendered clips: accuracy, interval coverage and speed (issue 12, item 4).

Renders clips of 512 x 256 pixels at 5000 fps, noise 5 grey levels, ball radius 20 px (40 px
across), random landings and lift-offs from ``Rigid.published("A")``, tracks them with
:func:`bouncelab.tracking.track_clip` and measures them with :func:`bouncelab.tracking.measure_clip`
(both velocity methods), and reports against the truth:

* velocity error as a fraction of the speed (target: within 0.5 %),
* spin error against 2 % of |omega| + 5 rad/s (target: within it),
* coverage of the 95 % intervals, by component and method,
* frames tracked per second (target: 300 on this 2-core machine), side by side with rendering.

With scikit-image installed it also compares the rough circle detector, OpenCV's ``HoughCircles``
against scikit-image's ``hough_circle``, on the same frames (time per frame, centre error).

Run::

    python benchmarks/bench_tracking.py --clips 40          # about 3 minutes
    python benchmarks/bench_tracking.py --quick             # 4 clips, the detectors on 12 frames (CI)
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np


def _clips(n: int, seed: int):
    from bouncelab import Rigid
    from bouncelab.tracking import render_clip

    rng = np.random.default_rng(seed)
    law = Rigid.published("A")
    landings = np.column_stack([rng.uniform(800, 1300, n), -rng.uniform(600, 900, n), rng.uniform(-200, 600, n)])
    liftoffs = law.predict(landings)
    for k in range(n):
        t = time.perf_counter()
        clip = render_clip(landings[k], liftoffs[k], size=(256, 512), radius_px=20.0, noise=5.0, seed=seed + k)
        yield clip, time.perf_counter() - t


def _compare_circle_detectors(frames_list, truths, n_frames: int = 60) -> dict:
    """Rough circle detection: OpenCV HoughCircles (gradient, ALT) against scikit-image hough_circle."""
    import cv2

    from bouncelab.tracking import estimate_background
    from bouncelab.tracking.detect import _hough

    out: dict = {}
    samples = []
    for frames, truth in zip(frames_list, truths, strict=True):
        bg = estimate_background(frames)
        flight = np.flatnonzero(truth.phase.values != "contact")
        for k in flight[:: max(len(flight) // 6, 1)]:
            samples.append((frames[k], bg, truth.col.values[k], truth.row.values[k]))
    samples = samples[:n_frames]
    t = time.perf_counter()
    err = []
    for img, bg, c, r in samples:
        found = _hough(img.astype(np.float32) - bg.image, 10, 40, bg.contrast)
        err.append(np.inf if found is None else np.hypot(found[0] - c, found[1] - r))
    out["opencv_ms_per_frame"] = 1e3 * (time.perf_counter() - t) / len(samples)
    out["opencv_centre_err_px_median"] = float(np.median(err))
    out["opencv_missed"] = int(np.isinf(err).sum())
    try:
        from skimage.feature import canny
        from skimage.transform import hough_circle, hough_circle_peaks
    except ImportError:
        out["skimage"] = "not installed"
        return out
    radii = np.arange(16, 25)
    t = time.perf_counter()
    err = []
    for img, bg, c, r in samples:
        fg = np.clip(img.astype(np.float32) - bg.image, 0, None)
        edges = canny(fg, sigma=1.5, low_threshold=10, high_threshold=30)
        acc = hough_circle(edges, radii)
        _, cx, cy, _ = hough_circle_peaks(acc, radii, total_num_peaks=1)
        err.append(np.hypot(cx[0] - c, cy[0] - r) if len(cx) else np.inf)
    out["skimage_ms_per_frame"] = 1e3 * (time.perf_counter() - t) / len(samples)
    out["skimage_centre_err_px_median"] = float(np.median(err))
    out["skimage_missed"] = int(np.isinf(err).sum())
    out["cv2_version"] = cv2.__version__
    import skimage

    out["skimage_version"] = skimage.__version__
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--clips", type=int, default=None, help="clips rendered (default 40; 4 with --quick)")
    ap.add_argument("--seed", type=int, default=100)
    ap.add_argument("--quick", action="store_true",
                    help="4 clips and the circle detectors compared on 12 frames: checks it runs (CI)")
    ap.add_argument("--json", metavar="FILE", help="also write the figures as JSON")
    args = ap.parse_args()
    args.clips = args.clips or (4 if args.quick else 40)

    from bouncelab.tracking import measure_clip, track_clip

    rows = []
    frames_kept, truths = [], []
    t_render = t_track = 0.0
    n_frames = 0
    failures = []
    for k, (clip, tr_time) in enumerate(_clips(args.clips, args.seed)):
        t_render += tr_time
        t = time.perf_counter()
        track = track_clip(clip.frames, fps=clip.fps, name=f"clip{k}")
        t_track += time.perf_counter() - t
        n_frames += clip.frames.shape[0]
        if k < 6:
            frames_kept.append(clip.frames)
            truths.append(clip.truth)
        for method, interval in (("differences", "prediction"), ("positions", "confidence")):
            try:
                m = measure_clip(track, method=method, interval=interval)
            except Exception as exc:  # a benchmark reports failures, it does not stop
                failures.append(f"clip{k} {method}: {exc}")
                continue
            for side, truth in (("landing", clip.landing), ("liftoff", clip.liftoff)):
                est, half = m[side].values, m[f"{side}_pi"].values
                rows.append({
                    "method": method, "side": side,
                    "v_err_frac": float(np.hypot(*(est[:2] - truth[:2])) / np.hypot(*truth[:2])),
                    "w_err": float(abs(est[2] - truth[2])), "w_tol": float(0.02 * abs(truth[2]) + 5.0),
                    "covered": (np.abs(est - truth) <= half).tolist(),
                    "half": half.tolist(),
                })
    res: dict = {"clips": args.clips, "frames": n_frames,
                 "track_fps": n_frames / t_track, "render_fps": n_frames / t_render, "failures": failures}
    print(f"{args.clips} clips, {n_frames} frames of 512 x 256 px, noise 5, ball 40 px across, 5000 fps")
    print(f"tracking: {res['track_fps']:.0f} frames/s (rendering: {res['render_fps']:.0f} frames/s; "
          f"target 300 frames/s)")
    for method in ("differences", "positions"):
        sel = [r for r in rows if r["method"] == method]
        if not sel:
            continue
        v = np.array([r["v_err_frac"] for r in sel])
        w_ok = np.array([r["w_err"] <= r["w_tol"] for r in sel])
        cov = np.array([r["covered"] for r in sel]).mean(axis=0)
        half = np.array([r["half"] for r in sel]).mean(axis=0)
        res[method] = {"v_err_frac_median": float(np.median(v)), "v_err_frac_max": float(v.max()),
                       "v_within_0.5pct": float((v <= 0.005).mean()), "spin_within_tol": float(w_ok.mean()),
                       "spin_err_median": float(np.median([r["w_err"] for r in sel])),
                       "coverage_xdot_ydot_omega": cov.tolist(), "mean_half_width": half.tolist()}
        kind = "95 % PI (paper)" if method == "differences" else "95 % CI (positions)"
        print(f"{method:>11} [{kind}]: |v error|/speed median {100 * np.median(v):.3f} %, max {100 * v.max():.3f} %, "
              f"within 0.5 %: {100 * (v <= 0.005).mean():.0f} %; spin within 2 %|w| + 5 rad/s: "
              f"{100 * w_ok.mean():.0f} % (median error {np.median([r['w_err'] for r in sel]):.2f} rad/s); "
              f"coverage xdot/ydot/omega {', '.join(f'{100 * c:.0f} %' for c in cov)} "
              f"(mean half-widths {', '.join(f'{h:.1f}' for h in half)})")
    if failures:
        print(f"{len(failures)} measurement(s) failed: " + "; ".join(failures[:5]))
    cmp_ = _compare_circle_detectors(frames_kept, truths, n_frames=12 if args.quick else 60)
    res["circle_detectors"] = cmp_
    print("rough circle detection on the same frames:")
    print(f"  OpenCV HoughCircles: {cmp_['opencv_ms_per_frame']:.2f} ms/frame, median centre error "
          f"{cmp_['opencv_centre_err_px_median']:.2f} px, missed {cmp_['opencv_missed']}")
    if "skimage_ms_per_frame" in cmp_:
        print(f"  scikit-image hough_circle: {cmp_['skimage_ms_per_frame']:.2f} ms/frame, median centre error "
              f"{cmp_['skimage_centre_err_px_median']:.2f} px, missed {cmp_['skimage_missed']}; "
              f"ratio {cmp_['skimage_ms_per_frame'] / cmp_['opencv_ms_per_frame']:.0f}x slower")
    else:
        print("  scikit-image: not installed (pip install scikit-image to compare)")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=2)


if __name__ == "__main__":
    main()
