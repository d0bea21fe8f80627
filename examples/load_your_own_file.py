"""Load your own bounce measurements from a CSV file in physical units, then fit laws to them.

What it shows
    * a small CSV file in physical units (velocities in m/s, spins in rpm) with column names
      bouncelab cannot guess, written to a temporary directory;
    * :func:`bouncelab.load_campaign` with ``columns=`` (which file column holds which
      quantity, plus the launcher setting) and ``units=`` (the file's units): the values are
      converted to the paper's scaled units (ball radii per second and rad/s);
    * what the loaded campaign holds, and the error you get without ``units=``;
    * fitting laws to it and reading the result back in physical units.

The "measurements" are made up for the example: 8 launcher settings x 5 repeats whose
lift-offs follow a rigid bounce with r = 0.4 and mu = 0.3 plus 2 % noise, so the fit
should find those values again.

Run it from the repository root (a few seconds; it writes only to a temporary directory)::

    python examples/load_your_own_file.py
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

import bouncelab as bl
from bouncelab.core import units


def write_measurements(path: Path, seed: int = 1) -> None:
    """A CSV of made-up bounces: one row per bounce, m/s and rpm, headers without units."""
    rng = np.random.default_rng(seed)
    speed = np.repeat(rng.uniform(8.0, 35.0, 8), 5) * (1 + 0.02 * rng.standard_normal(40))  # m/s
    angle = np.repeat(rng.uniform(20.0, 70.0, 8), 5) + 0.5 * rng.standard_normal(40)         # deg
    spin = np.repeat(rng.uniform(-2000.0, 8000.0, 8), 5) + 100 * rng.standard_normal(40)     # rpm, backspin > 0
    landing = units.landing_from_speed_angle_spin(speed, angle, spin)                      # scaled
    liftoff = bl.Rigid(r=0.4, mu=0.3).predict(landing)
    liftoff += 0.02 * np.linalg.norm(landing, axis=1, keepdims=True) * rng.standard_normal(liftoff.shape)
    land_si = units.from_scaled(landing, velocity="m/s", spin="rpm")
    lift_si = units.from_scaled(liftoff, velocity="m/s", spin="rpm")
    lines = ["shot;dial;horiz in;vert in;rot in;horiz out;vert out;rot out"]
    for i in range(40):
        values = [*land_si[i], *lift_si[i]]
        lines.append(f"{i + 1};D{i // 5 + 1};" + ";".join(f"{v:.3f}" for v in values))
    path.write_text("\n".join(lines) + "\n")


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "my_bounces.csv"
        write_measurements(path)
        print(f"{path.name}, first lines:")
        print("".join(path.read_text().splitlines(keepends=True)[:3]))

        columns = {
            "landing": ["horiz in", "vert in", "rot in"],      # xdot0, ydot0, omega0
            "liftoff": ["horiz out", "vert out", "rot out"],   # xdotF, ydotF, omegaF
            "setting": "dial",                                  # launcher setting of each bounce
        }
        try:
            bl.load_campaign(path, columns=columns)            # no units: radii/s would be assumed
        except bl.DataError as exc:
            print(f"without units=: DataError: {str(exc).replace(str(path), path.name)}\n")
        ds = bl.load_campaign(path, columns=columns, units={"velocity": "m/s", "spin": "rpm"},
                              surface="my practice green")

    print(f"loaded {ds.sizes['bounce']} bounces, {np.unique(ds.setting).size} settings "
          f"({ds.attrs['source_units']}; data kind {ds.attrs['data_kind']})")
    print("first landing in scaled units [radii/s, radii/s, rad/s]:", ds.landing.values[0].round(1))
    print("and back in m/s and rpm:", units.from_scaled(ds.landing.values[0], velocity="m/s", spin="rpm").round(3))

    res = bl.fit(bl.Rigid, ds)
    print(f"\n{res.model!r}: delta {res.delta:.2%} (made with r = 0.4, mu = 0.3)")
    cv = bl.cross_validate(bl.PennerFixed, ds, k=4)
    print(cv)

    landing = units.landing_from_speed_angle_spin(20.0, 45.0, 3000.0)       # 20 m/s, 45 deg, 3000 rpm
    out = units.speed_angle_spin(res.model.predict(landing), speed_unit="m/s", spin_unit="rpm")
    print(f"20 m/s at 45 deg with 3000 rpm of backspin lifts off at {float(out['speed']):.2f} m/s, "
          f"{-float(out['angle_deg']):.1f} deg above the horizontal, with {float(out['spin']):.0f} rpm")


if __name__ == "__main__":
    main()
