"""The numeric CSV every sweep and motion log is read from and written to, as drives and
spreadsheets write it: ',', ';', tab or whitespace between cells (detected on the header line,
or given), '.' or a decimal comma (detected on the first data line where the cells are not
','-separated, or given), and a preamble before the header (given as a line count, or found:
the first line followed by a numeric row of as many cells). A row of units under the header
(s, rpm, [mNm]) is read into the names (``t [s]``, as ``header_units`` reads them)."""
from __future__ import annotations

import csv
import itertools
import math
import re
from array import array
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from .._io import plain_float
from ..errors import DataError
from .header_units import named_unit, row_unit



#: What a header with ';' in it is told.
_SEMICOLONS = "looks ';'-separated: say --delimiter ';'"


def header_hint(cells: Sequence[str]) -> str:
    """Why a header may lack fricgen's column names ('' if no idea): it is ';'-separated, or
    its names carry units (read, ``header_units``, where the name is a quantity's or mapped)."""
    if any(";" in c for c in cells):
        return f"; it {_SEMICOLONS}"
    if all(row_unit(c) or not c.strip() for c in cells) and any(c.strip() for c in cells):
        return "; it reads as a row of units: are the names on the line above it (one --skip less)?"
    if any(named_unit(cell) for cell in cells):
        return ("; --columns maps the file's columns to fricgen's quantities, and the units their "
                "names write are read (e.g. --columns 'i=Iq [mA]')")
    return ""


#: What a refusal of a sample that is no number advises (the time column spaces the rest).
DROPPED_SAMPLE = "; a sample dropped? delete its row: the time column spaces the others"
#: Names of the signal a log may hold at a slower rate than its motion (blank cells between,
#: read as gaps and interpolated: ``inverse_dynamics.interpolated``).
SLOW_SIGNALS = ("temperature", "temp")


#: A cell that is the part of a number after a thousands separator: "1,740.65" splits into 1 and 740.65.
_THOUSANDS_TAIL = re.compile(r"\d{3}(\.\d*)?")


#: A number written with ',' between thousands, as one (quoted) cell: "15,998.7".
_GROUPED = re.compile(r"[-+]?\d{1,3}(,\d{3})+(\.\d*)?")
#: A number written with a decimal comma (a tab-separated export of a comma-decimal locale).
_DECIMAL_COMMA = re.compile(r"[-+]?\d*,\d+([eE][-+]?\d+)?")


def _thousands_hint(row: Sequence[str], width: int) -> str:
    """Why a row has more cells than the header, when its numbers look written with ','
    between thousands ('' if not)."""
    if len(row) > width and any(_THOUSANDS_TAIL.fullmatch(c.strip()) for c in row[1:]):
        return ("; are its numbers written with ',' between thousands (1,740.65)? fricgen reads "
                "them without (1740.65)")
    return ""


#: The delimiters by the names ``--delimiter`` takes; None splits on runs of whitespace.
DELIMITERS = {",": ",", ";": ";", "tab": "\t", "space": None}
#: The delimiter argument that asks for the delimiter to be read off the header line.
DETECT = ",?"
#: How many lines a preamble may have for the header to be found without ``skip``.
PREAMBLE_LINES = 100


def _delimiter(header: str, given: Optional[str] = DETECT) -> Optional[str]:
    """The delimiter of a CSV: ``given`` (a value of ``DELIMITERS``), or read off its header
    line: the most frequent of ';', tab and ',' (',' on a tie), else whitespace where the line
    holds several words, else ','."""
    if given != DETECT:
        return given
    counts = {sep: header.count(sep) for sep in (",", ";", "\t")}
    best = max(counts, key=lambda sep: (counts[sep], sep == ","))
    if counts[best]:
        return best
    return None if len(header.split()) > 1 else ","


def _split(line: str, sep: Optional[str]) -> List[str]:
    return line.split() if sep is None else line.split(sep)


def _decimal_comma(cells: Sequence[str], sep: Optional[str]) -> bool:
    """Whether a data row's cells are written with a decimal comma: a cell like 0,25 in a
    file not separated by ','."""
    return sep != "," and any(_DECIMAL_COMMA.fullmatch(c.strip()) for c in cells)


#: A units row's cell: the unit, bracketed or not.
_BRACKETED = re.compile(r"\s*[\[(]\s*(.*?)\s*[\])]\s*")
#: A units row's cell of a column without a unit.
_NO_UNIT = ("", "-", "--", "\u2013", "\u2014", "n/a", "na")


