import sys, warnings
sys.path.insert(0, sys.argv[1])
import bouncelab as bl
assert bl.__file__.startswith(sys.argv[1])
warnings.simplefilter("ignore")
ds = bl.load_campaign("/tmp/bouncelab_load_bench.csv")
res = bl.fit(bl.PiecewiseAffine, bl.load_campaign("B"), seed=0) if len(sys.argv) > 2 else None
