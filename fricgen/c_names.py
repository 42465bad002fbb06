"""The names of emitted C: a model's name is the prefix of NAME.h, NAME.c, NAME_force and the
include guard, so it must be a C identifier of file scope that clashes with neither the C runtime
nor a standard header."""
from __future__ import annotations

import re
from typing import Any

from .errors import ModelError

_C_KEYWORDS = frozenset("""auto break case char const continue default do double else enum extern
float for goto if inline int long register restrict return short signed sizeof static struct
switch typedef union unsigned void volatile while _Bool _Complex _Imaginary""".split())
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,62}\Z")
#: The C runtime's prefix: its files (fric_kernel.h, fric_fast.h, fric_ctrl.h), functions and
#: macros (FRIC_KERNEL_H, ...) begin with it, in any case; no model name may.
RUNTIME_PREFIX = "fric_"
#: The C standard library's headers: a model named like one would shadow it (NAME.h beside the
#: runtime, whose folder is on the include path) on any file system that ignores case.
_C_STD_HEADERS = frozenset("""assert complex ctype errno fenv float inttypes iso646 limits locale
math setjmp signal stdalign stdarg stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string
tgmath threads time uchar wchar wctype""".split())


def check_c_identifier(name: Any, what: str = "name") -> str:
    """A C identifier of file scope: at most 63 characters, no keyword, no leading underscore
    (C99 7.1.3 reserves every file-scope name that begins with one).

    Parameters
    ----------
    name : object
        The candidate.
    what : str
        What the message calls it.

    Returns
    -------
    str
        ``name``, unchanged; a ``ModelError`` naming ``what`` when it is no such identifier.

    Examples
    --------
    >>> from fricgen.c_names import check_c_identifier
    >>> check_c_identifier("axis_x")
    'axis_x'
    """
    if isinstance(name, str) and name in _C_KEYWORDS:
        raise ModelError(f"{what} must not be a C keyword, got {name!r}")
    if not isinstance(name, str) or not _IDENT.match(name):
        raise ModelError(f"{what} must be a C identifier (letters, digits, _; 1-63 characters), "
                         f"got {name!r}"[:200])
    if name.startswith("_"):
        raise ModelError(f"{what} must not begin with '_' (C reserves such names), got {name!r}")
    return name


def check_model_name(name: Any, what: str = "name") -> str:
    """A name the emitted C may use for NAME.h, NAME.c, NAME_force and the guard: a C identifier
    outside the runtime's prefix (``fric_``) and unlike any standard header, in any case.

    Parameters
    ----------
    name : object
        The candidate.
    what : str
        What the message calls it.

    Returns
    -------
    str
        ``name``, unchanged; a ``ModelError`` otherwise.

    Examples
    --------
    >>> from fricgen.c_names import check_model_name
    >>> try:
    ...     check_model_name("math")
    ... except ValueError as exc:
    ...     print(exc)
    name must not be the name of a C standard header (math.h), got 'math'
    """
    check_c_identifier(name, what)
    if name.lower().startswith(RUNTIME_PREFIX):
        raise ModelError(f"{what} must not begin with {RUNTIME_PREFIX!r} in any case (the C "
                         f"runtime's files and symbols use it), got {name!r}")
    if name.lower() in _C_STD_HEADERS:
        raise ModelError(f"{what} must not be the name of a C standard header "
                         f"({name.lower()}.h), got {name!r}")
    return name
