"""Closed-loop simulation of section 6: sampled controllers driving the axis of [C1].

Several controllers run side by side, each on its own copy of the axis (the axes advance as
one vectorized state), so compensation variants are compared on exactly the same reference.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..data import synthesize_benchmark
from ..effects import ConstantLoad
from ..fit import AnfisRegressor, default_elm
from ..friction import preset
from ..metrics import rmse
from ..model import FrictionModel
from ..sim.axis import AxisState, MotorAxis
from ..sim.bristle_axis import BristleAxis
from ..sim.effect_law import EffectLaw
from ..sim.trajectory import reversing, sampled
from .backstepping import AdaptiveBackstepping

#: Simulated time of the default comparison: one envelope period of ``reversing()``, s.
DEFAULT_DURATION = 4.0
#: RK4 steps per controller sample.
DEFAULT_SUBSTEPS = 10
#: The built-in axis: mass (kg), true force constant (N/A), the controller's nominal one (N/A).
DEFAULT_MASS, DEFAULT_FORCE_CONSTANT, DEFAULT_PHI_N = 2.0, 18.0, 20.0
#: The peak speeds of the built-in reference (``reversing()``), m/s.
DEFAULT_SPEEDS = (0.02, 0.2)


def default_axis(friction=None, mass: float = DEFAULT_MASS,
                 force_constant: float = DEFAULT_FORCE_CONSTANT,
                 i_max: float = 10.0, load: float = 0.0) -> MotorAxis:
    """The controlled axis of section 6: a linear permanent-magnet motor, m dv/dt = phi i - F_F(v)
    [C1], with thrust phi i [C2].

    The controller assumes a nominal phi_N = 20 N/A, so the default phi = 18 N/A is "not known
    exactly"; the current limit of 10 A gives 180 N peak thrust against up to 44 N breakaway.

    Parameters
    ----------
    friction : FrictionCurve, optional
        The axis' friction F_F(v) in N (default: Table 1's [F1], ``preset("paper3")``).
    mass : float
        The mover's mass m (kg).
    force_constant : float
        phi (N/A).
    i_max : float
        Current limit (A).
    load : float
        A constant external force opposing positive thrust (N), a disturbance no model knows.

    Returns
    -------
    MotorAxis

    Examples
    --------
    >>> from fricgen.control import default_axis
    >>> axis = default_axis()
    >>> axis.law.mass, axis.law.force_constant, axis.law.i_max
    (2.0, 18.0, 10.0)
    """
    if not np.isfinite(load):
        raise ValueError(f"load must be finite, got {load}")
    friction = preset("paper3") if friction is None else friction
    effects = (ConstantLoad(load=float(load)),) if load else ()
    return MotorAxis(EffectLaw(friction, effects, mass=mass, force_constant=force_constant,
                               i_max=i_max))


@dataclass(frozen=True)
class Plant:
    """An axis to simulate, the nominal force constant its controller assumes (N/A), the
    reference it follows, and one line that says what it is."""

    axis: MotorAxis
    phi_n: float
    trajectory: object
    text: str
    i_max: float = 10.0


def model_plant(model: FrictionModel, mass: float, offset: float = 0.0,
                speed_max: Optional[float] = None, mass_text: str = "",
                force_constant: Optional[float] = None) -> Plant:
    """The axis a model was trained on: [C1] with mass ``mass`` (kg), the model itself as its
    friction (sticking at rest up to F(0+)) and the constant force ``offset`` (N, the constant
    part of the drive force: an external force of -offset along +x, ``fricgen.axis``).

    Its motor: the axis's ``force_constant`` (N/A, the one training read the current with),
    which the controller then knows; without one, the built-in motor scaled with the mass
    (phi = 9 N/A per kg, the controller assuming 10 N/A per kg). The current limit gives the
    built-in's thrust per kg (90 N/kg), so that the controller's gains and loop stay those of the
    built-in axis up to m / phi. The reference reverses at peak speeds up to min(0.2 m/s,
    ``speed_max``), the fastest speed the model was trained on.
    """
    scale = mass / DEFAULT_MASS
    if force_constant is None:
        phi, phi_n, whose = DEFAULT_FORCE_CONSTANT * scale, DEFAULT_PHI_N * scale, "scaled with the mass"
    else:
        phi, phi_n, whose = force_constant, force_constant, "the model's axis"
    i_max = 10.0 * DEFAULT_FORCE_CONSTANT * scale / phi
    axis = default_axis(model, mass=mass, force_constant=phi, load=offset, i_max=i_max)
    friction = "the model"
    if model.presliding is not None:
        axis = BristleAxis(axis.law, model.presliding, model.stribeck, model.viscous_force)
        friction = (f"the model with its bristles (LuGre, sigma0 {model.presliding.stiffness:.4g}, "
                    f"sigma1 {model.presliding.damping:.4g})")
    units = model.units
    trajectory, speeds = reference_within(speed_max, units.speed)
    offset_text = (f", offset {offset:.4g} {units.force} as a constant force (the model variant "
                   "compensates it with the friction)") if offset else ""
    return Plant(axis, phi_n, trajectory,
                 f"plant: the model's axis, {mass_text or f'm = {mass:.4g} {units.mass}'}{offset_text}, "
                 f"friction = {friction}; motor {phi:.4g} {units.force}/A ({whose}), {i_max:.4g} A; "
                 f"{speeds}", i_max)


def builtin_plant(why: str, speed_max: Optional[float] = None) -> Plant:
    """The built-in 2 kg axis of ``default_axis()`` (Table 1 friction); ``why`` says why."""
    trajectory, speeds = reference_within(speed_max)
    return Plant(default_axis(), DEFAULT_PHI_N, trajectory,
                 f"plant: built-in {DEFAULT_MASS:g} kg axis (Table 1 friction); {why}; {speeds}")


def reference_within(speed_max: Optional[float] = None, unit: str = "m/s"):
    """``reversing()`` with its peak speeds scaled down to at most ``speed_max`` (m/s, or rad/s
    on a rotary axis: ``unit``; None: the defaults, 0.02 to 0.2), and a text that gives them."""
    low, high = DEFAULT_SPEEDS
    if speed_max is not None and speed_max < high:
        low, high = low * speed_max / high, speed_max
        where = f" (within the model's training speeds, up to {speed_max:.4g} {unit})"
    else:
        where = "" if speed_max is None else \
            f" (the model was trained up to {speed_max:.4g} {unit})"
    return reversing(low, high), f"reference peak speeds {low:.3g} to {high:.3g} {unit}{where}"


def peak_force(plant: Plant, duration: float, ts: float) -> float:
    """The largest force the plant's reference asks of the motor: m |x_d''| + |F(x_d')| +
    |offset| along it, N."""
    law = plant.axis.law
    ref = sampled(plant.trajectory, np.arange(0.0, duration, ts))
    friction = np.abs(law.sliding_friction(ref[:, 1], ref[:, 0] * 0, ref[:, 1] * 0))
    load = np.abs(law.external_force(ref[:, 0], ref[:, 1], ref[:, 0] * 0))
    return float(np.max(law.mass * np.abs(ref[:, 2]) + friction + load))


@dataclass(frozen=True)
class ClosedLoop:
    """Sampled signals of one closed-loop run, one row per controller sample k (t_k = k Ts).

    Parameters
    ----------
    t : ndarray
        Sample times (s).
    x, v : ndarray
        Position (m) and velocity (m/s) of the axis.
    xd : ndarray
        Desired position (m).
    i : ndarray
        Commanded current (A).
    m_o_hat, k_hat : ndarray
        The adaptive parameters of section 6: m_o = m / phi (kg A/N) and k (dimensionless).

    Notes
    -----
    ``e1`` = xd - x is the position error of [C3].

    Examples
    --------
    >>> import fricgen
    >>> run = fricgen.compare({"none": None}, duration=0.2)["none"]
    >>> run.t.shape == run.e1.shape == (200,)
    True
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    xd: np.ndarray
    i: np.ndarray
    m_o_hat: np.ndarray
    k_hat: np.ndarray

    @property
    def e1(self) -> np.ndarray:
        return self.xd - self.x

    @property
    def n_finite(self) -> int:
        """Samples before the first non-finite state, current or parameter (all when none)."""
        ok = np.isfinite(self.x) & np.isfinite(self.i) & np.isfinite(self.k_hat) \
            & np.isfinite(self.m_o_hat)
        return ok.size if ok.all() else int(np.argmin(ok))

    @property
    def finite(self) -> bool:
        return self.n_finite == self.t.size

    def metrics(self) -> dict:
        """rms_e1, max_e1 (m), rms_i, max_i (A), the final m_o_hat, k_hat, and ``finite``
        (False when the run blew up; the figures then cover the samples before that)."""
        n = self.n_finite
        if n == 0:
            nan = float("nan")
            return {"rms_e1": nan, "max_e1": nan, "rms_i": nan, "max_i": nan, "m_o_hat": nan,
                    "k_hat": nan, "finite": False}
        e1, i = self.e1[:n], self.i[:n]
        return {"rms_e1": rmse(e1, 0.0), "max_e1": float(np.max(np.abs(e1))),
                "rms_i": rmse(i, 0.0), "max_i": float(np.max(np.abs(i))),
                "m_o_hat": float(self.m_o_hat[n - 1]), "k_hat": float(self.k_hat[n - 1]),
                "finite": n == self.t.size}


