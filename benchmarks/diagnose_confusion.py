"""fricgen diagnose on logs it did not generate: false alarms, named effects, pairs, shapes
outside the vocabulary, the held-out gap, and how calibrated the p-values are.

Every log comes from ``fricgen.sim.scenarios`` (its own plant friction family, controllers,
trajectories, sensors; the user's model is trained on a sweep of the plant, close but not
equal). The cases, each seed drawing its own plant, controller, trajectory, noise, rate and
length unless fixed:

- null: nothing hidden; rates cycled over 250, 500, 1000, 2000, 4000 Hz, the three controllers
  and noise scales 0.5, 1, 2; lengths drawn in 5-120 s;
- lengths: nothing hidden, at 14, 60, 300 and 1200 s (rate and the rest drawn), 60 logs per
  length by default so that a 5 % rate is measured (its 95 % interval is printed);
- singles: each named effect at its reference magnitude;
- power: the singles' logs again with the effect at other multiples of its reference
  magnitude (``--magnitudes``; 0.5 and 2 by default), for how detection grows with size;
- pairs: two different named effects at once;
- triples: three (no target in the issue; scored as pairs are);
- oov: each out-of-vocabulary shape.

Prints and checks the targets (false alarms <= 5 % overall and per length, with the 95 %
Clopper-Pearson interval; singles correct >= 95 %; pairs exact set >= 90 %; out-of-vocabulary:
no named effect that worsens the gap, gap at least halved in >= 90 %; gap after <= 0.5 x before
wherever something was added; diagnose's gap at most 1.1 x the truth's on >= 95 % of the logs
where something is hidden, with each category's visible and invisible counts, and the same
with the values the selection fitted, before the output-error refinement), beside
each gap figure the truth's: the gap the user's model leaves when the current is corrected by
the hidden effects' true force and the simulation uses the true mass (``Scenario.truth_log``,
``Scenario.true_mass``): what knowing the hidden effects exactly would give on that log. Singles and pairs are also scored on the logs where
each hidden effect is visible: the truth's gap is at least the held-out guard's ``min_gain``
below the gap of the truth missing that effect (``Scenario.truth_log(without=...)``); where it
is not, the guard forbids naming the effect. Writes ``confusion.png`` (confusion
matrix of the singles and nulls) and the reliability table of the first step's p-value on
null logs (observed fraction with p < alpha against alpha).

    python benchmarks/diagnose_confusion.py [--small] [--jobs 2] [--out DIR]
        [--per-length N | LENGTH:N,...] [--magnitudes K,...] [--kinds KIND,...]

Results are appended to DIR/records.jsonl as each log finishes; a run that stops is resumed
by running the same command again (finished cases are not repeated).
"""
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")          # many small factorizations: one thread
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

from fricgen.cli.diagnose import asked_for
from fricgen.diagnose.diagnoser import Diagnoser, candidates_with, diagnose
from fricgen.effects import EFFECTS
from fricgen.errors import DataError
from fricgen.sim.closed_loop import CONTROLLERS
from fricgen.sim.hidden_effects import NAMED, OUT_OF_VOCABULARY
from fricgen.sim.scenarios import make_scenario

RATES = (250.0, 500.0, 1000.0, 2000.0, 4000.0)
NOISES = (0.5, 1.0, 2.0)
LENGTHS = (14.0, 60.0, 300.0, 1200.0)
#: The kinds of logs of a run (``cases``).
KINDS = ("null", "length", "single", "power", "pair", "triple", "oov")
SHORT = {"none": "none", "position_ripple": "ripple", "direction_asymmetry": "asym",
         "constant_load": "load", "inertia_mismatch": "mass", "force_constant_mismatch": "phi",
         "extra_friction_source": "extra", "frictional_lag": "lag", "thermal_drift": "drift",
         "position_friction": "pfric", "table": "table"}
ALPHAS = (0.001, 0.01, 0.05, 0.1, 0.25, 0.5)
#: The held-out guard's least relative shrink of the gap, for ``visible``.
MIN_GAIN = Diagnoser().min_gain
#: The effects diagnose considers: its default, and those --sensor-delay and --saturation ask
#: for (set by main before the workers start).
CANDIDATES = None


