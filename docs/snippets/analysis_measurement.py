import numpy as np

from bouncelab.analysis import detect_contact, measure_bounce, simulate_tracked_bounce

# A synthetic high-speed-camera track of one bounce (5000 fps, 40 frames either side).
track = simulate_tracked_bounce([1063.0, -810.0, 219.0], [700.0, 280.0, -550.0], seed=0)
print(track.sizes["frame"], "frames;", list(track.data_vars))

contact = detect_contact(track["t"].values, track["lowest"].values)
print(contact)
print("true first contact frame:", int(np.argmax(track["phase"].values == "contact")))

for kwargs in ({}, {"method": "positions", "interval": "confidence"}):
    m = measure_bounce(track, contact=contact, **kwargs)
    print(kwargs or "the paper's method (differences, prediction interval)")
    for state in ("landing", "liftoff"):
        truth = track.attrs[f"true_{state}"]
        print(f"    {state:<8} estimate {m[state].values.round(1)} +- {m[state + '_pi'].values.round(1)}"
              f"  truth {truth.round(1)}")