def simulate(axis: MotorAxis, controllers: Sequence, trajectory=None,
             duration: float = DEFAULT_DURATION, substeps: int = DEFAULT_SUBSTEPS,
             on_sample=None) -> List[ClosedLoop]:
    """Run each controller against its own copy of ``axis``, integrated with RK4 substeps.

    A controller has ``ts``, ``reset()``, ``step(x, v, xd, xd', xd'') -> i`` and
    ``adaptive_parameters``. The axes start at rest at x = 0; the current of sample k is held over
    [t_k, t_k + Ts). A run whose state stops being finite is cut short (NaN afterwards).

    Parameters
    ----------
    axis : MotorAxis
        The plant (``default_axis``).
    controllers : sequence
        Controllers, all with the same ``ts`` (``AdaptiveBackstepping``, ``CController``).
    trajectory : optional
        The desired position xd(t) with its derivatives (default: the section 6 trajectory).
    duration : float
        Simulated time (s).
    substeps : int
        RK4 steps per sample.
    on_sample : callable, optional
        Called with t_k before the controllers of each sample (for plants that change with time).

    Returns
    -------
    list of ClosedLoop
        One run per controller, in order.

    Examples
    --------
    >>> from fricgen import AdaptiveBackstepping
    >>> from fricgen.control import default_axis, simulate
    >>> axis = default_axis()
    >>> runs = simulate(axis, [AdaptiveBackstepping(), AdaptiveBackstepping(axis.law.friction)],
    ...                 duration=0.2)
    >>> len(runs), bool(abs(runs[1].e1[-50:]).max() < 1e-3)
    (2, True)
    """
    if not controllers:
        raise ValueError("controllers must hold at least one controller")
    ts = float(controllers[0].ts)
    for c in controllers:
        if float(c.ts) != ts:
            raise ValueError(f"all controllers must share one ts, got {c.ts} and {ts}")
        c.reset()
    if not (np.isfinite(duration) and duration > 0):
        raise ValueError(f"duration must be > 0, got {duration}")
    if int(substeps) != substeps or substeps < 1:
        raise ValueError(f"substeps must be a positive integer, got {substeps}")
    trajectory = reversing() if trajectory is None else trajectory
    n = int(round(duration / ts))
    t = np.arange(n) * ts
    ref = sampled(trajectory, t)
    m = len(controllers)
    out = {k: np.full((n, m), np.nan) for k in ("x", "v", "i", "m_o_hat", "k_hat")}
    state = AxisState.of(np.zeros(m))
    i = np.zeros(m)
    alive = np.ones(m, dtype=bool)
    with np.errstate(all="ignore"):
        for k in range(n):
            xd, xd1, xd2 = ref[k]
            if on_sample is not None:
                on_sample(t[k])
            x, v = state.x, state.v
            for j, c in enumerate(controllers):
                if alive[j]:
                    i[j] = c.step(x[j], v[j], xd, xd1, xd2)
                    out["m_o_hat"][k, j], out["k_hat"][k, j] = c.adaptive_parameters
            out["x"][k], out["v"][k], out["i"][k] = x, v, i
            alive &= np.isfinite(i) & np.isfinite(x) & np.isfinite(out["k_hat"][k]) \
                & np.isfinite(out["m_o_hat"][k])
            if not alive.any():
                break
            state = AxisState(np.where(alive, state.x, 0.0), np.where(alive, state.v, 0.0), state.t,
                              np.where(alive, state.s, 0.0))
            state = axis.advance(state, np.where(alive, i, 0.0), ts, substeps)
    return [ClosedLoop(t=t, xd=ref[:, 0], **{key: a[:, j] for key, a in out.items()})
            for j in range(m)]


