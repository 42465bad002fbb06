"""Fleets of axes on Dask: identify every axis of a manifest from its log, keep each result, and
flag the axes whose friction changed by more than the identification's own uncertainty.

Each log is trained with ``fricgen train``'s own code (``cli.train.fit``): the grey-box
eq. (1) (``--method stribeck``), one curve per direction (``--asymmetric``), with the export
options given. From each direction's curve come the Coulomb level sum f_c, the static peak
f_s = sum f_c + sum (f_s - f_c) (F at v -> 0), the Stribeck velocity v_s of the largest source
and B, each with its standard error (``StribeckRegressor.standard_errors_``; B's from the
high-speed line, ``data.viscous.viscous_se``, NaN where B was fitted with the sources).

A parameter p of an axis has drifted when its change from the axis's reference result (the
previous log by timestamp, or the first) exceeds both ``sigmas`` combined standard errors and
a practical threshold, ``min_change`` of the reference value:

    |p_new - p_ref| > sigmas * sqrt(se_new^2 + se_ref^2)   and   |p_new - p_ref| > min_change |p_ref|

Only the Coulomb levels, the static peaks and B (``MONITORED``) are tested; v_s is reported.

OUT holds ``results/KEY.json``, one per log, written atomically as soon as it is done, KEY the
log's content hash with the axis and the options, so a rerun skips finished work; the table
(``fleet.parquet``, ``fleet.csv``), ``report.md`` and ``plots/`` are rewritten from all of them.
Dask (``distributed``) and pyarrow are the optional extra ``fricgen[fleet]``, imported here only
when a fleet runs.
"""
from __future__ import annotations

import csv
import hashlib
import io
import json
import math
import os
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence

import numpy as np

from ._io import write_atomic
from ._plot import png, pyplot
from .data.viscous import viscous_se
from .errors import DataError, FricgenError, UsageError

#: The version of a stored result's fields: a result of another version is computed again.
RESULT_VERSION = 1
#: Default multiple of the combined standard errors a change must exceed.
SIGMAS = 3.0
#: Default practical threshold: the fraction of the reference value a change must exceed.
MIN_CHANGE = 0.10
#: The parameters the drift test watches, per direction (``pos``, ``neg``).
MONITORED = ("coulomb", "static", "viscous")
#: Every parameter of a result, per direction, each with ``_se``.
PARAMETERS = ("coulomb", "static", "stribeck", "viscous")
DIRECTIONS = ("pos", "neg")
#: The manifest's columns: required, then optional.
MANIFEST_REQUIRED = ("axis", "log", "timestamp")
MANIFEST_OPTIONAL = ("mass", "force_constant")
#: How ``train`` fits a fleet's logs (the grey-box eq. (1), one curve per direction).
TRAIN_FIT = ("--method", "stribeck", "--asymmetric")
#: The reference a new result is compared with.
BASELINES = ("previous", "first")
MISSING_EXTRA = "fricgen fleet needs Dask and pyarrow: pip install 'fricgen[fleet]'"


def _need(module: str):
    """Import an optional module of the ``fleet`` extra, or one ``UsageError`` line."""
    try:
        return __import__(module, fromlist=["_"])
    except ImportError:
        raise UsageError(f"{MISSING_EXTRA} ({module} is missing)") from None


# ----------------------------------------------------------------------------- manifest


@dataclass(frozen=True)
class Entry:
    """One row of the manifest: the axis, its log (resolved path), the log's timestamp (text,
    ordered as written: ISO 8601 sorts), and optionally the mass (kg) and force constant (N/A)."""

    axis: str
    log: str
    timestamp: str
    mass: Optional[float] = None
    force_constant: Optional[float] = None


