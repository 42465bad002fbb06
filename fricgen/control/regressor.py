"""The friction model as a regressor that is linear in its output parameters.

[F3], F(v) = AIM(x) sgn(v) / K_out + B v with x = K_in min(|v|, v_sat), is linear in

- the output weights beta_k of an ELM, [F7]: AIM(x) = sum_k beta_k h_k(x), h_k = act(w_k x + b_k);
- the amplitudes a_k and the offset c of the grey-box [F1] in the coordinates of [F9],
  AIM(x) = c + d x + sum_k a_k g(x / xs_k), once its Stribeck velocities xs_k are fixed;

and in B. So F(v) = f0(v) + theta^T phi(v) with

    ELM:      theta = [beta_1 .. beta_M, B],     phi = [s h_1(x) .. s h_M(x), v]
    [F1]:  theta = [a_1 .. a_S, c, B],        phi = [s g(x/xs_1) .. s g(x/xs_S), s, v]

where s = sgn(v) / K_out, and f0 = s d x for [F1] (its slope d stays fixed; 0 for an ELM).

A model that records its axis (``training.axis``, every model ``fricgen train`` writes) adds
the axis's constant force, its ``offset`` ([C1] with a constant force, ``FrictionModel.
axis_offset``), as a last parameter with phi = 1 at every velocity, rest included: gravity on
an inclined axis or a cable's pull that changes in service is adapted with the friction, and
the loop applies it (theta = [.., B, offset]).

An asymmetric model is two such curves, one per direction of motion (each with its own AIM,
scaling, B and v_sat, [F3]): theta = [theta+, theta-] and phi(v) = [phi+(v), 0] for v > 0,
[0, phi-(v)] for v < 0, 0 at rest, so each direction adapts its own parameters (the offset,
one for both directions, last).

In float32 (``dtype="float32"``) the regressor is the exact twin of the ``NAME_regressor``
that ``fricgen emit --adapt`` generates (``fricgen.codegen.adapt``): the same float operations
in the same order.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Tuple

import numpy as np

from ..codegen.fast_sigmoid import sigmoid_fast_f32
from ..codegen.twin import STRIBECK_SHAPES_F32, stribeck_table
from ..errors import ModelError
from ..friction import SHAPES
from ..model import FrictionModel
from ..networks import ElmNetwork, StribeckCurve
from ..networks.elm import ACTIVATIONS, ACTIVATIONS_F32

f32 = np.float32


def check_adaptable(model: FrictionModel) -> FrictionModel:
    """``model`` if its output parameters can be adapted online: every curve (one, or one per
    direction) an ELM or a grey-box [F1]; else ``ModelError``."""
    for curve in model.directions:
        if not isinstance(curve.aim, (ElmNetwork, StribeckCurve)):
            raise ModelError(f"online adaptation covers ELM and grey-box models; this model's AIM is "
                             f"{type(curve.aim).__name__}")
    return model


def _curve_parameters(curve) -> np.ndarray:
    net = curve.aim
    if isinstance(net, StribeckCurve):
        return np.concatenate([net.amplitudes, [net.offset, curve.viscous]])
    return np.concatenate([net.output_weights, [curve.viscous]])


def adapts_offset(model: FrictionModel) -> bool:
    """Whether theta ends with the axis's offset: the model records its axis."""
    return model.axis is not None


def trained_parameters(model: FrictionModel) -> np.ndarray:
    """theta of the trained model (see the module doc), float64."""
    curves = [_curve_parameters(c) for c in check_adaptable(model).directions]
    return np.concatenate(curves + ([[model.axis_offset]] if adapts_offset(model) else []))


def parameter_names(model: FrictionModel) -> Tuple[str, ...]:
    """The name of each entry of theta: beta_k or a_k (k from 0), c, B; with a "+" or "-"
    after each of an asymmetric model's (its direction); then ``offset`` (``adapts_offset``)."""
    curves = check_adaptable(model).directions
    names = []
    for curve, mark in zip(curves, ("", "") if len(curves) == 1 else ("+", "-")):
        net = curve.aim
        own = (tuple(f"a_{k}" for k in range(net.n_sources)) + ("c", "B")
               if isinstance(net, StribeckCurve) else
               tuple(f"beta_{k}" for k in range(net.n_hidden)) + ("B",))
        names += [n + mark for n in own]
    return tuple(names) + (("offset",) if adapts_offset(model) else ())


def _with_curve_parameters(curve, theta: np.ndarray):
    net = curve.aim
    if isinstance(net, StribeckCurve):
        aim = replace(net, amplitudes=theta[:-2], offset=float(theta[-2]))
    else:
        aim = replace(net, output_weights=theta[:-1])
    return aim, float(theta[-1])


