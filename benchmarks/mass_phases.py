"""The mass of a static train on logs whose friction has memory: flagged, or right.

fricgen's static ``train`` identifies the mass beside a friction curve of v alone. Friction with
memory (the bristles' build-up after each start, a frictional lag) makes the force differ
between speeding up and braking at the same speed, and the mass of both together comes out off
with a small standard error. ``RigidBody.phases_disagree`` fits the mass apart on the two
phases and warns when they differ (``PHASE_SIGMAS``, ``PHASE_SHARE`` of fricgen/data/idim.py);
``RigidBody.windows_disagree`` warns when smoothing windows whose dv/dt explains the force
about equally well give masses apart (the fast part of the force carried by the bristles).

Per seed (from 1000 up; none tuned anything, though the two constants were set after a look
at seeds 1000-1002 and at the real rigs below), the precision stage of
fricgen/sim/precision_axis.py (its own LuGre law, a quantized encoder, a closed loop):
its identification log with pre-sliding, and the same motion with the steady-state friction
alone. Printed: the true mass, the static train's with its standard error and its error in
standard errors, the two phases' masses, the windows' least and largest, and which warning
was given. Then, where ../shared/data is present, the same on the training logs of its robot
joints (no truth there: what is flagged).

    python benchmarks/mass_phases.py [--seeds 10] [--data ../shared/data]
"""
import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import fricgen  # noqa: E402
from fricgen.sim.precision_axis import identification_log, random_precision_axis, static_friction_log  # noqa: E402

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "data"


def trained_body(columns):
    """The body fricgen.train identifies, and what it warned of the mass: "WARNED (phases)",
    "(windows)", both, or "no warning"."""
    lines = []
    body = fricgen.train(columns, warn=lines.append).identification.body
    said = [name for name, words in (("phases", "speeding up gives"),
                                     ("windows", "smoothing windows that explain"))
            if any(words in line for line in lines)]
    return body, f"WARNED ({', '.join(said)})" if said else ""


def phases(body) -> str:
    def pair(masses, first, second):
        if masses is None:
            return f"{first}/{second} -"
        (m1, s1), (m2, s2) = masses
        return f"{first} {m1:.4g} +- {s1:.2g}, {second} {m2:.4g} +- {s2:.2g}"
    return (pair(body.phase_masses, "speeding up", "braking") + "; windows: "
            + pair(body.window_masses, "least", "largest"))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=10)
    p.add_argument("--data", type=Path, default=DATA)
    args = p.parse_args()
    tally = {True: [0, 0], False: [0, 0]}                   # presliding: [flagged, logs]
    for seed in range(1000, 1000 + args.seeds):
        axis = random_precision_axis(seed)
        for presliding, make in ((True, identification_log), (False, static_friction_log)):
            log = make(axis, seed)
            body, warned = trained_body({k: log[k] for k in ("t", "x", "force")})
            off = (body.mass - axis.mass) / body.mass_se if body.mass_se else float("nan")
            print(f"seed {seed} {'LuGre ' if presliding else 'static'} true {axis.mass:.4g} kg, "
                  f"train {body.mass:.4g} +- {body.mass_se:.2g} ({100 * (body.mass / axis.mass - 1):+.1f} %, "
                  f"{off:+.1f} SE); {phases(body)}; {warned or 'no warning'}", flush=True)
            tally[presliding][0] += bool(warned)
            tally[presliding][1] += 1
    for presliding, (warned, n) in tally.items():
        print(f"{'with pre-sliding' if presliding else 'without':17s}: warned on {warned}/{n} logs")
    if not args.data.is_dir():
        print(f"real rigs: {args.data} absent, skipped")
        return
    import real_data
    for rig, joints in (("ur10e", 6), ("panda", 7)):
        for j in range(joints):
            path = args.data / rig / f"joint{j + 1}_train.csv"
            if not path.exists():
                print(f"{rig} J{j + 1}: absent, skipped")
                continue
            body, warned = trained_body(real_data.log_columns(real_data.csv(path)))
            print(f"{rig} J{j + 1}: train {body.mass:.4g} +- {body.mass_se:.2g}; {phases(body)}; "
                  f"{warned or 'no warning'}", flush=True)


if __name__ == "__main__":
    main()
