"""The paper's reported numbers, its experiments over seeds, report.md and the figures."""
