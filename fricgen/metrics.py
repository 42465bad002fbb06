"""Error measures of section 2."""
from __future__ import annotations

import numpy as np


def rmse(y, t) -> float:
    """Root-mean-square error, eqs. (4)-(6)."""
    return float(np.sqrt(np.mean((np.asarray(y) - np.asarray(t)) ** 2)))
