"""The scenarios' sampled closed loop (section 6): the controllers, drawn per seed, and the
plant of [C1] under them.

The loop advances many stretches of the log at once (``stitched``): the log is cut where the
reference moves (never within a dwell) into stretches of about STRETCH_S; each stretch starts
on the reference, warms up over at least WARMUP_S and the whole stretch before it, and runs
in lockstep with the others through ``MotorAxis.karnopp``. A closed loop in motion forgets
its start; a stretch whose state at its seam (x, v, friction memory, controller memory)
differs from its predecessor's by more than SEAM_TOLERANCE of the sensor resolution it shows
on is re-run from the predecessor's state, until every seam agrees. So a log is a serial
simulation up to state jumps below half the sensor noise, at a fraction of its cost
(``conditions["passes"]``, ``conditions["seam_jump"]``). Quantizing the fed-back signals
would make the loop's state depend on rounding boundaries, and stretches would not agree.
"""
from __future__ import annotations

import math

import numpy as np

from .axis import AxisState, MotorAxis
from .hidden_effects import PlantLaw
from .plant_friction import log_uniform

#: Controller kinds.
CONTROLLERS = ("pid", "pd_i", "cascade")
#: Largest state jump at a seam of the stitched simulation, as a fraction of the sensor
#: resolution (noise or quantization step / sqrt(12), whichever is larger) it would show on.
SEAM_TOLERANCE = 0.5
#: Length of a stretch and of the warm-up before it (s); at most MAX_STRETCHES stretches.
STRETCH_S, WARMUP_S, MAX_STRETCHES = 0.5, 1.0, 4096


def draw_controller(rng, kind, mass, force_constant, rate, feedforward):
    """The gains of a ``kind`` controller from the nominal mass and force constant: bandwidth,
    damping and integral share drawn from ``rng``."""
    f_bw = min(log_uniform(rng, 4.0, 25.0), rate / 40.0)
    w = 2 * np.pi * f_bw
    zeta = rng.uniform(0.5, 1.2)
    share = rng.uniform(0.05, 0.3)
    c = {"kind": kind, "bandwidth_hz": f_bw, "damping": zeta, "integral_share": share,
         "mass": mass, "force_constant": force_constant,
         "inertia_ff": float(rng.uniform() < 0.7), "friction_ff": feedforward}
    if kind in ("pid", "pd_i"):
        c.update(kp=w * w, kd=2 * zeta * w, ki_m=mass * share * w ** 3)
        c["tf"] = max(1.0 / (w * rng.uniform(5.0, 15.0)), 2.0 / rate)
    else:
        wv = min(w * rng.uniform(2.0, 4.0), 2 * np.pi * rate / 15.0)
        c.update(kpos=w * rng.uniform(0.5, 1.0), kv=wv, ki_m=mass * share * wv * wv,
                 velocity_bandwidth_hz=wv / (2 * np.pi))
        c["tf"] = 1.0
    return c


def seam_resolution(sensors: dict, ctrl: dict, phi: float) -> dict:
    """The sensor resolution each state component shows on: x and v directly, the
    controller's memory through the force it commands (noise or quantization step /
    sqrt(12), whichever is larger)."""
    def resolution(sigma, step):
        return max(sigma, step / math.sqrt(12.0))

    x = resolution(sensors["sigma_x"], sensors["q_x"])
    v = resolution(sensors["sigma_v"], sensors["q_v"])
    force = phi * resolution(sensors["sigma_i"], sensors["q_i"])
    filtered = force * ctrl["tf"] / (ctrl["mass"] * ctrl["kd"]) if ctrl["kind"] == "pid" else 1.0
    return {"x": x, "v": v, "s": v, "integral": force / ctrl["ki_m"], "filtered": filtered,
            "hx": x, "hv": v}


def _quantize(value, step):
    return np.round(value / step) * step


