import matplotlib

matplotlib.use("Agg")

import bouncelab as bl
from bouncelab.analysis.repeats import repeatability
from bouncelab.laws.plane_fitting import fit_svm
from bouncelab.plots import plot_landing_space, plot_repeatability, plot_tangential, save_figure

a, b = bl.load_campaign("A", surrogate="published"), bl.load_campaign("B", surrogate="published")
save_figure(plot_tangential(a), "tangential_A.png", dpi=70)
save_figure(plot_repeatability(repeatability(b), units="lab"), "repeatability_B.png", dpi=75)  # m/s, rpm
plane = bl.fit(bl.PiecewiseAffine, b).model                  # the delta-optimal plane
svm = fit_svm(b.landing.values, b.liftoff.values)             # the paper's SVM: its support vectors
save_figure(plot_landing_space(b, plane, support=svm), "landing_space_B.png", dpi=60)
print("written: tangential_A.png, repeatability_B.png, landing_space_B.png")
