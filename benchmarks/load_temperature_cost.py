"""Instructions of one ``NAME_force_lt`` call (friction at a load and a temperature) on the
emulated MCUs, beside ``NAME_force`` of the same model, the most over a set of speeds.

The model: the grey-box [F1] (one gauss source, B) of a 2 Nm Coulomb, 3 Nm static friction
curve with a load dependence (slopes 0.05 and 0.02 per Nm, |L| up to 100 Nm) and a temperature
dependence (k_c 0.005, k_v 0.03 per degC, 20 to 60 degC about 40), emitted with
``--activation-impl`` libm and fast. Each speed v of SPEEDS is one firmware build calling the
function once with load = 100 v Nm and temperature = 40 + 100 v degC (both quadrants, inside and
beyond the trained range); QEMU counts the instructions of that call (as
benchmarks/instructions_per_call.py).

    python benchmarks/load_temperature_cost.py

Needs arm-none-eabi-gcc, libnewlib-arm-none-eabi and qemu-system-arm.
"""
from __future__ import annotations

import sys
from dataclasses import replace

import numpy as np

from fricgen.data.sweep import Sweep
from fricgen.effects.load_temperature import LoadDependence, LoadTemperature, TemperatureDependence
from fricgen.firmware import build as fw
from fricgen.fit import StribeckRegressor
from fricgen.training import train

#: Speeds of one call each, rad/s: rest, the Stribeck region, sliding, both ways.
SPEEDS = (0.0, 1e-3, -4e-3, 0.02, -0.1, 0.5, 2.0)
#: The wrappers that give each function the harness's float (float) signature.
WRAPPERS = {"fm_force": ("fm_force", ""),
            "fm_force_lt": ("fw_lt", "static float fw_lt(float v) { "
                            "return fm_force_lt(v, 100.0f * v, 40.0f + (100.0f * v)); }")}


def model():
    v = np.concatenate([-np.geomspace(1e-4, 2.0, 60)[::-1], np.geomspace(1e-4, 2.0, 60)])
    f = np.sign(v) * (2.0 + np.exp(-(v / 2e-2) ** 2)) + 10.0 * v
    m = train(Sweep(v, f), estimator=StribeckRegressor(), name="fm", rotary=True).model
    inputs = LoadTemperature(LoadDependence(0.05, 0.02, 100.0),
                             TemperatureDependence(40.0, 0.005, 0.03, (20.0, 60.0)))
    return replace(m, inputs=inputs)


def main() -> int:
    reason = fw.missing_tools()
    if reason:
        print(f"skipped: {reason}")
        return 0
    fw.print_call_costs(model(), WRAPPERS, SPEEDS, "rad/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