class ClosedLoop:
    """The sampled closed loop of one scenario, advancing a batch of stretches in lockstep."""

    def __init__(self, plant: PlantLaw, cond: dict, ref, feedforward, noise, ctrl: dict):
        self.axis = MotorAxis(plant)
        self.plant, self.cond, self.ctrl = plant, cond, ctrl
        self.xd, self.vd, self.ad = ref
        self.ff = feedforward
        self.noise = noise
        self.ts = 1.0 / cond["rate_hz"]
        self.substeps = cond["substeps"]
        self.delay = plant.hidden.delay_samples

    def initial(self, idx, exact):
        """States at samples ``idx``: at rest at 0 where ``exact`` (the log's start), else on
        the reference with the controller's memory empty."""
        x = np.where(exact, 0.0, self.xd[idx])
        v = np.where(exact, 0.0, self.vd[idx])
        state = {"x": x, "v": v, "s": np.abs(v), "integral": np.zeros_like(x),
                 "filtered": np.zeros_like(x)}
        if self.delay:
            state["hx"] = np.repeat(x[:, None], self.delay, axis=1)
            state["hv"] = np.repeat(v[:, None], self.delay, axis=1)
        return state

    def step(self, st, idx):
        """One sample: measure, control, log, then advance the plant by Ts."""
        c, cond = self.ctrl, self.cond
        z = self.noise[idx]
        if self.delay:
            xs, vs_ = st["hx"][:, 0], st["hv"][:, 0]
        else:
            xs, vs_ = st["x"], st["v"]
        xm = xs + cond["sigma_x"] * z[:, 0]     # the controller sees the noisy sensors, the
        vm = vs_ + cond["sigma_v"] * z[:, 1]    # log their quantized values
        xd, vd, ad = self.xd[idx], self.vd[idx], self.ad[idx]
        e = xd - xm
        m = c["mass"]
        acc_ff = ad * c["inertia_ff"]
        if c["kind"] == "pid":
            deriv = (e - st["filtered"]) / c["tf"]
            filtered = st["filtered"] + (self.ts / c["tf"]) * (e - st["filtered"])
            u = m * (acc_ff + c["kp"] * e + c["kd"] * deriv) + c["ki_m"] * st["integral"]
            err_int = e
        elif c["kind"] == "pd_i":
            filtered = st["filtered"]
            u = m * (acc_ff + c["kp"] * e + c["kd"] * (vd - vm)) + c["ki_m"] * st["integral"]
            err_int = e
        else:   # cascade
            filtered = st["filtered"]
            v_cmd = vd + c["kpos"] * e
            ev = v_cmd - vm
            u = m * (acc_ff + c["kv"] * ev) + c["ki_m"] * st["integral"]
            err_int = ev
        u = u + self.ff[idx]
        i_lim = self.plant.i_max
        i_cmd = u / c["force_constant"]
        i = np.clip(i_cmd, -i_lim, i_lim)
        # integrate unless the limit is pushing the same way (anti-windup)
        grow = ~((np.abs(i_cmd) > i_lim) & (np.sign(err_int) == np.sign(i_cmd)))
        integral = st["integral"] + np.where(grow, err_int * self.ts, 0.0)
        im = _quantize(i + cond["sigma_i"] * z[:, 2], cond["q_i"])
        applied = i if self.plant.hidden.actuator is None else self.plant.hidden.actuator(i)
        state = AxisState(st["x"], st["v"], idx * self.ts, st["s"])
        nxt = self.axis.karnopp(state, applied, self.ts, self.substeps)
        new = {"x": nxt.x, "v": nxt.v, "s": nxt.s, "integral": integral, "filtered": filtered}
        if self.delay:
            new["hx"] = np.concatenate([st["hx"][:, 1:], st["x"][:, None]], axis=1)
            new["hv"] = np.concatenate([st["hv"][:, 1:], st["v"][:, None]], axis=1)
        return new, (_quantize(xm, cond["q_x"]), _quantize(vm, cond["q_v"]), im)


def _mismatch(a: dict, b: dict, scale: dict) -> np.ndarray:
    """Per stretch: the largest |a - b| over the state components, in units of their
    ``scale``."""
    worst = None
    for key in a:
        d = np.abs(a[key] - b[key]) / scale[key]
        d = d.reshape(d.shape[0], -1).max(axis=1)
        worst = d if worst is None else np.maximum(worst, d)
    return worst


