"""What every generated file shares: the template environment and the file's identity."""
from __future__ import annotations

import jinja2

from .. import __version__
from .._io import resource_dir
from ..effects import model_effects
from ..model import FORMAT_VERSION, FrictionModel, check_model_name


def template_environment() -> jinja2.Environment:
    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(resource_dir("templates"))),
                              undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
                              autoescape=False)


def identity_context(model: FrictionModel, name: str) -> dict:
    """What every generated file states about itself: its name, guard, generator and model.
    The guard FRICGEN_NAME_H stays clear of the runtime's (FRIC_*_H) and the C library's."""
    check_model_name(name, "name")
    return {"name": name, "NAME": name.upper(), "GUARD": f"FRICGEN_{name.upper()}_H",
            "fricgen_version": __version__, "format_version": FORMAT_VERSION,
            "model_hash": model.model_hash}


def effects_context(model: FrictionModel) -> dict:
    """What the templates need for NAME_force_xv: the C terms and the effects left out of C."""
    effects = model_effects(model)
    return {"effects": [{"name": e.name, "c_expr": e.c_expr()} for e in effects if e.in_xv],
            "effects_not_in_c": [e.name for e in effects if not e.in_xv]}
