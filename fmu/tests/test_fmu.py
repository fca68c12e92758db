"""The FMU `hydroid export fmu` writes, checked with FMPy (docs/fmu.md).

Identifies the bundled KVLCC2 ship (configs/ship_kvlcc2.toml, mmg3) into a temporary
folder, exports it as an FMI 2.0 co-simulation FMU, validates it with FMPy and simulates a
zig-zag-like rudder sequence with FMPy against `hydroid simulate` of the same model,
coefficients, initial state and inputs (an independent program path: the simulation
configuration is written here from the run's config.toml and results.json).

Needs the debug builds of hydroid and of the FMU library (`cargo build` or `cargo test` at
the repository root builds both, the workspace's default members), or HYDROID_BIN naming a
hydroid executable with libhydroid_fmu.so beside it.
"""

import csv
import json
import os
import subprocess
import tomllib
from pathlib import Path

import fmpy
import fmpy.validation
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
HYDROID = Path(os.environ.get("HYDROID_BIN", ROOT / "target" / "debug" / "hydroid"))

# the comparison's tolerance: largest difference over the largest magnitude, per output. The
# issue asks for 1e-6; both sides run the same RK4 on the same grid, so they agree to
# rounding (3.0e-15 measured on 2026-11-27, docs/fmu.md), and 1e-12 catches an input read
# one step early or late, a different step count or a coefficient lost on the way.
RELATIVE = 1e-12
DT = 0.1  # s, communication step of FMPy and sample interval of hydroid simulate
DURATION = 80.0  # s
RPM = 710.8  # rev/min, the KVLCC2 model's self-propulsion point (Y&Y 2015)
U0 = 1.179  # m/s
# rudder steps (time s, angle deg): a 20/20 zig-zag's command sequence at fixed times
RUDDER_STEPS = [(5.0, 20.0), (20.0, -20.0), (38.0, 20.0), (56.0, -20.0), (70.0, 0.0)]
STATES = ["u", "v", "r", "x", "y", "psi"]


def hydroid(*args, cwd=ROOT):
    done = subprocess.run(
        [str(HYDROID), *map(str, args)], cwd=cwd, capture_output=True, text=True
    )
    assert done.returncode == 0, f"hydroid {' '.join(map(str, args))}:\n{done.stderr}"
    return done.stdout


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """The run's output folder and the FMU exported from it."""
    tmp = tmp_path_factory.mktemp("fmu")
    run = tmp / "run"
    hydroid("-q", "run", ROOT / "configs" / "ship_kvlcc2.toml", "--out", run)
    fmu = tmp / "kvlcc2.fmu"
    out = hydroid("export", "fmu", run, "-o", fmu)
    assert "wrote" in out and fmu.is_file()
    return run, fmu


def rudder_at(t):
    """The commanded rudder at time t, rad: the last step at or before t."""
    value = 0.0
    for at, deg in RUDDER_STEPS:
        if t >= at - 1e-9:
            value = np.radians(deg)
    return value


def test_fmpy_validation_reports_no_problem(exported):
    _, fmu = exported
    assert fmpy.validation.validate_fmu(str(fmu)) == []
    md = fmpy.read_model_description(str(fmu), validate=True)
    assert md.fmiVersion == "2.0"
    assert md.coSimulation is not None and md.modelExchange is None
    assert md.coSimulation.canGetAndSetFMUstate is False
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["rudder"].causality == "input" and by_name["rudder"].unit == "rad"
    assert by_name["rpm"].causality == "input" and by_name["rpm"].unit == "rev/s"
    for s, unit in zip(STATES, ["m/s", "m/s", "rad/s", "m", "m", "rad"]):
        assert by_name[s].causality == "output" and by_name[s].unit == unit
        assert by_name[s + "0"].causality == "parameter"
    fmpy.dump(str(fmu))


