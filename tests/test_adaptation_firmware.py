"""The adapted closed loop on the emulated Cortex-M4F: ``fric_adapt_ctrl_step`` (what `emit
--adapt` writes) against the float32 plant of examples/firmware/fw_plant.c for 60 s at 1 kHz,
bit for bit against its Python twin (``adapted(..., dtype="float32")`` and
``firmware.closed_loop.Float32Plant``). The fast sigmoid and the exact square root make every operation a
basic IEEE one, so the runs must be equal to the last bit. The reference is one 4 s period
of the reversing trajectory (``reversing()`` repeats every 4 s), looped, to keep the table in
flash small; the firmware prints every 100th sample and the adapted parameters at the end."""
import numpy as np
import pytest

from fricgen import codegen
from fricgen.control.adaptation import adapted
from fricgen.control.backstepping import AdaptiveBackstepping
from fricgen.control.c_abi import params_initializer
from fricgen.control.c_adapted import render_adapt
from fricgen.firmware import build as fw
from fricgen.firmware import closed_loop as cl
from fricgen.sim.trajectory import reversing, sampled

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(fw.missing_tools() is not None,
                                 reason=f"cross toolchain or QEMU absent: {fw.missing_tools()}")]
SECONDS, PERIOD, EVERY = 60.0, 4000, 100

LOOP = r"""
#include "fw_plant.h"
#include "fm_adapt.h"
%(arrays)s
static int fw_adapted_loop_run(void)
{
    static const fw_plant_params_t plant = %(plant)s;
    static const fric_ctrl_params_t cp = %(ctrl)s;
    static fric_ctrl_t c;
    static fric_adapt_t a;
    fric_adapt_params_t ap;
    fw_plant_t s = {0.0f, 0.0f};
    unsigned k;
    if ((fm_adapt_default_params(&ap, %(rule)s, 1e-3f) != 0) || (fric_ctrl_init(&c, &cp) != FRIC_CTRL_OK) || (fric_adapt_init(&a, &ap) != 0)) {
        sh_write0("al init-failed\n");
        return 1;
    }
    for (k = 0u; k < %(n)su; ++k) {
        const unsigned r = k %% %(period)su;
        float i = 0.0f;
        (void)fric_adapt_ctrl_step(&a, &c, fm_regressor, s.x, s.v, fw_ref_xd[r], fw_ref_xd_dot[r],
                                   fw_ref_xd_ddot[r], &i);
        if ((k %% %(every)su) == 0u) {
            const float row[5] = {s.x, s.v, i, c.m_o_hat, c.k_hat};
            fw_print_row("al", row, 5u);
        }
        fw_plant_advance(&s, &plant, i, cp.ts);
    }
    fw_print_row("th", a.theta, a.p.n);
    return 0;
}
#define FW_EXTRA() ((void)fw_adapted_loop_run())
"""


def _rows(lines, tag):
    words = [line.split()[1:] for line in lines if line.startswith(tag + " ")]
    return np.array([[int(w, 16) for w in r] for r in words], dtype=np.uint32).view(np.float32)


def _twin(model, rule, plant, ref):
    ctrl = adapted(model, rule, dtype="float32", activation_impl="fast").reset()
    ts = np.float32(ctrl.ts)
    x = v = np.float32(0.0)
    rows = []
    with np.errstate(all="ignore"):
        for k in range(int(round(SECONDS * 1000))):
            xd, xd1, xd2 = ref[k % PERIOD]
            i = ctrl.step(x, v, xd, xd1, xd2)
            if k % EVERY == 0:
                rows.append((x, v, i, *ctrl.controller.a_))
            x, v = plant.advance(x, v, i, ts)
    return np.array(rows, dtype=np.float32), np.asarray(ctrl.adapter.theta_, dtype=np.float32)


@pytest.mark.parametrize("rule", ["lyapunov", "rls"])
def test_the_adapted_loop_on_the_cortex_m4f_is_bit_equal_to_its_twin_over_60_s(default_model, rule,
                                                                               tmp_path):
    model, plant = default_model, cl.Float32Plant()
    ref = sampled(reversing(), np.arange(PERIOD) * 1e-3).astype(np.float32)
    src = tmp_path / "src"
    codegen.emit(model, src, "fm", activation_impl="fast", with_controller=True)
    for name, text in render_adapt(model, "fm", "fast").items():
        (src / name).write_text(text)
    extra = LOOP % {"arrays": cl.reference_arrays(ref), "plant": plant.c_initializer(),
                    "ctrl": params_initializer(AdaptiveBackstepping()),
                    "rule": f"FRIC_ADAPT_RULE_{rule.upper()}", "n": int(round(SECONDS * 1000)),
                    "period": PERIOD, "every": EVERY}
    cfg = fw.config_float("fm.h", "fm_force", [0.0], extra=extra)
    elf = fw.build_firmware(src, cfg, "cortex-m4f", tmp_path / "build",
                            extra_sources=cl.plant_sources(), strict_extra=True)
    lines = fw.run(elf, "cortex-m4f", timeout=600)
    c_rows, c_theta = _rows(lines, "al"), _rows(lines, "th").ravel()
    py_rows, py_theta = _twin(model, rule, plant, ref)
    assert c_rows.shape == py_rows.shape == (int(SECONDS * 1000) // EVERY, 5)
    np.testing.assert_array_equal(c_rows.view(np.uint32), py_rows.view(np.uint32))
    np.testing.assert_array_equal(c_theta.view(np.uint32), py_theta.view(np.uint32))
    # a loop that tracks and a theta that adapted (not a trivially equal run)
    assert np.all(np.isfinite(c_rows)) and np.abs(c_rows[:, 2]).max() > 1.0
    theta0 = np.asarray(adapted(model, rule, dtype="float32").adapter.reset()._theta0, dtype=np.float32)
    assert not np.array_equal(c_theta, theta0)
