"""Training from a motion log against training from a sweep, on the same asymmetric friction.

The worked example's rig (examples/motion_log/make_export.py: fricgen's simulator, friction
different in the two directions) is exported as its drive (1.5 kHz, rpm, preamble) and load
cell (2 kHz, 4 ms behind) would, and trained with the vendor-export options of ``fricgen
train``. Printed, per direction, the RMS error against the true friction over the speeds the
log covers, of:

- the model trained from the export, and of the model trained on the ideal sweep of the same
  friction (the paper's protocol per direction: 200 noisy points in [0, 3 vs_max] and 100 up to
  10 vs_max, noise uniform in +-0.5 N), and their ratio (target <= 1.3);
- ``fricgen train LOG.csv --mass M`` on the plain log (t, v, force on the drive's clock), the
  model trained on the sweep of friction samples obtained by doing the inverse dynamics by hand
  (Butterworth filtfilt, central differences, F = f - m a), their RMS difference, and the noise
  of that difference: each fit's noise is the RMS difference between its fits of two logs that
  differ only in their sensor noise, over sqrt(2); the two add in quadrature (target:
  difference <= 2 standard deviations);
- the parity of the exported model's emitted C (cffi, libm and fast kernels) with its float32
  twin and the float64 model, as for a symmetric model (bit-equal for > 99 %, within 1e-5 of
  max |F|), and which model ``train`` picks on the ideal sweep of symmetric friction (Table 1 in
  both directions).

    python benchmarks/motion_log_training.py [--seeds 2]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import sys
import tempfile
from pathlib import Path

import numpy as np
from scipy.signal import butter, filtfilt

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples" / "motion_log"))

from make_export import FRICTION, LOADCELL_LAG, METERS_PER_S_PER_RPM, export  # noqa: E402

from fricgen import codegen  # noqa: E402
from fricgen.cli import main  # noqa: E402
from fricgen.codegen import parity  # noqa: E402
from fricgen.codegen.cbuild import build_model  # noqa: E402
from fricgen.codegen.twin import force_f32  # noqa: E402
from fricgen.data import Sweep, sweep_csv_text  # noqa: E402
from fricgen.data.export import ExportLayout, merge_on_time, read_export  # noqa: E402
from fricgen.data.table import table_csv_text  # noqa: E402
from fricgen.model import FrictionModel  # noqa: E402
from fricgen.sim.identification import DirectionalFriction, SweepRun, simulate_sweep_run  # noqa: E402

MASS = SweepRun().mass
VS_MAX = 0.025          # the larger true Stribeck velocity of the two directions (both fits)


def train(argv) -> FrictionModel:
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["train", *argv, "--vs-max", str(VS_MAX)]) == 0
    return FrictionModel.load(argv[argv.index("-o") + 1])


def speeds_covered(model):
    """The speed grid where the log fit has data in both directions: from the slowest speed
    ``train`` kept (in either direction) to the fastest."""
    low = model.training["log"]["slowest"]
    return np.linspace(max(low), 0.2, 400)


def rms_errors(model, grid):
    """RMS of model - truth over ``grid`` for v > 0 and v < 0, N."""
    return [float(np.sqrt(np.mean((sign * model.force(sign * grid) - FRICTION.magnitude(grid, sign)) ** 2)))
            for sign in (1, -1)]


def rms_difference(a, b, grid):
    return [float(np.sqrt(np.mean((a.force(sign * grid) - b.force(sign * grid)) ** 2))) for sign in (1, -1)]


def ideal_sweep(seed, friction=FRICTION) -> Sweep:
    """The paper's sweep protocol in each direction, of ``friction``."""
    rng = np.random.default_rng(seed + 1000)
    v_sat = 3 * VS_MAX
    parts = []
    for sign in (1, -1):
        v = np.concatenate([rng.uniform(0, v_sat, 200), rng.uniform(v_sat, 0.2, 100)])
        parts.append(Sweep(sign * v, sign * (friction.magnitude(v, sign) + rng.uniform(-0.5, 0.5, v.size))))
    return parts[0].concat(parts[1])


def by_hand(columns) -> Sweep:
    """Inverse dynamics by hand: 4th-order Butterworth at 50 Hz forward and backward, central
    differences, F = f - m a, rows with |v| > 3 mm/s in a run of one direction."""
    t, v, f = columns["t"], columns["v"], columns["force"]
    ts = float(np.median(np.diff(t)))
    b, a = butter(4, 50.0 * 2 * ts)
    v_s, f_s = filtfilt(b, a, v), filtfilt(b, a, f)
    friction = f_s - MASS * np.gradient(v_s, ts)
    moving = np.abs(v_s) > 3e-3
    sign = np.sign(v_s)
    steady = moving.copy()
    for shift in range(1, 40):
        steady &= np.roll(sign, shift) == sign
        steady &= np.roll(sign, -shift) == sign
    steady[:100] = steady[-100:] = False
    return Sweep(v_s[steady], friction[steady])