def _unit_text(cell: str) -> str:
    """A units row's cell as its unit: brackets taken off, '' for none (``_NO_UNIT``)."""
    found = _BRACKETED.fullmatch(cell)
    unit = found.group(1) if found else cell.strip()
    return "" if unit.lower() in _NO_UNIT else unit


def _units_row(names: Sequence[str], row: Sequence[str]) -> bool:
    """Whether ``row``, the line under the header ``names``, writes the columns' units: as many
    cells, each a unit fricgen knows (``header_units.row_unit``), a bracketed one or none
    (blank, '-'), under names that are not units themselves."""
    return (len(row) == len(names) > 1 and not all(row_unit(c) for c in names if c.strip())
            and all(not _unit_text(c) or row_unit(c) or _BRACKETED.fullmatch(c) for c in row))


def _status_row(names: Sequence[str], row: Sequence[str]) -> bool:
    """Whether ``row``, a line of text under ``names``, is a row of the data (a status such as
    OK,OK,OK) rather than the header: it repeats a cell where ``names``, as many, repeat none."""
    folded = [c.strip().lower() for c in row]
    return (len(names) == len(row) and len(set(folded)) < len(folded)
            and len({c.strip().lower() for c in names}) == len(names))


def _names_over(names: Sequence[str], under: Optional[Sequence[str]]) -> Tuple[List[str], bool]:
    """The header's names and whether the row ``under`` them is a units row (``_units_row``),
    whose units are then written in: "v" and "rpm" as "v [rpm]" (a name that writes a unit of
    its own keeps it)."""
    if under is None or not _units_row(names, under):
        return list(names), False
    return [f"{name.strip()} [{_unit_text(unit)}]" if _unit_text(unit) and not named_unit(name) else name
            for name, unit in zip(names, under)], True


def header_skip(path: Union[str, Path], delimiter: Optional[str] = DETECT) -> int:
    """The lines before the header of ``path``: 0 where the first line is followed by a row of
    as many cells, else the first line among ``PREAMBLE_LINES`` that is (its next non-blank line
    numeric, with as many cells, blank cells allowed: a signal logged at a slower rate; a
    drive's preamble), else 0 (the reader then says what is wrong). Where that line is a units
    row (``_units_row``), the header is the line above it."""
    try:
        with open(path, encoding="utf-8-sig", newline="") as fh:
            lines = [fh.readline() for _ in range(PREAMBLE_LINES + 1)]
    except (OSError, UnicodeDecodeError):
        return 0
    lines = [line for line in lines if line]
    for k, line in enumerate(lines[:-1]):
        if not line.strip():
            continue
        sep = _delimiter(line, delimiter)
        cells = _split(line.strip("\r\n"), sep)
        following = next((n for n in lines[k + 1:] if n.strip()), "")
        row = _split(following.strip("\r\n"), sep)
        comma = _decimal_comma(row, sep)
        numeric = [_is_number(c, comma) for c in row]
        if len(cells) == len(row) and len(cells) > 1 and any(numeric) \
                and all(n or not c.strip() for n, c in zip(numeric, row)) \
                and not all(_is_number(c, comma) for c in cells):
            above = next((j for j in range(k - 1, -1, -1) if lines[j].strip()), None)
            names = None if above is None else _split(lines[above].strip("\r\n"), sep)
            if names is not None and (_units_row(names, cells) or _status_row(names, cells)):
                return above
            return k
    return 0


def _utf8_error(path, exc: UnicodeDecodeError) -> DataError:
    return DataError(f"{path}: not UTF-8 text (byte 0x{exc.object[exc.start]:02x})")


