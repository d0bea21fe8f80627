"""The ``bouncelab`` command line: reproduce, fit, predict, info."""
