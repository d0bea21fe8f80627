from bouncelab import published

print(published.CITATION)
print(published.TABLE1.loc["B"])
print(published.TABLE2)
print(published.TABLE3[["r", "mu", "beta_deg", "k_p", "delta"]])
print(published.DRIVER_LANDING)