def read_table_csv(path: Union[str, Path], required: Sequence[str],
                   keep_extra: bool = False, skip: int = 0, drop_text: bool = False,
                   delimiter: Optional[str] = DETECT,
                   decimal_comma: Optional[bool] = None,
                   sparse: Sequence[str] = (), numeric: Sequence[str] = ()) -> Dict[str, np.ndarray]:
    """Read a numeric CSV (the module doc's dialects) whose header names (at least) the
    ``required`` columns.

    Returns the columns by lower-case name: the required ones and, with ``keep_extra``, all
    others. Blank lines are skipped; a missing column, a repeated column name, a row of the
    wrong width or a non-numeric cell raises ``DataError`` naming the file and line. The file
    is streamed: memory holds the numbers, not the text. Finiteness and lengths are for the
    caller to judge. The first ``skip`` lines (an export's preamble) are passed over unread;
    line numbers in messages count them. With ``drop_text``, an extra column holding text is
    left out instead of refused, unless it is one of the ``numeric`` names (a quantity's).
    Without ``skip`` a preamble is found (``header_skip``); ``delimiter`` (a value of
    ``DELIMITERS``) and ``decimal_comma`` force the dialect.
    A blank cell of a ``sparse`` column (a signal logged at a slower rate) reads as NaN.
    """
    try:
        skip = skip or header_skip(path, delimiter)
        if delimiter == DETECT and not decimal_comma:
            fast = _read_plain(path, required, keep_extra, skip)
            if fast is not None:
                return fast
        with open(path, encoding="utf-8-sig", newline="") as fh:
            _skip_lines(path, fh, skip)
            start = fh.tell()
            sep = _delimiter(fh.readline(), delimiter)
            fh.seek(start)
            rows = (csv.reader(fh, delimiter=sep) if sep is not None else
                    (line.split() for line in fh))
            return _read_rows(path, rows, required, keep_extra, first_line=skip + 1,
                              drop_text=drop_text, sep=sep, decimal_comma=decimal_comma,
                              sparse=sparse, numeric=numeric)
    except UnicodeDecodeError as exc:
        raise _utf8_error(path, exc) from None
    except csv.Error as exc:
        raise DataError(f"{path}: not a readable CSV ({exc})") from None
    except OSError as exc:
        raise DataError(f"{path}: cannot read ({exc.strerror or exc})") from None


def header_cells(path: Union[str, Path], skip: int = 0, delimiter: Optional[str] = DETECT) -> List[str]:
    """The header's names as written (for messages; [] if unreadable); without ``skip`` after
    a preamble found by ``header_skip``."""
    try:
        skip = skip or header_skip(path, delimiter)
        with open(path, encoding="utf-8-sig", newline="") as fh:
            for _ in range(skip):
                fh.readline()
            line = fh.readline()
            sep = _delimiter(line, delimiter)
            return _names_over(*(_cells(text, sep) for text in (line, fh.readline())))[0]
    except (OSError, UnicodeDecodeError, csv.Error):
        return []


def _cells(line: str, sep: Optional[str]) -> List[str]:
    """The cells of one line, stripped."""
    if sep is None:
        return line.split()
    return [h.strip() for h in next(csv.reader([line], delimiter=sep), [])]


def _skip_lines(path, fh, skip: int) -> None:
    """Pass over the first ``skip`` lines of the open file ``fh``."""
    for n in range(skip):
        if not fh.readline():
            raise DataError(f"{path}: has {n} lines, fewer than the {skip} to skip before the header")


def _read_plain(path, required, keep_extra, skip=0) -> Optional[Dict[str, np.ndarray]]:
    """The fast path for a plain numeric CSV (numpy's C parser); None when the file needs the
    careful reader, which then names the exact problem (numpy's parser also takes '_'
    separators and digits of other scripts, which fricgen refuses)."""
    with open(path, "rb") as fh:
        raw = fh.read()
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
    if skip:
        lines = raw.split(b"\n", skip)
        if len(lines) <= skip:
            return None
        raw = lines[skip]
    if not raw.isascii() or b"_" in raw:
        return None
    raw = lines = None   # the parser reads the file again: hold the numbers only, not the text
    with open(path, encoding="utf-8-sig", newline="") as fh:
        for _ in range(skip):
            fh.readline()
        line = fh.readline()
        if not line.strip():        # an empty file or a blank header: the careful reader says which
            return None
        sep = _delimiter(line)
        under = fh.tell()
        header, units_row = _names_over([h.strip() for h in line.split(sep)],
                                        [c.strip() for c in fh.readline().split(sep)])
        if not units_row:
            fh.seek(under)
        header = [h.lower() for h in header]
        if len(set(header)) != len(header) or not set(required) <= set(header):
            return None
        try:
            table = np.loadtxt(fh, delimiter=sep, ndmin=2, dtype=float, comments=None)
        except ValueError:
            return None
    if not table.size or table.shape[1] != len(header):
        return None                 # no rows, or ragged: the careful reader says which
    table = table.reshape(-1, len(header))
    return {h: table[:, k].copy() for k, h in enumerate(header) if keep_extra or h in required}


