"""What ``fricgen diagnose`` writes: report.md, the residual and velocity plots, the model.

Everything is rendered in memory: ``render_files`` returns DIR's files by name.
"""
from __future__ import annotations

from pathlib import Path
from typing import Dict

import numpy as np

from .._plot import PNG_SOFTWARE, png, pyplot
from ..model import FORMAT
from ..data import MotionLog
from ..effects import EFFECTS, PLAUSIBLE_FACTOR
from .decision import p_text, p_value_text
from .diagnoser import MISMATCH_RELEVANT, TABLE_PREFERENCE, UNDERSTATED_GAIN, Diagnoser


def format_value(value) -> str:
    if isinstance(value, list):
        if len(value) > 6:
            return f"{len(value)} values in [{min(value):.4g}, {max(value):.4g}]"
        return "[" + ", ".join(format_value(v) for v in value) + "]"
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def effect_sentence(step, speed: str = "m/s") -> str:
    """One line on an added effect: what, how large, how sure, how much of the gap it closes
    (the gap's ``speed`` unit)."""
    params = ", ".join(f"{k} = {format_value(v)}" for k, v in step.fitted.parameters().items())
    closed = 1.0 - step.gap_after / step.gap_before if step.gap_before > 0 else 0.0
    return (f"- `{step.effect}` ({params}): {step.size:.0%} of the RMS friction force, "
            f"{p_text(step.p_value)}; it closes {closed:.0%} of the held-out gap "
            f"({step.gap_before:.3g} -> {step.gap_after:.3g} {speed}).")


def verdict(d: Diagnoser) -> str:
    """The effects added, in order, as one phrase."""
    if not d.effects_:
        return "none"
    return ", then ".join(f"`{s.effect}` ({p_text(s.p_value)})" for s in d.effects_)


def refinement_note(d: Diagnoser) -> str:
    """What the output-error refinement changed, in one phrase; "" when it changed nothing."""
    if not d.fit_gap_after_ < d.fit_gap_before_:
        return ""
    refit = (f"fitted again to simulations of the fit part (its gap {d.fit_gap_before_:.4g} -> "
             f"{d.fit_gap_after_:.4g} {d.units_.speed})")
    if d.refinement_refused_:
        return (f"the parameters were {refit}, but then {d.refinement_refused_}; the values the "
                "selection fitted are kept")
    if not d.refinement_kept:
        return (f"the parameters were {refit}, but the held-out gap grew to {d.gap_refined_:.4g} "
                f"{d.units_.speed} against {d.gap_selected_:.4g} with the values the selection "
                "fitted, which are kept")
    return (f"the parameters above were {refit}; the held-out gap with the values the selection "
            f"fitted was {d.gap_selected_:.4g} {d.units_.speed}")


#: Effects that change with time in service: a fixed model cannot follow them.
DRIFTS = ("thermal_drift",)


def augmented_sentence(d) -> str:
    """What ``model.json`` holds after the effects named: appended to ``effects``, but a
    pre-sliding, which becomes the model's bristles."""
    contact = [s.effect for s in d.effects_ if getattr(s.fitted, "via_contact", False)]
    others = len(d.effects_) - len(contact)
    parts = (["these effects appended to `effects`" if others > 1 else
              "this effect appended to `effects`"] if others else []) + \
        ([f"`{contact[0]}` as its bristles, the model's `presliding`, which `emit --sample-time "
          "TS` writes as `NAME_step`"] if contact else [])
    return f"`model.json` is the augmented model: {'; '.join(parts)}."


def service_hint(d: Diagnoser) -> str:
    """What addresses a drift the diagnosis named, in one sentence; "" when it named none."""
    drifts = [s for s in d.effects_ if s.effect in DRIFTS]
    if not drifts:
        return ""
    fitted = drifts[0].fitted
    shape = (f"time constant {fitted.time_constant:.3g} s" if fitted.time_constant > 0
             else "linear in time")
    return (f"the friction level drifts in service ({drifts[0].effect}, rate {fitted.rate:.3g}/s, "
            f"{shape}): a fixed model cannot follow it; "
            "`fricgen emit --adapt` adds online adaptation of the model's output parameters "
            "(the Lyapunov rule, fric_adapt_params_t.rule, by default; leak and box bound it), "
            "and `fricgen readback` keeps what it learned")


#: The first line of report.md begins with this (then the log's name).
REPORT_TITLE = "# fricgen diagnose: "


