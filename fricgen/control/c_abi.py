"""The C ABI of the controller (c_runtime/fric_ctrl.h) as one table.

It lists the header's enums (status codes, adaptation laws, friction input), the flags a step
returns, the fields of
``fric_ctrl_params_t`` and ``fric_ctrl_t`` in order, and how each parameter comes from an
``AdaptiveBackstepping`` (``settings``). The cffi declarations (``CDEF``), the parameters of
``CController`` (``param_values``) and the firmware's C initializer (``params_initializer``)
derive from it; tests/test_c_abi.py checks it against the header.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from operator import attrgetter
from typing import Callable, Dict, List, Optional, Tuple, Union

from .._io import resource_dir
from ..c_literal import c_float
from .gamma import gamma_matrix

#: FRIC_CTRL_VERSION of the header.
VERSION = 4


@dataclass(frozen=True)
class Enumerator:
    """A C enumerator: its name, value and Python key (a settings value, or for a status code
    what it means)."""

    name: str
    value: int
    key: str


@dataclass(frozen=True)
class CEnum:
    """A ``typedef enum {...} ctype;`` of the header."""

    ctype: str
    members: Tuple[Enumerator, ...]

    @property
    def keys(self) -> Tuple[str, ...]:
        return tuple(m.key for m in self.members)

    def member(self, key: str) -> Enumerator:
        """The enumerator of ``key`` (KeyError if there is none)."""
        for m in self.members:
            if m.key == key:
                return m
        raise KeyError(f"{self.ctype} has no enumerator for {key!r}")

    def key_of(self, value: int) -> str:
        """The key of the enumerator with ``value``, or the value as text if there is none."""
        return next((m.key for m in self.members if m.value == value), str(value))

    def value(self, key: str) -> int:
        """The value of the enumerator of ``key``."""
        return self.member(key).value

    def cdef(self) -> str:
        body = ", ".join(f"{m.name} = {m.value}" for m in self.members)
        return f"typedef enum {{ {body} }} {self.ctype};\n"


@dataclass(frozen=True)
class CFlags(CEnum):
    """Bit flags of the header: ``typedef unsigned int ctype;`` and one ``#define`` each."""

    def cdef(self) -> str:
        return f"typedef unsigned int {self.ctype};\n" + "".join(
            f"#define {m.name} {m.value}\n" for m in self.members)

    def keys_of(self, value: int) -> Tuple[str, ...]:
        """The keys of the flags set in ``value`` (those of 0: ("ok",))."""
        return tuple(m.key for m in self.members if m.value & value) or (self.key_of(0),)


@dataclass(frozen=True)
class CChoice(CEnum):
    """A choice a struct holds: ``typedef int32_t ctype;`` and one typed constant each
    (``#define NAME ((ctype)value)`` in the header), one layout whatever the enum size."""

    def cdef(self) -> str:
        return f"typedef int32_t {self.ctype};\n" + "".join(
            f"#define {m.name} {m.value}\n" for m in self.members)


def _enum(ctype: str, *members: Tuple[str, int, str]) -> CEnum:
    return CEnum(ctype, tuple(Enumerator(*m) for m in members))


def choice(ctype: str, *members: Tuple[str, int, str]) -> CChoice:
    return CChoice(ctype, tuple(Enumerator(*m) for m in members))


#: What fric_ctrl_init returns.
STATUS = _enum("fric_ctrl_status_t",
               ("FRIC_CTRL_OK", 0, "ok"),
               ("FRIC_CTRL_ERR_NULL", -1, "NULL pointer"),
               ("FRIC_CTRL_ERR_PARAM", -2, "parameter out of range"))
#: The adaptation laws of [C14], keyed by ``AdaptiveBackstepping.law``.
LAW = choice("fric_ctrl_law_t",
            ("FRIC_CTRL_LAW_A", 0, "a"),
            ("FRIC_CTRL_LAW_B", 1, "b"),
            ("FRIC_CTRL_LAW_C", 2, "c"))
#: Where the friction model is evaluated, keyed by ``AdaptiveBackstepping.friction_input``.
FRICTION_INPUT = choice("fric_ctrl_friction_at_t",
                       ("FRIC_CTRL_FRICTION_AT_V", 0, "v"),
                       ("FRIC_CTRL_FRICTION_AT_VD", 1, "vd"),
                       ("FRIC_CTRL_FRICTION_AT_REF", 2, "reference"))
ENUMS = (STATUS, LAW, FRICTION_INPUT)
#: What fric_ctrl_step and fric_ctrl_step_fn return (and fric_ctrl_t.flags holds): an OR of these.
FLAGS = CFlags("fric_ctrl_flags_t", tuple(Enumerator(*m) for m in (
    ("FRIC_CTRL_STEP_OK", 0, "ok"),
    ("FRIC_CTRL_FAULT_NULL", 1, "NULL pointer"),
    ("FRIC_CTRL_INPUT_FAULT", 2, "input fault"),
    ("FRIC_CTRL_SATURATED", 4, "saturated"),
    ("FRIC_CTRL_PROJECTED", 8, "projected"))))