def _take(state: dict, rows) -> dict:
    return {k: np.array(v[rows]) for k, v in state.items()}


def seams(speed: np.ndarray, stretch: int) -> np.ndarray:
    """Sample indices that cut a log into stretches of about ``stretch`` samples, each cut
    where the reference ``speed`` is largest within half a stretch of the regular grid, and
    none within a dwell (an axis in motion forgets its past; one stuck does not)."""
    n = speed.size
    cuts = [0]
    for b in range(stretch, n - stretch // 2, stretch):
        a, z = max(b - stretch // 2, cuts[-1] + stretch // 2), min(b + stretch // 2, n - 1)
        if z > a:
            c = a + int(np.argmax(speed[a:z]))
            if speed[c] > 0:
                cuts.append(c)
    return np.array(cuts + [n])


def stitched(loop: ClosedLoop, cuts: np.ndarray, warmup: int, resolution: dict):
    """The log's measured x, v, i, simulated as the stretches between ``cuts`` in lockstep
    (see the module docstring). Returns the arrays, the number of passes and the largest
    state jump at a seam in units of ``resolution``."""
    n = int(cuts[-1])
    k = cuts.size - 1
    lo, hi = cuts[:-1], cuts[1:]
    out = np.zeros((3, n))

    def run(rows, start, init, steps):
        """Advance stretches ``rows`` from ``init`` at samples ``start`` for ``steps`` samples,
        logging their own samples; returns their states at lo and hi."""
        st = init
        at_lo, at_hi = _take(init, slice(None)), _take(init, slice(None))
        for j in range(steps + 1):
            idx = start + j
            mark = idx == lo[rows]
            if mark.any():
                for key in st:
                    at_lo[key][mark] = st[key][mark]
            mark = idx == hi[rows]
            if mark.any():
                for key in st:
                    at_hi[key][mark] = st[key][mark]
            if j == steps:
                break
            clipped = np.minimum(idx, n - 1)
            st, meas = loop.step(st, clipped)
            own = (idx >= lo[rows]) & (idx < hi[rows])
            if own.any():
                out[:, idx[own]] = np.stack(meas)[:, own]
        return at_lo, at_hi

    # each stretch warms up for at least ``warmup`` samples and over the whole stretch before
    start = np.maximum(np.minimum(lo - warmup, np.concatenate([[0], lo[:-1]])), 0)
    exact = start == 0
    rows = np.arange(k)
    at_lo, at_hi = run(rows, start, loop.initial(start, exact), int(np.max(hi - start)))
    passes = 1
    seam = np.zeros(k)
    while True:
        for j in range(1, k):
            if not exact[j] and exact[j - 1]:
                seam[j] = _mismatch(_take(at_lo, [j]), _take(at_hi, [j - 1]), resolution)[0]
                exact[j] = bool(seam[j] <= SEAM_TOLERANCE)
        bad = np.flatnonzero(~exact)
        if bad.size == 0:
            break
        first = bad[0]
        redo = bad
        init = _take(at_hi, redo - 1)
        new_lo, new_hi = run(redo, lo[redo], init, int(np.max(hi[redo] - lo[redo])))
        for key in at_lo:
            at_lo[key][redo] = new_lo[key]
            at_hi[key][redo] = new_hi[key]
        exact[first] = True
        seam[first] = 0.0
        passes += 1
    return out, passes, float(np.max(seam))


def simulate_log(loop: ClosedLoop, speed: np.ndarray, resolution: dict):
    """``stitched`` over stretches of about STRETCH_S cut where the reference ``speed`` moves
    (at most MAX_STRETCHES), each warmed up over at least WARMUP_S."""
    rate, n = loop.cond["rate_hz"], speed.size
    stretch = max(int(round(STRETCH_S * rate)), -(-n // MAX_STRETCHES))
    warmup = int(round(WARMUP_S * rate))
    return stitched(loop, seams(speed, stretch), warmup, resolution)
