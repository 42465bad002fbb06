"""Cortex-M cross builds of emitted models and the controller, and their runs under QEMU.

The public names: ``config_float`` writes the harness's fw_config.h, ``build_firmware`` links
a model folder with the bare-metal harness into an ELF for one of ``TARGETS``, ``run`` runs it
on QEMU (failures: ``FirmwareError``), ``missing_tools`` says why that cannot happen here, and
``available_flag_sets`` lists the compiler flag sets (``FlagSet``) of the flag matrix. The
modules hold the rest: ``build`` (fixed-point configs, section sizes, instruction counts),
``closed_loop`` (the closed-loop run against a float32 plant) and ``flag_matrix``. The names load on first use (PEP 562).
"""
from __future__ import annotations

from .._lazy import lazy_names

#: Each public name -> the module that defines it.
_PUBLIC = {name: "build" for name in (
    "TARGETS", "FirmwareError", "missing_tools", "build_firmware", "run", "config_float")}
_PUBLIC.update({"FlagSet": "flag_matrix", "available_flag_sets": "flag_matrix"})

__all__ = list(_PUBLIC)

__getattr__, __dir__ = lazy_names(globals(), _PUBLIC)