def read_manifest(path) -> List[Entry]:
    """The manifest CSV's rows (header: axis, log, timestamp[, mass][, force_constant]); log
    paths relative to the manifest's folder. ``DataError`` naming the row otherwise."""
    path = Path(path)
    text = path.read_text(encoding="utf-8-sig")
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        raise DataError(f"{path}: empty manifest, need a header {','.join(MANIFEST_REQUIRED)}")
    header = [h.strip().lower() for h in rows[0]]
    missing = [c for c in MANIFEST_REQUIRED if c not in header]
    if missing:
        raise DataError(f"{path}: manifest misses column {missing[0]!r} (header is "
                        f"{','.join(rows[0])[:80]})")
    entries = []
    for n, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise DataError(f"{path}: line {n} has {len(row)} cells, the header {len(header)}")
        cells = {h: c.strip() for h, c in zip(header, row)}
        for c in MANIFEST_REQUIRED:
            if not cells[c]:
                raise DataError(f"{path}: line {n}: empty {c}")
        numbers = {}
        for c in MANIFEST_OPTIONAL:
            text_value = cells.get(c, "")
            if text_value:
                try:
                    value = float(text_value)
                except ValueError:
                    value = math.nan
                if not (math.isfinite(value) and value > 0):
                    raise DataError(f"{path}: line {n}: {c} must be a number > 0, got {text_value[:40]!r}")
                numbers[c] = value
        entries.append(Entry(cells["axis"], str(path.parent / cells["log"]), cells["timestamp"],
                             **numbers))
    if not entries:
        raise DataError(f"{path}: the manifest lists no log")
    return entries


def train_arguments(entry: Entry, options: Sequence[str]) -> List[str]:
    """The ``fricgen train`` arguments of one log: the fleet's fit, the options and the row's
    mass and force constant."""
    argv = [entry.log, *TRAIN_FIT, "-o", os.devnull, *options]
    if entry.mass is not None:
        argv += ["--mass", repr(entry.mass)]
    if entry.force_constant is not None:
        argv += ["--force-constant", repr(entry.force_constant)]
    return argv