def run(seed: int, work: Path):
    signals = simulate_sweep_run(FRICTION)
    rows = {}
    for k, noise_seed in enumerate((seed, seed + 500)):
        drive, loadcell = export(signals, noise_seed)
        (work / f"drive{k}.csv").write_text(drive)
        (work / f"loadcell{k}.csv").write_text(loadcell)
    vendor = ["--skip", "5", "--columns", "t=Time [s],v=Speed [rpm]", "--scale",
              f"v={METERS_PER_S_PER_RPM!r}", "--merge-skip", "3", "--merge-columns",
              "t=Timestamp [s],force=Load [N]", "--merge-shift", repr(LOADCELL_LAG), "--mass", str(MASS)]
    exported = train([str(work / "drive0.csv"), "--merge", str(work / "loadcell0.csv"), *vendor,
                      "-o", str(work / "exported.json")])
    # the plain logs: the same two files aligned and scaled in Python, on the drive's clock
    plain = []
    for k in (0, 1):
        first = read_export(work / f"drive{k}.csv", ExportLayout(5, {"t": "Time [s]", "v": "Speed [rpm]"}),
                            {"v": METERS_PER_S_PER_RPM})
        second = read_export(work / f"loadcell{k}.csv", ExportLayout(3, {"t": "Timestamp [s]",
                                                                         "force": "Load [N]"}))
        cols = merge_on_time({c: first[c] for c in ("t", "v")}, second, LOADCELL_LAG)
        (work / f"log{k}.csv").write_text(table_csv_text(cols))
        plain.append(cols)
    log_fits = [train([str(work / f"log{k}.csv"), "--mass", str(MASS), "--asymmetric",
                       "-o", str(work / f"log{k}.json")]) for k in (0, 1)]
    hands = []
    for k in (0, 1):
        (work / f"hand{k}.csv").write_text(sweep_csv_text(by_hand(plain[k])))
        hands.append(train([str(work / f"hand{k}.csv"), "--asymmetric", "-o", str(work / f"hand{k}.json")]))
    hand = hands[0]
    (work / "ideal.csv").write_text(sweep_csv_text(ideal_sweep(seed)))
    ideal = train([str(work / "ideal.csv"), "-o", str(work / "ideal.json")])
    symmetric = DirectionalFriction(FRICTION.positive, FRICTION.positive)
    (work / "symmetric.csv").write_text(sweep_csv_text(ideal_sweep(seed, symmetric)))
    rows["symmetric_picks"] = train([str(work / "symmetric.csv"), "-o", str(work / "sym.json")]).symmetric
    rows["parity"] = {}
    for impl in ("libm", "fast"):
        folder = work / f"c_{impl}"
        codegen.emit(exported, folder, "rig", activation_impl=impl)
        lib = build_model(folder, "rig", build_dir=folder / "build")
        v = parity.parity_velocities(max(c.v_sat for c in exported.directions))
        c = parity.c_forces(lib, "rig", v).astype(float)
        twin = force_f32(exported, v, impl).astype(float)
        exact = exported.force(v.astype(float))
        rows["parity"][impl] = {"n_velocities": int(v.size), "n_not_bit_equal": int(np.sum(c != twin)),
                                "max_abs_c_vs_twin": float(np.max(np.abs(c - twin))),
                                "max_rel_c_vs_model": float(np.max(np.abs(c - exact)) / np.max(np.abs(exact)))}
    grid = speeds_covered(log_fits[0])
    rows["grid"] = (grid[0], grid[-1])
    rows["asymmetric"] = (not exported.symmetric, not ideal.symmetric)
    rows["exported"] = rms_errors(exported, grid)
    rows["ideal"] = rms_errors(ideal, grid)
    rows["log_vs_hand"] = rms_difference(log_fits[0], hand, grid)
    # the noise of each fit: half the variance of the difference between two noise draws
    log_noise = np.array(rms_difference(log_fits[0], log_fits[1], grid)) / np.sqrt(2)
    hand_noise = np.array(rms_difference(hands[0], hands[1], grid)) / np.sqrt(2)
    rows["log_noise"] = log_noise
    rows["diff_noise"] = np.sqrt(log_noise ** 2 + hand_noise ** 2)
    rows["log"] = rms_errors(log_fits[0], grid)
    rows["hand"] = rms_errors(hand, grid)
    return rows


def main_(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=2)
    args = p.parse_args(argv)
    for seed in range(args.seeds):
        with tempfile.TemporaryDirectory() as tmp:
            r = run(seed, Path(tmp))
        print(f"seed {seed}: speeds {r['grid'][0]:.4f} to {r['grid'][1]:.3f} m/s; asymmetric model "
              f"chosen: export {r['asymmetric'][0]}, ideal sweep {r['asymmetric'][1]}")
        for j, direction in enumerate(("v > 0", "v < 0")):
            e, i = r["exported"][j], r["ideal"][j]
            d, n = r["log_vs_hand"][j], r["diff_noise"][j]
            print(f"  {direction}: RMS error vs truth, export {e:.4f} N, ideal sweep {i:.4f} N, "
                  f"ratio {e / i:.2f} (target <= 1.3) [{'met' if e <= 1.3 * i else 'NOT met'}]")
            print(f"  {direction}: train LOG --mass vs by hand: RMS difference {d:.4f} N, noise of "
                  f"the difference {n:.4f} N (log fit alone {r['log_noise'][j]:.4f} N), "
                  f"{d / n:.2f} sd [{'met' if d <= 2 * n else 'NOT met'} at 2 sd] (errors vs truth: "
                  f"log {r['log'][j]:.4f} N, by hand {r['hand'][j]:.4f} N)")
        print(f"  symmetric friction (ideal sweep, both directions): train picks the "
              f"{'symmetric' if r['symmetric_picks'] else 'asymmetric'} model")
        for impl, m in r["parity"].items():
            print(f"  C parity of the exported (asymmetric) model, {impl}: {m['n_not_bit_equal']} of "
                  f"{m['n_velocities']} velocities not bit-equal to its float32 twin (max "
                  f"{m['max_abs_c_vs_twin']:.3g} N), max |C - float64| / max |F| = "
                  f"{m['max_rel_c_vs_model']:.3g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main_())
