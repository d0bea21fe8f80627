"""Measurement error from tracked frames: the paper's landing and lift-off estimates.

The paper (sections "Data extraction" and "Measurement error") measures each
bounce from a high-speed video in three steps, all implemented here:

1. **Contact detection** (:func:`detect_contact`): touch-down and lift-off are
   the abrupt changes in the velocity of the lowest visible point of the ball.
2. **Velocities** (:func:`estimate_velocity`): finite differences of the tracked
   centre, ``(x_{i+1} - x_i)/dt`` assigned to ``t_{i+1}``, are fitted with a
   straight line ``v(t) = m t + c`` by least squares on each side of the
   bounce, and evaluated at the touch-down (lift-off) time with its 95 %
   prediction interval (PI).
3. **Spin** (:func:`estimate_spin`): the per-frame spin samples on each side
   are taken as normal; the spin is their mean and its PI the 95 % confidence
   interval (CI) of the mean.

:func:`measure_bounce` chains them on one tracked trajectory and returns the
``landing``, ``liftoff``, ``landing_pi`` and ``liftoff_pi`` of a campaign.

Calibration of the intervals
----------------------------
A finite difference ``d_i = (x_{i+1} - x_i)/dt`` shares the position error of
``x_{i+1}`` with ``d_{i+1}``: the errors of consecutive differences have
correlation -1/2, not 0 as ordinary least squares assumes, and the errors of
the fitted line telescope: its true error falls like ``1/n`` with ``n``
differences, while the OLS formulas assume ``1/sqrt(n)``. Measured by
simulation (:func:`interval_coverage` with 2000 synthetic bounces at the
default noise, 5000 fps, 40 frames a side; see its docstring) against the true
velocity at the true touch-down or lift-off instant:

* the paper's PI (``interval="prediction"``) covered the true velocity in all
  2000 bounces. Its mean half-width, 46 radii/s (~5 % of a typical velocity,
  as in the paper), is about 13 times the actual 95 % error of the estimate
  (1.96 x an rms error of 1.8 radii/s). The PI measures the frame-to-frame
  scatter of the differences, not the error of the fitted velocity: it is a
  very conservative measurement error, as the paper suspects ("the true
  error is likely to be significantly smaller");
* the CI of the fitted line at that time (``interval="confidence"``, nominal
  95 %) also covered it in all 2000 bounces, being about 4 times too wide
  (half-width 15 radii/s). With fewer frames it is less conservative: in a
  pure-noise simulation it covers 98 % with 5 frames, 99.6 % with 8, 99.9 %
  with 10 and 100 % from 20;
* fitting the *positions* with a quadratic, ``x(t) = a + b t + c t^2``
  (ordinary least squares on independent position errors,
  ``method="positions"``), gives a calibrated 95 % CI for ``v = b + 2 c t``:
  coverage 94.8-95.2 % by component, half-width 1.8 radii/s. Its estimate is
  also twice as precise as the paper's (rms error 0.90 radii/s against 1.8).
  It is the correlation-aware option: generalised least squares of the
  differences with their true covariance is the same estimator.

The spin CI is calibrated (95 %) when the rotation between each pair of frames
is estimated independently, as by feature matching (the generator's model);
were each frame's absolute orientation measured and differenced, spin errors
would be correlated like the velocities' and the CI conservative.
"""

# The API page lists the members in this order (mkdocs: members_order source): the results, the
# three steps, the whole measurement and its coverage check.
# isort: off
from bouncelab.analysis.measurement.input_checks import FRAME_RATE_RANGE, JITTER_RTOL
from bouncelab.analysis.measurement.results import VelocityEstimate, SpinEstimate, ContactDetection
from bouncelab.analysis.measurement.velocity import estimate_velocity
from bouncelab.analysis.measurement.velocity import IntervalKind as IntervalKind
from bouncelab.analysis.measurement.velocity import VelocityMethod as VelocityMethod
from bouncelab.analysis.measurement.spin import estimate_spin
from bouncelab.analysis.measurement.contact import detect_contact
from bouncelab.analysis.measurement.bounce import measure_bounce
from bouncelab.analysis.measurement.coverage import interval_coverage
# isort: on

__all__ = [
    "FRAME_RATE_RANGE",
    "JITTER_RTOL",
    "ContactDetection",
    "SpinEstimate",
    "VelocityEstimate",
    "detect_contact",
    "estimate_spin",
    "estimate_velocity",
    "interval_coverage",
    "measure_bounce",
]
