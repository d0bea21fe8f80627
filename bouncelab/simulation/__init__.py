"""Simulated campaigns: a launcher, a turf that varies from spot to spot and a high-speed camera.

The paper's measured bounces cannot be had here. This package produces
campaigns the way the real ones were produced (see ``docs/simulation.md``):

* :class:`LauncherDesign` (:mod:`~bouncelab.simulation.launcher`): the
  paper's discrete dial settings spanning Table 1, repeats, lost bounces and
  per-repeat scatter of the landing state;
* :class:`Turf` (:mod:`~bouncelab.simulation.turf`): any bounce law with
  spot-to-spot scatter of its parameters (:class:`LogNormal`,
  :class:`Normal`) and a :class:`ContactDuration`;
* :class:`Camera` (:mod:`~bouncelab.simulation.camera`): frames of the
  ball's centre and rotation with tracking noise, the turf hiding the ball
  during contact;
* :func:`measure_frames` (:mod:`~bouncelab.simulation.measure`): the
  paper's estimators (:mod:`bouncelab.analysis.measurement`) over many
  tracks at once;
* :func:`simulate_campaign` (:mod:`~bouncelab.simulation.campaign`): all of
  it, returning a campaign Dataset that says it is simulated;
* :mod:`~bouncelab.simulation.calibration`: the objective that compares a
  simulated campaign with the paper's Tables 2 and 3.
"""

from bouncelab.simulation.camera import Camera, Frames
from bouncelab.simulation.campaign import SIMULATOR_VERSION, simulate_campaign
from bouncelab.simulation.launcher import LauncherDesign, LaunchPlan
from bouncelab.simulation.measure import FrameMeasurement, measure_frames
from bouncelab.simulation.turf import ContactDuration, LogNormal, Normal, Turf

__all__ = [
    "SIMULATOR_VERSION",
    "Camera",
    "ContactDuration",
    "FrameMeasurement",
    "Frames",
    "LaunchPlan",
    "LauncherDesign",
    "LogNormal",
    "Normal",
    "Turf",
    "measure_frames",
    "simulate_campaign",
]
