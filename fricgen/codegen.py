"""Render a FrictionModel as fixed-size C (templates/ + c_runtime/), eq. (3) and eq. (7)."""
from __future__ import annotations

from pathlib import Path
from typing import Dict, Iterable, Optional, Union

import jinja2
import numpy as np

from . import __version__
from .elm import ElmNetwork
from .files import write_all_atomic
from .model import FORMAT_VERSION, FrictionModel, ModelError, check_c_identifier
from .effects import c_context as effects_c_context

#: Runtime files every emitted model needs beside NAME.h and NAME.c.
RUNTIME_FILES = ("fric_kernel.h", "fric_kernel.c")
#: The float controller runtime (section 6) copied beside every float model, see fric_ctrl.h.
CONTROLLER_FILES = ("fric_ctrl.h", "fric_ctrl.c")


def resource_dir(kind: str) -> Path:
    """The folder of the shipped ``templates`` or ``c_runtime`` files.

    A wheel installs them inside the package (``fricgen/templates``); a source checkout keeps
    them at the top of the repository, beside ``fricgen/``.
    """
    package = Path(__file__).resolve().parent
    for path in (package / kind, package.parent / kind):
        if path.is_dir():
            return path
    raise FileNotFoundError(f"fricgen {kind} folder not found beside {package} (broken install?)")


def c_float(value: float) -> str:
    """A C float literal that round-trips the float32 rounding of ``value`` exactly (9 digits)."""
    with np.errstate(over="ignore"):
        f = np.float32(value)
    if not np.isfinite(f):
        raise ModelError(f"value {value!r} is not representable as a finite float")
    text = f"{float(f):.9g}"
    if not any(c in text for c in ".en"):
        text += ".0"
    elif "e" in text and "." not in text.split("e")[0]:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}.0e{exponent}"
    return text + "f"


def c_list(items: Iterable[str], per_line: int) -> str:
    """Body of a C array initializer: the literals ``items``, ``per_line`` to an indented line."""
    items = list(items)
    lines = [", ".join(items[i:i + per_line]) for i in range(0, len(items), per_line)]
    return ",\n".join("    " + line for line in lines)


def c_array(values: Iterable[float], per_line: int = 4) -> str:
    """A float table's initializer body, every value an exact float literal."""
    return c_list((c_float(v) for v in values), per_line)


def template_environment() -> jinja2.Environment:
    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(resource_dir("templates"))),
                              undefined=jinja2.StrictUndefined, keep_trailing_newline=True,
                              autoescape=False)


def identity_context(model: FrictionModel, name: str) -> dict:
    """What every generated file states about itself: its name, guard, generator and model."""
    check_c_identifier(name, "name")
    return {"name": name, "NAME": name.upper(), "GUARD": f"{name.upper()}_H",
            "fricgen_version": __version__, "format_version": FORMAT_VERSION,
            "model_hash": model.model_hash}


def template_context(model: FrictionModel, name: str) -> dict:
    """Everything the templates need, every number already a checked C literal."""
    ident = identity_context(model, name)
    net = model.aim
    if not isinstance(net, ElmNetwork):
        raise ModelError(f"emit supports ELM models; this model's AIM is {type(net).__name__}")
    return {
        **ident, "n_hidden": net.n_hidden, "activation": net.activation,
        "input_weights": c_array(net.input_weights), "biases": c_array(net.biases),
        "output_weights": c_array(net.output_weights),
        "k_in": c_float(model.scaling.k_in), "inv_k_out": c_float(1.0 / model.scaling.k_out),
        "viscous": c_float(model.viscous), "v_sat": c_float(model.v_sat),
        "kernel": f"fric_elm_{net.activation}_f32", "kernel_header": "fric_kernel.h",
        "tables_note": "",  # a comment above the tables when they are not plain w and b
        **effects_c_context(model),  # effects, effects_not_in_c: NAME_force_xv
    }


#: ``--activation-impl``: libm's expf (the default) or the fast sigmoid without libm (fric_fast.c).
ACTIVATION_IMPLS = ("libm", "fast")
#: ``--dtype``: float, or the fixed-point models of fricgen.fixedpoint (no FPU needed).
DTYPES = ("float", "q15", "q31")


def render(model: FrictionModel, name: Optional[str] = None, activation_impl: str = "libm",
           dtype: str = "float") -> Dict[str, str]:
    """All files of the emitted folder, by file name: NAME.h, NAME.c and the runtime."""
    name = model.name if name is None else name
    if activation_impl not in ACTIVATION_IMPLS:
        raise ModelError(f"activation_impl must be one of {list(ACTIVATION_IMPLS)}, got {activation_impl!r}")
    if dtype not in DTYPES:
        raise ModelError(f"dtype must be one of {list(DTYPES)}, got {dtype!r}")
    if dtype != "float":
        if model.effects:
            raise ModelError(f"--dtype {dtype} does not emit effects; this model has "
                             f"{len(model.effects)} (emit it with --dtype float)")
        from .fixedpoint import render_fixed
        return render_fixed(model, name, dtype)
    env = template_environment()
    ctx = template_context(model, name)
    runtime_files = RUNTIME_FILES
    if activation_impl == "fast":
        from .fast_sigmoid import check_fast_model, fast_tables
        check_fast_model(model)
        w, b, _ = fast_tables(model.aim)  # t = w' x + b' = -log2(e) (w x + b), see fric_fast.h
        ctx.update(kernel="fric_elm_sigmoid_fast_f32", kernel_header="fric_fast.h",
                   input_weights=c_array(w), biases=c_array(b),
                   tables_note="w and b times -log2(e): t = w x + b, sigma = 1 / (1 + 2^t)")
        runtime_files = ("fric_fast.h", "fric_fast.c")
    files = {f"{name}.h": env.get_template("model.h.j2").render(ctx),
             f"{name}.c": env.get_template("model.c.j2").render(ctx)}
    runtime = resource_dir("c_runtime")
    for fname in runtime_files + CONTROLLER_FILES:
        files[fname] = (runtime / fname).read_text()
    return files


def emit(model: FrictionModel, out_dir: Union[str, Path], name: Optional[str] = None,
         activation_impl: str = "libm", dtype: str = "float") -> Dict[str, Path]:
    """Render everything first, then write each file atomically into ``out_dir``."""
    return write_all_atomic(out_dir, render(model, name, activation_impl, dtype))

