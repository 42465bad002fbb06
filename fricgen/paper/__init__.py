"""The paper's reported numbers, its experiments over seeds, report.md and the figures.

What ``fricgen reproduce`` runs: ``reproduce`` (every experiment of sections 3-5 over seeds),
``fitted_seed0`` (the headline models on seed 0), ``render`` (report.md: Table 2 measured
beside the paper's) and ``render_figures`` (the PNGs of ``FIGURES``); the paper's own figures
are ``REPORTED``, ``HEADLINE_ELMS`` and ``SEEDS``. The names load on first use (PEP 562), so
that importing the reported numbers loads no numerics.
"""
from __future__ import annotations

from .._lazy import lazy_names

#: Each public name -> the module that defines it.
_PUBLIC = {"reproduce": "experiments", "fitted_seed0": "experiments", "HEADLINE": "experiments",
           "render": "report", "render_figures": "figures", "FIGURES": "figures",
           "REPORTED": "reported", "HEADLINE_ELMS": "reported", "SEEDS": "reported"}

__all__ = list(_PUBLIC)

__getattr__, __dir__ = lazy_names(globals(), _PUBLIC)
