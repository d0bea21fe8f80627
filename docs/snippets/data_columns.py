from pathlib import Path

import bouncelab as bl

Path("bounces.csv").write_text(
    "Test,Vx in,Vy in,Spin in,Vx out,Vy out,Spin out,dVx in,dVy in,dSpin in,dVx out,dVy out,dSpin out\n"
    "3,20.1,-15.2,3000,9.5,5.1,1500,0.4,0.4,90,0.3,0.3,120\n"
    "3,19.8,-15.0,3050,9.7,5.0,1480,0.5,0.4,80,0.3,0.2,110\n"
)
ds = bl.load_campaign("bounces.csv", columns={
    "landing": ["Vx in", "Vy in", "Spin in"],         # xdot0, ydot0, omega0
    "liftoff": ["Vx out", "Vy out", "Spin out"],      # xdotF, ydotF, omegaF
    "setting": "Test",                                 # optional
    "landing_pi": ["dVx in", "dVy in", "dSpin in"],    # optional
    "liftoff_pi": ["dVx out", "dVy out", "dSpin out"],
}, units={"velocity": "m/s", "spin": "rpm"})
print(sorted(ds.data_vars), ds.setting.values, ds.attrs["source_units"])
print(ds.landing_pi.values.round(2))                   # half-widths, converted like the values