def result_key(entry: Entry, options: Sequence[str]) -> str:
    """The key of a log's result: the SHA-256 of its content, with the axis and the training
    options (a log that changes, or is trained otherwise, is a new result)."""
    digest = hashlib.sha256()
    with open(entry.log, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    settings = json.dumps([RESULT_VERSION, entry.axis, entry.mass, entry.force_constant,
                           list(options)])
    return digest.hexdigest()[:32] + "-" + hashlib.sha256(settings.encode()).hexdigest()[:8]


# ----------------------------------------------------------------------------- one log


def friction_parameters(trained) -> Dict[str, float]:
    """The friction parameters (SI units) and their standard errors of a model ``cli.train.fit``
    fitted with the grey-box eq. (1) (a ``FitReport``), per direction (the same values for both when the fit is
    symmetric): see the module."""
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
    be trained (``stored`` False for an unexpected error, tried again on a rerun). ``train``
    (``cli.train.train_argv``) trains a log from ``train``'s arguments."""
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


# ----------------------------------------------------------------------------- store


def results_dir(out) -> Path:
    return Path(out) / "results"


def check_out(out) -> Path:
    """OUT and OUT/results created and writable (a file written and removed there), else
    ``DataError`` in one line."""
    folder = results_dir(out)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise DataError(f"{out}: cannot write results there ({exc.strerror or exc})") from None
    return folder


def load_results(out) -> Dict[str, dict]:
    """Every stored result of OUT by key (files of another version, or unreadable, skipped)."""
    found = {}
    for path in sorted(results_dir(out).glob("*.json")):
        try:
            record = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        if isinstance(record, dict) and record.get("version") == RESULT_VERSION:
            found[path.stem] = record
    return found


def store(out, record: dict) -> None:
    """Write one result atomically (a temporary file renamed over OUT/results/KEY.json)."""
    write_atomic(results_dir(out) / f"{record['key']}.json", json.dumps(record, allow_nan=True))


# ----------------------------------------------------------------------------- drift


def _change(new: dict, ref: dict, name: str, sigmas: float, min_change: float):
    """(change, change / combined se, flagged) of parameter ``name``."""
    a, b = new.get(name, math.nan), ref.get(name, math.nan)
    se = math.hypot(new.get(name + "_se", math.nan), ref.get(name + "_se", math.nan))
    change = a - b
    if not (math.isfinite(change) and math.isfinite(se)):
        return change, math.nan, False
    z = abs(change) / se if se > 0 else math.inf
    return change, z, bool(z > sigmas and abs(change) > min_change * abs(b))


def drift_table(records: Sequence[dict], sigmas: float = SIGMAS, min_change: float = MIN_CHANGE,
                baseline: str = "previous") -> List[dict]:
    """One row per result, in order of axis and timestamp: the result, its reference (the
    axis's previous, or first, good result), the change of each parameter and its size in
    combined standard errors, and ``flagged`` with the parameters that drifted (see the module)."""
    if baseline not in BASELINES:
        raise ValueError(f"baseline must be one of {list(BASELINES)}, got {baseline!r}")
    rows, good = [], {}
    for r in sorted(records, key=lambda r: (r["axis"], r["timestamp"], r["key"])):
        row = {k: v for k, v in r.items() if k not in ("version", "stored")}
        earlier = good.get(r["axis"], [])
        ref = (earlier[-1] if baseline == "previous" else earlier[0]) if earlier else None
        row["reference"] = ref["timestamp"] if ref else ""
        drifted = []
        for p in PARAMETERS:
            for d in DIRECTIONS:
                name = f"{p}_{d}"
                if ref is None or r["status"] != "ok":
                    row[f"{name}_change"] = row[f"{name}_z"] = math.nan
                    continue
                change, z, flag = _change(r, ref, name, sigmas, min_change)
                row[f"{name}_change"], row[f"{name}_z"] = change, z
                if flag and p in MONITORED:
                    drifted.append(name)
        row["flagged"] = bool(drifted)
        row["drifted"] = " ".join(drifted)
        if r["status"] == "ok":
            good.setdefault(r["axis"], []).append(r)
        rows.append(row)
    return rows


def latest(rows: Sequence[dict]) -> List[dict]:
    """Each axis's newest row (``drift_table`` orders them)."""
    newest = {}
    for row in rows:
        newest[row["axis"]] = row
    return list(newest.values())


# ----------------------------------------------------------------------------- outputs


def _columns(rows: Sequence[dict]) -> List[str]:
    names = []
    for row in rows:
        names += [k for k in row if k not in names]
    return names


def table_csv(rows: Sequence[dict]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=_columns(rows), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: (f"{v:.9g}" if isinstance(v, float) else v) for k, v in row.items()})
    return buf.getvalue()


def table_parquet(rows: Sequence[dict]) -> bytes:
    """The table as Parquet bytes (pyarrow)."""
    pa, pq = _need("pyarrow"), _need("pyarrow.parquet")
    names = _columns(rows)
    table = pa.Table.from_pylist([{k: row.get(k) for k in names} for row in rows])
    buf = pa.BufferOutputStream()
    pq.write_table(table, buf)
    return buf.getvalue().to_pybytes()


def report_markdown(rows: Sequence[dict], sigmas: float, min_change: float, baseline: str) -> str:
    """report.md: the flagged axes first (their newest result), then the failed logs, then
    counts."""
    newest = latest(rows)
    flagged = [r for r in newest if r["flagged"]]
    failed = [r for r in rows if r["status"] != "ok"]
    lines = ["# Fleet friction report", "",
             f"{len(newest)} axes, {len(rows)} logs; {len(flagged)} axes flagged, {len(failed)} logs "
             f"failed. A parameter drifted when its change from the {baseline} result exceeds "
             f"{sigmas:g} combined standard errors and {min_change:.0%} of its earlier value.", "",
             "## Flagged axes", ""]
    if flagged:
        lines += ["| axis | timestamp | reference | drifted | changes (N, N s/m; in combined SE) |",
                  "|---|---|---|---|---|"]
        for r in sorted(flagged, key=lambda r: r["axis"]):
            changes = ", ".join(f"{n} {r[n + '_change']:+.3g} ({r[n + '_z']:.1f} SE)"
                                for n in r["drifted"].split())
            lines.append(f"| {r['axis']} | {r['timestamp']} | {r['reference']} | {r['drifted']} "
                         f"| {changes} |")
    else:
        lines.append("None.")
    lines += ["", "## Failed logs", ""]
    lines += [f"- {r['axis']} {r['timestamp']} `{r['log']}`: {r['error']}" for r in failed] or ["None."]
    return "\n".join(lines) + "\n"


