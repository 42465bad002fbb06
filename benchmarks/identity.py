"""Outputs to compare byte for byte before and after a change that must not change behaviour.

Writes into DIR: the diagnosis (summary JSON, report.md, plots, model.json, and digests of the
arrays it keeps) of a few synthetic logs with different hidden effects and of two generator
scenarios; the generator's scenarios (conditions, log, hidden forces, the user's model); and
``fricgen synth``/``train``/``emit`` and ``synth-log``/``diagnose``/``emit`` run through the
command line. Floats are written with ``repr`` (exact), arrays as SHA-256 of their bytes.

    python benchmarks/identity.py DIR            # then: diff -r BEFORE AFTER
"""
import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from fricgen.diagnose import Diagnoser  # noqa: E402
from fricgen.diagnose.report import render_files  # noqa: E402
from fricgen.sim.logsynth import LogSpec, nominal_model, synthesize_log  # noqa: E402
from fricgen.sim.scenarios import make_scenario  # noqa: E402

#: (effect, seed, magnitude) of the synthetic logs diagnosed (8 s each).
LOGS = [("none", 0, 1.0), ("position_ripple", 1, 1.0), ("frictional_lag", 2, 1.5),
        ("direction_asymmetry", 3, 1.0)]
#: (seed, hidden) of the generator's scenarios (5 s at 1 kHz).
SCENARIOS = [(0, ()), (1, ("thermal_drift", "oov:local_drag")), (2, ("oov:actuator_deadzone",))]
FIXED = dict(rate_hz=1000.0, duration_s=5.0, controller="pd_i", trajectory="multisine")


def digest(a) -> str:
    a = np.ascontiguousarray(a)
    return f"{a.dtype}{a.shape}:{hashlib.sha256(a.tobytes()).hexdigest()}"


def write(folder: Path, name: str, content) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content if isinstance(content, str) else json.dumps(content, indent=1))


def diagnosis(folder: Path, log, model, mass, force_constant) -> None:
    d = Diagnoser().fit(log, model, mass, force_constant)
    for name, content in render_files(d, log, "log.csv").items():
        write(folder, name, content)
    write(folder, "summary.json", d.summary())
    write(folder, "steps.json", [dict(s.summary(), label=s.label, beside=s.beside, added=s.added,
                                      reason=s.reason, n_effective=s.n_effective,
                                      joint=[e.to_dict() for e in s.joint])
                                 for s in d.steps_])
    write(folder, "arrays.json", {
        "residual_after": digest(d.residual_after_), "v_sim_before": digest(d.v_sim_before_),
        "v_sim_after": digest(d.v_sim_after_), "target": digest(d.problem_.target),
        "localization": d.localization_, "localization_after": d.localization_after_,
        "force_gap": [d.force_gap_before_, d.force_gap_after_]})


def main() -> None:
    out = Path(sys.argv[1])
    model = nominal_model()
    for effect, seed, magnitude in LOGS:
        spec = LogSpec(effect=effect, seed=seed, magnitude=magnitude, duration=8.0)
        log = synthesize_log(spec, model)
        diagnosis(out / f"diagnose_{effect}", log, model, spec.mass, spec.force_constant)
    for seed, hidden in SCENARIOS:
        sc = make_scenario(seed, hidden, **FIXED)
        folder = out / f"scenario_{seed}"
        write(folder, "conditions.json", sc.conditions)
        write(folder, "model.json", sc.model.to_json())
        write(folder, "arrays.json", {
            "hidden": list(sc.hidden), "mass": sc.mass, "force_constant": sc.force_constant,
            "true_mass": sc.true_mass, "t": digest(sc.log.t), "x": digest(sc.log.x),
            "v": digest(sc.log.v), "i": digest(sc.log.i), "x_d": digest(sc.log.extra["x_d"]),
            "hidden_forces": {k: digest(f) for k, f in sc.hidden_forces.items()},
            "truth_i": digest(sc.truth_log().i)})
        if hidden:
            diagnosis(folder / "diagnose", sc.log, sc.model, sc.mass, sc.force_constant)
    cli = out / "cli"
    cli.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for argv in (["synth", "--seed", "3", "-o", "sweep.csv"],
                 ["train", "sweep.csv", "--seed", "3", "-o", "model.json"],
                 ["emit", "model.json", "-o", "c"],
                 ["synth-log", "--effect", "constant_load", "--seed", "4", "--duration", "8",
                  "-o", "log.csv"],
                 ["diagnose", "log.csv", "--model", "model.json", "--mass", "4",
                  "--force-constant", "20", "--json", "-o", "diag"],
                 ["emit", "diag/model.json", "-o", "c_diag"]):
        run = subprocess.run([sys.executable, "-m", "fricgen", *argv], cwd=cli, env=env,
                             capture_output=True, text=True)
        write(cli, f"{argv[0]}_{argv[-1].replace('/', '_')}.out",
              f"exit {run.returncode}\n{run.stdout}{run.stderr}")


if __name__ == "__main__":
    main()