def with_parameters(model: FrictionModel, theta) -> FrictionModel:
    """``model`` with its output parameters set to ``theta`` (hidden layers, Stribeck
    velocities, slopes and scalings kept; the offset into ``training.axis``, its standard
    error dropped): the read-back of an adapted model."""
    check_adaptable(model)
    theta = np.asarray(theta, dtype=float)
    if theta.shape != trained_parameters(model).shape or not np.all(np.isfinite(theta)):
        raise ModelError(f"expected {trained_parameters(model).size} finite parameters, "
                         f"got {theta.size}")
    n_positive = _curve_parameters(model.positive).size
    aim, viscous = _with_curve_parameters(model.positive, theta[:n_positive])
    negative = model.negative
    if negative is not None:
        n_negative = _curve_parameters(negative).size
        neg_aim, neg_viscous = _with_curve_parameters(negative, theta[n_positive:n_positive + n_negative])
        negative = replace(negative, aim=neg_aim, viscous=neg_viscous)
    adapted = replace(model, aim=aim, viscous=viscous, negative=negative, recorded_hash=None)
    return with_offset(adapted, float(theta[-1])) if adapts_offset(model) else adapted


def with_offset(model: FrictionModel, offset: float) -> FrictionModel:
    """``model`` whose ``training.axis`` (it must have one) holds ``offset`` (N), an adapted
    value: its standard error dropped, the recorded hashes with it."""
    axis = {**model.training["axis"], "offset": offset, "offset_se": None}
    return replace(model, training={**model.training, "axis": axis}, recorded_hash=None,
                   recorded_axis_hash=None)


class _CurveRegressor:
    """phi and f0 of one curve (a ``Direction``) at a velocity, in the regressor's precision."""

    def __init__(self, curve, f, activation_impl: str):
        net = self.net = curve.aim
        if activation_impl == "fast" and isinstance(net, ElmNetwork) and net.activation != "sigmoid":
            raise ModelError(f"--activation-impl fast covers the sigmoid only, this model uses "
                             f"{net.activation!r}")
        self._f = f
        self.n = _curve_parameters(curve).size
        self._k_in, self._v_sat = f(curve.scaling.k_in), f(curve.v_sat)
        self._inv_k_out = f(1.0 / curve.scaling.k_out)
        if isinstance(net, StribeckCurve):
            self._slope = f(net.slope)
            self._inv_xs = stribeck_table(net) if f is f32 else 1.0 / net.stribeck
            self._g = (STRIBECK_SHAPES_F32[activation_impl][net.shape] if f is f32 else
                       lambda u, g=SHAPES[net.shape]: g(u, 1.0))
        else:
            kind = np.float32 if f is f32 else np.float64
            self._w, self._b = (np.asarray(a, dtype=kind) for a in (net.input_weights, net.biases))
            if f is f32:
                self._act = sigmoid_fast_f32 if activation_impl == "fast" else ACTIVATIONS_F32[net.activation]
            else:
                self._act = ACTIVATIONS[net.activation]

    def __call__(self, v):
        f = self._f
        speed = -v if v < 0 else v
        x = self._k_in * (speed if speed < self._v_sat else self._v_sat)
        sign = f(1.0) if v > 0 else (f(-1.0) if v < 0 else f(0.0))
        scale = sign * self._inv_k_out
        with np.errstate(over="ignore", under="ignore"):
            if isinstance(self.net, StribeckCurve):
                g = self._g(x * self._inv_xs)
                phi = np.concatenate([scale * g, [scale, v]])
                return scale * (self._slope * x), phi.astype(g.dtype)
            h = self._act(self._w * x + self._b)
            return f(0.0), np.concatenate([scale * h, [v]]).astype(h.dtype)


class Regressor:
    """phi(v) and f0(v) of the module doc for one model, in float64 or as the float32 twin of
    the generated C (``activation_impl`` "libm" or "fast" as given to ``emit``)."""

    def __init__(self, model: FrictionModel, dtype: str = "float64", activation_impl: str = "libm"):
        check_adaptable(model)
        if dtype not in ("float64", "float32"):
            raise ValueError(f"dtype must be 'float64' or 'float32', got {dtype!r}")
        if activation_impl not in ("libm", "fast"):
            raise ValueError(f"activation_impl must be 'libm' or 'fast', got {activation_impl!r}")
        self.model, self.dtype, self.activation_impl = model, dtype, activation_impl
        self.theta0 = trained_parameters(model)
        self.n = self.theta0.size
        self._f = float if dtype == "float64" else f32
        self._curves = [_CurveRegressor(c, self._f, activation_impl) for c in model.directions]
        self._offset = adapts_offset(model)

    def __call__(self, v) -> Tuple[object, np.ndarray]:
        """(f0, phi) at the finite velocity v (m/s), in the regressor's precision."""
        v = self._f(v)
        phi = np.zeros(self.n, dtype=np.float32 if self._f is f32 else np.float64)
        positive = self._curves[0]
        if len(self._curves) == 1 or v > 0:
            f0, phi[:positive.n] = positive(v)
        elif v < 0:
            f0, phi[positive.n:positive.n + self._curves[1].n] = self._curves[1](v)
        else:
            f0 = self._f(0.0)
        if self._offset:
            phi[-1] = 1.0
        return f0, phi
