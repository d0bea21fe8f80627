import numpy as np

import bouncelab as bl


def energy(state, mass_kg=0.0459, radius_m=bl.units.BALL_RADIUS_M, k2=0.4):
    """Kinetic energy (J) of scaled states: (m R^2 / 2) (xdot^2 + ydot^2 + k2 omega^2), I = k2 m R^2."""
    s = np.asarray(state, dtype=float)
    return 0.5 * mass_kg * radius_m**2 * (s[..., 0] ** 2 + s[..., 1] ** 2 + k2 * s[..., 2] ** 2)


landing = bl.units.landing_from_speed_angle_spin(93.6, 37.3, 34.9, speed_unit="ft/s", spin_unit="rev/s")
print(f"landing: {landing.round(1)}, kinetic energy {energy(landing):.2f} J")
for law in (bl.Rigid.published("A"), bl.PennerFixed.published("A"), bl.PiecewiseAffine.published("A")):
    out = law.predict(landing)
    print(f"{type(law).__name__:<16} lift-off {out.round(1)}: {energy(out):.2f} J "
          f"({energy(out) / energy(landing):.0%} of the landing energy)")
