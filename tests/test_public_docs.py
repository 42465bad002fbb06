"""Every public class and function of the documented packages carries a numpydoc docstring:
Parameters naming every argument of its signature, Attributes for the estimators, and Examples
(which run as doctests in tests/test_api.py)."""
import importlib
import inspect
import re

import pytest

import fricgen

#: The packages and modules held to numpydoc here: their ``__all__``, or for a module without
#: one its own public classes and functions. ``fricgen`` means the top-level names defined in one
#: of the others.
DOCUMENTED = ("fricgen", "fricgen.data", "fricgen.fit", "fricgen.networks", "fricgen.effects",
              "fricgen.codegen", "fricgen.control", "fricgen.training", "fricgen.model", "fricgen.direction",
              "fricgen.c_names", "fricgen.friction", "fricgen.errors", "fricgen.diagnose",
              "fricgen.sim", "fricgen.firmware", "fricgen.paper", "fricgen.fleet")

SECTION_LINE = re.compile(r"^(\w[\w ]*)\n-{3,}$", flags=re.M)


def sections(doc: str) -> dict:
    """A numpydoc docstring's sections: title -> body (the text up to the next title)."""
    heads = list(SECTION_LINE.finditer(doc))
    return {m.group(1): doc[m.end():heads[i + 1].start() if i + 1 < len(heads) else len(doc)]
            for i, m in enumerate(heads)}


def entries(body: str) -> list:
    """The names a Parameters or Attributes section documents (``name : type``, ``a, b : type``,
    ``*args``), in order."""
    names = []
    for line in body.splitlines():
        match = re.match(r"^(\*{0,2}\w+(?:, \*{0,2}\w+)*)\s*(?::|$)", line)
        if match and not line.startswith(" "):
            names += [n.lstrip("*") for n in match.group(1).split(", ")]
    return names


def _defined_in_documented(value) -> bool:
    module = getattr(value, "__module__", "") or ""
    return any(module == m or module.startswith(m + ".") for m in DOCUMENTED[1:])


def public_objects() -> dict:
    """``module.name`` -> object, for every public class and function of ``DOCUMENTED``, each
    once (under the first name that exports it)."""
    found, seen = {}, set()
    for name in DOCUMENTED:
        module = importlib.import_module(name)
        names = getattr(module, "__all__", None)
        if names is None:
            names = [n for n, v in vars(module).items()
                     if not n.startswith("_") and getattr(v, "__module__", None) == name]
        for n in names:
            value = getattr(module, n)
            if ((inspect.isclass(value) or inspect.isfunction(value)) and id(value) not in seen
                    and _defined_in_documented(value)):
                found[f"{name}.{n}"] = value
                seen.add(id(value))
    return found


PUBLIC = public_objects()


def arguments(value) -> list:
    """The arguments a docstring must document: the signature's (a class: its ``__init__``'s),
    without self/cls; none for a typing protocol (never instantiated), and not the *args of an
    exception (they are its message)."""
    if getattr(value, "_is_protocol", False):
        return []
    try:
        signature = inspect.signature(value)
    except (TypeError, ValueError):
        return []
    params = signature.parameters.values()
    if inspect.isclass(value) and issubclass(value, BaseException):
        params = [p for p in params if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    return [p.name for p in params if p.name not in ("self", "cls")]


def test_the_documented_packages_hold_the_headline_names():
    assert {"fricgen.ELMRegressor", "fricgen.data.prepare", "fricgen.effects.PositionRipple",
            "fricgen.control.simulate", "fricgen.errors.BuildError"} <= set(PUBLIC)
    assert {"fricgen.diagnose.diagnose", "fricgen.diagnose.render_files", "fricgen.sim.MotorAxis",
            "fricgen.sim.make_scenario", "fricgen.sim.Scenario", "fricgen.firmware.build_firmware",
            "fricgen.paper.reproduce"} <= set(PUBLIC)


@pytest.mark.parametrize("path", sorted(PUBLIC))
def test_public_object_has_numpydoc_sections(path):
    value = PUBLIC[path]
    doc = inspect.getdoc(value) or ""
    found = sections(doc)
    args = arguments(value)
    if args:
        assert "Parameters" in found, f"{path}: no Parameters section"
    undocumented = [a for a in args if a not in entries(found.get("Parameters", ""))]
    assert undocumented == [], f"{path}: Parameters misses {undocumented}"
    if path.endswith("Regressor"):
        attributes = entries(found.get("Attributes", ""))
        assert attributes and all(a.endswith("_") for a in attributes), \
            f"{path}: no fitted attributes (ending in _) in Attributes"
    assert ">>>" in found.get("Examples", ""), f"{path}: no Examples"


def test_the_parser_sees_an_undocumented_argument_and_a_missing_section():
    def f(a, b, *rest):
        """Do.

        Parameters
        ----------
        a, *rest : int
            Something.

        Returns
        -------
        int
        """
    found = sections(inspect.getdoc(f))
    assert sorted(found) == ["Parameters", "Returns"]
    assert entries(found["Parameters"]) == ["a", "rest"]
    assert [a for a in arguments(f) if a not in entries(found["Parameters"])] == ["b"]
    assert entries(found["Returns"]) == ["int"]   # a type line reads as a name; Returns is not checked


def test_the_examples_of_every_documented_object_run_as_doctests():
    from test_api import DOCTESTED     # the modules whose examples tests/test_api.py runs

    assert sorted({v.__module__ for v in PUBLIC.values()} - set(DOCTESTED)) == []
