"""How much of the textbook fit's lead on real logs is its acceleration filter.

benchmarks/real_data.py scores every model with the acceleration of each folder's own filter
(its baseline.py's Butterworth), and the textbook fit is trained through that same filter. The
default identifies its inertia through Savitzky-Golay smoothing instead. Here the textbook law
itself (per-direction Coulomb + viscous + inertia, least squares on the moving rows) is trained
twice on each joint's training log, once through the folder's filter and once through a cubic
Savitzky-Golay filter of 21, 81 and 321 samples (over the sample index, at the median step, as
fricgen reads a log), and both are scored the same way on the held-out log: the ratio is what
the filter alone costs a law trained outside the scorer's filter.

Run: python benchmarks/filter_advantage.py [--data ../shared/data]
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from fricgen.data.smoothing import smooth               # noqa: E402
from real_data import DATA, csv, load_baseline, rms, textbook   # noqa: E402

WINDOWS = (21, 81, 321)
JOINTS = {"ur10e": 6, "panda": 7}


def score(folder, j):
    """The textbook law's held-out RMS error trained through the folder's filter, and the
    ratios of those trained through each Savitzky-Golay window to it."""
    b = load_baseline(folder)
    tr, te = csv(folder / f"joint{j}_train.csv"), csv(folder / f"joint{j}_test.csv")
    v, a = b.va(te["t"], te["dq"])
    keep = np.abs(v) > b.VMIN
    v, a, y = v[keep], a[keep], te["tau"][keep]
    own_v, own_a = b.va(tr["t"], tr["dq"])
    moving = np.abs(own_v) > b.VMIN
    base = rms(y - textbook(own_v[moving], own_a[moving], tr["tau"][moving])(v, a))
    step = float(np.median(np.diff(tr["t"])))
    ratios = []
    for window in WINDOWS:
        sg_v, sg_a = smooth(tr["dq"], window), smooth(tr["dq"], window, deriv=1, delta=step)
        moving = np.abs(sg_v) > b.VMIN
        ratios.append(rms(y - textbook(sg_v[moving], sg_a[moving], tr["tau"][moving])(v, a)) / base)
    return base, ratios


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--data", type=Path, default=DATA)
    args = p.parse_args()
    print(f"{'joint':10s} {'own filter':>10s} " + " ".join(f"{'SG ' + str(w):>7s}" for w in WINDOWS)
          + "   (textbook law's held-out RMS; ratios trained through SG / through the folder's filter)")
    for name, joints in JOINTS.items():
        folder = args.data / name
        if not folder.is_dir():
            print(f"{name}: skipped, no folder {folder}")
            continue
        for j in range(1, joints + 1):
            base, ratios = score(folder, j)
            print(f"{name + ' J' + str(j):10s} {base:10.4f} " + " ".join(f"{r:7.3f}" for r in ratios))


if __name__ == "__main__":
    main()