def _is_number(cell: str, decimal_comma: bool = False) -> bool:
    try:
        plain_float(cell.replace(",", ".") if decimal_comma else cell)
    except ValueError:
        return False
    return True


def _read_rows(path, rows, required, keep_extra, first_line=1, drop_text=False, sep=",",
               decimal_comma=None, sparse=(), numeric=()) -> Dict[str, np.ndarray]:
    header = next(rows, None)
    if header is None:
        raise DataError(f"{path}: empty file")
    if not any(h.strip() for h in header):
        raise DataError(f"{path}: the header line is blank; the first line must name the columns")
    under = next(rows, None)
    written, units_row = _names_over([h.strip() for h in header], under)
    if units_row:
        first_line += 1
    elif under is not None:
        rows = itertools.chain([under], rows)
    header = [h.lower() for h in written]
    named = {",": "','", ";": "';'", "\t": "tab", None: "whitespace"}[sep]
    if len(header) == 1 and any(c in header[0] for c in ",;\t"):
        raise DataError(f"{path}: the header {written[0][:40]!r} does not split at {named}; "
                        f"say which delimiter it uses (--delimiter)")
    repeated = sorted({h for h in header if h and header.count(h) > 1})
    if repeated:
        raise DataError(f"{path}: column {repeated[0]!r} appears more than once in the header")
    missing = [c for c in required if c not in header]
    if missing:
        raise DataError(f"{path}: missing column {', '.join(repr(c) for c in missing)} "
                        f"(header is {','.join(written)[:80]}){header_hint(written)}")
    wanted = [k for k, h in enumerate(header) if keep_extra or h in required]
    values = array("d")
    text = set()            # extra columns with a cell that is not a number: left out
    comma = decimal_comma
    for n, row in enumerate(rows, start=first_line + 1):
        if not any(c.strip() for c in row):
            continue
        if comma is None:
            comma = _decimal_comma(row, sep)
        if comma:
            row = [c.replace(",", ".") for c in row]
        if len(row) != len(header):
            raise DataError(f"{path}: line {n}: {len(row)} cells, the header names {len(header)}"
                            f"{_thousands_hint(row, len(header))}")
        try:
            values.extend([plain_float(row[k]) for k in wanted])
        except ValueError:
            bad = [k for k in wanted if not _is_number(row[k])]
            if all(header[k] in sparse and not row[k].strip() for k in bad):
                values.extend([math.nan if k in bad else plain_float(row[k]) for k in wanted])
                continue
            if not drop_text or any(header[k] in required or header[k] in numeric for k in bad):
                grouped = any(_GROUPED.fullmatch(row[k].strip()) for k in bad)
                decimal_comma = any(_DECIMAL_COMMA.fullmatch(row[k].strip()) for k in bad)
                hint = (_thousands_hint(['', '000'], 1) if grouped else
                        "; decimal commas? fricgen reads '.' decimals" if decimal_comma else "")
                if not hint and not row[bad[0]].strip() and header[bad[0]] not in required:
                    slow = header[bad[0]] in SLOW_SIGNALS or header[bad[0]] not in numeric
                    hint = ("; a signal logged at a slower rate? --columns temperature=NAME reads its "
                            "blank cells as gaps" if slow else DROPPED_SAMPLE)
                raise DataError(f"{path}: line {n}: non-numeric or missing cell {row[bad[0]][:40]!r} "
                                f"in column {written[bad[0]][:40]!r}{hint}") from None
            text.update(bad)
            values.extend([math.nan if k in bad else plain_float(row[k]) for k in wanted])
    table = np.frombuffer(values, dtype=float).reshape(-1, len(wanted))
    if not table.shape[0]:
        raise DataError(f"{path}: a header and no data rows")
    return {header[k]: table[:, j].copy() for j, k in enumerate(wanted) if k not in text}


def table_csv_text(columns: Dict[str, np.ndarray]) -> str:
    """CSV text of named columns (in the given order), floats written to round-trip (-0.0 as 0.0)."""
    names = list(columns)
    lines = [",".join(names)]
    lines += [",".join(repr(float(c) + 0.0) for c in row)
              for row in zip(*(np.asarray(columns[k]).tolist() for k in names))]
    return "\n".join(lines) + "\n"
