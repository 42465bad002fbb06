"""The fleet's outputs, rewritten from all its results: the drift table (``fleet.parquet``,
``fleet.csv``), ``report.md`` (the flagged axes, the failed logs) and ``plots/``."""
from __future__ import annotations

import csv
import io
import math
from pathlib import Path
from typing import Dict, List, Sequence

from .._io import write_atomic
from .._plot import png, pyplot
from .drift import MONITORED, latest
from .extra import need
from .identification import DIRECTIONS, PARAMETERS


def _columns(rows: Sequence[dict]) -> List[str]:
    names = []
    for row in rows:
        names += [k for k in row if k not in names]
    return names


def table_csv(rows: Sequence[dict]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=_columns(rows), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: (f"{v:.9g}" if isinstance(v, float) else v) for k, v in row.items()})
    return buf.getvalue()


def table_parquet(rows: Sequence[dict]) -> bytes:
    """The table as Parquet bytes (pyarrow)."""
    pa, pq = need("pyarrow"), need("pyarrow.parquet")
    names = _columns(rows)
    table = pa.Table.from_pylist([{k: row.get(k) for k in names} for row in rows])
    buf = pa.BufferOutputStream()
    pq.write_table(table, buf)
    return buf.getvalue().to_pybytes()


def report_markdown(rows: Sequence[dict], sigmas: float, min_change: float, baseline: str) -> str:
    """report.md: the flagged axes first (their newest result), then the failed logs, then
    counts."""
    newest = latest(rows)
    flagged = [r for r in newest if r["flagged"]]
    failed = [r for r in rows if r["status"] != "ok"]
    lines = ["# Fleet friction report", "",
             f"{len(newest)} axes, {len(rows)} logs; {len(flagged)} axes flagged, {len(failed)} logs "
             f"failed. A parameter drifted when its change from the {baseline} result exceeds "
             f"{sigmas:g} combined standard errors and {min_change:.0%} of its earlier value.", "",
             "## Flagged axes", ""]
    if flagged:
        lines += ["| axis | timestamp | reference | drifted | changes (N, N s/m; in combined SE) |",
                  "|---|---|---|---|---|"]
        for r in sorted(flagged, key=lambda r: r["axis"]):
            changes = ", ".join(f"{n} {r[n + '_change']:+.3g} ({r[n + '_z']:.1f} SE)"
                                for n in r["drifted"].split())
            lines.append(f"| {r['axis']} | {r['timestamp']} | {r['reference']} | {r['drifted']} "
                         f"| {changes} |")
    else:
        lines.append("None.")
    lines += ["", "## Failed logs", ""]
    lines += [f"- {r['axis']} {r['timestamp']} `{r['log']}`: {r['error']}" for r in failed] or ["None."]
    return "\n".join(lines) + "\n"


def plots(rows: Sequence[dict]) -> Dict[str, bytes]:
    """PNG figures: the fleet's distribution of each parameter (newest results) and each
    flagged axis's trend; empty when matplotlib is missing."""
    plt = pyplot()
    if plt is None:
        return {}
    figures = {}
    newest = [r for r in latest(rows) if r["status"] == "ok"]
    if newest:
        fig, axes = plt.subplots(len(PARAMETERS), 2, figsize=(8, 2.2 * len(PARAMETERS)))
        for i, p in enumerate(PARAMETERS):
            for j, d in enumerate(DIRECTIONS):
                values = [r[f"{p}_{d}"] for r in newest if math.isfinite(r[f"{p}_{d}"])]
                axes[i, j].hist(values, bins=30)
                axes[i, j].set_title(f"{p} ({'v > 0' if d == 'pos' else 'v < 0'})", fontsize=9)
        fig.tight_layout()
        figures["distribution.png"] = png(fig)
    for axis in sorted({r["axis"] for r in latest(rows) if r["flagged"]}):
        history = [r for r in rows if r["axis"] == axis and r["status"] == "ok"]
        fig, axes = plt.subplots(1, len(MONITORED), figsize=(3.2 * len(MONITORED), 2.6))
        for ax, p in zip(axes, MONITORED):
            for d in DIRECTIONS:
                ax.errorbar(range(len(history)), [r[f"{p}_{d}"] for r in history],
                            yerr=[r[f"{p}_{d}_se"] for r in history], marker="o", label=d)
            ax.set_xticks(range(len(history)), [r["timestamp"] for r in history], rotation=30,
                          fontsize=7)
            ax.set_title(p, fontsize=9)
        axes[0].legend(fontsize=7)
        fig.suptitle(f"axis {axis}", fontsize=9)
        fig.tight_layout()
        safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in axis)
        figures[f"trend_{safe}.png"] = png(fig)
    return figures


def write_outputs(out, rows, sigmas, min_change, baseline) -> List[str]:
    """The table (Parquet and CSV), report.md and plots/, each written atomically; the notes to
    say (plots skipped without matplotlib)."""
    out = Path(out)
    write_atomic(out / "fleet.parquet", table_parquet(rows))
    write_atomic(out / "fleet.csv", table_csv(rows))
    write_atomic(out / "report.md", report_markdown(rows, sigmas, min_change, baseline))
    figures = plots(rows)
    if not figures:
        return ["no plots: matplotlib is not installed (pip install 'fricgen[plot]')"]
    (out / "plots").mkdir(exist_ok=True)
    for name, data in figures.items():
        write_atomic(out / "plots" / name, data)
    return []
