"""hydroid.read, hydroid.simulate and the catalogue, against numbers worked out here."""

import math

import pytest

import hydroid


def _cfx_rows(path):
    """The data rows of a CFX export, parsed here (after the header line under [Data])."""
    lines = path.read_text().splitlines()
    start = lines.index("[Data]") + 2
    return [[float(x) for x in l.split(",")] for l in lines[start:] if l.strip()]


def test_read_gives_si_columns_with_their_units(root):
    path = root / "cfd_exports" / "surge_run.csv"
    df = hydroid.read(path)
    rows = _cfx_rows(path)
    assert df.height == len(rows)
    assert df.columns == ["Time", "Velocity u", "Thrust"]
    assert df.units == {"Time": "s", "Velocity u": "m/s", "Thrust": "N"}
    assert df.format == "cfx" and df.time == "Time"
    assert df["Velocity u"].to_list() == [r[1] for r in rows]


def test_read_converts_degrees_to_radians(root):
    df = hydroid.read(root / "cfd_exports" / "polar_sweep.csv", format="starccm")
    assert df.units["Angle of Attack"] == "rad"
    assert df["Angle of Attack"][0] == pytest.approx(-12 * math.pi / 180, rel=1e-15)
    with pytest.raises(hydroid.HydroidError, match="unknown format 'cvs'"):
        hydroid.read(root / "cfd_exports" / "polar_sweep.csv", format="cvs")


def test_simulate_surge_matches_the_closed_form(root):
    # surge1: (m - Xud) u' = Xuu u|u| + T from rest; with k = -Xuu, U = sqrt(T/k) and
    # tau = (m - Xud)/sqrt(T k): u = U tanh(t/tau), x = U tau ln cosh(t/tau)
    m, xud, xuu, thrust = 50.0, -1.2, -1.3, 20.0
    k = -xuu
    big_u, tau = math.sqrt(thrust / k), (m - xud) / math.sqrt(thrust * k)
    t = [0.1 * i for i in range(201)]
    vehicle = {"mass": m, "length": 1.2, "diameter": 0.2, "izz": 3.7, "reference_area": 0.0314, "reference_length": 1.0}
    df = hydroid.simulate(
        "surge1",
        {"Xud": xud, "Xuu": xuu},
        vehicle,
        {"t": t, "thrust": thrust},
        fluid={"rho": 1025.0, "mu": 0.0009},
    )
    assert df.columns == ["t", "u", "x"]
    assert df.units == {"t": "s", "u": "m/s", "x": "m"}
    for ti, u, x in df.iter_rows():
        assert u == pytest.approx(big_u * math.tanh(ti / tau), rel=1e-9, abs=1e-12)
        assert x == pytest.approx(big_u * tau * math.log(math.cosh(ti / tau)), rel=1e-8, abs=1e-12)


def test_simulate_reads_the_vehicle_of_a_configuration_and_names_bad_inputs(root):
    cfg = root / "configs" / "spheroid.toml"
    coefs = {"Xud": -1.2, "Xuu": -1.3}
    df = hydroid.simulate("surge1", coefs, cfg, {"t": [0.0, 1.0], "thrust": [20.0, 20.0]}, initial={"u": 1.0})
    assert df["u"][0] == 1.0 and df.height == 2
    with pytest.raises(hydroid.HydroidError, match="'rudder' is not an input of the surge1 model"):
        hydroid.simulate("surge1", coefs, cfg, {"t": [0.0, 1.0], "thrust": 1.0, "rudder": 0.0})
    with pytest.raises(hydroid.HydroidError, match="needs values for Xuu"):
        hydroid.simulate("surge1", {"Xud": -1.0}, cfg, {"t": [0.0, 1.0], "thrust": 1.0})
    with pytest.raises(hydroid.HydroidError, match="spheroid7"):
        hydroid.simulate("spheroid7", coefs, cfg, {"t": [0.0, 1.0]})


def test_models_and_coefficients_list_the_catalogue():
    ms = hydroid.models()
    row = ms.filter(ms["name"] == "spheroid3").row(0, named=True)
    assert row["states"] == ["u", "v", "r", "x", "y", "psi"]
    c = hydroid.coefficients("spheroid3")
    xvr = c.filter(c["name"] == "Xvr").row(0, named=True)
    assert xvr["derived_by"] == "paper eq. 4: Xvr = -Yvd"
    every = hydroid.coefficients()
    assert every.filter(every["name"] == "Xud")["unit"][0] == "kg"
    with pytest.raises(hydroid.HydroidError, match="did you mean"):
        hydroid.coefficients("spheroid7")
