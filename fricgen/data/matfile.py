"""MATLAB files: the variables of a ``.mat`` file (v4 to v7, what ``scipy.io.loadmat`` reads)
as the columns and scalars of an export.

A real numeric vector, (N,), (N,1) or (1,N), is a column named by its variable; a real numeric
(1,1) is a scalar (a factor ``--scale`` may name, e.g. EMPS's ``gtau``, N/V). Anything else
(text, struct, cell, matrix, complex) is ignored until asked for, then refused naming its shape.
Names are read regardless of case, as CSV headers are.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, Union

import numpy as np
from scipy.io import loadmat

from ..errors import DataError

#: How a MAT-file's 128-byte header begins (v5, v7 and v7.3: "MATLAB 5.0 MAT-file, ...").
MAGIC = b"MATLAB "
#: What a v7.3 file (HDF5, which loadmat does not read) is told.
V73_HINT = "save it in MATLAB with save(FILE, '-v7')"


def is_matfile(path: Union[str, Path]) -> bool:
    """Whether ``path`` is a MATLAB file: named ``.mat``, or its header says so."""
    if Path(path).suffix.lower() == ".mat":
        return True
    try:
        with open(path, "rb") as fh:
            head = fh.read(128)
    except OSError:
        return False          # the reader of the file says why it cannot be read
    return head.startswith(MAGIC) and b"MAT-file" in head[:40]


def _shape(a) -> str:
    return "x".join(str(n) for n in np.shape(a))


def _kind(a) -> str:
    """What a variable that is neither a column nor a scalar is, for messages."""
    if not isinstance(a, np.ndarray):
        return f"a {_shape(a)} sparse matrix" if hasattr(a, "toarray") else "not numeric"
    if a.dtype.names:
        return f"a {_shape(a)} struct"
    if a.dtype.kind in "US":
        return "text"
    if a.dtype == object:
        return f"a {_shape(a)} cell array"
    if a.dtype.kind == "c":
        return f"complex, {_shape(a)}"
    if a.size == 0:
        return f"empty ({_shape(a)})"
    if a.dtype.kind == "b":
        return f"logical, {_shape(a)}"
    return f"a {_shape(a)} matrix, not a vector"


def _real(a) -> bool:
    return isinstance(a, np.ndarray) and a.dtype.kind in "iuf"


@dataclass(frozen=True)
class MatFile:
    """The variables of one MATLAB file by lower-case name: ``vectors`` (float, 1-D),
    ``scalars`` and the ``others`` (what each is, for messages)."""

    path: str
    vectors: Dict[str, np.ndarray]
    scalars: Dict[str, float]
    others: Dict[str, str]

    def columns(self, required: Iterable[str], wanted: Iterable[str] = ()) -> Dict[str, np.ndarray]:
        """The vectors of the length of the ``required`` variables and of the vectors among
        ``wanted``, which must all have one length (else ``DataError`` naming the first and one
        of another length; a required variable the file lacks, or that is no vector, is a
        ``DataError`` too). Vectors of another length are no columns of this table: left out."""
        named = list(dict.fromkeys([*required, *(w for w in wanted if w in self.vectors)]))
        for name in named:
            self._check_vector(name)
        sizes = [self.vectors[name].size for name in named]
        for name, size in zip(named, sizes):
            if size != sizes[0]:
                raise DataError(f"{self.path}: variables {named[0]!r} ({sizes[0]} values) and "
                                f"{name!r} ({size} values) differ in length")
        if not sizes:                       # nothing named: the most common length
            sizes = [a.size for a in self.vectors.values()]
            sizes = [max(sizes, key=sizes.count, default=0)]
        return {k: a for k, a in self.vectors.items() if a.size == sizes[0]}

    def _check_vector(self, name: str) -> None:
        if name in self.vectors:
            return
        if name in self.scalars:
            raise DataError(f"{self.path}: variable {name!r} is a scalar (1x1), not a column")
        if name in self.others:
            raise DataError(f"{self.path}: variable {name!r} is {self.others[name]}; a column "
                            "is a real vector (N,1) or (1,N)")
        raise DataError(f"{self.path}: no variable {name!r} (its vectors: "
                        f"{', '.join(self.vectors)[:80] or 'none'})")


def read_matfile(path: Union[str, Path]) -> MatFile:
    """The variables of the MATLAB file ``path``; ``DataError`` in one line for a v7.3 file
    (with the hint to save it as v7), an unreadable one, one without variables, or two names
    that differ only in case."""

    try:
        with open(path, "rb"):
            pass
    except OSError as exc:
        raise DataError(f"{path}: cannot read ({exc.strerror or exc})") from None
    try:
        raw = loadmat(path, appendmat=False)
    except NotImplementedError:
        raise DataError(f"{path}: a MATLAB v7.3 (HDF5) file, which fricgen does not read; "
                        f"{V73_HINT}") from None
    except Exception as exc:              # noqa: BLE001 - scipy raises many kinds on bad bytes
        why = str(exc).splitlines()[0][:80] if str(exc) else type(exc).__name__
        raise DataError(f"{path}: not a readable MATLAB file ({why})") from None
    variables = {k: a for k, a in raw.items() if not k.startswith("__")}
    if not variables:
        raise DataError(f"{path}: a MATLAB file without variables")
    lower: Dict[str, str] = {}
    for name in variables:
        if name.lower() in lower:
            raise DataError(f"{path}: variables {lower[name.lower()]!r} and {name!r} differ only in "
                            "case; fricgen reads names regardless of case")
        lower[name.lower()] = name
    vectors, scalars, others = {}, {}, {}
    for name, a in variables.items():
        key = name.lower()
        if _real(a) and a.ndim <= 2 and a.size == 1:
            scalars[key] = float(a.ravel()[0])
        elif _real(a) and a.size >= 2 and (a.ndim == 1 or a.ndim == 2 and min(a.shape) == 1):
            vectors[key] = np.asarray(a, dtype=float).ravel()
        else:
            others[key] = _kind(a)
    return MatFile(str(path), vectors, scalars, others)
