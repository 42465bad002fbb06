"""What ``fricgen diagnose`` writes: report.md, the residual and velocity plots, the model.

Everything is rendered in memory: ``render_files`` returns DIR's files by name.
"""
from __future__ import annotations

from typing import Dict

import numpy as np

from .._plot import png, pyplot
from ..data import MotionLog
from .diagnoser import Diagnoser


def format_value(value) -> str:
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def report_markdown(d: Diagnoser, log_name: str, plots) -> str:
    """The human report: verdict, candidates, localization, gap, parameters, plots."""
    p = d.problem_
    lines = [f"# fricgen diagnose: {log_name}", "",
             f"**Missing effect: `{d.effect_}`** (confidence {d.confidence_:.2f}).", "",
             f"Where the residual lives: {d.where_}.", ""]
    if d.fitted_ is not None:
        lines += ["## Fitted parameters", "", "| parameter | value |", "|---|---|"]
        lines += [f"| {k} | {format_value(v)} |" for k, v in d.parameters().items()]
        lines += ["", "The augmented model (with this effect appended to `effects`) is `model.json`.", ""]
    else:
        lines += ["Nothing explains the residual beyond noise; `model.json` is the input model "
                  "unchanged.", ""]
    lines += ["## Gap on the held-out part", "",
              f"Metric: {d.gap_metric_}.", "",
              "| | before | after |", "|---|---|---|",
              f"| velocity gap (m/s) | {d.gap_before_:.4g} | {d.gap_after_:.4g} |",
              f"| force residual rms (N) | {d.force_gap_before_:.4g} | {d.force_gap_after_:.4g} |", ""]
    lines += ["## Candidates", "",
              "Score: cross-validated log-likelihood gain over `none` (blocked "
              f"{d.folds}-fold on the first {1 - d.holdout:.0%} of the log, "
              f"{p.n_effective:.0f} effective samples) less the penalty {d.penalty:g}; "
              "`none` scores 0.", "",
              "| effect | score | cross-validated residual rms (N) |", "|---|---|---|"]
    lines += [f"| {c.effect} | {c.score:.1f} | {np.sqrt(c.mse):.4g} |" for c in d.candidates_]
    lines += ["", "## Where the residual lives", "",
              "Share of the residual's sum of squares explained by binned means along each axis "
              "(adjusted for the number of bins).", "", "| axis | share | detail |", "|---|---|---|"]
    lines += [f"| {a['axis']} | {a['share']:.0%} | {a['detail']} |" for a in d.localization_]
    lines += ["", "## Data", "",
              f"{len(p.signals.t)} samples at {1 / p.sample_time:.6g} Hz; residual smoothed over "
              f"{p.window} samples (Savitzky-Golay, order 2); {p.rows.size} decimated rows where "
              f"|v| > {p.v_min:.3g} m/s (velocity noise {p.sigma_v:.3g} m/s); "
              f"nominal m = {p.mass:g} kg, phi = {p.force_constant:g} N/A.", ""]
    if plots:
        lines += ["## Plots", ""] + [f"![{name}]({name})" for name in sorted(plots)] + [""]
    else:
        lines += ["(No plots: matplotlib is not installed.)", ""]
    return "\n".join(lines)


def plot_pngs(d: Diagnoser, log: MotionLog) -> Dict[str, bytes]:
    """residuals.png (residual against x, v, a, t before and after) and velocity.png
    (simulated and measured velocity on the held-out part); {} without matplotlib."""
    plt = pyplot()
    if plt is None:
        return {}
    p = d.problem_
    rows = np.arange(p.rows.size)
    idx = p.rows
    before = p.target
    after = p.at_rows(d.residual_after_, rows)
    coords = [("position x (m)", p.x_smooth[idx]), ("velocity v (m/s)", p.v_smooth[idx]),
              ("acceleration a (m/s^2)", p.at_rows(p.signals.a, rows)), ("time t (s)", p.signals.t[idx])]
    out = {}
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), constrained_layout=True)
    for ax, (label, c) in zip(axes.flat, coords):
        ax.plot(c, before, ".", ms=2, alpha=0.5, label="before")
        ax.plot(c, after, ".", ms=2, alpha=0.5, label=f"after ({d.effect_})")
        ax.set_xlabel(label)
        ax.set_ylabel("force residual (N)")
    axes.flat[0].legend(markerscale=5)
    fig.suptitle(f"force residual phi i - m a - F(v): {d.effect_}")
    out["residuals.png"] = png(fig)
    t = p.signals.t
    start = p.split
    stop = min(t.size, start + int(round(2.0 / p.sample_time)))
    fig, ax = plt.subplots(figsize=(10, 4), constrained_layout=True)
    ax.plot(t[start:stop], log.v[start:stop], "k-", lw=0.8, label="measured")
    ax.plot(t[start:stop], d.v_sim_before_[start:stop], "-", lw=0.8, label="model")
    if d.fitted_ is not None:
        ax.plot(t[start:stop], d.v_sim_after_[start:stop], "-", lw=0.8, label=f"model + {d.effect_}")
    ax.set_xlabel("time t (s)")
    ax.set_ylabel("velocity v (m/s)")
    ax.set_title("simulations restarted from the measured state, held-out part")
    ax.legend()
    out["velocity.png"] = png(fig)
    return out


def render_files(d: Diagnoser, log: MotionLog, log_name: str) -> Dict[str, object]:
    """Every file of the diagnosis folder, by name: the plots, report.md and model.json."""
    plots = plot_pngs(d, log)
    files: Dict[str, object] = dict(plots)
    files["report.md"] = report_markdown(d, log_name, plots)
    files["model.json"] = d.model_.to_json()
    return files
