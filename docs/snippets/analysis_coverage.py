from bouncelab.analysis import interval_coverage

r = interval_coverage(300, seed=0)       # 300 simulated bounces (the docstring's table used 2000)
print(r.coverage.stack(col=("state", "component")).to_pandas().round(3))
print(r.mean_half_width.stack(col=("state", "component")).to_pandas().round(1))
print(r.rms_error.stack(col=("state", "component")).to_pandas().round(2))
