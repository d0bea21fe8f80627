"""Integer ids of the compiled laws and their regime codes (kept apart so importing a law
does not import numba; the kernels load on first use)."""

RIGID = 0
PENNER_FIXED = 1
PENNER_VARYING = 2
TANGENTIAL = 3

# Regime codes of the rigid family (lab frame: "forward" is +x).
SLIP_FORWARD = 0
ROLL = 1
SLIP_BACKWARD = 2
