"""Friction data (section 2): sweeps, the paper benchmark, B identification, eq. (9) targets."""
from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, Optional, Sequence, Tuple, Union

import numpy as np

from .friction import MultisourceFriction

#: Fewest rows a sweep may have before training refuses it.
MIN_ROWS = 20
#: Fewest high-speed rows (|v| > v_sat) the regression for B needs.
MIN_HIGH_SPEED_ROWS = 5
#: v_sat = SAT_FACTOR * vs_max: beyond it g(v, v_s) ~ 0 and eq. (3) saturates the network input.
SAT_FACTOR = 3.0


class DataError(ValueError):
    """Unusable friction data; the message names the problem in one line."""


@dataclass(frozen=True)
class Sweep:
    """A measured (or synthesized) friction sweep: velocity v (m/s) and force f (N)."""

    v: np.ndarray
    f: np.ndarray

    def __post_init__(self):
        v = np.asarray(self.v, dtype=float).ravel()
        f = np.asarray(self.f, dtype=float).ravel()
        if v.shape != f.shape:
            raise DataError(f"v and f must have equal lengths, got {v.size} and {f.size}")
        if not (np.all(np.isfinite(v)) and np.all(np.isfinite(f))):
            raise DataError("sweep contains NaN or infinite values")
        object.__setattr__(self, "v", v)
        object.__setattr__(self, "f", f)

    def __len__(self):
        return self.v.size

    def folded(self) -> "Sweep":
        """The symmetric fold: (|v|, sgn(v) f), so negative velocities join the positive half."""
        s = np.sign(self.v)
        keep = s != 0
        return Sweep(np.abs(self.v[keep]), (s * self.f)[keep])

    def concat(self, other: "Sweep") -> "Sweep":
        return Sweep(np.concatenate([self.v, other.v]), np.concatenate([self.f, other.f]))


def read_table_csv(path: Union[str, Path], required: Sequence[str],
                   keep_extra: bool = False) -> Dict[str, np.ndarray]:
    """Read a numeric CSV whose header names (at least) the ``required`` columns.

    Returns the columns by lower-case name: the required ones and, with ``keep_extra``, all
    others. Blank lines are skipped; a missing column or a non-numeric cell raises ``DataError``
    naming the file and line. Finiteness and lengths are for the caller to judge.
    """
    rows = list(csv.reader(io.StringIO(Path(path).read_text())))
    if not rows:
        raise DataError(f"{path}: empty file")
    header = [h.strip().lower() for h in rows[0]]
    missing = [c for c in required if c not in header]
    if missing:
        raise DataError(f"{path}: missing column {', '.join(repr(c) for c in missing)} "
                        f"(header is {','.join(header)[:80]})")
    wanted = [k for k, h in enumerate(header) if keep_extra or h in required]
    data = []
    for n, row in enumerate(rows[1:], start=2):
        if not any(c.strip() for c in row):
            continue
        try:
            data.append([float(row[k]) for k in wanted])
        except (ValueError, IndexError):
            raise DataError(f"{path}: line {n}: non-numeric or missing cell in "
                            f"{','.join(row)[:80]!r}") from None
    table = np.array(data, dtype=float).reshape(len(data), len(wanted))
    return {header[k]: table[:, j] for j, k in enumerate(wanted)}


def table_csv_text(columns: Dict[str, np.ndarray]) -> str:
    """CSV text of named columns (in the given order), floats written to round-trip."""
    names = list(columns)
    lines = [",".join(names)]
    lines += [",".join(repr(float(c)) for c in row)
              for row in zip(*(np.asarray(columns[k]).tolist() for k in names))]
    return "\n".join(lines) + "\n"


def read_sweep_csv(path: Union[str, Path]) -> Sweep:
    """Read a CSV with a header naming columns ``v`` and ``f`` (SI units; other columns ignored)."""
    cols = read_table_csv(path, ("v", "f"))
    v, f = cols["v"], cols["f"]
    bad = ~(np.isfinite(v) & np.isfinite(f))
    if bad.any():
        raise DataError(f"{path}: data row {int(np.flatnonzero(bad)[0]) + 1}: NaN or infinite value")
    if v.size < MIN_ROWS:
        raise DataError(f"{path}: {v.size} data rows, need at least {MIN_ROWS}")
    return Sweep(v, f)


