"""One log of the fleet identified (a worker's task): trained with ``fricgen train``'s own code
(``cli.train.fit``): the grey-box [F1] (``--method stribeck``), one curve per direction
(``--asymmetric``), with the export options given. From each direction's curve come the Coulomb
level sum f_c, the static peak f_s = sum f_c + sum (f_s - f_c) (F at v -> 0), the Stribeck
velocity v_s of the largest source and B, each with its standard error
(``StribeckRegressor.standard_errors_``; B's from the high-speed line, ``data.viscous.viscous_se``,
NaN where B was fitted with the sources)."""
from __future__ import annotations

import math
import os
import time
from dataclasses import asdict
from typing import Callable, Dict, List, Sequence

import numpy as np

from ..data.viscous import viscous_se
from ..errors import FricgenError
from .manifest import Entry
from .store import RESULT_VERSION

#: Every parameter of a result, per direction, each with ``_se``.
PARAMETERS = ("coulomb", "static", "stribeck", "viscous")
DIRECTIONS = ("pos", "neg")
#: How ``train`` fits a fleet's logs (the grey-box [F1], one curve per direction).
TRAIN_FIT = ("--method", "stribeck", "--asymmetric")


def train_arguments(entry: Entry, options: Sequence[str]) -> List[str]:
    """The ``fricgen train`` arguments of one log: the fleet's fit, the options and the row's
    mass and force constant."""
    argv = [entry.log, *TRAIN_FIT, "-o", os.devnull, *options]
    if entry.mass is not None:
        argv += ["--mass", repr(entry.mass)]
    if entry.force_constant is not None:
        argv += ["--force-constant", repr(entry.force_constant)]
    return argv


def friction_parameters(trained) -> Dict[str, float]:
    """The friction parameters (SI units) and their standard errors of a model ``cli.train.fit``
    fitted with the grey-box [F1] (a ``FitReport``), per direction (the same values for both when the fit is
    symmetric): see the module.

    Parameters
    ----------
    trained : FitReport
        The training of one log with the grey-box model (``TRAIN_FIT``).

    Returns
    -------
    dict of str to float
        ``coulomb_pos``, ``static_pos``, ``stribeck_pos``, ``viscous_pos`` (N, N, m/s, N s/m), the
        same for ``neg``, each with its ``_se``.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.fleet import friction_parameters
    >>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
    >>> report = fricgen.train(sweep, vs_max=0.02, estimator=fricgen.StribeckRegressor())
    >>> p = friction_parameters(report)
    >>> sorted(k for k in p if k.endswith("_pos")), p["coulomb_pos"] == p["coulomb_neg"]
    (['coulomb_pos', 'static_pos', 'stribeck_pos', 'viscous_pos'], True)
    """
    fits = trained.fit.fits
    ident = trained.identification
    independence = ident.independent / ident.n_kept if ident is not None else 1.0
    out = {}
    for k, d in enumerate(DIRECTIONS):
        fit = fits[min(k, len(fits) - 1)]
        est, ds = fit.estimator, fit.dataset
        net, se = est.network_, est.standard_errors_
        k_in, k_out = ds.scaling.k_in, ds.scaling.k_out
        big = int(np.argmax(np.abs(net.amplitudes)))
        half = (trained.sweep.folded() if len(fits) == 1 else
                trained.sweep.direction(1 if k == 0 else -1).folded())
        high = type(half)(half.v[half.v > ds.v_sat], half.f[half.v > ds.v_sat])
        out.update({
            f"coulomb_{d}": net.offset / k_out, f"coulomb_{d}_se": se["offset"] / k_out,
            f"static_{d}": (net.offset + float(np.sum(net.amplitudes))) / k_out,
            f"static_{d}_se": se["peak"] / k_out,
            f"stribeck_{d}": float(net.stribeck[big]) / k_in,
            f"stribeck_{d}_se": float(se["stribeck"][big]) / k_in,
            f"viscous_{d}": ds.viscous + net.slope * k_in / k_out,
            f"viscous_{d}_se": viscous_se(high, ds.viscous, independence)
            if ds.n_high_speed else math.nan,
        })
    return {k: float(v) for k, v in out.items()}


def identify(entry: Entry, options: Sequence[str], key: str, train: Callable) -> dict:
    """The result of one log (a worker's task): the entry, the model's hash, the mass, the
    friction parameters; or ``status`` failed and the one-line ``error`` of a log that cannot
    be trained (``stored`` False for an unexpected error, tried again on a rerun).

    Parameters
    ----------
    entry : Entry
        The manifest row.
    options : sequence of str
        ``train``'s options for every log (the export options).
    key : str
        The result's key (``result_key``).
    train : callable
        Trains a log from ``train``'s arguments (``cli.train.train_argv``).

    Returns
    -------
    dict
        The result record.

    Examples
    --------
    >>> from fricgen.fleet import Entry, identify
    >>> from fricgen.cli.train import train_argv
    >>> record = identify(Entry("x1", str(tmp / "missing.csv"), "2026"), [], "k", train_argv)
    >>> record["status"], "missing.csv" in record["error"]
    ('failed', True)
    """
    record = {**asdict(entry), "key": key, "version": RESULT_VERSION}
    start = time.perf_counter()
    try:
        trained = train(train_arguments(entry, options))
        record.update(status="ok", error="", model_hash=trained.model.model_hash,
                      mass_identified=trained.identification.body.mass if trained.identification else math.nan,
                      **friction_parameters(trained))
    except (FricgenError, OSError) as exc:
        where = f"{exc.filename}: " if isinstance(exc, OSError) and exc.filename else ""
        text = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        record.update(status="failed", error=(where + text).splitlines()[0][:300])
        record["stored"] = isinstance(exc, FricgenError)
    except Exception as exc:            # a bug: recorded, the others go on, tried again next run
        record.update(status="failed", error=f"{type(exc).__name__}: {exc}".splitlines()[0][:300],
                      stored=False)
    record["seconds"] = time.perf_counter() - start
    return record
