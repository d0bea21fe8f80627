"""Analyses of bounce data: measurement error from tracked video frames, and more.

Submodules
----------
trajectories
    Synthetic high-speed-camera tracks of a bounce (:func:`simulate_tracked_bounce`).
measurement
    The paper's extraction of landing and lift-off states with their 95 %
    intervals from tracked frames (:func:`measure_bounce`).
"""
