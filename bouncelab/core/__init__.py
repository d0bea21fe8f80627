"""The ground floor: conventions, units, validation, plausibility, the paper's published values, errors.

Every other layer of bouncelab builds on these modules, and they build on nothing of bouncelab's
above them: importing them imports neither pandas nor xarray nor the file loader (tested).

=========================  ======================================================================
:mod:`~.core.units`        scaled units and conversions (ball radii, rad/s; y up; omega > 0 backspin)
:mod:`~.core.validation`   shapes and values of landing and lift-off states
:mod:`~.core.plausibility` what a golf bounce can measure: the unit guard's ranges
:mod:`~.core.published`    the reference paper's tables and laws
:mod:`~.core.slip_roll`    the paper's slip/roll classification of measured bounces
:mod:`~.core.errors`       the exceptions and warnings bouncelab raises on purpose
:mod:`~.core.files`        reading files with checks (a regular file, of a sane size)
:mod:`~.core.atomic`       writing files all at once or not at all
=========================  ======================================================================
"""

__all__ = ["__version__"]

#: bouncelab's version (also in pyproject.toml), written into every law, posterior and report it saves.
__version__ = "0.1.0"
