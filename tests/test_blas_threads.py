"""One BLAS thread for train and diagnose unless FRICGEN_BLAS_THREADS asks for more: the
command sets the thread count before numpy loads, and OpenBLAS takes it."""
import json
import os
import subprocess
import sys

import pytest

from fricgen.cli import BLAS_VARIABLES

PROBE = """
import json, sys
from fricgen.cli import main
loaded_before = "numpy" in sys.modules
rc = main(sys.argv[1:])
from threadpoolctl import threadpool_info
blas = [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]
print(json.dumps({"rc": rc, "loaded_before": loaded_before, "blas": blas}))
"""


def _run(argv, threads=None):
    env = {k: v for k, v in os.environ.items() if k not in BLAS_VARIABLES + ("FRICGEN_BLAS_THREADS",)}
    if threads is not None:
        env["FRICGEN_BLAS_THREADS"] = threads
    proc = subprocess.run([sys.executable, "-c", PROBE, *argv], env=env, capture_output=True,
                          text=True, timeout=300)
    return json.loads(proc.stdout.splitlines()[-1]), proc


@pytest.mark.parametrize("command", ["train", "diagnose"])
def test_train_and_diagnose_run_on_one_blas_thread(cli_inputs, tmp_path, command):
    pytest.importorskip("threadpoolctl")
    d = cli_inputs
    argv = {"train": ["train", str(d / "sweep.csv"), "-o", str(tmp_path / "m.json"), "--vs-max", "0.02"],
            "diagnose": ["diagnose", str(d / "log.csv"), "--model", str(d / "model.json"), "--mass", "4",
                         "--force-constant", "20", "-o", str(tmp_path / "diag")]}[command]
    got, proc = _run(argv)
    assert got["rc"] == 0, proc.stderr
    assert not got["loaded_before"]          # the thread count is set before numpy loads
    assert got["blas"] and set(got["blas"]) == {1}


def test_fricgen_blas_threads_asks_for_more(cli_inputs, tmp_path):
    pytest.importorskip("threadpoolctl")
    argv = ["train", str(cli_inputs / "sweep.csv"), "-o", str(tmp_path / "m.json"), "--vs-max", "0.02"]
    got, proc = _run(argv, threads="2")
    assert got["rc"] == 0, proc.stderr
    assert got["blas"] and set(got["blas"]) == {min(2, os.cpu_count())}


def test_the_python_api_trains_on_the_threads_the_command_line_uses(bench, monkeypatch):
    """fricgen.train sets every OpenBLAS of the process to FRICGEN_BLAS_THREADS (default 1)
    for the fit and restores the count after (numpy loaded before it: no variable helps)."""
    import fricgen
    from fricgen import _blas
    before = _blas.thread_counts()
    if not before:
        pytest.skip("no OpenBLAS loaded in this process")
    seen = []
    real = _blas.blas_threads

    def spy(count):
        seen.append(count)
        return real(count)
    monkeypatch.setattr("fricgen.training.trainer.blas_threads", spy)
    with _blas.blas_threads(3):
        assert _blas.thread_counts() == [3] * len(before)
    assert _blas.thread_counts() == before
    fricgen.train(bench.train, vs_max=0.02, estimator=fricgen.StribeckRegressor())
    monkeypatch.setenv("FRICGEN_BLAS_THREADS", "2")
    fricgen.train(bench.train, vs_max=0.02, estimator=fricgen.StribeckRegressor())
    assert seen == [1, 2] and _blas.thread_counts() == before
