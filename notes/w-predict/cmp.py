import sys, numpy as np
a, b = np.load(sys.argv[1]), np.load(sys.argv[2])
assert set(a.files) == set(b.files), set(a.files) ^ set(b.files)
bad = [k for k in a.files if not (a[k].shape == b[k].shape and a[k].tobytes() == b[k].tobytes())]
print("identical" if not bad else f"DIFFER: {bad}", len(a.files))