def plots(rows: Sequence[dict]) -> Dict[str, bytes]:
    """PNG figures: the fleet's distribution of each parameter (newest results) and each
    flagged axis's trend; empty when matplotlib is missing."""
    plt = pyplot()
    if plt is None:
        return {}
    figures = {}
    newest = [r for r in latest(rows) if r["status"] == "ok"]
    if newest:
        fig, axes = plt.subplots(len(PARAMETERS), 2, figsize=(8, 2.2 * len(PARAMETERS)))
        for i, p in enumerate(PARAMETERS):
            for j, d in enumerate(DIRECTIONS):
                values = [r[f"{p}_{d}"] for r in newest if math.isfinite(r[f"{p}_{d}"])]
                axes[i, j].hist(values, bins=30)
                axes[i, j].set_title(f"{p} ({'v > 0' if d == 'pos' else 'v < 0'})", fontsize=9)
        fig.tight_layout()
        figures["distribution.png"] = png(fig)
    for axis in sorted({r["axis"] for r in latest(rows) if r["flagged"]}):
        history = [r for r in rows if r["axis"] == axis and r["status"] == "ok"]
        fig, axes = plt.subplots(1, len(MONITORED), figsize=(3.2 * len(MONITORED), 2.6))
        for ax, p in zip(axes, MONITORED):
            for d in DIRECTIONS:
                ax.errorbar(range(len(history)), [r[f"{p}_{d}"] for r in history],
                            yerr=[r[f"{p}_{d}_se"] for r in history], marker="o", label=d)
            ax.set_xticks(range(len(history)), [r["timestamp"] for r in history], rotation=30,
                          fontsize=7)
            ax.set_title(p, fontsize=9)
        axes[0].legend(fontsize=7)
        fig.suptitle(f"axis {axis}", fontsize=9)
        fig.tight_layout()
        safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in axis)
        figures[f"trend_{safe}.png"] = png(fig)
    return figures


def write_outputs(out, rows, sigmas, min_change, baseline) -> List[str]:
    """The table (Parquet and CSV), report.md and plots/, each written atomically; the notes to
    say (plots skipped without matplotlib)."""
    out = Path(out)
    write_atomic(out / "fleet.parquet", table_parquet(rows))
    write_atomic(out / "fleet.csv", table_csv(rows))
    write_atomic(out / "report.md", report_markdown(rows, sigmas, min_change, baseline))
    figures = plots(rows)
    if not figures:
        return ["no plots: matplotlib is not installed (pip install 'fricgen[plot]')"]
    (out / "plots").mkdir(exist_ok=True)
    for name, data in figures.items():
        write_atomic(out / "plots" / name, data)
    return []


# ----------------------------------------------------------------------------- the run


@dataclass
class FleetRun:
    """What ``run_fleet`` did: logs skipped (stored before), computed, failed, and the table."""

    skipped: int = 0
    computed: int = 0
    failed: int = 0
    flagged: int = 0
    rows: Optional[List[dict]] = None
    dashboard: str = ""


def _client(scheduler: Optional[str], workers: int, env: Dict[str, str]):
    """A Dask client: of the cluster at ``scheduler``, or of a LocalCluster of ``workers``
    processes with one thread each and the environment ``env`` (one BLAS thread)."""
    distributed = _need("distributed")
    if scheduler:
        return distributed.Client(scheduler), None
    cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", env=dict(env))
    return distributed.Client(cluster), cluster