def cases(small: bool, per_length=None, magnitudes=()):
    """(key, kind, seed, hidden, fixed conditions) of every log of the run; ``per_length`` maps
    a length to its number of null logs (missing: 2 in a small run, 60 in a full one);
    ``magnitudes`` the multiples of the reference magnitude the singles are run at again."""
    n_null, default_per_length, lengths = (15, 2, LENGTHS[:2]) if small else (100, 60, LENGTHS)
    per_length = per_length or {}
    named_seeds, n_pairs, n_triples, oov_seeds = (1, 6, 2, 1) if small else (8, 30, 12, 4)
    out = []
    for k in range(n_null):
        fixed = {"rate_hz": RATES[k % len(RATES)], "controller": CONTROLLERS[k % len(CONTROLLERS)],
                 "noise": NOISES[(k // len(RATES)) % len(NOISES)]}
        out.append((f"null-{k}", "null", 1000 + k, (), fixed))
    for length in lengths:
        for k in range(per_length.get(length, default_per_length)):
            out.append((f"length{length:g}-{k}", "length", 2000 + 100 * int(length) + k, (),
                        {"duration_s": length}))
    for s in range(named_seeds):
        for j, e in enumerate(NAMED):
            out.append((f"single-{e}-{s}", "single", 3000 + 10 * s + j, (e,), {}))
            for k in magnitudes:        # the same log with the effect k times as large
                out.append((f"power{k:g}-{e}-{s}", "power", 3000 + 10 * s + j, (e,),
                            {"magnitude": k}))
    rng = np.random.default_rng(7)
    for k in range(n_pairs):
        a, b = rng.choice(len(NAMED), 2, replace=False)
        out.append((f"pair-{k}", "pair", 4000 + k, (NAMED[a], NAMED[b]), {}))
    rng = np.random.default_rng(11)
    for k in range(n_triples):
        out.append((f"triple-{k}", "triple", 6000 + k,
                    tuple(NAMED[j] for j in rng.choice(len(NAMED), 3, replace=False)), {}))
    for s in range(oov_seeds):
        for j, shape in enumerate(OUT_OF_VOCABULARY):
            out.append((f"oov-{shape}-{s}", "oov", 5000 + 10 * s + j, ("oov:" + shape,), {}))
    return out


def run_case(case):
    key, kind, seed, hidden, fixed = case
    start = time.time()
    sc = make_scenario(seed, hidden, **fixed)
    made = time.time()
    try:
        d = diagnose(sc.log, sc.model, sc.mass, sc.force_constant, candidates=CANDIDATES)
    except DataError as e:              # a log diagnose refuses (too little motion): apart
        return {"key": key, "kind": kind, "seed": seed, "hidden": list(sc.hidden),
                "rate_hz": sc.conditions["rate_hz"], "duration_s": sc.conditions["duration_s"],
                "refused": str(e), "effects": [], "seconds_diagnose": time.time() - made}
    seconds_diagnose = time.time() - made
    c = sc.conditions
    # the oracle: the gap the user's model leaves with the true effects, shapes and parameters;
    # and the oracle missing one named effect (for a single: the user's model as it is)
    oracle = Diagnoser()
    gap_truth = oracle.held_out_gap(sc.truth_log(), sc.model, sc.truth_mass(), sc.force_constant)
    gap_truth_without = {}
    if kind in ("single", "power", "pair", "triple"):
        gap_truth_without = {e: d.gap_before_ if len(sc.hidden) == 1 else oracle.held_out_gap(
            sc.truth_log(without=(e,)), sc.model, sc.truth_mass((e,)), sc.force_constant)
            for e in sc.hidden}
    return {"key": key, "kind": kind, "seed": seed, "hidden": list(sc.hidden),
            "rate_hz": c["rate_hz"], "duration_s": c["duration_s"],
            "controller": c["controller"].get("kind", fixed.get("controller", "?")),
            "noise": c["noise"]["scale"], "trajectory": c["trajectory"]["kind"],
            "magnitude": c["magnitude"],
            "effects": [s.effect for s in d.effects_],
            "steps": [{"effect": s.effect, "p_value": s.p_value, "size": s.size, "share": s.share,
                       "gap_before": s.gap_before,
                       "gap_after": None if np.isnan(s.gap_after) else s.gap_after,
                       "added": s.added, "reason": s.reason, "beside": s.beside} for s in d.steps_],
            "p_first": d.steps_[0].p_value if d.steps_ else 1.0,
            "gap_before": d.gap_before_, "gap_after": d.gap_after_, "gap_truth": gap_truth,
            "gap_selected": d.gap_selected_,
            "gap_truth_without": gap_truth_without,
            "seconds_generate": made - start, "seconds_diagnose": seconds_diagnose}


def named_set(r):
    return sorted(e for e in r["effects"] if e in EFFECTS)


def rate(flags):
    flags = list(flags)
    return (sum(flags) / len(flags), sum(flags), len(flags)) if flags else (float("nan"), 0, 0)


def interval(k: int, n: int) -> str:
    """The 95 % Clopper-Pearson interval of a rate of k in n."""
    from scipy.stats import beta
    lo = beta.ppf(0.025, k, n - k + 1) if k > 0 else 0.0
    hi = beta.ppf(0.975, k + 1, n - k) if k < n else 1.0
    return f"95 % interval {lo:.1%}-{hi:.1%}"


def halves(r, gap):
    """Whether ``r[gap]`` is at most half the log's gap before the diagnosis."""
    return r[gap] <= 0.5 * r["gap_before"]


def visible(r):
    """Whether every hidden named effect is visible: the truth's gap is at least the held-out
    guard's MIN_GAIN below the gap of the truth missing that effect (``gap_truth_without``)."""
    return "gap_truth_without" in r and all(r["gap_truth"] <= (1.0 - MIN_GAIN) * g
                                            for g in r["gap_truth_without"].values())


def shows(r):
    """Whether a shape outside the vocabulary is visible: the truth shrinks the log's gap by at
    least MIN_GAIN."""
    return r["gap_truth"] <= (1.0 - MIN_GAIN) * r["gap_before"]


def verdict(ok):
    return "met" if ok else "NOT MET"


def report(records, out: Path, small: bool):
    refused = [r for r in records if "refused" in r]
    records = [r for r in records if "refused" not in r]
    by = {}
    for r in records:
        by.setdefault(r["kind"], []).append(r)
    lines = []

    def say(text=""):
        print(text)
        lines.append(text)

    for r in refused:
        say(f"{r['key']}: refused by diagnose, left out of every figure: {r['refused'][:100]}")
    nulls = by.get("null", [])
    fa, k, n = rate(bool(r["effects"]) for r in nulls)
    if n:
        say(f"null logs (nothing hidden): false alarms {k}/{n} = {fa:.1%} ({interval(k, n)})   "
            f"target <= 5 %: {verdict(fa <= 0.05)}")
    for label, field, values in (("rate (Hz)", "rate_hz", RATES), ("controller", "controller", CONTROLLERS),
                                 ("noise scale", "noise", NOISES)) if n else ():
        parts = []
        for v in values:
            f, kk, nn = rate(bool(r["effects"]) for r in nulls if r[field] == v)
            parts.append(f"{v}: {kk}/{nn}")
        say(f"    by {label}: " + ", ".join(parts))
    durations = np.array([r["duration_s"] for r in nulls]) if nulls else np.zeros(0)
    if durations.size:
        say(f"    lengths {durations.min():.1f}-{durations.max():.1f} s; false alarms named: "
            + ", ".join(f"{r['key']}: {r['effects']}" for r in nulls if r["effects"]) or "none")
    say("\nfalse alarms per length (nothing hidden)")
    say(f"{'length (s)':>10s} {'alarms':>8s} {'rate':>7s}  target <= 5 %")
    for length in LENGTHS:
        rows = [r for r in by.get("length", []) if r["duration_s"] == length]
        if rows:
            f, kk, nn = rate(bool(r["effects"]) for r in rows)
            say(f"{length:10g} {kk:4d}/{nn:<3d} {f:7.1%}  {verdict(f <= 0.05)} ({interval(kk, nn)})"
                + (f"   ({', '.join(e for r in rows for e in r['effects'])})" if kk else ""))

    say("\nreliability of the first step's p-value on null logs (nulls and lengths together):")
    say("the fraction of logs with p < alpha (a calibrated test of 'the effect explains nothing' "
        "gives <= alpha when nothing is there; the model's own bias is something)")
    pooled = nulls + by.get("length", [])
    say(f"{'alpha':>7s} {'p < alpha':>10s} {'added':>7s}")
    for a in ALPHAS:
        f, kk, nn = rate(r["p_first"] < a for r in pooled)
        say(f"{a:7g} {f:10.1%} {rate(bool(r['effects']) for r in pooled)[0]:7.1%}")
    singles = by.get("single", [])
    if singles:
        ok = [named_set(r) == r["hidden"] for r in singles]
        f, kk, nn = rate(ok)
        say(f"\nsingle named effects at reference magnitude: exactly the hidden one {kk}/{nn} = {f:.1%}   "
            f"target >= 95 %: {verdict(f >= 0.95)}")
        for e in NAMED:
            rows = [r for r in singles if r["hidden"] == [e]]
            wrong = [str(r["effects"]) for r in rows if named_set(r) != [e]]
            say(f"    {e:>24s}: {sum(named_set(r) == [e] for r in rows)}/{len(rows)}"
                + (f"   got {'; '.join(wrong)}" if wrong else ""))
        say(visible_line(singles))
    power = by.get("power", [])
    if power:
        ks = sorted({r["magnitude"] for r in power} | {1.0})
        say("\ndetection against size: singles found exactly, at k times the reference magnitude "
            "(in brackets: logs where the truth halves the gap)")
        say(f"{'':>24s} " + " ".join(f"{f'{k:g} x':>11s}" for k in ks))
        for e in NAMED:
            cells = []
            for k in ks:
                rows = [r for r in singles + power if r["hidden"] == [e]
                        and r.get("magnitude", 1.0) == k]
                cells.append(f"{sum(named_set(r) == [e] for r in rows)}/{len(rows)} "
                             f"({sum(halves(r, 'gap_truth') for r in rows)})")
            say(f"{e:>24s} " + " ".join(f"{c:>11s}" for c in cells))
    for kind, label, target in (("pair", "pairs", 0.9), ("triple", "triples", None)):
        sets = by.get(kind, [])
        if not sets:
            continue
        f, kk, nn = rate(named_set(r) == sorted(r["hidden"]) for r in sets)
        say(f"\n{label} of named effects: exact set {kk}/{nn} = {f:.1%}   "
            + (f"target >= 90 %: {verdict(f >= target)}" if target else "no target"))
        for r in sets:
            if named_set(r) != sorted(r["hidden"]):
                gains = ", ".join(f"{e} {1 - r['gap_truth'] / g:.0%}" for e, g in r["gap_truth_without"].items())
                say(f"    {r['key']} hidden {r['hidden']} -> {r['effects']}   (each effect's "
                    f"shrink of the truth's gap: {gains}; gap {r['gap_after'] / r['gap_before']:.3f} "
                    f"of before, the truth {r['gap_truth'] / r['gap_before']:.3f})")
        say(visible_line(sets))
    oov = by.get("oov", [])
    if oov:
        worse = [r for r in oov for s in r["steps"] if s["added"] and s["effect"] in EFFECTS
                 and s["gap_after"] > s["gap_before"]]
        halved = rate(halves(r, "gap_after") for r in oov)
        reachable = [r for r in oov if halves(r, "gap_truth")]
        say(f"\nout-of-vocabulary shapes: named effects that worsen the held-out gap {len(worse)} "
            f"(target 0: {verdict(not worse)}); gap at least halved {halved[1]}/{halved[2]} = "
            f"{halved[0]:.1%} (target >= 90 %: {verdict(halved[0] >= 0.9)})")
        say(f"    the truth (the hidden shape itself) halves it on {len(reachable)}/{len(oov)}; "
            f"diagnose halves it on {sum(halves(r, 'gap_after') for r in reachable)} of those")
        say(f"{'shape':>22s} {'added':>40s} {'gap before':>11s} {'after':>10s} {'ratio':>6s} {'truth':>6s}")
        for r in sorted(oov, key=lambda r: r["key"]):
            say(f"{r['hidden'][0][4:]:>22s} {','.join(r['effects']) or 'none':>40s} "
                f"{r['gap_before']:11.3e} {r['gap_after']:10.3e} {r['gap_after'] / r['gap_before']:6.2f} "
                f"{r['gap_truth'] / r['gap_before']:6.2f}")
    added = [r for r in records if r["effects"] and r["kind"] != "power"]
    bad = [r for r in added if not halves(r, "gap_after")]
    say(f"\nheld-out gap after <= 0.5 x before wherever something was added: {len(added) - len(bad)}/"
        f"{len(added)}   {verdict(not bad)}; the truth reaches it on "
        f"{sum(halves(r, 'gap_truth') for r in added)}/{len(added)} of them")
    for r in bad:
        say(f"    {r['key']} hidden {r['hidden']} -> {r['effects']}: {r['gap_before']:.3e} -> "
            f"{r['gap_after']:.3e} (truth {r['gap_truth']:.3e})")
    say("\nthe gap after diagnose against the truth's (gap after / gap of the truth; 1 = as good "
        "as knowing the hidden effects):")
    hidden = []
    for kind in ("single", "pair", "triple", "oov"):
        rows = by.get(kind, [])
        hidden += rows
        ratios = [r["gap_after"] / r["gap_truth"] for r in rows]
        if ratios:
            q = np.quantile(ratios, [0.1, 0.5, 0.9])
            seen = sum(map(visible if kind != "oov" else shows, rows))
            say(f"    {kind:>7s}: median {q[1]:.2f} (10 % {q[0]:.2f}, 90 % {q[2]:.2f}), within 1.1 x "
                f"on {sum(x <= 1.1 for x in ratios)}/{len(ratios)}, within 1.25 x on "
                f"{sum(x <= 1.25 for x in ratios)}; visible {seen}, invisible {len(rows) - seen}")
    if hidden:
        f, kk, nn = rate(r["gap_after"] <= 1.1 * r["gap_truth"] for r in hidden)
        say(f"    all logs where something is hidden: within 1.1 x of the truth's gap on {kk}/{nn} = "
            f"{f:.1%}   target >= 95 %: {verdict(f >= 0.95)}")
        selected = [r for r in hidden if "gap_selected" in r]
        if selected:
            f, kk, nn = rate(r["gap_selected"] <= 1.1 * r["gap_truth"] for r in selected)
            say(f"    with the values the selection fitted (before the output-error refinement): "
                f"within 1.1 x on {kk}/{nn} = {f:.1%}")
    secs = sum(r["seconds_diagnose"] for r in records)
    say(f"\n{len(records)} logs; diagnose took {secs:.0f} s in total "
        f"(median {np.median([r['seconds_diagnose'] for r in records]):.1f} s per log)")
    (out / "summary.txt").write_text("\n".join(lines) + "\n")
    confusion_figure(nulls + singles, out / "confusion.png")


def visible_line(rows) -> str:
    """The exact-set rate on the logs where ``visible`` holds."""
    seen = [r for r in rows if visible(r)]
    f, kk, nn = rate(named_set(r) == sorted(r["hidden"]) for r in seen)
    return (f"    on the logs where each hidden effect shrinks the truth's gap by >= {MIN_GAIN:.0%} "
            f"(the held-out guard's threshold; else the guard forbids naming it): {len(seen)}/"
            f"{len(rows)} logs, exact set {kk}/{nn} = {f:.1%}")


def confusion_figure(records, path: Path):
    """Rows: hidden effect (none or one named effect); columns: first effect named."""
    rows = ["none"] + list(NAMED)
    cols = rows + ["table"]
    m = np.zeros((len(rows), len(cols)), dtype=int)
    for r in records:
        hidden = r["hidden"][0] if r["hidden"] else "none"
        first = r["effects"][0] if r["effects"] else "none"
        m[rows.index(hidden), cols.index(first if first in cols else "table")] += 1
    print("\nconfusion (rows: hidden; columns: first effect named)")
    print(f"{'':>8s} " + " ".join(f"{SHORT[c]:>6s}" for c in cols))
    for k, name in enumerate(rows):
        print(f"{SHORT[name]:>8s} " + " ".join(f"{c:6d}" for c in m[k]))
    try:
        import matplotlib
    except ImportError:
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    frac = m / np.maximum(m.sum(axis=1, keepdims=True), 1)
    fig, ax = plt.subplots(figsize=(8, 6.5), constrained_layout=True)
    ax.imshow(frac, cmap="Blues", vmin=0, vmax=1)
    for i in range(len(rows)):
        for j in range(len(cols)):
            if m[i, j]:
                ax.text(j, i, str(m[i, j]), ha="center", va="center",
                        color="white" if frac[i, j] > 0.5 else "black")
    ax.set_xticks(range(len(cols)), [SHORT[c] for c in cols], rotation=45)
    ax.set_yticks(range(len(rows)), [SHORT[r] for r in rows])
    ax.set_xlabel("first effect named")
    ax.set_ylabel("hidden effect")
    ax.set_title("fricgen diagnose on fricgen.sim.scenarios logs (nulls and singles)")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def per_length_counts(text: str) -> dict:
    """``N`` (every length) or ``LENGTH:N,...`` as {length: N}."""
    try:
        if ":" not in text:
            return {length: int(text) for length in LENGTHS}
        pairs = [part.split(":") for part in text.split(",")]
        counts = {float(a): int(b) for a, b in pairs}
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected N or LENGTH:N,..., got {text!r}")
    unknown = set(counts) - set(LENGTHS)
    if unknown:
        raise argparse.ArgumentTypeError(f"lengths must be among {LENGTHS}, got {sorted(unknown)}")
    return counts


def magnitude_list(text: str) -> tuple:
    """``K,...`` (positive multiples other than 1) or ``none`` as a tuple."""
    if text.strip() == "none":
        return ()
    try:
        ks = tuple(float(part) for part in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected K,... or none, got {text!r}")
    if not all(np.isfinite(k) and k > 0 and k != 1.0 for k in ks):
        raise argparse.ArgumentTypeError(f"multiples must be positive and not 1, got {text!r}")
    return ks


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="a quick run: 15 nulls, 14 s and 60 s "
                    "lengths, one seed per effect and shape, 6 pairs, 2 triples")
    ap.add_argument("--sensor-delay", action="store_true",
                    help="let diagnose consider sensor_delay too (as fricgen diagnose --sensor-delay)")
    ap.add_argument("--saturation", action="store_true",
                    help="let diagnose consider actuator_saturation too (as fricgen diagnose --saturation)")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--out", default="diagnose_confusion", help="folder for records, summary, figure")
    ap.add_argument("--report-only", action="store_true", help="report the records found, run nothing")
    ap.add_argument("--magnitudes", type=magnitude_list, default=None,
                    help="multiples of the reference magnitude the singles are run at again, "
                    "K,... (default 0.5,2; none with --small); 'none' for none")
    ap.add_argument("--kinds", type=lambda text: set(text.split(",")), default=set(KINDS),
                    help="the kinds of logs to run and report, of " + ",".join(KINDS)
                    + " (default all)")
    ap.add_argument("--per-length", type=per_length_counts, default={},
                    help="null logs at each length of " + ", ".join(f"{x:g}" for x in LENGTHS)
                    + " s: N for all, or LENGTH:N,... (default 60; 2 with --small)")
    args = ap.parse_args()
    global CANDIDATES
    CANDIDATES = candidates_with(*asked_for(args))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "records.jsonl"
    magnitudes = args.magnitudes if args.magnitudes is not None else (() if args.small else (0.5, 2.0))
    if not args.kinds <= set(KINDS):
        ap.error(f"--kinds: unknown {', '.join(sorted(args.kinds - set(KINDS)))}; of {','.join(KINDS)}")
    todo = [c for c in cases(args.small, args.per_length, magnitudes) if c[1] in args.kinds]
    keys = {c[0] for c in todo}
    done = {}
    if path.exists():
        for line in path.read_text().splitlines():
            r = json.loads(line)
            done[r["key"]] = r
    pending = [c for c in todo if c[0] not in done]
    pending.sort(key=lambda c: -c[4].get("duration_s", 0.0))     # the longest logs first
    if not args.report_only and pending:
        print(f"{len(pending)} logs to diagnose ({len(done)} done before)", flush=True)
        with ProcessPoolExecutor(args.jobs) as pool, path.open("a") as f:
            futures = {pool.submit(run_case, c): c for c in pending}
            for fut in as_completed(futures):
                try:
                    r = fut.result()
                except BaseException:           # stop at once, not after every pending log
                    pool.shutdown(wait=False, cancel_futures=True)
                    raise
                f.write(json.dumps(r) + "\n")
                f.flush()
                done[r["key"]] = r
                print(f"{r['key']:>28s} {r['rate_hz']:6.0f} Hz {r['duration_s']:7.1f} s -> "
                      f"{','.join(r['effects']) or 'none'} ({r['seconds_diagnose']:.0f} s)", flush=True)
    report([done[k] for k in done if k in keys], out, args.small)


if __name__ == "__main__":
    main()
