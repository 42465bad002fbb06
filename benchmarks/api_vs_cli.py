"""The Python API against the command on the same large log: `fricgen train LOG.csv` and
`fricgen.train(columns)` side by side, each timed as a whole process (imports, the read, the
fit and the save).

The log is ``benchmarks/scale.py``'s (a 60 s closed-loop log of `fricgen synth-log` at 1 kHz,
repeated end to end with continuous position) at ``--rows`` rows. Three ways, alternated over
``--repeats`` rounds so that a busy spell of the machine falls on each alike:

- cli: ``fricgen train LOG.csv --mass 4 --force-constant 20 -o m.json``;
- api: ``fricgen.read_log_csv``, then ``fricgen.train(columns, mass=4, force_constant=20)`` and
  ``model.save``: what a script that starts from the same file does.

Printed: the median wall and CPU seconds of each and the ratios api / cli (target: the API
within 1.2x of the command).

    python benchmarks/api_vs_cli.py [--rows 1e6] [--repeats 3]
"""
import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

for _key in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_key, "1")   # as the fricgen command does, before numpy loads

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "benchmarks"), str(ROOT)]

from scale import measure, write_log  # noqa: E402

from fricgen.sim.logsynth import LogSpec, synthesize_log  # noqa: E402

API = """
import sys
import fricgen
log = fricgen.read_log_csv(sys.argv[1])
columns = {"t": log.t, "x": log.x, "v": log.v, "i": log.i}
fricgen.train(columns, mass=4.0, force_constant=20.0).model.save(sys.argv[2])
"""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=float, default=1e6)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    rows = int(args.rows)
    with tempfile.TemporaryDirectory(prefix="fricgen_api_") as tmp:
        tmp = Path(tmp)
        log = tmp / "log.csv"
        write_log(log, rows, synthesize_log(LogSpec(duration=60.0, seed=0)))
        fricgen = [sys.executable, "-m", "fricgen"]
        ways = {
            "cli": fricgen + ["train", str(log), "--mass", "4", "--force-constant", "20",
                              "-o", str(tmp / "cli.json"), "--force"],
            "api": [sys.executable, "-c", API, str(log), str(tmp / "api.json")],
        }
        times = {way: [] for way in ways}
        for k in range(args.repeats):
            for way, cmd in ways.items():
                seconds, _, rc, cpu = measure(cmd)
                if rc != 0:
                    print(f"{way}: exit {rc}")
                    return 1
                times[way].append((seconds, cpu))
                print(f"round {k + 1}: {way:4s} {seconds:7.2f} s wall, {cpu:7.2f} s CPU", flush=True)
    med = {way: np.median(np.array(t), axis=0) for way, t in times.items()}
    print(f"\n{rows} rows, median of {args.repeats} runs, each a fresh process")
    for way, (wall, cpu) in med.items():
        print(f"{way:4s} {wall:7.2f} s wall {cpu:7.2f} s CPU")
    print(f"api / cli: {med['api'][0] / med['cli'][0]:.3f} (wall), {med['api'][1] / med['cli'][1]:.3f} (CPU); "
          "target <= 1.2")
    return 0


if __name__ == "__main__":
    sys.exit(main())
