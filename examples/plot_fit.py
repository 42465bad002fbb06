"""Draw the README picture: the paper benchmark data, the true friction and fricgen's model.

    python examples/plot_fit.py docs/fit.png
"""
import sys

import numpy as np

from fricgen.data import synthesize_benchmark
from fricgen.fit import default_elm
from fricgen.friction import preset
from fricgen.model import FrictionModel


def main(path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    bench = synthesize_benchmark(preset("paper3"), seed=0)
    model = FrictionModel.fit(bench.dataset, default_elm(0))
    v = np.linspace(-0.1, 0.1, 2001)
    fig, ax = plt.subplots(figsize=(7, 3.6), dpi=110)
    ax.plot(bench.train.v, bench.train.f, ".", ms=3, color="0.6", label="noisy sweep (±0.5 N)")
    ax.plot(-bench.train.v, -bench.train.f, ".", ms=3, color="0.6")
    ax.plot(v, bench.friction(v), color="k", lw=1, label="true 3-source friction, [F1]")
    ax.plot(v, model.force(v), "--", color="tab:red", lw=1.5,
            label=f"fricgen model, [F3], {model.aim.n_hidden} neurons")
    ax.set_xlabel("velocity v (m/s)")
    ax.set_ylabel("friction force (N)")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    print(f"wrote {path}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "fit.png")