def sweep_csv_text(sweep: Sweep) -> str:
    """The CSV text of a sweep, columns v,f, floats written to round-trip."""
    return table_csv_text({"v": sweep.v, "f": sweep.f})


def identify_viscous(high: Sweep) -> Tuple[float, float]:
    """B and the intercept of the line f = F0 + B v through high-speed folded data (section 2)."""
    if len(high) < MIN_HIGH_SPEED_ROWS:
        raise DataError(f"no high-speed data for B: {len(high)} rows beyond v_sat, "
                        f"need at least {MIN_HIGH_SPEED_ROWS}")
    if np.ptp(high.v) <= 0:
        raise DataError("high-speed data for B spans no velocity range")
    A = np.column_stack([np.ones_like(high.v), high.v])
    (f0, B), *_ = np.linalg.lstsq(A, high.f, rcond=None)
    return float(B), float(f0)


def estimate_vs_max(folded: Sweep) -> float:
    """Estimate vs_max from a folded sweep when the user gives none.

    A line is fitted to the fastest quarter of the data (assumed free of the Stribeck effect);
    the excess force over that line is averaged in velocity bins, and the fastest bin whose
    excess still stands 3 standard errors above zero marks the end of the Stribeck region.
    Eq. (2) shapes have fallen to a few percent at 2 v_s, so vs_max is taken as half that edge.
    """
    order = np.argsort(folded.v)
    v, f = folded.v[order], folded.f[order]
    fast = v >= np.quantile(v, 0.75)
    if fast.sum() < MIN_HIGH_SPEED_ROWS:
        raise DataError("too few data to estimate vs_max; pass --vs-max")
    coef = np.polyfit(v[fast], f[fast], 1)
    resid = f - np.polyval(coef, v)
    sigma = max(np.std(resid[fast]), 1e-12)
    edges = np.quantile(v, np.linspace(0.0, 0.75, 16))
    edge = edges[1]
    for lo, hi in zip(edges[:-1], edges[1:]):
        inside = (v >= lo) & (v < hi)
        if inside.sum() >= 3 and resid[inside].mean() > 3 * sigma / np.sqrt(inside.sum()):
            edge = hi
    return float(edge / 2.0)


@dataclass(frozen=True)
class Scaling:
    """Normalization of eq. (9): x = K_in v, t = K_out (F - B v)."""

    k_in: float
    k_out: float


@dataclass(frozen=True)
class Dataset:
    """Normalized training data of eq. (9) with what eq. (3) needs to rebuild forces."""

    x: np.ndarray
    t: np.ndarray
    scaling: Scaling
    viscous: float
    v_sat: float
    vs_max_estimated: bool = False
    n_high_speed: int = 0

    def targets(self, v, f) -> Tuple[np.ndarray, np.ndarray]:
        """Eq. (9) applied to other (folded) data: (K_in v, K_out (f - B v))."""
        v = np.asarray(v, dtype=float)
        return self.scaling.k_in * v, self.scaling.k_out * (np.asarray(f, dtype=float) - self.viscous * v)