def report_markdown(d: Diagnoser, log_name: str, plots) -> str:
    """The human report (report.md): verdict, the selection steps, refusals, localization, gap,
    plots.

    Parameters
    ----------
    d : Diagnoser
        A fitted diagnosis (``Diagnoser.fit``).
    log_name : str
        The log's name, in the title line.
    plots : dict
        The plot files by name (``{}``: a line saying there are none); linked, not embedded.

    Returns
    -------
    str
        Markdown; its first line begins with ``REPORT_TITLE``.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.diagnose import diagnose, report_markdown
    >>> from fricgen.sim import LogSpec, synthesize_log
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> elm = fricgen.ELMRegressor(n_hidden=10, scheme="enlarged", solver="ridge", C=1e5, random_state=0)
    >>> model = fricgen.FrictionModel.fit(data, elm)
    >>> log = synthesize_log(LogSpec("constant_load", duration=1.5, substeps=2), model)
    >>> d = diagnose(log, model, 4.0, 20.0, candidates=["constant_load"], tables=False)
    >>> text = report_markdown(d, "axis.csv", {})
    >>> text.splitlines()[0], "**Missing effects: `constant_load`" in text
    ('# fricgen diagnose: axis.csv', True)
    """
    p = d.problem_
    lines = [f"{REPORT_TITLE}{log_name}", "",
             f"**Missing effects: {verdict(d)}.**", ""]
    lines += [effect_sentence(s, d.units_.speed) for s in d.effects_] + ([""] if d.effects_ else [])
    lines += [f"Where the residual lives before: {d.where_}.", "",
              f"After the effects added: {d.where_after_}.", ""]
    tables = [s.effect for s in d.effects_ if s.effect not in EFFECTS]
    if tables:
        lines += [f"No named effect explains this structure; the model carries a table instead "
                  f"({', '.join(f'`{t}`' for t in tables)}): a force tabulated along that signal, "
                  "without a physical name.", ""]
    elif d.localization_after_[0]["share"] >= 0.05:
        lines += ["Structure remains that nothing added explains (see the refusals below).", ""]
    lines += ["## Decision", "",
              f"Each step fits the sets of named effects one larger than the chosen set jointly on "
              f"the first {1 - d.holdout:.0%} of the log, ranks them by Akaike's criterion, and takes "
              "the best that (1) reduces the squared force residual on the held-out last "
              f"{d.holdout:.0%} (one-sided t-test with the effective sample size from the "
              f"autocorrelation, p < {d.alpha:g}), (2) has its mass and force constant within a factor "
              f"{PLAUSIBLE_FACTOR:g} of the nominal ones, (3) changes the force there by at least "
              f"{d.min_size:.0%} of the RMS friction force (a frictional lag, or a mass or force "
              f"constant {MISMATCH_RELEVANT:.0%} off the nominal one, may instead shrink the gap by "
              f"{UNDERSTATED_GAIN:.0%}) and (4) shrinks the held-out gap by at least "
              f"{d.min_gain:.0%}; of the sets that pass, among those within one standard error of the "
              "smallest held-out gap, the best by the criterion per unit of mass. A set may drop an "
              "earlier effect (marked replaced). When no set one larger is taken, sets two larger "
              "that keep the chosen ones are tried, each new effect "
              f"at least {d.min_size:.0%} on its own; effects that enter together share one step "
              "number and its figures. Tables (no physical name) compete when no named set is taken, "
              f"or first when their cross-validated gain is more than {TABLE_PREFERENCE:g} times the "
              f"best named one's. At most {d.max_effects} effects.", "",
              "| step | effect | p-value | share of residual | size | "
              f"gap before ({d.units_.speed}) | gap after ({d.units_.speed}) | decision |",
              "|---|---|---|---|---|---|---|---|"]
    k, last = 0, None
    for s in d.steps_:
        if s.added and s.joint is not last:         # effects that enter together: one step
            k, last = k + 1, s.joint
        after = "" if np.isnan(s.gap_after) else f"{s.gap_after:.4g}"
        lines.append(f"| {k if s.added else ''} | {s.label} | {p_value_text(s.p_value)} | {s.share:.1%} | "
                     f"{s.size:.1%} | {s.gap_before:.4g} | {after} | "
                     f"{'added' if s.added else 'refused: ' + s.reason} |")
    lines.append("")
    for j, s in enumerate(d.effects_, 1):
        lines += [f"## Effect {j}: `{s.effect}`", "", "| parameter | value |", "|---|---|"]
        lines += [f"| {key} | {format_value(v)} |" for key, v in s.fitted.parameters().items()]
        lines.append("")
    if d.effects_:
        lines += [augmented_sentence(d), ""]
    else:
        lines += ["Nothing explains the residual beyond noise; `model.json` is the input model "
                  "unchanged.", ""]
    hint = service_hint(d)
    if hint:
        lines += ["## In service", "", hint[0].upper() + hint[1:] + ".", ""]
    lines += ["## Gap on the held-out part", "",
              f"Metric: {d.gap_metric_}.", "",
              "| | before | after |", "|---|---|---|",
              f"| velocity gap ({d.units_.speed}) | {d.gap_before_:.4g} | {d.gap_after_:.4g} |",
              f"| force residual rms (N) | {d.force_gap_before_:.4g} | {d.force_gap_after_:.4g} |", ""]
    refined = refinement_note(d)
    if refined:
        lines += [refined[0].upper() + refined[1:] + ".", ""]
    if d.steps_:
        lines += ["## Candidates of the first step", "",
                  "| effect | cross-validated residual rms (N) |", "|---|---|"]
        lines += [f"| {c.effect} | {np.sqrt(c.mse):.4g} |" for c in d.steps_[0].candidates]
    lines += ["", "## Where the residual lives", "",
              "Share of the residual's sum of squares explained by binned means along each axis "
              "(adjusted for the number of bins), before and after the effects added.", "",
              "| axis | before | after | detail (before) |", "|---|---|---|---|"]
    after = {a["axis"]: a["share"] for a in d.localization_after_}
    lines += [f"| {a['axis']} | {a['share']:.0%} | {after[a['axis']]:.0%} | {a['detail']} |"
              for a in d.localization_]
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
    """residuals.png (residual against x, v, a, t before and after each effect added) and
    velocity.png (simulated and measured velocity on the held-out part); {} without matplotlib."""
    plt = pyplot()
    if plt is None:
        return {}
    p = d.problem_
    rows = np.arange(p.rows.size)
    idx = p.rows
    stages = [("before", p.target)]
    chosen = []
    for s in d.effects_:
        chosen.append(s.fitted)
        stages.append((" + ".join(e.name for e in chosen),
                       p.at_rows(p.raw_residual(list(p.effects) + chosen), rows)))
    coords = [("position x (m)", p.x_smooth[idx]), ("velocity v (m/s)", p.v_smooth[idx]),
              ("acceleration a (m/s^2)", p.at_rows(p.signals.a, rows)), ("time t (s)", p.signals.t[idx])]
    out = {}
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), constrained_layout=True)
    for ax, (label, c) in zip(axes.flat, coords):
        for name, r in stages:
            ax.plot(c, r, ".", ms=2, alpha=0.5, label=name)
        ax.set_xlabel(label)
        ax.set_ylabel("force residual (N)")
    axes.flat[0].legend(markerscale=5, fontsize=7)
    fig.suptitle(f"force residual phi i - m a - F(v), effects added in order: "
                 f"{', '.join(s.effect for s in d.effects_) or 'none'}")
    out["residuals.png"] = png(fig)
    t = p.signals.t
    start = p.split
    stop = min(t.size, start + int(round(2.0 / p.sample_time)))
    fig, ax = plt.subplots(figsize=(10, 4), constrained_layout=True)
    ax.plot(t[start:stop], log.v[start:stop], "k-", lw=0.8, label="measured")
    ax.plot(t[start:stop], d.v_sim_before_[start:stop], "-", lw=0.8, label="model")
    if d.effects_:
        ax.plot(t[start:stop], d.v_sim_after_[start:stop], "-", lw=0.8,
                label="model + " + " + ".join(s.effect for s in d.effects_))
    ax.set_xlabel("time t (s)")
    ax.set_ylabel("velocity v (m/s)")
    ax.set_title("simulations restarted from the measured state, held-out part")
    ax.legend()
    out["velocity.png"] = png(fig)
    return out


