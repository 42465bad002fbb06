"""CPU time of the scenario generator (fricgen.sim.scenarios) per log, and what its logs show.

For each setting it generates the null log and one with a hidden effect for several seeds
(plant, controller and trajectory drawn per seed) and prints the CPU time per log (model fit
included, the median and the largest over seeds), the number of passes of the stitched
simulation, the largest state jump at a seam in units of the sensor resolution, and the
hidden effect's RMS force against the smoothed current noise.

    python benchmarks/scenario_cost.py [--seeds 6] [--settings 60@1000,1200@1000,120@4000,120@250]

Target: a 60 s log at 1 kHz in well under 1-2 s; a 1200 s log at 1 kHz feasible.
"""
import argparse
import math
import time

import numpy as np

from fricgen.sim.scenarios import make_scenario


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=6)
    parser.add_argument("--settings", default="60@1000,1200@1000,120@4000,120@250",
                        help="comma-separated DURATION_S@RATE_HZ")
    parser.add_argument("--effect", default="constant_load")
    args = parser.parse_args()
    print(f"{'duration':>9} {'rate':>6} {'cpu median':>11} {'cpu max':>8} {'passes max':>10} "
          f"{'seam jump max':>13} {'effect/noise min':>16}  trajectories")
    for setting in args.settings.split(","):
        duration, rate = (float(s) for s in setting.split("@"))
        cpu, passes, seams, visible, kinds = [], [], [], [], []
        for seed in range(args.seeds):
            for hidden in ((), (args.effect,)):
                start = time.process_time()
                sc = make_scenario(seed, hidden, rate_hz=rate, duration_s=duration)
                cpu.append(time.process_time() - start)
                c = sc.conditions
                passes.append(c["passes"])
                seams.append(c["seam_jump"])
                if hidden:
                    w = max(1, int(round(0.01 * rate)))
                    visible.append(c["signature_rms"][args.effect]
                                   / (c["force_noise"] / math.sqrt(w)))
                    kinds.append(c["trajectory"]["kind"])
        print(f"{duration:9.0f} {rate:6.0f} {np.median(cpu):10.2f}s {max(cpu):7.2f}s "
              f"{max(passes):10d} {max(seams):13.2f} {min(visible):16.1f}  {','.join(kinds)}",
              flush=True)


if __name__ == "__main__":
    main()
