"""Figures without a display: matplotlib (an optional dependency) and PNG bytes in memory."""
from __future__ import annotations

import io


def pyplot():
    """matplotlib.pyplot on the Agg backend, or None when matplotlib is not installed."""
    try:
        import matplotlib
    except ImportError:
        return None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


#: The PNG "Software" text of every figure fricgen writes: how ``diagnose`` knows its own plots.
PNG_SOFTWARE = "fricgen"


def png(fig, dpi: int = 100) -> bytes:
    """The figure as PNG bytes (nothing touches the disk); the figure is closed."""
    plt = pyplot()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": PNG_SOFTWARE})
    plt.close(fig)
    return buf.getvalue()
