"""One log of the fleet identified (a worker's task): trained with ``fricgen train``'s own code
(``cli.train.fit``): the grey-box [F1] (``--method stribeck``), one curve per direction
(``--asymmetric``), with the export options given, on the log less the position force it
holds (``training.with_cogging.less_position_force``: a cogging that changed is not friction
that changed); its hash is recorded. The friction
parameters come from the fleet's monitoring law (``law.fit_law``), one fixed law per direction
fitted to the same rows, so that every log of an axis is described in the same terms: the
Coulomb level F_c, the static peak F_s (F at v -> 0), the Stribeck velocity v_s and B, each
with its standard error. The trained model's own parameters would not compare: its shape,
number of sources and vs_max may change between two logs of one axis, and its Coulomb level
with them, by far more than its standard errors (which hold its structure fixed) say."""
from __future__ import annotations

import math
import os
import time
from dataclasses import asdict
from typing import Callable, Dict, List, Sequence

from ..errors import FricgenError
from .law import fit_law
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
    """The friction parameters (SI units) and their standard errors of one trained log (a
    ``FitReport``), per direction: the monitoring law (``law.fit_law``) fitted to the folded
    rows of each direction (of both, the same values, when the model is symmetric), binned to
    their independent samples. A log's rows hold its constant force, whether train kept it in
    the curves or apart as a load, so that every log of an axis is described alike.

    Parameters
    ----------
    trained : FitReport
        The training of one log (``TRAIN_FIT``).

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
    ident = trained.identification
    independence = ident.independent / ident.n_kept if ident is not None else 1.0
    sweep = trained.sweep if ident is None else ident.sweep     # a load held, as train may not
    symmetric = len(trained.fit.fits) == 1
    out = {}
    for d, sign in zip(DIRECTIONS, (1, -1)):
        half = (sweep if symmetric else sweep.direction(sign)).folded()
        law = fit_law(half, len(half) * independence)
        out.update({f"{p}_{d}" + suffix: law[p + suffix] for p in PARAMETERS
                    for suffix in ("", "_se")})
    return out


def identify(entry: Entry, options: Sequence[str], key: str, train: Callable) -> dict:
    """The result of one log (a worker's task): the entry, the model's hash, the mass, the
    cogging the log holds (its map's RMS and period: 0 and NaN for none; ``train`` takes it out
    before the friction is fitted), the friction parameters; or ``status`` failed and the one-line ``error`` of a log that cannot
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
        cogging = trained.model.cogging_map
        record.update(status="ok", error="", model_hash=trained.model.model_hash,
                      mass_identified=trained.identification.body.mass if trained.identification else math.nan,
                      cogging_rms=cogging.rms if cogging is not None else 0.0,
                      cogging_period=cogging.period if cogging is not None else math.nan,
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
