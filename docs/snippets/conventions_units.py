from bouncelab import units

print(units.BALL_RADIUS_M, units.COMPONENTS, units.COMPONENT_UNITS)

# One state [xdot, ydot, omega] in physical units -> scaled units and back.
state = [20.0, -15.0, 3000.0]                                  # m/s, m/s, rpm
scaled = units.to_scaled(state, velocity="m/s", spin="rpm")
print(scaled.round(2))                                         # radii/s, radii/s, rad/s
print(units.from_scaled(scaled, velocity="mph", spin="rev/s").round(3))

# Single quantities, and another ball radius.
print(units.velocity_to_scaled(1.0, "m/s"), units.spin_to_scaled(60.0, "rpm"))
print(units.velocity_to_scaled(1.0, "m/s", radius_m=0.0200))

# Speed, angle of incidence below the horizontal, and backspin -> a landing state.
landing = units.landing_from_speed_angle_spin(93.6, 37.3, 34.9, speed_unit="ft/s", spin_unit="rev/s")
print(landing.round(1))
print({k: round(float(v), 2) for k, v in units.speed_angle_spin(landing, speed_unit="ft/s", spin_unit="rev/s").items()})

# The contact point P: v_P = xdot + omega (radii/s).
print(units.tangential_velocity(landing).round(1))