def simulation_config(run, path, export):
    """A `hydroid simulate` configuration of the run's model, vehicle and coefficients with
    the test's initial state and rudder steps, noise-free, every digit written."""
    config = tomllib.loads((run / "config.toml").read_text())
    results = json.loads((run / "results.json").read_text())
    vehicle, fluid = config["vehicle"], config["fluid"]
    lines = ['title = "FMU check"', 'model = "mmg3"', "", "[vehicle]"]

    def toml_value(v):
        return json.dumps(v) if isinstance(v, str) else repr(v)

    for k, v in vehicle.items():
        if not isinstance(v, dict):
            lines.append(f"{k} = {toml_value(v)}")
    lines.append("[vehicle.particulars]")
    for k, v in vehicle.get("particulars", {}).items():
        lines.append(f"{k} = {toml_value(v)}")
    lines.append("[fluid]")
    for k, v in fluid.items():
        lines.append(f"{k} = {toml_value(v)}")
    lines.append("[coefficients]")
    for c in results["coefficients"]:
        lines.append(f"{c['name']} = {c['value']!r}")
    steps = ", ".join(f'{{ time = {t!r}, rudder = "{d!r} deg" }}' for t, d in RUDDER_STEPS)
    lines += [
        "[manoeuvre]",
        'kind = "time_history"',
        f"duration = {DURATION!r}",
        f"dt = {DT!r}",
        "substeps = 10",
        f'initial = {{ u = "{U0!r} m/s" }}',
        f'inputs = {{ rpm = "{RPM!r} rpm" }}',
        f"steps = [ {steps} ]",
        "[noise]",
        "seed = 1",
        "[export]",
        f"file = {json.dumps(str(export))}",
        'layout = "delimited"',
        "digits = 17",
        "columns = [",
    ]
    for q, unit in [("time", "s"), ("u", "m/s"), ("v", "m/s"), ("r", "rad/s"),
                    ("x", "m"), ("y", "m"), ("yaw", "rad"), ("rudder", "rad")]:
        lines.append(f'  {{ quantity = "{q}", name = "{q}", unit = "{unit}" }},')
    lines.append("]")
    path.write_text("\n".join(lines) + "\n")


def read_export(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}


def test_fmpy_matches_hydroid_simulate(exported, tmp_path):
    run, fmu = exported
    export = tmp_path / "sim.csv"
    config = tmp_path / "sim.toml"
    simulation_config(run, config, export)
    hydroid("simulate", config)
    ref = read_export(export)

    times = np.round(np.arange(0.0, DURATION + DT / 2, DT), 10)
    signals = np.array(
        [(t, rudder_at(t), RPM / 60.0) for t in times],
        dtype=[("time", np.float64), ("rudder", np.float64), ("rpm", np.float64)],
    )
    starts = {s + "0": 0.0 for s in STATES}
    starts["u0"] = U0
    result = fmpy.simulate_fmu(
        str(fmu),
        start_time=0.0,
        stop_time=DURATION,
        step_size=DT,
        output_interval=DT,
        start_values=starts,
        input=signals,
        output=STATES,
    )
    assert len(result) == len(ref["time"]), (len(result), len(ref["time"]))
    np.testing.assert_allclose(result["time"], ref["time"], atol=1e-9)
    # the input the reference read is the one given to FMPy
    np.testing.assert_allclose(ref["rudder"], signals["rudder"], atol=1e-12)
    worst = 0.0
    for state, column in zip(STATES, ["u", "v", "r", "x", "y", "yaw"]):
        scale = np.max(np.abs(ref[column]))
        assert scale > 0, column
        rel = np.max(np.abs(result[state] - ref[column])) / scale
        print(f"{state}: max |FMPy - hydroid simulate| / max |hydroid simulate| = {rel:.3g}")
        worst = max(worst, rel)
        assert rel < RELATIVE, (state, rel)
    print(f"largest relative difference over the outputs: {worst:.3g}")
    # the zig-zag really turned the ship (the comparison is not of a straight run)
    assert np.max(np.abs(ref["yaw"])) > np.radians(10)
