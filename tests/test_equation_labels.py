"""The paper's equations are cited by label ([F1]-[F17], [C1]-[C16]), never by bare number.

Section 6 of the paper prints its equations numbered again from (2), so "eq. (3)" would be both
the friction model [F3] and the virtual control [C3]; docs/reference/equations.md defines each
label once."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LABEL_PAGE = ROOT / "docs" / "reference" / "equations.md"
SCANNED = ("fricgen", "c_runtime", "templates", "docs", "benchmarks", "examples", "README.md")
SUFFIXES = {".py", ".c", ".h", ".j2", ".md"}
#: "eq. (3)", "Eqs. 16-17", "equation (18)", "equations 4": a citation by number.
OLD_FORM = re.compile(r"\b(?:eqs?\.|equations?)\s*\(?\d", re.IGNORECASE)
LABEL = re.compile(r"\[([FC])(\d+)[a-c]?\]")
DEFINITION = re.compile(r"^\| \[([FC]\d+)\] \|", re.MULTILINE)


def _files():
    for name in SCANNED:
        path = ROOT / name
        for f in [path] if path.is_file() else sorted(path.rglob("*")):
            if f.is_file() and f.suffix in SUFFIXES:
                yield f


def _defined():
    return set(DEFINITION.findall(LABEL_PAGE.read_text(encoding="utf-8")))


def _old_citations(text):
    return [m.group(0) for m in OLD_FORM.finditer(text)]


def _undefined_labels(text, defined):
    return sorted({f"{kind}{n}" for kind, n in LABEL.findall(text)} - defined)


def test_the_label_page_defines_both_sections_once_each_and_is_in_the_nav():
    names = DEFINITION.findall(LABEL_PAGE.read_text(encoding="utf-8"))
    assert len(names) == len(set(names))
    assert set(names) == {f"F{n}" for n in range(1, 18)} | {f"C{n}" for n in range(1, 17)}
    assert "reference/equations.md" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")


def test_no_equation_is_cited_by_its_bare_number():
    found = [f"{f.relative_to(ROOT)}: {cite}" for f in _files()
             for cite in _old_citations(f.read_text(encoding="utf-8"))]
    assert not found, "cite by label (docs/reference/equations.md): " + "; ".join(found[:20])


def test_every_cited_label_is_defined():
    defined = _defined()
    found = [f"{f.relative_to(ROOT)}: {label}" for f in _files()
             for label in _undefined_labels(f.read_text(encoding="utf-8"), defined)]
    assert not found, "labels missing from docs/reference/equations.md: " + "; ".join(found)


@pytest.mark.parametrize("text", ["F(v) of eq. (3)", "eqs. 16-17", "Eq. (18)", "equation (9)",
                                  "equations 4-6", "(eq. 12a)"])
def test_the_scan_sees_an_old_citation(text):
    assert _old_citations(text)


def test_the_scan_sees_an_undefined_label_and_passes_a_defined_one():
    defined = _defined()
    assert _undefined_labels("the virtual control [C17], law [C14c]", defined) == ["C17"]
    assert _undefined_labels("[F3] and [C3], [F16]-[F17]", defined) == []
    assert not _old_citations("the equation is linear; see [F3] (sec. 2)")