def prepare(sweep: Sweep, vs_max: Optional[float] = None, f_sat: Optional[float] = None,
            viscous: Optional[float] = None) -> Dataset:
    """Turn a sweep into the eq. (9) training set of section 2.

    The sweep is folded (symmetric model). Rows with |v| > v_sat = 3 vs_max identify B by linear
    regression (unless ``viscous`` is given); rows within [0, v_sat] become training data, with
    the two added points (0, mean force of the four slowest rows) and (v_sat, f_sat), where f_sat
    defaults to the high-speed line evaluated at v_sat. K_in = 1/v_sat, K_out = 1/max(t).
    """
    if vs_max is not None and not (np.isfinite(vs_max) and vs_max > 0):
        raise DataError(f"vs_max must be > 0, got {vs_max}")
    if len(sweep) < MIN_ROWS:
        raise DataError(f"sweep has {len(sweep)} rows, need at least {MIN_ROWS}")
    folded = sweep.folded()
    estimated = vs_max is None
    if estimated:
        vs_max = estimate_vs_max(folded)
    v_sat = SAT_FACTOR * vs_max
    high = Sweep(folded.v[folded.v > v_sat], folded.f[folded.v > v_sat])
    low = Sweep(folded.v[folded.v <= v_sat], folded.f[folded.v <= v_sat])
    if viscous is None:
        viscous, f0 = identify_viscous(high)
    else:
        f0 = float(np.mean(high.f - viscous * high.v)) if len(high) else None
    if len(low) < MIN_ROWS:
        raise DataError(f"{len(low)} rows within [0, v_sat = {v_sat:g}], need at least {MIN_ROWS}")
    if f_sat is None:
        if f0 is None:
            raise DataError("no high-speed data to anchor the force at v_sat")
        f_sat = f0 + viscous * v_sat
    slowest = np.argsort(low.v)[:4]
    v = np.concatenate([[0.0], low.v, [v_sat]])
    f = np.concatenate([[low.f[slowest].mean()], low.f, [f_sat]])
    k_in = 1.0 / v_sat
    t_raw = f - viscous * v
    peak = np.max(t_raw)
    if not peak > 0:
        raise DataError("friction minus viscous part is never positive: not a friction sweep")
    scaling = Scaling(k_in=float(k_in), k_out=float(1.0 / peak))
    return Dataset(x=k_in * v, t=scaling.k_out * t_raw, scaling=scaling, viscous=float(viscous),
                   v_sat=float(v_sat), vs_max_estimated=estimated, n_high_speed=len(high))


@dataclass(frozen=True)
class Benchmark:
    """The paper's benchmark (section 2) for one seed."""

    friction: MultisourceFriction
    vs_max: float
    train: Sweep          # N noisy points in [0, v_sat] plus the high-speed points
    test: Sweep           # another N noisy points in [0, v_sat]
    theory: Sweep         # Nt equidistant noise-free points in [0, v_sat]
    dataset: Dataset = field(repr=False)

    def errors(self, aim) -> dict:
        """E_train, E_test, E_Ttest of eqs. (4)-(6), normalized and in newtons, for AIM ``aim``."""
        d = self.dataset
        x_test, t_test = d.targets(self.test.v, self.test.f)
        x_th, t_th = d.targets(self.theory.v, self.theory.f)
        out = {"e_train": rmse(aim(d.x), d.t), "e_test": rmse(aim(x_test), t_test),
               "e_ttest": rmse(aim(x_th), t_th)}
        for key in list(out):
            out[key + "_newton"] = out[key] / d.scaling.k_out
        return out


def rmse(y, t) -> float:
    """Root-mean-square error, eqs. (4)-(6)."""
    return float(np.sqrt(np.mean((np.asarray(y) - np.asarray(t)) ** 2)))


def synthesize_benchmark(friction: MultisourceFriction, seed=0, vs_max: Optional[float] = None,
                         n_train: int = 200, n_test: int = 200, n_theory: int = 500,
                         noise: float = 0.5, n_high: int = 100, high_factor: float = 10.0) -> Benchmark:
    """Synthesize the paper benchmark exactly (section 2) plus high-speed data for B.

    Training: ``n_train`` velocities uniform in [0, 3 vs_max] with noise uniform in
    [-noise, noise] N; ``prepare`` adds (0, mean of the four slowest) and (3 vs_max, F(3 vs_max))
    with the true F, as the paper does. Test: another ``n_test`` such points. Theory: ``n_theory``
    equidistant noise-free points. High speed: ``n_high`` noisy points uniform in
    (3 vs_max, high_factor vs_max] for the regression of B.
    """
    rng = np.random.default_rng(seed)
    vs_max = friction.vs_max if vs_max is None else vs_max
    v_sat = SAT_FACTOR * vs_max

    def noisy(v):
        return Sweep(v, friction(v) + rng.uniform(-noise, noise, v.size))

    train = noisy(rng.uniform(0.0, v_sat, n_train))
    test = noisy(rng.uniform(0.0, v_sat, n_test))
    high = noisy(rng.uniform(v_sat, high_factor * vs_max, n_high))
    v_th = np.linspace(0.0, v_sat, n_theory)
    theory = Sweep(v_th, friction.stribeck(v_th) + friction.viscous * v_th)  # F(0+) at v = 0
    measured = train.concat(high)
    dataset = prepare(measured, vs_max=vs_max, f_sat=float(friction(v_sat)))
    return Benchmark(friction=friction, vs_max=vs_max, train=measured, test=test, theory=theory,
                     dataset=dataset)
