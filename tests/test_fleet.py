"""``fricgen fleet`` on a real Dask LocalCluster: a killed worker's task retried, a corrupt log
recorded while the others go on, a read-only OUT refused in one line, a rerun after an
interrupt that recomputes nothing, and the drift rule on known changes."""
import json
import math
import os
import signal
import threading
import time

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

from independent_axis import fleet_axis, fleet_friction, fleet_log, write_fleet_log  # noqa: E402

from fricgen.cli import main  # noqa: E402
from fricgen.cli import blas_env  # noqa: E402
from fricgen.cli.train import train_argv  # noqa: E402
from fricgen.fleet import Entry, drift_table, read_manifest, run_fleet  # noqa: E402
from fricgen.data import Sweep  # noqa: E402
from fricgen.fleet.law import fit_law  # noqa: E402
from fricgen.fleet.store import load_results  # noqa: E402

DURATION = 8.0          # s: short logs, each still identified


@pytest.fixture(scope="module")
def cluster():
    """One worker process of one thread, shared by the tests that do not kill it."""
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None, env=blas_env()) as c:
        yield c


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    """Three axes' logs (the independent axis, not [F1]) and their manifest."""
    folder = tmp_path_factory.mktemp("fleet_logs")
    lines = ["axis,log,timestamp"]
    for a in range(3):
        write_fleet_log(folder / f"a{a}.csv", fleet_log(fleet_axis(a), a, DURATION))
        lines.append(f"ax{a},a{a}.csv,2024-01-0{a + 1}")
    (folder / "manifest.csv").write_text("\n".join(lines) + "\n")
    return folder


def test_a_corrupt_log_is_recorded_in_one_line_and_the_others_go_on(logs, cluster, tmp_path, capsys):
    (logs / "bad.csv").write_text("t,v,force\n0,0.1,1\n0.001,0.2,oops\n")
    manifest = tmp_path / "m.csv"
    manifest.write_text((logs / "manifest.csv").read_text().replace("a0.csv", str(logs / "a0.csv"))
                        .replace("a1.csv", str(logs / "a1.csv")).replace("a2.csv", str(logs / "bad.csv")))
    out = tmp_path / "out"
    assert main(["fleet", str(manifest), "-o", str(out), "--scheduler", cluster.scheduler_address]) == 0
    rows = {r["axis"]: r for r in _csv_rows(out / "fleet.csv")}
    assert rows["ax0"]["status"] == rows["ax1"]["status"] == "ok"
    assert rows["ax2"]["status"] == "failed" and "bad.csv" in rows["ax2"]["error"]
    assert "\n" not in rows["ax2"]["error"]
    assert float(rows["ax0"]["coulomb_pos"]) > 0 and len(rows["ax0"]["model_hash"]) == 16
    assert "bad.csv" in (out / "report.md").read_text()
    import pyarrow.parquet as pq
    assert pq.read_table(out / "fleet.parquet").num_rows == 3
    assert "1 failed" in capsys.readouterr().err