#: A parameter's value: a float, the floats of an array, or an enumerator.
Value = Union[float, List[float], Enumerator]


@dataclass(frozen=True)
class Field:
    """A struct field: C name, C type (of the elements, for an array), and for a parameter its
    value from validated settings (``of_settings``); ``length`` > 0 makes it an array."""

    name: str
    ctype: str
    of_settings: Optional[Callable[[object], object]] = None
    length: int = 0

    def declaration(self) -> str:
        return f"{self.ctype} {self.name}" + (f"[{self.length}]" if self.length else "")

    def value(self, settings) -> Value:
        """The field's value for validated ``settings``."""
        v = self.of_settings(settings)
        if isinstance(v, Enumerator):
            return v
        return [float(x) for x in v] if self.length else float(v)


#: fric_ctrl_params_t, field by field.
PARAMS = (
    Field("k1", "float", attrgetter("k1")),
    Field("k2", "float", attrgetter("k2")),
    Field("gamma", "float", lambda s: gamma_matrix(s.gamma).ravel(), length=4),  # row-major
    Field("delta", "float", attrgetter("delta")),
    Field("ts", "float", attrgetter("ts")),
    Field("phi_n", "float", attrgetter("phi_n")),
    Field("i_max", "float", attrgetter("i_max")),
    Field("m_o_hat0", "float", lambda s: s.a0[0]),
    Field("k_hat0", "float", lambda s: s.a0[1]),
    Field("m_o_min", "float", lambda s: s.a_min[0]),
    Field("m_o_max", "float", lambda s: s.a_max[0]),
    Field("k_min", "float", lambda s: s.a_min[1]),
    Field("k_max", "float", lambda s: s.a_max[1]),
    Field("law", LAW.ctype, lambda s: LAW.member(s.law)),
    Field("friction_at", FRICTION_INPUT.ctype, lambda s: FRICTION_INPUT.member(s.friction_input)),
)
#: fric_ctrl_t, field by field.
STATE = (
    Field("p", "fric_ctrl_params_t"),
    Field("m_o_hat", "float"),
    Field("k_hat", "float"),
    Field("e1", "float"),
    Field("e2", "float"),
    Field("i", "float"),
    Field("flags", FLAGS.ctype),
)
#: fric_ctrl_sample_t (the _sample steps' measurements and reference), field by field.
SAMPLE = tuple(Field(name, "float") for name in ("x", "v", "xd", "xd_dot", "xd_ddot"))
STRUCTS = {"fric_ctrl_params_t": PARAMS, "fric_ctrl_t": STATE, "fric_ctrl_sample_t": SAMPLE}

def function_declarations() -> str:
    """The prototypes of fric_ctrl.h's functions, read from the header itself (comments and
    line breaks dropped): the header is the one place they are written."""
    text = re.sub(r"/\*.*?\*/", " ", (resource_dir("c_runtime") / "fric_ctrl.h").read_text(),
                  flags=re.S)
    found = re.findall(r"^\s*(?:void|float|fric_ctrl_status_t|fric_ctrl_flags_t)\s+fric_ctrl_\w+\s*\([^;{]*\)\s*;",
                       text, flags=re.M)
    return "".join(" ".join(proto.split()) + "\n" for proto in found)


def _struct_cdef(ctype: str, fields: Tuple[Field, ...]) -> str:
    body = "".join(f"    {f.declaration()};\n" for f in fields)
    return f"typedef struct {{\n{body}}} {ctype};\n"


#: The cffi declarations of fric_ctrl.h.
CDEF = ("".join(e.cdef() for e in ENUMS + (FLAGS,))
        + "typedef float (*fric_ctrl_friction_fn)(float v);\n"
        + "".join(_struct_cdef(ctype, fields) for ctype, fields in STRUCTS.items())
        + function_declarations())


def _values(settings) -> Dict[str, Value]:
    s = settings.validate()
    return {f.name: f.value(s) for f in PARAMS}


def param_values(settings) -> Dict[str, Union[float, List[float], int]]:
    """The fric_ctrl_params_t of ``settings`` (an ``AdaptiveBackstepping``, validated first) as
    cffi takes it: field name -> float, list of floats, or an enum's value."""
    return {name: v.value if isinstance(v, Enumerator) else v
            for name, v in _values(settings).items()}


def _c_literal(v: Value) -> str:
    if isinstance(v, Enumerator):
        return v.name
    if isinstance(v, list):
        return "{" + ", ".join(c_float(x) for x in v) + "}"
    return c_float(v)


def params_initializer(settings) -> str:
    """The fric_ctrl_params_t of ``settings`` as a C designated initializer (exact float
    literals, enumerators by name)."""
    return "{" + ", ".join(f".{name} = {_c_literal(v)}" for name, v in _values(settings).items()) + "}"
