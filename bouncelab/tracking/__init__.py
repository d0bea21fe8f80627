"""From high-speed video to bounce states: the paper's data extraction (section "Data extraction").

The pipeline:

1. :func:`open_clip`: a camera file (Phantom ``.cine``, Photron ``.mraw``; with its frame
   times and full bit depth), a video file, a folder of images, a ``.npy``/``.npz`` file or an
   array, read frame by frame within a memory budget (:func:`read_frames` reads it whole);
2. :func:`track_clip`: the ball found in each frame (Hough circle, refined to a
   sub-pixel centre and radius), its lowest visible point, and its rotation
   between consecutive frames from matched features (:func:`frame_rotation`),
   in scaled units (radii, seconds, rad/s anticlockwise with y up);
3. :func:`measure_clip`: touch-down and lift-off from the lowest visible point
   and the landing and lift-off states with the paper's intervals
   (:func:`bouncelab.analysis.measurement.measure_bounce`);
4. :func:`measure_clips`: many clips to a campaign Dataset, failures reported.

:func:`render_clip` renders synthetic clips with known truth for tests and benchmarks;
:func:`write_cine` and :func:`write_mraw` write frames as camera files.
Requires the ``video`` extra (OpenCV; PyAV for any video FFmpeg reads).
"""

from bouncelab.tracking.camera import CameraFileError
from bouncelab.tracking.campaign import (
    ClipFailure,
    ClipSettings,
    TrackedCampaign,
    clip_settings,
    measure_clip,
    measure_clips,
)
from bouncelab.tracking.cine import read_cine, write_cine
from bouncelab.tracking.detect import Background, Circle, estimate_background, find_ball
from bouncelab.tracking.frames import Clip, open_clip, read_frames
from bouncelab.tracking.photron import read_mraw, write_mraw
from bouncelab.tracking.render import RenderedClip, render_clip
from bouncelab.tracking.rotation import Rotation, frame_rotation
from bouncelab.tracking.tracker import FPS_RANGE, FrameRateError, track_clip

__all__ = [
    "FPS_RANGE",
    "Background",
    "CameraFileError",
    "Circle",
    "Clip",
    "ClipFailure",
    "ClipSettings",
    "FrameRateError",
    "RenderedClip",
    "Rotation",
    "TrackedCampaign",
    "clip_settings",
    "estimate_background",
    "find_ball",
    "frame_rotation",
    "measure_clip",
    "measure_clips",
    "open_clip",
    "read_cine",
    "read_frames",
    "read_mraw",
    "render_clip",
    "track_clip",
    "write_cine",
    "write_mraw",
]