def _csv_rows(path):
    import csv
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("make_unwritable", ["a file in the way", "read-only folder"])
def test_an_unwritable_out_is_one_line_and_a_nonzero_exit(logs, tmp_path, capsys, make_unwritable):
    if make_unwritable == "a file in the way":
        (tmp_path / "blocker").write_text("")
        out = tmp_path / "blocker" / "out"
    else:
        if os.geteuid() == 0:
            pytest.skip("root writes into a read-only folder")
        out = tmp_path / "out"
        out.mkdir()
        out.chmod(0o500)
    code = main(["fleet", str(logs / "manifest.csv"), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code != 0 and len(err) == 1 and "cannot write results" in err[0]
    assert not (tmp_path / "out" / "results").exists()


def test_a_rerun_after_an_interrupt_recomputes_nothing_and_loses_nothing(logs, cluster, tmp_path):
    entries = read_manifest(logs / "manifest.csv")
    out = tmp_path / "out"

    def interrupt(record):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_fleet(entries, out, train_argv, scheduler=cluster.scheduler_address, on_result=interrupt)
    kept = load_results(out)
    assert len(kept) == 1 and not list((out / "results").glob(".*"))     # whole results only
    first = next((out / "results").glob("*.json"))
    stamp = first.stat().st_mtime_ns
    again = run_fleet(entries, out, train_argv, scheduler=cluster.scheduler_address)
    assert (again.skipped, again.computed) == (1, 2)
    assert first.stat().st_mtime_ns == stamp
    third = run_fleet(entries, out, train_argv, scheduler=cluster.scheduler_address)
    assert (third.skipped, third.computed) == (3, 0)
    assert len(third.rows) == 3 and all(r["status"] == "ok" for r in third.rows)


def test_a_worker_killed_during_a_run_has_its_task_retried(logs, tmp_path):
    entries = read_manifest(logs / "manifest.csv")
    out = tmp_path / "out"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None, env=blas_env()) as c, \
            distributed.Client(c) as client:
        pid = next(iter(client.run(os.getpid).values()))
        done = {}
        thread = threading.Thread(target=lambda: done.update(run=run_fleet(
            entries, out, train_argv, scheduler=c.scheduler_address)))
        thread.start()
        deadline = time.monotonic() + 120
        while not list((out / "results").glob("*.json")) and time.monotonic() < deadline:
            time.sleep(0.05)
        os.kill(pid, signal.SIGKILL)        # mid-run: the next log is being identified
        thread.join(timeout=300)
        client.wait_for_workers(1, timeout=60)
        assert next(iter(client.run(os.getpid).values())) != pid       # the nanny restarted it
    run = done["run"]
    assert run.computed == 3 and run.failed == 0
    assert all(r["status"] == "ok" for r in run.rows)


def _record(axis, stamp, value, se, key):
    r = {"axis": axis, "timestamp": stamp, "key": key, "status": "ok", "log": "", "error": ""}
    for p in ("coulomb", "static", "stribeck", "viscous"):
        for d in ("pos", "neg"):
            r[f"{p}_{d}"], r[f"{p}_{d}_se"] = value, se
    return r


@pytest.mark.parametrize("new, flagged", [
    (10.0, False),          # nothing changed
    (10.5, False),          # 35 SE, but below the practical 10 %
    (11.2, True),           # 85 SE and 12 %
])
def test_drift_needs_both_the_combined_standard_errors_and_the_practical_threshold(new, flagged):
    rows = drift_table([_record("a", "1", 10.0, 0.01, "k1"), _record("a", "2", new, 0.01, "k2")],
                       sigmas=3.0, min_change=0.10)
    assert rows[1]["flagged"] is flagged and rows[0]["flagged"] is False


def test_drift_below_the_combined_standard_errors_is_not_flagged():
    rows = drift_table([_record("a", "1", 10.0, 1.0, "k1"), _record("a", "2", 14.0, 1.0, "k2")],
                       sigmas=3.0, min_change=0.10)      # 4 / sqrt(2) = 2.8 SE
    assert not rows[1]["flagged"]
    assert rows[1]["coulomb_pos_z"] == pytest.approx(4 / math.sqrt(2))


@pytest.mark.parametrize("text, message", [
    ("axis,log\nax,a.csv\n", "misses column 'timestamp'"),
    ("axis,log,timestamp\n", "lists no log"),
    ("axis,log,timestamp,mass\nax,a.csv,1,-3\n", "mass must be a number > 0"),
    ("axis,log,timestamp\nax,,1\n", "empty log"),
])
def test_a_bad_manifest_is_one_line_and_nothing_written(tmp_path, capsys, text, message):
    (tmp_path / "m.csv").write_text(text)
    assert main(["fleet", str(tmp_path / "m.csv"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0]
    assert not (tmp_path / "out").exists()


def test_the_monitoring_laws_standard_errors_hold_the_spread_of_noise_draws():
    """The law fitted to noisy rows of a friction it is not (a squared-rational drop and
    quadratic drag): over 40 draws the Coulomb level and static peak scatter by about their own
    standard errors, and a 10 % growth of both is several of them."""
    axis = fleet_axis(3)
    rng = np.random.default_rng(0)
    v = rng.uniform(0.001, 0.25, 2000)
    fits = [fit_law(Sweep(v, fleet_friction(axis, v) + rng.normal(0.0, 0.3, v.size)), v.size)
            for _ in range(40)]
    for name in ("coulomb", "static", "viscous"):
        values = np.array([f[name] for f in fits])
        se = np.array([f[name + "_se"] for f in fits])
        assert 0.6 < np.std(values) / np.mean(se) < 1.5, name
    grown = dict(axis, coulomb=1.1 * axis["coulomb"], static=1.1 * axis["static"])
    worn = fit_law(Sweep(v, fleet_friction(grown, v) + rng.normal(0.0, 0.3, v.size)), v.size)
    change = worn["coulomb"] - fits[0]["coulomb"]
    assert change / math.hypot(worn["coulomb_se"], fits[0]["coulomb_se"]) > 5