# ----------------------------------------------------------------------------- variants


def paper_benchmark():
    """The paper benchmark the built-in variants are trained on (Table 1, seed 0)."""
    return synthesize_benchmark(preset("paper3"), seed=0)


def default_model(name: str = "fric_model", bench=None) -> FrictionModel:
    """fricgen's default model trained on the paper benchmark (Table 1, seed 0)."""
    bench = paper_benchmark() if bench is None else bench
    return FrictionModel.fit(bench.dataset, default_elm(0), name=name,
                             training={"source": "paper3 benchmark, seed 0"})


def fuzzy_model(name: str = "fuzzy_model", bench=None) -> FrictionModel:
    """The paper's fuzzy baseline (ANFIS, 4 bell MFs) on the paper benchmark."""
    bench = paper_benchmark() if bench is None else bench
    return FrictionModel.fit(bench.dataset, AnfisRegressor(n_mfs=4, mf="bell"), name=name)


def compensations(axis: MotorAxis, model: Optional[FrictionModel] = None,
                  with_fuzzy: bool = True, ts: Optional[float] = None) -> Dict[str, Optional[object]]:
    """The compensation variants to compare: "none", "exact" (the axis' true friction, unless that is
    ``model``), and ``model`` as "model" (its ``force_with_offset`` where the axis carries the
    model's offset, ``carries_offset``: the constant force is compensated with the friction);
    without a model, fricgen's default model of the paper
    benchmark as "elm" and the fuzzy baseline as "fuzzy". A model with bristles compensates
    through its stepper at ``ts`` as "model" (a stateful callable, reset with its controller)
    and with its steady-state curve alone as "steady".

    Parameters
    ----------
    axis : MotorAxis
        The plant whose friction is "exact".
    model : FrictionModel, optional
        The model to compare.
    with_fuzzy : bool
        Add the fuzzy baseline (without ``model`` only).
    ts : float, optional
        The controllers' sample time, s: needed for a model with bristles.

    Returns
    -------
    dict of str to callable or None
        Variant -> F_Fm(v) in N (None: no compensation).

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.control import compensations, default_axis
    >>> axis = default_axis()
    >>> sorted(compensations(axis, model=axis.law.friction))    # the model is the truth
    ['model', 'none']
    """
    variants: Dict[str, Optional[object]] = {"none": None}
    if axis.law.friction is not model:        # else exact compensation is the model's
        variants["exact"] = axis.law.friction
    if model is None:
        bench = paper_benchmark()
        variants["elm"] = default_model(bench=bench)
        if with_fuzzy:
            variants["fuzzy"] = fuzzy_model(bench=bench)
    elif getattr(model, "presliding", None) is None:       # a curve, or a model without state
        variants["model"] = model.force_with_offset if carries_offset(axis, model) else model
    else:
        if ts is None:
            raise ValueError("a model with bristles compensates sample by sample: give ts, the "
                             "controllers' sample time")
        variants["steady"] = model
        variants["model"] = model.stepper(ts)
    return variants


