"""Public names of a package loaded on first use (PEP 562): ``import fricgen`` (and ``fricgen
--help``) loads no numerics."""
from __future__ import annotations

import importlib
from typing import Callable, Dict, Tuple


def lazy_names(namespace: dict, public: Dict[str, str]) -> Tuple[Callable, Callable]:
    """The ``__getattr__`` and ``__dir__`` of the package whose globals are ``namespace``:
    each name of ``public`` imported from its submodule (``public[name]``) on first use."""
    package = namespace["__name__"]

    def __getattr__(name: str):
        if name not in public:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{public[name]}"), name)
        namespace[name] = value
        return value

    def __dir__():
        return sorted(set(namespace) | set(namespace.get("__all__", ())))

    return __getattr__, __dir__