def written_by_diagnose(path) -> bool:
    """Whether the file ``path`` is one ``diagnose`` writes: report.md under its title line, a
    model.json of fricgen's format, or a plot whose PNG names fricgen as its software."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            head = fh.read(4096)
    except OSError:
        return False
    if path.suffix == ".png":
        return PNG_SOFTWARE.encode() in head
    if path.suffix == ".json":
        return f'"format": "{FORMAT}"'.encode() in head
    return head.startswith(REPORT_TITLE.encode())


def render_files(d: Diagnoser, log: MotionLog, log_name: str) -> Dict[str, object]:
    """Every file of the diagnosis folder, by name: the plots, report.md and model.json.

    Parameters
    ----------
    d : Diagnoser
        A fitted diagnosis.
    log : MotionLog
        The log it was fitted on (for the velocity plot).
    log_name : str
        The log's name, in report.md's title.

    Returns
    -------
    dict
        File name -> content: str (report.md, model.json) or PNG bytes (residuals.png and
        velocity.png, when matplotlib is installed).

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.diagnose import diagnose, render_files
    >>> from fricgen.sim import LogSpec, synthesize_log
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> elm = fricgen.ELMRegressor(n_hidden=10, scheme="enlarged", solver="ridge", C=1e5, random_state=0)
    >>> model = fricgen.FrictionModel.fit(data, elm)
    >>> log = synthesize_log(LogSpec("constant_load", duration=1.5, substeps=2), model)
    >>> d = diagnose(log, model, 4.0, 20.0, candidates=["constant_load"], tables=False)
    >>> files = render_files(d, log, "axis.csv")
    >>> sorted(name for name in files if not name.endswith(".png"))
    ['model.json', 'report.md']
    >>> import json
    >>> [e["effect"] for e in json.loads(files["model.json"])["effects"]]
    ['constant_load']
    """
    plots = plot_pngs(d, log)
    files: Dict[str, object] = dict(plots)
    files["report.md"] = report_markdown(d, log_name, plots)
    files["model.json"] = d.model_.to_json()
    return files
