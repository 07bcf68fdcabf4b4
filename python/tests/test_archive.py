"""trajectories.nc opens directly in h5py and xarray: its dimensions, units, attributes and values
agree with drones.csv (docs/output-format.md, "trajectories.nc")."""

import importlib.util
import json
import shutil

import numpy as np
import pandas as pd
import pytest

from conftest import cli

h5py = pytest.importorskip("h5py")
xr = pytest.importorskip("xarray")

TEST = {
    "name": "rec",
    "groups": [
        {"name": "scouts", "behavior": "random_walk", "drones": 5, "drone": {"base": "small", "battery_capacity": 0.05}},
        {"name": "mappers", "behavior": "flocking", "drones": 3},
    ],
    "map": {"name": "forest", "params": {"size": 200}},
    "targets": {"kind": "tree", "count": 40},
    "time": 6,
    "log_interval": 0.5,
    "failures": {"drone_mtbf": 20},
    "seed": 3,
    "changes": [{"time": 2, "set": {"groups.scouts.drones": 2}}, {"time": 4, "set": {"groups.scouts.drones": 6}}],
}
STATUS = ["flying", "landed", "failed", "removed"]


@pytest.fixture(scope="module")
def folder(tmp_path_factory, program):
    root = tmp_path_factory.mktemp("archive")
    (root / "rec.json").write_text(json.dumps(TEST))
    status, _, err = cli(program, "run", "rec.json", "--out", "out", "-q", "--no-plots", "--archive",
                         "--drone-columns", "status_since,battery_left,energy_used", cwd=root)
    assert status == 0, err
    return root / "out" / "rec"


def test_h5py_reads_the_hdf5_underneath(folder):
    drones = pd.read_csv(folder / "drones.csv", float_precision="round_trip")
    with h5py.File(folder / "trajectories.nc", "r") as f:
        assert f.attrs["Conventions"] == b"CF-1.8" or f.attrs["Conventions"] == "CF-1.8"
        assert int(f.attrs["salsa_archive_version"][0]) == 1
        assert int(f.attrs["seed"][0]) == 3
        assert json.loads(f.attrs["config"])["name"] == "rec"
        # Lengths and speeds are whole millimetres (CF packing): h5py gives the integers and the scale.
        packed, scale = f["position"][...], f["position"].attrs["scale_factor"]
        assert packed.dtype == np.int32 and scale == pytest.approx(1e-3)
        assert f["position"].attrs["_FillValue"] == -2147483647
        position = np.where(packed == -2147483647, np.nan, packed * scale)
        status, since = f["status"][...], f["status_since"][...]
        assert f["position"].compression == "gzip" and f["position"].shuffle
        assert "commanded" not in f and "energy_used" in f  # not asked for; asked for by --drone-columns
        assert f["velocity"].attrs["units"] in (b"m s-1", "m s-1")
        times = f["time"][...]
    assert position.shape == (len(times), status.shape[1], 2)
    frame = np.searchsorted(times, drones["time"].to_numpy() - 1e-9)
    ids = drones["id"].to_numpy()
    # drones.csv's 4 decimals and the archive's millimetres: within both roundings
    assert np.abs(position[frame, ids, 0] - drones["x"]).max() <= 0.5e-3 + 0.5e-4 + 1e-9
    assert np.abs(position[frame, ids, 1] - drones["y"]).max() <= 0.5e-3 + 0.5e-4 + 1e-9
    assert (since[frame, ids] == drones["status_since"]).all()  # written with all their digits
    assert [STATUS[s] for s in status[frame, ids]] == list(drones["status"])
    # drones.csv lists exactly the drones that are there: neither removed (3) nor not yet added (fill 255)
    assert len(drones) == int(((status != 3) & (status != 255)).sum())


@pytest.mark.parametrize("engine,module", [(None, "netCDF4"), ("h5netcdf", "h5netcdf")])  # None: xarray's default
def test_xarray_opens_it(folder, engine, module):
    if importlib.util.find_spec(module) is None:
        pytest.skip(f"{module} is not installed")
    drones = pd.read_csv(folder / "drones.csv", float_precision="round_trip")
    targets = pd.read_csv(folder / "targets.csv")
    with xr.open_dataset(folder / "trajectories.nc", engine=engine) as ds:
        assert dict(ds.sizes) == {"time": 13, "drone": 12, "xy": 2, "target": 40}
        assert list(ds["xy"].values) == ["x", "y"]
        assert ds["position"].dims == ("time", "drone", "xy")
        assert ds["position"].attrs["units"] == "m" and ds["energy_used"].attrs["units"] == "J"
        assert ds["velocity"].attrs["long_name"] == "its ground velocity"
        assert ds["battery_left"].attrs["salsa_model"] == "fleet"
        assert ds["group"].attrs["flag_meanings"] == "scouts mappers"
        assert ds["status"].attrs["flag_meanings"] == "flying landed failed removed"
        assert ds.attrs["test_name"] == "rec" and ds.attrs["log_interval"] == 0.5 and ds.attrs["salsa_version"]
        # Selected by drones.csv's rows: the same values; a removed drone's are NaN.
        rows = ds.sel(time=xr.DataArray(drones["time"].to_numpy(), dims="row"), drone=xr.DataArray(drones["id"].to_numpy(), dims="row"),
                      method="nearest")
        assert ds["velocity"].dtype == np.float64  # unpacked from millimetres
        assert np.abs(rows["velocity"].sel(xy="x").values - drones["vx"]).max() <= 0.5e-3 + 0.5e-4 + 1e-9
        assert np.abs(rows["energy_used"].values / 3600 - drones["energy_used_Wh"]).max() <= 0.5e-4 + 1e-9
        groups = ds["group"].attrs["flag_meanings"].split()
        assert [groups[int(g)] for g in rows["group"].values] == list(drones["group"])
        assert (rows["battery_left"].values == drones["battery_left"]).all()
        removed = ds["status"].values == 3
        assert removed.any() and np.isnan(ds["position"].values[removed]).all()
        found = targets["found_by"].notna()
        assert (ds["target_found_by"].values[found.to_numpy()] == targets["found_by"][found]).all()
        assert np.isnan(ds["target_found_time"].values[~found.to_numpy()]).all()


def test_load_gives_the_archive_as_a_dataset(folder, tmp_path):
    import salsa
    if importlib.util.find_spec("netCDF4") is None:
        pytest.skip("netCDF4 is not installed")
    drones = pd.read_csv(folder / "drones.csv", float_precision="round_trip")
    ds = salsa.load(folder).trajectories
    assert ds["position"].dims == ("time", "drone", "xy") and ds["position"].dtype == np.float64
    first = drones[drones["time"] == 0]
    assert np.abs(ds["position"].sel(time=0).values[first["id"], 0] - first["x"]).max() <= 0.5e-3 + 0.5e-4 + 1e-9
    ds.close()
    # No archive: None. A damaged one: InputError naming the file.
    plain = tmp_path / "plain"
    shutil.copytree(folder, plain)
    (plain / "trajectories.nc").unlink()
    assert salsa.load(plain).trajectories is None
    (plain / "trajectories.nc").write_bytes((folder / "trajectories.nc").read_bytes()[:4096])
    with pytest.raises(salsa.InputError, match=r"plain/trajectories.nc: cannot be read as a trajectory archive"):
        salsa.load(plain).trajectories

