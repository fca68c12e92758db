"""Simulates an FMU `hydroid export fmu` wrote, with FMPy: .ci/run's check that the README's
first command (`cargo run --release -- run configs/spheroid.toml`) followed by the export it
documents gives an FMU that an importer runs (issue 48, docs/fmu.md).

    python fmu/tests/simulate_fmu.py out/spheroid.fmu

FMPy's validation must report no problem; the FMU is simulated for 20 s in communication
steps of 0.1 s from its own start values (its inputs, if any, at their start values); every
output must stay finite, start at its start value, and the vehicle must move. Exits non-zero
with the reason otherwise. (fmu/tests/test_fmu.py compares an FMU with `hydroid simulate`
to 1e-12; this only checks that the out-of-the-box FMU runs.)
"""

import sys

import fmpy
import fmpy.validation
import numpy as np


def main(path):
    problems = fmpy.validation.validate_fmu(path)
    assert problems == [], f"FMPy's validation of {path}: {problems}"
    md = fmpy.read_model_description(path, validate=True)
    assert md.coSimulation is not None, "not a co-simulation FMU"
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    starts = {
        v.name: float(v.start)
        for v in md.modelVariables
        if v.causality == "parameter" and v.start is not None
    }
    assert outputs, "the FMU has no outputs"
    result = fmpy.simulate_fmu(path, stop_time=20.0, output_interval=0.1, step_size=0.1)
    assert len(result) >= 200, f"{len(result)} rows for 20 s at 0.1 s"
    for name in outputs:
        series = result[name]
        assert np.all(np.isfinite(series)), f"{name} is not finite"
        start = starts.get(name + "0")
        if start is not None:
            assert series[0] == start, f"{name} starts at {series[0]}, its start value {start}"
    moved = max(np.ptp(result[name]) for name in outputs)
    assert moved > 0, "no output moved in 20 s"
    print(
        f"{path}: FMPy validated it and simulated 20 s ({len(result)} rows); outputs "
        + ", ".join(f"{n} {result[n][0]:.4g} -> {result[n][-1]:.4g}" for n in outputs)
    )


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(f"usage: {sys.argv[0]} FMU")
    main(sys.argv[1])
