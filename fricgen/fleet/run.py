"""A fleet's run on Dask: every log of the manifest not stored before identified on a cluster,
each result stored as it arrives, then the table, report and plots written."""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass
from typing import Callable, Dict, List, Optional, Sequence

from .drift import MIN_CHANGE, SIGMAS, drift_table, latest
from .extra import need
from .identification import identify
from .manifest import Entry
from .report import write_outputs
from .store import RESULT_VERSION, check_out, load_results, result_key, store


@dataclass
class FleetRun:
    """What ``run_fleet`` did.

    Parameters
    ----------
    skipped, computed, failed, flagged : int
        Logs stored before (skipped), identified now, failed, and axes flagged.
    rows : list of dict, optional
        The drift table (``drift_table``).
    dashboard : str
        The Dask dashboard's link, when there is one.

    Examples
    --------
    >>> from fricgen.fleet import FleetRun
    >>> FleetRun(computed=3).failed
    0
    """

    skipped: int = 0
    computed: int = 0
    failed: int = 0
    flagged: int = 0
    rows: Optional[List[dict]] = None
    dashboard: str = ""


def _client(scheduler: Optional[str], workers: int, env: Dict[str, str]):
    """A Dask client: of the cluster at ``scheduler``, or of a LocalCluster of ``workers``
    processes with one thread each and the environment ``env`` (one BLAS thread)."""
    distributed = need("distributed")
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
    and the dashboard link.

    Parameters
    ----------
    entries : sequence of Entry
        The manifest's rows.
    out : str or pathlib.Path
        OUT: results, table, report and plots.
    train : callable
        Trains one log from ``train``'s arguments.
    options : sequence of str
        ``train``'s options for every log.
    env : dict, optional
        The embedded cluster's worker environment.
    scheduler : str, optional
        The address of an existing Dask cluster (default: a LocalCluster).
    workers : int
        The LocalCluster's worker processes.
    sigmas, min_change, baseline
        As for ``drift_table``.
    progress : callable, optional
        Hears each progress line.
    on_result : callable, optional
        Hears each result after it is stored.

    Returns
    -------
    FleetRun

    Examples
    --------
    >>> from fricgen.fleet import run_fleet
    >>> from fricgen.cli.train import train_argv
    >>> try:
    ...     run_fleet([], tmp / "out", train_argv, baseline="newest")
    ... except ValueError as exc:
    ...     print(exc)
    baseline must be one of ['previous', 'first'], got 'newest'
    """
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
            distributed = need("distributed")
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
