"""elm_auto against the honest [F1] oracle and the default-sized enlarged ELM on held-out seed sets.

The oracle is [F1] alone with the true shape and S = 3 on the B identified from the
high-speed rows (no free slope): ``fricgen.fit.oracle``. benchmarks/default_vs_oracle.py measures
fricgen's default model against it.

Prints the median E_Ttest (newtons) over 20 seeds for three disjoint seed sets and the three
Stribeck shapes of [F2], so the design of elm_auto can be checked away from seeds 0-19.
Run: python benchmarks/auto_vs_oracle.py   (about 1 min on one core)
"""
import numpy as np

from fricgen.fit.auto import AutoELMRegressor
from fricgen.data import synthesize_benchmark
from fricgen.fit import DEFAULT_ELM, ELMRegressor
from fricgen.friction import preset
from fricgen.fit.oracle import OracleRegressor

print(f"{'shape':12s} {'seeds':>9s} {'auto N':>8s} {'oracle N':>9s} {'auto/oracle':>11s} "
      f"{'elm(40) N':>10s} {'units':>6s}")
for shape in ("gauss", "exponential", "rational"):
    for first in (0, 100, 200) if shape == "gauss" else (100,):
        rows = []
        for seed in range(first, first + 20):
            bench = synthesize_benchmark(preset("paper3", shape), seed=seed)
            d = bench.dataset
            auto = AutoELMRegressor().fit(d.x, d.t)
            oracle = OracleRegressor(shape).fit(d.x, d.t)
            elm = ELMRegressor(random_state=seed, **DEFAULT_ELM).fit(d.x, d.t)
            rows.append([bench.errors(m.predict)["e_ttest_newton"] for m in (auto, oracle, elm)]
                        + [auto.n_hidden])
        med = np.median(rows, axis=0)
        print(f"{shape:12s} {first:4d}-{first + 19:<4d} {med[0]:8.4f} {med[1]:9.4f} "
              f"{med[0] / med[1]:11.2f} {med[2]:10.4f} {med[3]:6.0f}")
