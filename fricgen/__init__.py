"""fricgen: multisource friction models trained in Python, emitted as fixed-size C.

The public names are importable from here, loaded on first use (PEP 562), so that
``import fricgen`` (and ``fricgen --help``) loads no numerics:

- data: ``Sweep``, ``read_sweep_csv``, ``MotionLog``, ``read_log_csv``, ``synthesize_benchmark``,
  ``preset`` and ``MultisourceFriction`` [F1]-[F2];
- the model and its model.json: ``FrictionModel`` (``load``, ``save``, ``force``);
- training: ``train`` -> ``FitReport``, and the estimators ``DefaultRegressor``,
  ``StribeckRegressor``, ``AutoELMRegressor``, ``ELMRegressor``;
- C: ``emit`` and ``render``;
- diagnosis: ``Diagnoser``; control: ``AdaptiveBackstepping`` and ``compare`` (closed loops);
- errors: ``FricgenError``, ``DataError``, ``ModelError``, ``UsageError``.

Subpackages, in their one-way import order: ``networks`` and ``effects`` (what a model holds),
``model`` ([F3] and model.json), ``data``, ``fit``, ``codegen``, ``training``, ``sim``,
``control``, ``diagnose``, ``paper``, ``firmware``, ``fleet``, ``cli``.

Examples
--------
>>> import fricgen
>>> sweep = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).train
>>> len(sweep)
300
"""
from __future__ import annotations

from ._lazy import lazy_names

__version__ = "0.1.0"

#: Each public name -> the module that defines it.
_PUBLIC = {
    "FricgenError": "errors", "DataError": "errors", "ModelError": "errors", "UsageError": "errors",
    "MultisourceFriction": "friction", "preset": "friction",
    "FrictionModel": "model",
    "Sweep": "data", "read_sweep_csv": "data", "MotionLog": "data", "read_log_csv": "data",
    "synthesize_benchmark": "data",
    "DefaultRegressor": "fit", "StribeckRegressor": "fit", "AutoELMRegressor": "fit",
    "ELMRegressor": "fit",
    "train": "training.trainer", "FitReport": "training.report",
    "emit": "codegen", "render": "codegen",
    "Diagnoser": "diagnose",
    "AdaptiveBackstepping": "control", "compare": "control",
}

__all__ = ["__version__", *_PUBLIC]

__getattr__, __dir__ = lazy_names(globals(), _PUBLIC)
