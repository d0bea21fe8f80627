import numpy as np

import bouncelab as bl
from bouncelab.laws.base import BounceModel, Parameter


class Restitution(BounceModel):
    """Frictionless bounce: pF = [xdot0, -e ydot0, omega0]."""

    parameter_specs = (Parameter("e", (0.0, 1.0), (0.0, 1.0), "1", "restitution"),)
    regimes = ("bounce",)

    def __init__(self, e=None):
        self.e = e
        super().__init__()

    def _predict(self, p, theta):
        return p * np.array([1.0, -theta[0], 1.0])

    def _regime(self, p, theta):
        return np.zeros(len(p), dtype=np.int8)


print(Restitution(e=0.5).predict([[100.0, -200.0, 30.0]]))
res = bl.fit(Restitution, bl.load_campaign("B"))          # the generic fitter works for any law
print(res.model, f"delta = {res.delta:.4f}")
text = res.model.to_json()                                # JSON round trip by class name
print(text)
print(bl.BounceModel.from_dict(res.model.to_dict()) == res.model)
