"""Closed-loop runs on the emulated MCU: the float32 plant of examples/firmware/fw_plant.c
(``Float32Plant``), the fw_config.h text of a run (``config_closed_loop``, ``reference_arrays``),
its Python twin (``closed_loop_f32``) and the rows the firmware prints (``parse_closed_loop``)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, List, Optional

import numpy as np

from ..c_literal import c_float, c_list
from ..control.c_abi import params_initializer
from ..sim.axis import AxisState, MotorAxis
from .build import FirmwareError, firmware_dir


@dataclass(frozen=True)
class Float32Plant:
    """Float32 twin of ``examples/firmware/fw_plant.c``: the force law of a ``MotorAxis``
    [C1] with F(v) = (f_c + (f_s - f_c) v_s^2 / (v_s^2 + v^2)) v / (|v| + v_eps)
    + viscous v (no libm), the current limited to [-i_max, i_max], integrated with
    ``MotorAxis.euler_f32`` in ``substeps`` steps per sample.
    The defaults resemble the paper's benchmark axis (2 kg, 18 N/A, 15 N Coulomb and 44 N
    breakaway friction, 57.5 N s/m); the stiffest slope, f_s / v_eps + viscous ~ 8.9e3 N s/m,
    keeps h slope / m below 1 at Ts = 1 ms with 5 substeps (stable explicit velocity update)."""

    mass: float = 2.0
    phi: float = 18.0
    i_max: float = 10.0
    f_c: float = 15.0
    f_s: float = 44.0
    v_s: float = 0.01
    v_eps: float = 0.005
    viscous: float = 57.5
    substeps: int = 5

    _FLOATS = ("mass", "phi", "i_max", "f_c", "f_s", "v_s", "v_eps", "viscous")
    #: No friction memory.
    lag_tau = 0.0

    @property
    def force_constant(self) -> float:
        return self.phi

    def friction(self, v):
        """``fw_plant_friction``, float32."""
        f = np.float32
        v = f(v)
        speed = -v if v < 0 else v
        vs2 = f(self.v_s) * f(self.v_s)
        level = f(self.f_c) + (f(self.f_s) - f(self.f_c)) * (vs2 / (vs2 + v * v))
        return level * (v / (speed + f(self.v_eps))) + f(self.viscous) * v

    def thrust(self, i):
        return self.phi * i

    def sliding_friction(self, v, t, s):
        return self.friction(v)

    def external_force(self, x, v, t):
        return np.float32(0.0)

    def advance(self, x, v, i, ts):
        """(x, v) after ``ts`` seconds with the current ``i`` held, as ``fw_plant_advance``."""
        end = MotorAxis(self).euler_f32(AxisState(x, v, 0.0, 0.0), i, ts, self.substeps)
        return end.x, end.v

    def c_initializer(self) -> str:
        items = [f".{k} = {c_float(getattr(self, k))}" for k in self._FLOATS]
        return "{" + ", ".join(items + [f".substeps = {int(self.substeps)}"]) + "}"


#: Columns of a closed-loop run, one row per sample (``closed_loop_f32``, ``parse_closed_loop``).
LOOP_COLUMNS = ("x", "v", "i", "m_o_hat", "k_hat")


def plant_sources() -> List[Path]:
    """The C sources of the closed-loop run (``fw_plant.c``), for ``build_firmware``."""
    return [firmware_dir() / "fw_plant.c"]


def reference_arrays(reference) -> str:
    """The reference rows (x_d, x_d', x_d'') as the float32 C arrays fw_ref_xd, fw_ref_xd_dot and
    fw_ref_xd_ddot of fw_config.h; ``ValueError`` unless their shape is (n, 3)."""
    ref = np.asarray(reference, dtype=np.float32)
    if ref.ndim != 2 or ref.shape[1] != 3 or ref.shape[0] == 0:
        raise ValueError(f"reference must have shape (n, 3), got {ref.shape}")
    return "\n".join(
        f"static const float fw_ref_{name}[{ref.shape[0]}] = {{\n{c_list((c_float(v) for v in ref[:, j]), 6)}\n}};"
        for j, name in enumerate(("xd", "xd_dot", "xd_ddot")))


def config_closed_loop(settings, plant: Float32Plant, reference, friction_fn: Optional[str]) -> str:
    """The ``extra`` text of fw_config.h for a closed-loop run (``FW_EXTRA()`` calls
    ``fw_closed_loop_run``): controller parameters from ``settings`` (an
    ``AdaptiveBackstepping``), the plant, the reference rows (x_d, x_d', x_d'') as float32
    arrays, and the compensation ``friction_fn`` (a C function name, or None)."""
    arrays, n = reference_arrays(reference), len(reference)
    return f"""#include "fw_plant.h"
{arrays}
static const fw_loop_t fw_loop = {{
    {plant.c_initializer()},
    {params_initializer(settings)},
    {friction_fn or "0"}, {n}u, fw_ref_xd, fw_ref_xd_dot, fw_ref_xd_ddot
}};
#define FW_EXTRA() ((void)fw_closed_loop_run(&fw_loop))
"""


def closed_loop_f32(controller, plant: Float32Plant, reference) -> np.ndarray:
    """The Python twin of ``fw_closed_loop_run``: ``controller`` (a float32
    ``AdaptiveBackstepping``, e.g. ``control_c.float32_twin``) against ``plant`` from rest,
    one row (``LOOP_COLUMNS``) per reference sample, float32."""
    ref = np.asarray(reference, dtype=np.float32)
    ctrl = controller.reset()
    ts = np.float32(ctrl.ts)
    x = v = np.float32(0.0)
    rows = np.empty((ref.shape[0], len(LOOP_COLUMNS)), dtype=np.float32)
    with np.errstate(all="ignore"):
        for k, (xd, xd1, xd2) in enumerate(ref):
            i = ctrl.step(x, v, xd, xd1, xd2)
            rows[k] = (x, v, i, ctrl.a_[0], ctrl.a_[1])
            x, v = plant.advance(x, v, i, ts)
    return rows


def parse_closed_loop(lines: Iterable[str]) -> np.ndarray:
    """The rows a closed-loop run printed ("cl X V I M K"), float32, shape (n, 5)."""
    rows = [line.split()[1:] for line in lines if line.startswith("cl ")]
    if any(r == ["init-failed"] for r in rows):
        raise FirmwareError("fric_ctrl_init rejected the closed-loop parameters")
    bits = np.array([[int(w, 16) for w in r] for r in rows], dtype=np.uint32).reshape(-1, len(LOOP_COLUMNS))
    return bits.view(np.float32)
