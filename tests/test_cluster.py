"""Issue 11 item 6: dask. Lazy predict on dask-backed DataArrays; compare, bootstrap, cross_validate and sweep
on a dask.distributed Client give exactly the serial results for the same seed (a two-worker LocalCluster)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import bouncelab as bl
from bouncelab.core.errors import DataError, FitError

da = pytest.importorskip("dask.array", reason="dask is not installed (pip install -e '.[cluster]')")
distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed")


@pytest.fixture(scope="module")
def client():
    # Two workers in this process (threads): light enough for the default suite; the same code runs on any cluster.
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") as cl, \
            distributed.Client(cl) as c:
        yield c


@pytest.fixture(scope="module")
def campaign():
    return bl.load_campaign("A")


# ------------------------------------------------------------------------------ lazy predict
def lazy_landings(n: int = 10_000, chunk: int = 2_500) -> tuple[np.ndarray, xr.DataArray]:
    p = bl.load_campaign("B").landing.values
    big = np.tile(p, (n // len(p) + 1, 1))[:n]
    arr = xr.DataArray(da.from_array(big, chunks=(chunk, 3)), dims=("bounce", "component"),
                       coords={"component": ["xdot", "ydot", "omega"], "bounce": np.arange(n)})
    return big, arr


def test_predict_on_dask_dataarray_is_lazy_and_chunked() -> None:
    big, arr = lazy_landings()
    law = bl.PennerVarying(r=0.45, mu=0.5, k_p=1e-4)
    out = law.predict(arr)
    assert isinstance(out.data, da.Array)  # nothing computed yet
    assert out.data.numblocks == (4, 1)  # one task per chunk of bounces
    assert out.dims == ("bounce", "component") and list(out["unit"].values) == ["radius/s", "radius/s", "rad/s"]
    np.testing.assert_array_equal(out.compute().values, law.predict(big))
    codes = law.regime(arr, codes=True)
    assert isinstance(codes.data, da.Array) and codes.dtype == np.int8
    np.testing.assert_array_equal(codes.values, law.regime(big, codes=True))
    np.testing.assert_array_equal(law.regime(arr).values, law.regime(big))


def test_lazy_predict_reorders_components_and_raises_on_compute() -> None:
    big, arr = lazy_landings(1000, 250)
    law = bl.Rigid(r=0.5, mu=0.3)
    swapped = arr.isel(component=[2, 0, 1])  # omega, xdot, ydot
    np.testing.assert_array_equal(law.predict(swapped).values, law.predict(big))
    bad = big.copy()
    bad[700, 1] = 5.0  # a landing moving up, in the third chunk
    lazy = law.predict(xr.DataArray(da.from_array(bad, chunks=(250, 3)), dims=("bounce", "component")))
    with pytest.raises(DataError) as e:  # a landing moving up
        lazy.compute()
    assert e.value.column == "landing.ydot"
    # lazily in scaled Cartesian states only: the option that asks for more is named
    for call, option in ((lambda: law.predict(arr, units={"velocity": "m/s", "spin": "rpm"}), "units"),
                         (lambda: law.predict(arr, return_flags=True), "return_flags"),
                         (lambda: law.predict(arr, warn_outside_fitted=True), "warn_outside_fitted"),
                         (lambda: law.regime(arr, form="polar"), "form")):
        with pytest.raises(DataError) as e:
            call()
        assert e.value.option == option


# ------------------------------------------------------------------------------ a Client as executor
def test_compare_on_client_equals_serial(client, campaign) -> None:
    laws = ["Rigid", "PennerFixed", "PennerVarying"]
    serial = bl.compare(campaign, laws, split="setting", seed=5)
    remote = bl.compare(campaign, laws, split="setting", seed=5, executor=client)
    pd.testing.assert_frame_equal(remote.table, serial.table, check_exact=True)


def test_bootstrap_on_client_equals_serial(client, campaign) -> None:
    serial = bl.bootstrap(bl.PennerFixed, campaign, n=6, seed=11)
    remote = bl.bootstrap(bl.PennerFixed, campaign, n=6, seed=11, executor=client)
    pd.testing.assert_frame_equal(remote.samples, serial.samples, check_exact=True)
    assert remote.estimate == serial.estimate
    other = bl.bootstrap(bl.PennerFixed, campaign, n=6, seed=12, executor=client)
    assert not other.samples.equals(serial.samples)  # the seed matters: the comparison above could fail


def test_cross_validate_on_client_equals_serial(client, campaign) -> None:
    serial = bl.cross_validate(bl.PennerVarying, campaign, k=4, seed=2)
    remote = bl.cross_validate(bl.PennerVarying, campaign, k=4, seed=2, executor=client)
    pd.testing.assert_frame_equal(remote.folds, serial.folds, check_exact=True)


def test_sweep_on_client_equals_serial(client, campaign) -> None:
    grid = {"r": [0.4, 0.5], "mu": np.linspace(0.1, 0.5, 5)}
    serial = bl.sweep(bl.Rigid, campaign, grid)
    remote = bl.sweep(bl.Rigid, campaign, grid, executor=client)
    pd.testing.assert_frame_equal(remote, serial, check_exact=True)
    assert len(serial) == 10 and list(serial[["r", "mu"]].iloc[1]) == [0.4, 0.2]
    # every point sets every parameter: delta is the law's own delta there
    law = bl.Rigid(r=0.5, mu=0.3)
    row = serial[(serial.r == 0.5) & np.isclose(serial.mu, 0.3)].iloc[0]
    assert row["delta"] == pytest.approx(bl.delta(campaign.landing, campaign.liftoff,
                                                  law.predict(campaign.landing.values)), rel=1e-12)
    profile = bl.sweep(bl.PennerFixed, campaign, [{"beta_deg": 0.0}, {"beta_deg": 10.0}], executor=client)
    assert list(profile["beta_deg"]) == [0.0, 10.0] and "objective_value" in profile
    # beta held at 0 is the rigid bounce: its fit is Rigid's
    assert profile["delta"].iloc[0] == pytest.approx(bl.fit(bl.Rigid, campaign).delta, rel=1e-3)


def test_sweep_and_executor_errors(campaign) -> None:
    with pytest.raises(FitError) as e:  # no parameter or option e
        bl.sweep(bl.Rigid, campaign, {"e": [0.1]})
    assert (e.value.law, e.value.option) == ("Rigid", "grid") and "['e']" in e.value.message
    with pytest.raises(FitError) as e:
        bl.sweep(bl.Rigid, campaign, {})
    assert (e.value.law, e.value.option) == (None, "grid")
    with pytest.raises(bl.ParameterError):
        bl.sweep(bl.Rigid, campaign, {"r": [0.5, 1.5]})
    with pytest.raises(FitError) as e:
        bl.cross_validate(bl.Rigid, campaign, k=2, executor=object())
    assert e.value.option == "executor"


@pytest.mark.slow
def test_process_cluster_equals_serial(campaign) -> None:
    """Worker processes (as on a real cluster): the laws compile there and still give the serial numbers."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cl, \
            distributed.Client(cl) as c:
        serial = bl.bootstrap(bl.PennerVarying, campaign, n=8, seed=1)
        remote = bl.bootstrap(bl.PennerVarying, campaign, n=8, seed=1, executor=c)
    pd.testing.assert_frame_equal(remote.samples, serial.samples, check_exact=True)


def test_client_executor_face_equals_serial(client, campaign) -> None:
    """dask's concurrent.futures face (client.get_executor()) is an executor like any other: the serial numbers."""
    serial = bl.bootstrap(bl.PennerFixed, campaign, n=6, seed=11)
    remote = bl.bootstrap(bl.PennerFixed, campaign, n=6, seed=11, executor=client.get_executor())
    pd.testing.assert_frame_equal(remote.samples, serial.samples, check_exact=True)
    cv = bl.cross_validate(bl.Rigid, campaign, k=3, seed=2, executor=client.get_executor())
    pd.testing.assert_frame_equal(cv.folds, bl.cross_validate(bl.Rigid, campaign, k=3, seed=2).folds,
                                  check_exact=True)
