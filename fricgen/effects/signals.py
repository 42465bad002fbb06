"""What an effect's force may depend on: the measured signals and the friction curve."""
from __future__ import annotations

import math
from typing import Optional, Protocol

import numpy as np
from scipy.signal import lfilter


class FrictionCurve(Protocol):
    """A friction curve F(v) = S(|v|) sgn(v) + B v: a ``FrictionModel`` [F3] or a
    ``MultisourceFriction`` [F1], as a typing protocol (``viscous``, ``__call__``,
    ``stribeck``). Tabulating it (``Signals(tabulate=True)``) also needs ``v_sat``. An
    asymmetric curve (a ``FrictionModel`` of format version 2, a ``DirectionalFriction``) also
    has ``negative``, the curve for v < 0 (its own ``stribeck`` and ``v_sat``); its own
    ``stribeck`` is then that of v >= 0 at the speeds u >= 0.

    Examples
    --------
    >>> from fricgen import preset
    >>> curve = preset("paper3")
    >>> round(float(curve(0.5) - curve.stribeck(0.5) - curve.viscous * 0.5), 6)   # S sgn(v) + B v
    0.0
    """

    viscous: float

    def __call__(self, v) -> np.ndarray:
        """F(v)."""

    def stribeck(self, v) -> np.ndarray:
        """S(|v|), the velocity-weakening part (F(0+) at v = 0)."""


class Signals:
    """What an effect's force may depend on: t, x, v, a, i (arrays) and the friction curve.

    ``s`` is the friction-memory state (a low-passed speed) when a simulation carries it;
    otherwise ``lagged_speed`` filters |v| over the samples. With ``tabulate``, the curve's
    velocity-weakening part is interpolated from a table of 4097 speeds in [0, v_sat] (error
    ~1e-5 N), for fits that evaluate it many times. An asymmetric curve is read, at each
    sample, as the curve of the direction of v there ([F3] of each direction).

    Parameters
    ----------
    model : FrictionCurve
        F(v) of [F3] or [F1].
    t, x, v, a, i : ndarray, optional
        Time (s), position (m), velocity (m/s), acceleration (m/s^2), current (A).
    s : ndarray, optional
        The friction-memory state (m/s).
    sample_time : float, optional
        The uniform sampling interval (s), for ``lagged_speed``.
    tabulate : bool
        Interpolate the velocity-weakening part from a table (a ``FrictionModel`` only).
    friction : ndarray, optional
        The friction at each sample where it is not F(v): a model with memory (bristles)
        driven along the log (``FrictionModel.force_along``).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), v=np.array([0.0, 1.0]))
    >>> sig.stribeck_speed.round(1).tolist()          # sum f_s at rest, sum f_c far above v_s
    [44.0, 15.0]
    """

    def __init__(self, model: FrictionCurve, t=None, x=None, v=None, a=None, i=None, s=None,
                 sample_time: Optional[float] = None, tabulate: bool = False, friction=None):
        self.model, self.t, self.x, self.v, self.a, self.i, self.s = model, t, x, v, a, i, s
        self.sample_time = sample_time
        self._friction = friction
        self._stribeck_speed = None
        negative = getattr(model, "negative", None)
        #: the curve of v >= 0 (the model's own, at speeds u >= 0), then that of v < 0 if any
        self._curves = (model,) if negative is None else (model, negative)
        self._tables = None
        if tabulate:
            self._tables = tuple((float(c.v_sat), c.stribeck(np.linspace(0.0, c.v_sat, 4097)))
                                 for c in self._curves)

    @property
    def friction(self) -> np.ndarray:
        """F(v) of [F3] (or [F1]), or the friction given."""
        if self._friction is None:
            self._friction = self.model(self.v)
        return self._friction

    def stribeck(self, speed, v) -> np.ndarray:
        """The velocity-weakening part S(u) = |F(u)| - B u at speeds u >= 0 of the curve of the
        direction of ``v`` (broadcast with ``speed``): that of v < 0 where v < 0 if the curve
        is asymmetric, else the curve's own (F(0+) at v = 0)."""
        out = self._stribeck(0, speed)
        if len(self._curves) == 1:
            return out
        return np.where(np.asarray(v) < 0, self._stribeck(1, speed), out)

    def _stribeck(self, k: int, speed) -> np.ndarray:
        """S(u) of curve k of ``_curves`` (its table's interpolation when tabulated)."""
        if self._tables is not None:
            # linear interpolation on the uniform table: the cell is found by arithmetic, not
            # by search; constant beyond v_sat, as [F3]
            top, values = self._tables[k]
            cells = values.size - 1
            pos = np.clip(np.asarray(speed, dtype=float), 0.0, top) * (cells / top)
            k = np.minimum(pos.astype(np.intp), cells - 1)
            return values[k] + (pos - k) * (values[k + 1] - values[k])
        return self._curves[k].stribeck(speed)

    @property
    def stribeck_speed(self) -> np.ndarray:
        """The velocity-weakening part at the current speed |v|, of v's direction (cached)."""
        if self._stribeck_speed is None:
            self._stribeck_speed = self.stribeck(np.abs(self.v), self.v)
        return self._stribeck_speed

    def lagged_speed(self, tau: float) -> np.ndarray:
        """|v| low-passed with time constant ``tau`` (exact first-order discretization)."""
        if self.s is not None:
            return self.s
        speed = np.abs(self.v)
        alpha = 1.0 - math.exp(-self.sample_time / tau)
        out, _ = lfilter([alpha], [1.0, alpha - 1.0], speed, zi=[(1.0 - alpha) * speed[0]])
        return out
