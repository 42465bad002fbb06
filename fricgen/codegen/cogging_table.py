"""The cogging map as the firmware evaluates it: a table of N points of one period (N a power of
two, the fewest whose linear interpolation stays within TABLE_TOLERANCE of the map's RMS),
in float (``NAME_cogging(x)``), in q15 (``NAME_cogging_q15(phase)``) and in q31
(``NAME_cogging_q31(phase)``), the phase a uint32 with 2^32 per period (an encoder count times
2^(32 - bits) for a power-of-two encoder). Each comes with the largest error against the fitted
series, measured here over the whole period, and the integer arithmetic mirrored in numpy
(``q15_twin``, ``q31_twin``) so that tests compare the C bit for bit. ``blob`` gives the
bytes ``NAME_cogging_map_save`` writes, for one unit's non-volatile memory.
"""
from __future__ import annotations

import math
import struct
import zlib
from dataclasses import dataclass

import numpy as np

from ..c_literal import c_float
from ..effects.cogging_map import ERROR_GRID, MAX_TABLE, CoggingMap

#: The table's interpolation error allowed, as a fraction of the map's RMS.
TABLE_TOLERANCE = 0.01
#: The format of a saved map (NAME_COGGING_MAP_FORMAT), and the hash characters it holds.
MAP_FORMAT = 1
MAP_HASH_CHARS = 16
#: q15's largest magnitude.
Q15_MAX = 32767
#: q31's largest magnitude.
Q31_MAX = 2 ** 31 - 1


@dataclass(frozen=True)
class CoggingTable:
    """The tables and their error bounds (N or Nm)."""

    map: CoggingMap
    points: int
    values: np.ndarray        # float32, N
    float_bound: float
    q15: np.ndarray           # int16, N
    q15_scale: float          # the force of q15 32768
    q15_bound: float
    q31: np.ndarray           # int32, N
    q31_scale: float          # the force of q31 2^31
    q31_bound: float

    @classmethod
    def of(cls, cogging: CoggingMap) -> "CoggingTable":
        points, interpolation = cogging.table_size(TABLE_TOLERANCE * cogging.rms)
        exact = cogging.table(points)
        values = exact.astype(np.float32)
        peak = float(np.max(np.abs(exact)))
        scale = peak * 32768.0 / Q15_MAX if peak > 0 else 1.0
        q15 = np.clip(np.round(exact / scale * 32768.0), -Q15_MAX, Q15_MAX).astype(np.int16)
        scale31 = peak * 2.0 ** 31 / Q31_MAX if peak > 0 else 1.0
        q31 = np.clip(np.round(exact / scale31 * 2.0 ** 31), -Q31_MAX, Q31_MAX).astype(np.int32)
        eps = float(np.finfo(np.float32).eps)
        slope = float(np.sum(cogging.amplitude * cogging.wavenumber * np.asarray(cogging.harmonics)))
        # float: the interpolation's error, float32 rounding of table and product, and the
        # series' slope times the rounding of the phase (two roundings of u, up to the table's
        # size: eps of a period each; the reduction adds none within 4096 periods)
        float_bound = interpolation + 4 * eps * peak + 2 * eps * cogging.period * slope
        # q15: evaluated at ERROR_GRID phases per interval (the integer arithmetic exactly) plus
        # what lies between them: the series' slope times a grid step, and one LSB
        phases = (np.arange(points * ERROR_GRID, dtype=np.uint64) << np.uint64(32)) // np.uint64(points * ERROR_GRID)
        want = cogging.force(phases.astype(float) / 2.0 ** 32 * cogging.period)
        between = slope * cogging.period / (points * ERROR_GRID)
        got = q15_twin(q15, phases.astype(np.uint32)) * (scale / 32768.0)
        q15_bound = float(np.max(np.abs(got - want))) + between + scale / 32768.0
        got = q31_twin(q31, phases.astype(np.uint32)) * (scale31 / 2.0 ** 31)
        q31_bound = float(np.max(np.abs(got - want))) + between + scale31 / 2.0 ** 31
        return cls(cogging, points, values, float_bound, q15, scale, q15_bound, q31, scale31,
                   q31_bound)

    def shortfall(self, name: str, unit: str) -> str:
        """One line where the largest table (MAX_TABLE points) leaves the float map further from
        the series than TABLE_TOLERANCE of its RMS (harmonics too fine for it), else ""."""
        if self.points < MAX_TABLE or self.float_bound <= TABLE_TOLERANCE * self.map.rms:
            return ""
        return (f"fricgen: warning: the cogging table's {self.points} points hold the map within "
                f"{self.float_bound:.3g} {unit}, {self.float_bound / self.map.rms:.1%} of its RMS "
                f"(not {TABLE_TOLERANCE:.0%}): harmonic {max(self.map.harmonics)} of the period is too "
                f"fine for them; {name.upper()}_COGGING_ERROR_BOUND states it")

    @property
    def shift(self) -> int:
        return phase_shift(self.points)

    def context(self) -> dict:
        """The template's values for ``cogging.c.j2`` and the header."""
        m = self.map
        mantissa, exponent = math.frexp(m.period)
        period_hi = math.ldexp(round(mantissa * 4096) / 4096, exponent)     # 12 significant bits
        return {
            "points": self.points, "shift": self.shift, "period": c_float(m.period),
            "per_unit": c_float(self.points / m.period), "inv_period": c_float(1.0 / m.period),
            "period_hi": c_float(period_hi), "period_lo": c_float(m.period - period_hi),
            "values": [c_float(v) for v in self.values],
            "q15": [str(int(q)) for q in self.q15], "q15_scale": c_float(self.q15_scale),
            "float_bound": c_float(self.float_bound), "q15_bound": c_float(self.q15_bound),
            "q31": [str(int(q)) for q in self.q31], "frac_mask": f"0x{(1 << self.shift) - 1:X}u",
            "unit_shift": str(1 << self.shift), "half": str(1 << (self.shift - 1)),
            "offset_shifted": str(1 << (62 - self.shift)),
            "q31_scale": c_float(self.q31_scale), "q31_bound": c_float(self.q31_bound),
            "harmonics": ", ".join(str(h) for h in m.harmonics), "rms": f"{m.rms:.4g}"}

    def blob(self, model_hash: str) -> bytes:
        """The bytes of ``NAME_cogging_map_save`` for this table (NAME.h describes them):
        "FRCM", format and points, the period's float32 bits, ``model_hash`` NUL-padded to
        MAP_HASH_CHARS, the table's float32 values, and their CRC-32; little-endian."""
        code = model_hash.encode("ascii")
        if len(code) > MAP_HASH_CHARS:
            raise ValueError(f"a map's blob holds a hash of at most {MAP_HASH_CHARS} characters, "
                             f"got {len(code)}")
        body = (b"FRCM" + struct.pack("<HHf", MAP_FORMAT, self.points, np.float32(self.map.period))
                + code.ljust(MAP_HASH_CHARS, b"\0") + self.values.astype("<f4").tobytes())
        return body + struct.pack("<I", zlib.crc32(body))


