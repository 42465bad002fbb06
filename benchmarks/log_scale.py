"""Time and peak memory of `fricgen train LOG.csv --mass 4 --force-constant 20` against the log's rows.

The logs are `benchmarks/scale.py`'s: a 60 s closed-loop log of `fricgen synth-log` (1 kHz),
repeated end to end with continuous position. Each size is trained in a fresh process; one
row per size gives wall seconds, CPU seconds (user + system: the wall time of an idle machine,
as training runs on one thread), peak resident memory (getrusage of the child) and the
smoothing window chosen; the last line says whether the largest log is within the target
(2e6 rows in <= 30 s and <= 1 GB), by wall time and by CPU time.

    python benchmarks/log_scale.py [--sizes 2.5e5,5e5,1e6,2e6]
"""
import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

for _key in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_key, "1")   # as the fricgen command does, before numpy loads

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "benchmarks"), str(ROOT)]   # scale.py's helpers; this repository's fricgen

from scale import measure, write_log  # noqa: E402

from fricgen.sim.logsynth import LogSpec, synthesize_log  # noqa: E402

#: The target for the largest log.
TARGET_ROWS, TARGET_SECONDS, TARGET_MIB = 2_000_000, 30.0, 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="2.5e5,5e5,1e6,2e6")
    args = ap.parse_args()
    sizes = [int(float(s)) for s in args.sizes.split(",")]
    base = synthesize_log(LogSpec(duration=60.0, seed=1))
    print(f"{'rows':>10s} {'wall s':>8s} {'CPU s':>7s} {'peak MiB':>9s} {'window':>7s}")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for n in sizes:
            log, model = folder / f"log{n}.csv", folder / "model.json"
            write_log(log, n, base)
            argv = [sys.executable, "-m", "fricgen", "train", str(log), "--mass", "4",
                    "--force-constant", "20", "-o", str(model), "--force"]
            cwd = os.getcwd()
            os.chdir(ROOT)                      # python -m fricgen: this repository's
            try:
                sec, mib, rc, cpu = measure(argv)
            finally:
                os.chdir(cwd)
            window = json.loads(model.read_text())["training"]["log"]["window"] if rc == 0 else None
            rows.append((n, sec, cpu, mib, rc))
            print(f"{n:10d} {sec:8.1f} {cpu:7.1f} {mib:9.0f} {window if window else '-':>7}"
                  + ("" if rc == 0 else f"   exit {rc}"), flush=True)
            log.unlink()
    for n, sec, cpu, mib, rc in rows:
        if n == TARGET_ROWS:
            print(f"{n} rows within {TARGET_SECONDS:g} s and {TARGET_MIB:g} MiB: wall "
                  f"{'yes' if rc == 0 and sec <= TARGET_SECONDS and mib <= TARGET_MIB else 'no'}, CPU "
                  f"{'yes' if rc == 0 and cpu <= TARGET_SECONDS and mib <= TARGET_MIB else 'no'}")


if __name__ == "__main__":
    main()
