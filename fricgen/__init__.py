"""fricgen: multisource friction models trained in Python, emitted as fixed-size C.

Subpackages, in their one-way import order: ``networks`` and ``effects`` (what a model holds),
``model`` (eq. 3 and model.json), ``data``, ``fit``, ``codegen``, ``sim``, ``control``,
``diagnose``, ``paper``, ``firmware``, ``cli``. This module imports none of them.
"""
__version__ = "0.1.0"
