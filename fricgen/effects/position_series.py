"""Forces periodic in position, as a Fourier series of a fundamental period P (k = 2 pi / P):

    F(x) = sum_{h=1..H} A_h sin(h k x + phi_h) = sum_h a_h sin(h k x) + b_h cos(h k x),

with a_h = A_h cos(phi_h), b_h = A_h sin(phi_h): cogging or force ripple (``position_ripple``,
a force that acts at rest too) and a friction level that changes periodically along the travel
(``position_friction``: sgn(v) F(x), it acts against motion), extending [C1] as ``base`` says.

The fit finds P (a least-squares periodogram over wavenumbers, refined by Brent; the peak or
the fundamental it is the 2nd to 4th harmonic of), or takes the problem's ``pitch`` (a known
pole pitch or screw lead), chooses H (and the fundamental) by blocked cross-validation
(``fitting.choose_by_cross_validation``: the fewest harmonics within one standard error of the
best), and solves (a_h, b_h) by least squares. model.json holds ``amplitude`` and ``phase`` per
harmonic (lists, or numbers for one harmonic: the one-sinusoid form of earlier versions).
C evaluates sin(k x) and cos(k x) once and the harmonics by angle addition.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, ClassVar, Dict, Tuple

import numpy as np

from .._validate import finite_number
from ..c_literal import c_float
from ..errors import ModelError
from .base import Effect
from .fitting import choose_by_cross_validation, lstsq, refine

#: Most harmonics a fit tries; most a model.json may hold.
HARMONICS = 4
MAX_HARMONICS = 16


def _harmonics(value) -> Tuple[float, ...]:
    """A number or a sequence of numbers as a tuple (arrays, as a batch of axes stacks them
    (``sim.effect_law``), stay arrays)."""
    if isinstance(value, np.ndarray):
        return value
    if isinstance(value, (list, tuple)):
        return tuple(float(a) for a in value)
    return (float(value),)


def _waves(k: float, x: np.ndarray, harmonics: int, weight=None):
    """The function of sample indices that gives sin(h k x), cos(h k x), h = 1..H, interleaved
    (times ``weight`` if given), for ``ResidualProblem.at_rows``."""
    h = np.arange(1, harmonics + 1)

    def at(idx):
        arg = (k * x[idx])[..., None] * h
        out = np.stack([np.sin(arg), np.cos(arg)], axis=-1).reshape(*idx.shape, 2 * harmonics)
        return out if weight is None else out * weight[idx][..., None]
    return at


@dataclass(frozen=True)
class PositionSeries(Effect):
    """Base of the effects periodic in position: a Fourier series of fundamental period P.

    Parameters
    ----------
    amplitude : float or tuple of float
        A_h of each harmonic h = 1..H (N).
    period : float
        The fundamental period P (m), > 0.
    phase : float or tuple of float
        phi_h of each harmonic (rad).

    Notes
    -----
    .. math:: F(x) = \\sum_{h=1}^{H} A_h \\sin(2 \\pi h x / P + \\phi_h)

    times sgn(v) for ``position_friction``.

    Examples
    --------
    >>> from fricgen.effects import PositionRipple
    >>> r = PositionRipple(amplitude=(2.0, 0.5), period=0.01, phase=(0.0, 1.0))
    >>> r.harmonics, r.n_params, PositionRipple(2.0, 0.01, 0.0).amplitude
    (2, 5, (2.0,))
    """

    amplitude: Any
    period: float
    phase: Any
    #: Multiplied by sgn(v): a friction level rather than a force.
    signed: ClassVar[bool] = False
    in_xv: ClassVar[bool] = True
    acts_at_rest: ClassVar[bool] = True       # the simulation reads x only in external forces
    positive: ClassVar[Tuple[str, ...]] = ("period",)
    given_by_pitch: ClassVar[Tuple[str, ...]] = ("period",)

    def __post_init__(self):
        object.__setattr__(self, "amplitude", _harmonics(self.amplitude))
        object.__setattr__(self, "phase", _harmonics(self.phase))

    @property
    def harmonics(self) -> int:
        """H, the number of harmonics."""
        return int(np.shape(self.amplitude)[-1])

    @property
    def n_params(self) -> int:
        return 1 + 2 * self.harmonics

    def parameters(self) -> Dict[str, Any]:
        """Lists of A_h and phi_h, or numbers for one harmonic (the one-sinusoid form)."""
        if self.harmonics == 1:
            return {"amplitude": self.amplitude[0], "period": self.period, "phase": self.phase[0]}
        return {"amplitude": list(self.amplitude), "period": self.period, "phase": list(self.phase)}

    def coefficients(self) -> Tuple[np.ndarray, np.ndarray]:
        """a_h = A_h cos(phi_h) and b_h = A_h sin(phi_h), the sine and cosine coefficients."""
        amp, ph = np.asarray(self.amplitude, float), np.asarray(self.phase, float)
        return amp * np.cos(ph), amp * np.sin(ph)

    def _sign(self, sig):
        return np.sign(np.asarray(sig.v)) if self.signed else 1.0

    def force(self, sig):
        k = 2 * np.pi / np.asarray(self.period) * np.asarray(sig.x)
        amp, ph = np.asarray(self.amplitude), np.asarray(self.phase)
        total = sum(amp[..., h] * np.sin((h + 1) * k + ph[..., h]) for h in range(self.harmonics))
        return self._sign(sig) * total

    def linear(self, sig):
        k = 2 * np.pi / self.period
        x = np.asarray(sig.x, dtype=float)
        weight = np.sign(np.asarray(sig.v, dtype=float)) if self.signed else None
        regressors = _waves(k, x, self.harmonics, weight)(np.arange(x.size))
        a, b = self.coefficients()
        return regressors, np.column_stack([a, b]).ravel()

    def with_coefficients(self, coef):
        a, b = np.asarray(coef, dtype=float).reshape(-1, 2).T
        return replace(self, amplitude=tuple(float(v) for v in np.hypot(a, b)),
                       phase=tuple(float(v) for v in np.arctan2(b, a) % (2 * np.pi)))

    @classmethod
    def from_dict(cls, d: dict) -> "PositionSeries":
        params, where = cls.parameters_of(d, ("amplitude", "period", "phase"))
        for key in ("amplitude", "period", "phase"):
            if key not in params:
                raise ModelError(f"{where}.parameters: missing field {key!r}")
        period = params["period"]
        if not finite_number(period):
            raise ModelError(f"{where}.parameters.period must be a finite number, got {period!r}"[:200])
        if period <= 0:
            raise ModelError(f"{where}.parameters.period must be > 0, got {period}")
        lists = {}
        for key in ("amplitude", "phase"):
            value = params[key]
            items = value if isinstance(value, list) else [value]
            if not 1 <= len(items) <= MAX_HARMONICS or not all(finite_number(a) for a in items):
                raise ModelError(f"{where}.parameters.{key} must be a finite number or a list of 1 "
                                 f"to {MAX_HARMONICS} finite numbers, got {value!r}"[:200])
            lists[key] = tuple(float(a) for a in items)
        if len(lists["amplitude"]) != len(lists["phase"]):
            raise ModelError(f"{where}.parameters: amplitude and phase must list as many harmonics, "
                             f"got {len(lists['amplitude'])} and {len(lists['phase'])}")
        return cls(amplitude=lists["amplitude"], period=float(period), phase=lists["phase"])

    @classmethod
    def fit(cls, problem, rows) -> "PositionSeries":
        """P from the problem's ``pitch`` or by the periodogram and Brent (the peak, or the
        fundamental it is a harmonic of), H by blocked cross-validation (one-standard-error
        rule), (a_h, b_h) by least squares."""
        x, r = problem.signals.x, problem.target[rows]
        weight = np.sign(problem.signals.v) if cls.signed else None

        def design(k, harmonics):
            return problem.at_rows(_waves(k, x, harmonics, weight), rows)

        def rss(harmonics):
            return lambda k: lstsq(design(k, harmonics), r)[1]

        pitch = getattr(problem, "pitch", None)
        if pitch is not None:
            fundamentals = [(1, 2 * np.pi / pitch)]
        else:
            ks, j = cls._periodogram(problem, rows)
            lo, hi = ks[max(j - 1, 0)], ks[min(j + 1, ks.size - 1)]
            # the periodogram's peak may be a harmonic (a slot harmonic of cogging often
            # outweighs the fundamental): the fundamentals peak / m whose period the travel
            # holds, each with the peak as its m-th harmonic, compete with the peak itself
            peak = refine(rss(1), lo, hi)
            fundamentals = [(m, peak / m) for m in range(1, HARMONICS + 1) if ks[j] / m >= ks[0]]
        # one cross-validation over every fundamental's series, the fewest harmonics first
        options = []
        for m, k_m in fundamentals:
            basis = design(k_m, HARMONICS)
            options += [(h, m, k_m, basis[:, :2 * h]) for h in range(1, HARMONICS + 1)]
        options.sort(key=lambda o: o[:2])
        harmonics, m, k, basis = options[choose_by_cross_validation([o[3] for o in options], r) - 1]
        if pitch is None and harmonics > 1:         # the harmonics sharpen the period
            k = refine(rss(harmonics), lo / m, hi / m)
            basis = design(k, harmonics)
        coef, _ = lstsq(basis[:, :2 * harmonics], r)
        return cls(amplitude=(0.0,) * harmonics, period=float(2 * np.pi / k),
                   phase=(0.0,) * harmonics).with_coefficients(coef)

    @classmethod
    def _periodogram(cls, problem, rows) -> Tuple[np.ndarray, int]:
        """The wavenumbers of ``problem.ripple_bank`` and the index of the one whose sinusoid
        (times sgn(v), constant over the window at the rows, for a signed series) reduces the
        residual's sum of squares most."""
        ks, bank = problem.ripple_bank()
        B = bank[:, rows, :]                                   # (K, n, 2)
        if cls.signed:
            B = B * np.sign(problem.v_smooth[problem.rows[rows]])[None, :, None]
        G = np.einsum("kni,knj->kij", B, B)
        b = np.einsum("kni,n->ki", B, problem.target[rows])
        coef = np.linalg.solve(G + 1e-12 * np.eye(2), b[..., None])[..., 0]
        gain = np.einsum("ki,ki->k", coef, b)                  # RSS reduction per wavenumber
        return ks, int(np.argmax(gain))

    # C: a static helper evaluates the series: sin(kx), cos(kx) once, the harmonics by angle addition
    def c_function(self, symbol: str) -> str:
        a, b = self.coefficients()
        n = self.harmonics
        return "\n".join([
            f"/* {self.name}: sum over h = 1..{n} of a_h sin(h k x) + b_h cos(h k x), k = 2 pi / "
            f"{self.period:.6g} m; the harmonics by angle addition. */",
            f"static float {symbol}(float x)",
            "{",
            f"    static const float a[{n}] = {{{', '.join(c_float(c) for c in a)}}};",
            f"    static const float b[{n}] = {{{', '.join(c_float(c) for c in b)}}};",
            f"    const float s1 = sinf({c_float(2 * np.pi / self.period)} * x);",
            f"    const float c1 = cosf({c_float(2 * np.pi / self.period)} * x);",
            "    float s = s1;",
            "    float c = c1;",
            "    float f = 0.0f;",
            "    int h;",
            f"    for (h = 0; h < {n}; h++) {{",
            "        const float s_next = (s * c1) + (c * s1);",
            "        const float c_next = (c * c1) - (s * s1);",
            "        f = f + ((a[h] * s) + (b[h] * c));",
            "        s = s_next;",
            "        c = c_next;",
            "    }",
            "    return f;",
            "}",
            ""])

    def c_call(self, symbol: str) -> str:
        return f"sgn * {symbol}(x)" if self.signed else f"{symbol}(x)"

    def force_f32(self, v, x, base):
        """Float32 mirror of ``c_function`` (same operations, same order)."""
        f32 = np.float32
        x = np.asarray(x, dtype=f32)
        arg = (f32(2 * np.pi / self.period) * x).astype(np.float64)
        s1, c1 = np.sin(arg).astype(f32), np.cos(arg).astype(f32)
        s, c, f = s1, c1, np.zeros_like(x)
        for a, b in zip(*(np.asarray(u, dtype=f32) for u in self.coefficients())):
            s, c, f = (s * c1) + (c * s1), (c * c1) - (s * s1), f + ((a * s) + (b * c))
        if not self.signed:
            return f
        v = np.asarray(v, dtype=f32)
        return np.where(v > 0, f32(1), np.where(v < 0, f32(-1), f32(0))).astype(f32) * f


