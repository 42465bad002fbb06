"""Instructions of one ``NAME_step`` (pre-sliding) and ``NAME_compensation`` call on the emulated
MCUs, beside ``NAME_force`` of the same model, the most over a set of speeds.

The model: the grey-box [F1] (one gauss source, B) of a 2 N Coulomb, 3 N static friction
curve with LuGre bristles (sigma0 1e5 N/m, sigma1 300 N s/m fading at 2 mm/s) and a velocity
band of 1 mm/s, emitted with ``--activation-impl`` libm and fast at a sample time of 100 us.
Each speed of SPEEDS is one firmware build calling the function once from a relaxed state;
QEMU counts the instructions of that call (as benchmarks/instructions_per_call.py).

    python benchmarks/presliding_cost.py

Needs arm-none-eabi-gcc, libnewlib-arm-none-eabi and qemu-system-arm.
"""
from __future__ import annotations

import sys
from dataclasses import replace

import numpy as np

from fricgen.data.sweep import Sweep
from fricgen.effects.presliding import Bristles
from fricgen.firmware import build as fw
from fricgen.fit import StribeckRegressor
from fricgen.training import train

#: Speeds of one call each, m/s: rest, pre-sliding, the Stribeck region, sliding, both ways.
SPEEDS = (0.0, 1e-5, -3e-4, 1e-3, 4e-3, -0.02, 0.1, 1e3)
#: The wrappers that give each function the harness's float (float) signature.
WRAPPERS = {"fm_force": ("fm_force", ""),
            "fm_compensation": ("fm_compensation", ""),
            "fm_step": ("fw_step", "static float fw_step(float v) { static fm_state_t s; "
                        "return fm_step(&s, v); }")}


def model():
    v = np.concatenate([-np.geomspace(1e-5, 0.1, 60)[::-1], np.geomspace(1e-5, 0.1, 60)])
    f = np.sign(v) * (2.0 + np.exp(-(v / 2e-3) ** 2)) + 10.0 * v
    m = train(Sweep(v, f), estimator=StribeckRegressor(), name="fm").model
    return replace(m, presliding=Bristles(1e5, 300.0, 2e-3), velocity_band=1e-3)


def main() -> int:
    reason = fw.missing_tools()
    if reason:
        print(f"skipped: {reason}")
        return 0
    fw.print_call_costs(model(), WRAPPERS, SPEEDS, "m/s", sample_time=1e-4)
    return 0


if __name__ == "__main__":
    sys.exit(main())
