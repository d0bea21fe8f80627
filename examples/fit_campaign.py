"""Fit every bounce law to campaign A, print the fit reports, and save a law to JSON and reload it.

What it shows
    * loading an embedded campaign (campaign A, artificial turf; a *synthetic surrogate*
      of the paper's data, simulated from turf physics, see docs/simulation.md);
    * fitting each of bouncelab's laws with :func:`bouncelab.fit` (the default global
      search minimising the paper's error delta) and reading the :class:`~bouncelab.FitResult`
      report, including its notes on parameters that ended on a bound;
    * the fitted values beside the paper's published ones;
    * writing a fitted law to JSON and loading it back unchanged.

Run it from the repository root (about 5 s; it writes only to a temporary directory)::

    python examples/fit_campaign.py
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import bouncelab as bl

LAWS = (bl.Rigid, bl.PennerVarying, bl.PennerFixed, bl.PiecewiseAffine, bl.TangentialRestitution)


def main() -> None:
    ds = bl.load_campaign("A")
    print(f"campaign {ds.attrs['campaign']}: {ds.sizes['bounce']} bounces ({ds.attrs['data_kind']})\n")

    results = {}
    for law in LAWS:
        res = bl.fit(law, ds, seed=0)
        results[law.__name__] = res
        print(res.report())
        print()

    print("fitted delta beside the paper's (Table 3; Table 2 for the piecewise law):")
    for name, res in results.items():
        if name == "PiecewiseAffine":
            paper = bl.published.TABLE2.loc[("A", "overall"), "delta"]
        elif name in ("Rigid", "PennerVarying", "PennerFixed"):
            paper = bl.published.TABLE3.loc[("A", name), "delta"]
        else:
            paper = None  # TangentialRestitution goes beyond the paper
        ref = f"{paper:.1%}" if paper is not None else "(not in the paper)"
        print(f"    {name:<22} delta {res.delta:6.1%}   paper {ref}")

    law = results["PennerFixed"].model
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "penner_fixed_A.json"
        law.to_json(path)
        again = bl.load_law(path)
        print(f"\nsaved {law!r} to {path.name}:")
        print(path.read_text().strip())
        print(f"reloaded: {again!r}; identical: {again == law}")
        landing = [[1000.0, -800.0, 300.0]]
        print(f"same prediction: {(again.predict(landing) == law.predict(landing)).all()}")


if __name__ == "__main__":
    main()