@dataclass(frozen=True)
class PositionRipple(PositionSeries):
    """Cogging / force ripple, periodic in position: sum_h A_h sin(2 pi h x / P + phi_h)
    (``PositionSeries``), a force that acts at rest too.

    Parameters
    ----------
    amplitude : float or tuple of float
        A_h of each harmonic (N).
    period : float
        The fundamental period P (m), > 0.
    phase : float or tuple of float
        phi_h of each harmonic (rad).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), t=np.array([0.0, 1.0]), x=np.array([0.0, 0.25]),
    ...               v=np.array([0.1, -0.1]), a=np.array([2.0, 2.0]), i=np.array([1.0, 1.0]),
    ...               sample_time=1.0)
    >>> from fricgen.effects import PositionRipple
    >>> PositionRipple(amplitude=2.0, period=1.0, phase=0.0).force(sig).round(3).tolist()
    [0.0, 2.0]
    """

    name: ClassVar[str] = "position_ripple"


@dataclass(frozen=True)
class PositionFriction(PositionSeries):
    """A friction level periodic in position: sgn(v) sum_h A_h sin(2 pi h x / P + phi_h)
    (``PositionSeries``), which acts against motion (a screw's or a guide's periodic drag).

    Parameters
    ----------
    amplitude : float or tuple of float
        A_h of each harmonic (N).
    period : float
        The fundamental period P (m), > 0.
    phase : float or tuple of float
        phi_h of each harmonic (rad).

    Examples
    --------
    >>> import numpy as np
    >>> from fricgen import preset
    >>> from fricgen.effects import Signals
    >>> sig = Signals(preset("paper3"), x=np.array([0.25, 0.25]), v=np.array([0.1, -0.1]))
    >>> from fricgen.effects import PositionFriction
    >>> PositionFriction(amplitude=2.0, period=1.0, phase=0.0).force(sig).round(3).tolist()
    [2.0, -2.0]
    """

    name: ClassVar[str] = "position_friction"
    signed: ClassVar[bool] = True
