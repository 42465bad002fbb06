"""Gamma, the adaptation gain of [C13], in the one form the controllers use."""
from __future__ import annotations

import numpy as np


def gamma_matrix(gamma) -> np.ndarray:
    """Gamma of [C13] as a 2x2 array from a scalar, a diagonal (2 values) or a 2x2 matrix;
    it must be symmetric positive definite."""
    g = np.asarray(gamma, dtype=float)
    if g.ndim == 0:
        g = g * np.eye(2)
    elif g.shape == (2,):
        g = np.diag(g)
    if g.shape != (2, 2):
        raise ValueError(f"gamma must be a scalar, 2 values or a 2x2 matrix, got shape {g.shape}")
    if not np.all(np.isfinite(g)):
        raise ValueError(f"gamma must be finite, got {g.tolist()}")
    if g[0, 1] != g[1, 0]:
        raise ValueError(f"gamma must be symmetric, got {g.tolist()}")
    if np.linalg.eigvalsh(g).min() <= 0:
        raise ValueError(f"gamma must be positive definite, got {g.tolist()}")
    return g