def phase_shift(points: int) -> int:
    """32 - log2 N: the bits of a uint32 phase below the index of a table of N points."""
    return 32 - int(points).bit_length() + 1


def q15_twin(table: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """``NAME_cogging_q15`` in numpy: the same integer operations on the same int16 table."""
    points = table.size
    shift = phase_shift(points)
    phase = np.asarray(phase, dtype=np.uint64)
    k = (phase >> np.uint64(shift)).astype(np.int64)
    frac = ((phase >> np.uint64(shift - 15)) & np.uint64(0x7FFF)).astype(np.int64)
    lo = table.astype(np.int64)[k]
    hi = table.astype(np.int64)[(k + 1) & (points - 1)]
    y = lo * 32768 + (hi - lo) * frac + 16384 + 1073741824
    return ((y.astype(np.uint64) >> np.uint64(15)).astype(np.int64) - 32768).astype(np.int16)


def q31_twin(table: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """``NAME_cogging_q31`` in numpy: the same integer operations on the same int32 table (the
    interpolation in 64 bits, rounded, the offset 2^62 keeping the shift on a positive value)."""
    points = table.size
    shift = phase_shift(points)
    phase = np.asarray(phase, dtype=np.uint64)
    k = (phase >> np.uint64(shift)).astype(np.int64)
    frac = (phase & np.uint64((1 << shift) - 1)).astype(np.int64)
    lo = table.astype(np.int64)[k]
    hi = table.astype(np.int64)[(k + 1) & (points - 1)]
    y = (lo << shift) + (hi - lo) * frac + (1 << (shift - 1)) + (1 << 62)
    return ((y.astype(np.uint64) >> np.uint64(shift)).astype(np.int64) - (1 << (62 - shift))).astype(np.int32)
