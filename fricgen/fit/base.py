"""The estimator contract every fricgen regressor follows (scikit-learn's).

Hyperparameters are stored unchanged in ``__init__`` and listed by its signature;
``get_params``/``set_params`` read and write them (so ``sklearn.base.clone`` and
``cross_val_score`` work); all work happens in ``fit(x, t)``, which returns ``self`` and sets
learned attributes ending in ``_``, among them ``network_``, the trained AIM of [F3];
``predict`` returns an array shaped like its input; ``score`` is the coefficient of
determination R^2. Randomness enters through one ``random_state``.
"""
from __future__ import annotations

import inspect

import numpy as np

from ..errors import FricgenError


def as_rng(random_state) -> np.random.Generator:
    """One source of randomness: an int seed, a Generator, or None.

    Parameters
    ----------
    random_state : int, numpy.random.Generator or None
        A Generator is returned as is; anything else seeds a new one.

    Returns
    -------
    numpy.random.Generator

    Examples
    --------
    >>> from fricgen.fit import as_rng
    >>> int(as_rng(0).integers(100)) == int(as_rng(0).integers(100))
    True
    """
    if isinstance(random_state, np.random.Generator):
        return random_state
    return np.random.default_rng(random_state)


def interleaved_folds(x, n_folds: int, rng=None) -> np.ndarray:
    """The cross-validation fold of each point: the points sorted by x are dealt to the
    ``n_folds`` folds in turn, so every fold spans the whole range of x. With a Generator
    ``rng`` each run of ``n_folds`` consecutive points is dealt in a random order (another
    partition of the same kind, for repeated cross-validation)."""
    n, k = np.size(x), int(n_folds)
    labels = np.arange(n) % k
    if rng is not None:
        labels = np.concatenate([rng.permutation(k) for _ in range(-(-n // k))])[:n]
        labels = labels % k
    fold = np.empty(n, dtype=int)
    fold[np.argsort(np.asarray(x, dtype=float).ravel(), kind="stable")] = labels
    return fold


class NotFittedError(FricgenError, AttributeError):
    """``predict`` or ``score`` called before ``fit``.

    Examples
    --------
    >>> from fricgen import ELMRegressor
    >>> from fricgen.fit import NotFittedError
    >>> try:
    ...     ELMRegressor().predict([0.5])
    ... except NotFittedError as exc:
    ...     print(exc)
    this ELMRegressor is not fitted yet; call fit first
    """


class Estimator:
    """Base of fricgen's regressors from the normalized input x to the target t of [F9].

    Hyperparameters are stored unchanged in ``__init__``; ``get_params``/``set_params`` read and
    write them (so ``sklearn.base.clone`` works); ``fit(x, t)`` returns self and sets learned
    attributes ending in ``_``, among them ``network_``; ``predict`` returns an array shaped like
    its input; ``score`` is R^2.

    Examples
    --------
    >>> from fricgen import ELMRegressor
    >>> from fricgen.fit import Estimator
    >>> elm = ELMRegressor(n_hidden=5)
    >>> isinstance(elm, Estimator), elm.set_params(n_hidden=8).get_params()["n_hidden"]
    (True, 8)
    """

    #: What scikit-learn before 1.6 reads to tell a regressor.
    _estimator_type = "regressor"

    def __sklearn_tags__(self):
        """The tags scikit-learn 1.6+ reads (``clone``, ``cross_val_score``): a regressor."""
        from sklearn.utils import RegressorTags, Tags, TargetTags   # optional dependency

        return Tags(estimator_type="regressor", target_tags=TargetTags(required=True),
                    regressor_tags=RegressorTags())

    @classmethod
    def _param_names(cls):
        signature = inspect.signature(cls.__init__)
        return sorted(p.name for p in signature.parameters.values()
                      if p.name != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD))

    def get_params(self, deep: bool = True) -> dict:
        """The hyperparameters, by name, exactly as given to ``__init__``."""
        return {name: getattr(self, name) for name in self._param_names()}

    def set_params(self, **params) -> "Estimator":
        """Set hyperparameters by name; unknown names raise ``ValueError``."""
        valid = self._param_names()
        for name, value in params.items():
            if name not in valid:
                raise ValueError(f"{type(self).__name__} has no parameter {name!r}; "
                                 f"valid: {', '.join(valid)}")
            setattr(self, name, value)
        return self

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.get_params().items())
        return f"{type(self).__name__}({args})"

    @staticmethod
    def _inputs(x, t=None):
        """x (any shape, or scikit-learn's (n, 1) column) and t as flat float arrays."""
        x = np.asarray(x, dtype=float)
        if x.ndim == 2 and x.shape[1] == 1:
            x = x[:, 0]
        x = x.ravel()
        if t is None:
            return x
        t = np.asarray(t, dtype=float).ravel()
        if x.size != t.size or x.size == 0:
            raise ValueError(f"x and t must have one equal, non-zero length, got {x.size}, {t.size}")
        return x, t

    def _network(self):
        network = getattr(self, "network_", None)
        if network is None:
            raise NotFittedError(f"this {type(self).__name__} is not fitted yet; call fit first")
        return network

    def predict(self, x) -> np.ndarray:
        """The fitted network at x, shaped like x (an (n, 1) column gives n values)."""
        x = np.asarray(x, dtype=float)
        shape = x.shape[:1] if x.ndim == 2 and x.shape[1] == 1 else x.shape
        return np.asarray(self._network()(x.reshape(-1))).reshape(shape)

    def score(self, x, t) -> float:
        """Coefficient of determination R^2 of ``predict(x)`` against ``t``."""
        t = np.asarray(t, dtype=float).ravel()
        y = np.asarray(self.predict(x), dtype=float).ravel()
        total = float(np.sum((t - t.mean()) ** 2))
        residual = float(np.sum((t - y) ** 2))
        return 1.0 - residual / total if total > 0 else (1.0 if residual == 0 else 0.0)
