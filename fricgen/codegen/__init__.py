"""Emit a FrictionModel as fixed-size C and prove it: rendering (float, fast sigmoid, fixed point),
the float32 and integer twins, cffi builds and parity figures."""
from __future__ import annotations

from .package import PACKAGE_FILES, emit, package_files
from .render import (ACTIVATION_IMPLS, CONTROLLER_FILES, DTYPES, FAST_RUNTIME_FILES, RUNTIME_FILES,
                     check_name_in_folder, check_overwrite, controller_files,
                     generated_models, render, runtime_files, template_context)

__all__ = ["ACTIVATION_IMPLS", "CONTROLLER_FILES", "DTYPES", "FAST_RUNTIME_FILES", "PACKAGE_FILES",
           "RUNTIME_FILES", "package_files",
           "check_name_in_folder", "check_overwrite", "controller_files", "emit", "generated_models",
           "render", "runtime_files", "template_context"]