def carries_offset(axis: MotorAxis, model) -> bool:
    """Whether ``axis`` holds ``model``'s axis offset as its constant load (``model_plant``'s)."""
    offset = model.axis_offset if isinstance(model, FrictionModel) else 0.0
    return offset != 0.0 and any(isinstance(e, ConstantLoad) and e.load == offset
                                 for e in getattr(axis.law, "effects", ()))


def compare(compensation: Dict[str, Optional[object]], axis: Optional[MotorAxis] = None,
            trajectory=None, duration: float = DEFAULT_DURATION, substeps: int = DEFAULT_SUBSTEPS,
            **controller) -> Dict[str, ClosedLoop]:
    """Simulate one ``AdaptiveBackstepping(**controller)`` per compensation variant on one axis.

    Parameters
    ----------
    compensation : dict of str to callable or None
        Variant -> F_Fm(v) in N, e.g. from ``compensations``.
    axis : MotorAxis, optional
        The plant (default: ``default_axis()``).
    trajectory, duration, substeps
        As for ``simulate``.
    **controller
        Settings of ``AdaptiveBackstepping`` shared by every variant.

    Returns
    -------
    dict of str to ClosedLoop

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.control import default_axis
    >>> axis = default_axis()
    >>> runs = fricgen.compare({"none": None, "exact": axis.law.friction}, axis=axis, duration=0.2)
    >>> err = {k: float(abs(r.e1[-50:]).max()) for k, r in runs.items()}
    >>> err["exact"] < err["none"]      # compensating [F1] shrinks the tracking error
    True
    """
    axis = default_axis() if axis is None else axis
    ctrls = [AdaptiveBackstepping(compensation=comp, **controller) for comp in compensation.values()]
    runs = simulate(axis, ctrls, trajectory, duration, substeps)
    return dict(zip(compensation, runs))