def _dashboard(client) -> str:
    try:
        return client.dashboard_link if "dashboard" in client.scheduler_info().get("services", {}) else ""
    except Exception:
        return ""


def run_fleet(entries: Sequence[Entry], out, train: Callable, options: Sequence[str] = (),
              env: Optional[Dict[str, str]] = None, scheduler: Optional[str] = None, workers: int = 2, sigmas: float = SIGMAS,
              min_change: float = MIN_CHANGE, baseline: str = "previous",
              progress: Optional[Callable[[str], None]] = None,
              on_result: Optional[Callable[[dict], None]] = None) -> FleetRun:
    """Identify every entry's log on Dask (see the module) and write OUT's table, report and
    plots. Each result is stored as it arrives (``on_result`` hears of it after); logs stored
    before are skipped. ``train`` trains one log from ``train``'s arguments (``identify``);
    ``env``: the embedded cluster's worker environment. ``progress`` hears the counts and rate,
    and the dashboard link."""
    say = progress or (lambda line: None)
    check_out(out)
    stored = load_results(out)
    keys, failed_rows, todo = {}, [], []
    for e in entries:
        try:
            key = result_key(e, options)
        except OSError as exc:
            failed_rows.append({**asdict(e), "key": "", "status": "failed", "seconds": 0.0,
                                "error": f"{e.log}: {exc.strerror or exc}"})
            continue
        if key not in stored and key not in keys:
            todo.append((e, key))
        keys[key] = e
    run = FleetRun(skipped=len({k for k in keys if k in stored}), failed=len(failed_rows))
    fresh = {}
    if todo:
        client, cluster = _client(scheduler, workers, env or {})
        futures = []
        try:
            run.dashboard = _dashboard(client)
            say(f"fleet: {len(todo)} logs to identify, {run.skipped} done before"
                + (f"; dashboard {run.dashboard}" if run.dashboard else ""))
            distributed = _need("distributed")
            futures = [client.submit(identify, e, list(options), key, train, key=f"fleet-{key}", pure=False)
                       for e, key in todo]
            history = list(stored.values())
            start = last = time.perf_counter()
            for future in distributed.as_completed(futures):
                try:
                    record = future.result()
                except Exception as exc:           # the task died with its workers too often
                    e, key = todo[futures.index(future)]
                    record = {**asdict(e), "key": key, "version": RESULT_VERSION,
                              "status": "failed", "stored": False, "seconds": 0.0,
                              "error": f"{type(exc).__name__}: {exc}".splitlines()[0][:300]}
                if record.get("stored", True):
                    store(out, record)
                fresh[record["key"]] = record
                run.computed += 1
                run.failed += record["status"] != "ok"
                if record["status"] == "ok":
                    mine = drift_table([r for r in history + [record]
                                        if r["axis"] == record["axis"]], sigmas, min_change, baseline)
                    run.flagged += any(r["flagged"] for r in mine if r["key"] == record["key"])
                    history.append(record)
                if on_result is not None:
                    on_result(record)
                now = time.perf_counter()
                if now - last >= 2.0 or run.computed == len(todo):
                    say(f"fleet: {run.computed}/{len(todo)} done, {run.failed} failed, "
                        f"{run.flagged} flagged, {60 * run.computed / (now - start):.1f} logs/min")
                    last = now
        finally:
            for f in futures:
                f.cancel()
            client.close()
            if cluster is not None:
                cluster.close()
    records = list(stored.values()) + list(fresh.values()) + failed_rows
    run.rows = drift_table(records, sigmas, min_change, baseline)
    run.flagged = sum(r["flagged"] for r in latest(run.rows))
    for note in write_outputs(out, run.rows, sigmas, min_change, baseline):
        say(f"fleet: {note}")
    return run


__all__ = ["Entry", "FleetRun", "SIGMAS", "MIN_CHANGE", "MONITORED", "drift_table",
           "friction_parameters", "identify", "read_manifest", "result_key", "run_fleet"]
