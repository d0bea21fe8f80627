"""Compare the paper's four laws on campaign B with the paper's validation split.

What it shows
    * :func:`bouncelab.compare` fitting Rigid, Penner (varying and fixed angle) and the
      piecewise-affine law to the same bounces;
    * the paper's split (:func:`bouncelab.split_by_setting`): one random bounce of each
      launcher setting is held out, the laws are fitted on the rest and scored on both;
    * the results laid out as the paper's Tables 3 and 2, in markdown, with the paper's
      published values in brackets.

Campaign B is the embedded *synthetic surrogate* of the paper's natural-turf campaign (by
default simulated from turf physics through camera frames, docs/simulation.md), so agreement
with the paper's numbers is expected only roughly.

Run it from the repository root (about 5 s; it writes nothing)::

    python examples/compare_laws.py [--seed N]
"""

from __future__ import annotations

import argparse

import bouncelab as bl
from bouncelab.fitting import PAPER_LAWS


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0, help="seed of the split and of every fit")
    args = parser.parse_args(argv)

    ds = bl.load_campaign("B")
    cmp = bl.compare(ds, PAPER_LAWS, split="setting", seed=args.seed)
    print(cmp.to_markdown())

    train = cmp.results["Rigid"].n_train
    test = cmp.results["Rigid"].n_test
    print(f"{train} bounces fitted, {test} held out (one per launcher setting), seed {args.seed}.")
    print("Held-out delta of each law (the paper's Table 3 delta was measured on all its bounces):")
    for law, res in cmp.results.items():
        print(f"    {law:<16} {res.test_delta:6.1%}")


if __name__ == "__main__":
    main()
