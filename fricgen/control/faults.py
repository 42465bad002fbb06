"""Fault injection into the controller's inputs, for the contract of fric_ctrl.h (section 6's
controller must keep its current within +-i_max and its estimates within their intervals,
whatever a sensor or the reference delivers).

A glitch replaces one input (``INPUTS``: x, v, x_d, x_d', x_d'' or the compensation force) by
one value (``KINDS``: NaN, +-inf, 1e20, a float32 denormal) for a number of samples.
``Glitched`` wraps a controller (``AdaptiveBackstepping`` or ``CController``) so that
``fricgen.control.loop.simulate`` runs it with the glitches, and records its flags.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Sequence

import numpy as np

#: The inputs of fric_ctrl_step, in its order.
INPUTS = ("x", "v", "xd", "xd_dot", "xd_ddot", "friction")
#: What a glitch puts in place of an input.
KINDS = {"nan": float("nan"), "+inf": float("inf"), "-inf": float("-inf"), "1e20": 1e20,
         "denormal": 1e-41}


@dataclass(frozen=True)
class Glitch:
    """``input`` replaced by ``KINDS[kind]`` for samples start .. start + length - 1."""

    input: str
    kind: str
    start: int
    length: int

    @property
    def end(self) -> int:
        """The first sample after the glitch."""
        return self.start + self.length

    @property
    def value(self) -> float:
        return KINDS[self.kind]


def random_glitches(n: int, rng: np.random.Generator, count: int, max_length: int = 20,
                    gap: int = 0, first: int = 0) -> List[Glitch]:
    """``count`` glitches within samples [first, n), cycling through every input x kind in a
    random order, each of a random length 1 .. ``max_length``, at random starts. With
    ``gap`` > 0 they do not overlap and at least ``gap`` clean samples follow each one (a
    ValueError when they do not fit); else they may overlap."""
    pairs = [(i, k) for i in INPUTS for k in KINDS]
    order = rng.permutation(len(pairs))
    lengths = rng.integers(1, max_length + 1, size=count)
    if gap:
        slack = (n - first) - int(np.sum(lengths + gap))
        if slack < 0:
            raise ValueError(f"{count} glitches with {gap} clean samples after each do not fit "
                             f"in {n - first} samples")
        cuts = np.sort(rng.integers(0, slack + 1, size=count))
        starts = first + cuts + np.concatenate([[0], np.cumsum(lengths + gap)[:-1]])
    else:
        starts = rng.integers(first, n - max_length, size=count)
    return [Glitch(*pairs[order[j % len(pairs)]], int(s), int(m))
            for j, (s, m) in enumerate(zip(starts, lengths))]


class Glitched:
    """``controller`` with ``glitches`` applied to its inputs at its k-th step (k from 0 after
    ``reset``); ``flags_`` lists the flags of every step, ``rows_`` its inputs (``INPUTS``, as
    float32). The compensation force is the controller's own (``compensation_force``),
    evaluated at the glitched inputs."""

    def __init__(self, controller, glitches: Sequence[Glitch]):
        self.controller = controller
        self.glitches = tuple(glitches)

    @property
    def ts(self) -> float:
        return self.controller.ts

    def reset(self) -> "Glitched":
        self.controller.reset()
        self.k_ = 0
        self.flags_: List[int] = []
        self.rows_: List[np.ndarray] = []
        return self

    def step(self, x, v, xd, xd_dot, xd_ddot) -> float:
        inputs = dict(x=x, v=v, xd=xd, xd_dot=xd_dot, xd_ddot=xd_ddot)
        active = [g for g in self.glitches if g.start <= self.k_ < g.end]
        for g in active:
            if g.input != "friction":
                inputs[g.input] = g.value
        c = self.controller
        force = c.compensation_force(inputs["x"], inputs["v"], inputs["xd"], inputs["xd_dot"])
        for g in active:
            if g.input == "friction":
                force = g.value
        i = c.step_with_force(friction=force, **inputs)
        self.rows_.append(np.array([*inputs.values(), force], dtype=np.float32))
        self.flags_.append(int(c.flags_))
        self.k_ += 1
        return i

    @property
    def adaptive_parameters(self):
        return self.controller.adaptive_parameters
