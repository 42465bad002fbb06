"""Every public C function of the headers `fricgen emit` writes (the generated NAME.h,
NAME_adapt.h and the runtime's fric_*.h) carries a Doxygen block in the house style of
c_runtime/fric_ctrl.h: `/** ... */` right above the prototype, with `@brief`, an `@param` naming
each parameter (one line may name several: `@param[in] xd, xd_dot, xd_ddot ...`) and `@return`
unless the function returns void."""
import re
from dataclasses import dataclass, replace
from typing import List, Optional, Tuple

import numpy as np
import pytest

from emit_variants import emit_every_variant
from fricgen import codegen
from fricgen.effects import CoggingMap
from fricgen.effects.load_temperature import LoadDependence, LoadTemperature, TemperatureDependence
from fricgen.fit.textbook import fit_law
from fricgen.model import FrictionModel

COMMENT = re.compile(r"/\*.*?\*/", re.S)
FUNCTION = re.compile(r"^(?P<ret>(?:[A-Za-z_]\w*[\s*]+)+?)(?P<name>[A-Za-z_]\w*)\s*\((?P<params>[^()]*)\)$")
PARAM = re.compile(r"@param\s*(?:\[\s*(?:in|out|in\s*,\s*out)\s*\])?\s+([A-Za-z_]\w*(?:\s*,\s*[A-Za-z_]\w*)*)")


@dataclass(frozen=True)
class Declaration:
    name: str
    returns: str
    params: Tuple[str, ...]
    comment: Optional[str]          # the comment right above it (only whitespace between), if any


def _blank(text: str, start: int, end: int) -> str:
    return text[:start] + re.sub(r"[^\n]", " ", text[start:end]) + text[end:]


def _param_names(params: str) -> Tuple[str, ...]:
    names = []
    for p in params.split(","):
        p = re.sub(r"\[[^\]]*\]", "", p).strip()
        if p in ("", "void"):
            continue
        names.append(re.findall(r"[A-Za-z_]\w*", p)[-1])
    return tuple(names)


def declarations(text: str) -> Tuple[List[Declaration], List[str]]:
    """The functions declared or defined at file scope in the C header ``text``, each with the
    comment right above it; and the file-scope statements with parentheses that are neither a
    function, a typedef nor an initializer (the parser's blind spots, which fail the test)."""
    comments = [(m.start(), m.end(), m.group()) for m in COMMENT.finditer(text)]
    code = text
    for start, end, _ in comments:
        code = _blank(code, start, end)
    lines, offset, continued = code.splitlines(keepends=True), 0, False
    for line in lines:                            # preprocessor lines and their continuations
        if continued or line.lstrip().startswith("#"):
            continued = line.rstrip("\n").endswith("\\")
            code = _blank(code, offset, offset + len(line.rstrip("\n")))
        offset += len(line)
    for m in re.finditer(r'extern\s*"C"\s*\{', code):
        code = _blank(code, m.start(), m.end())
    statements = []                               # (start offset, text at depth 0, is a definition)
    depth, start, buf, body_is_function = 0, None, [], False
    for k, ch in enumerate(code):
        if depth == 0:
            if ch == "{":
                head = " ".join("".join(buf).split())
                body_is_function = bool(FUNCTION.match(head)) and not head.startswith("typedef")
                if body_is_function:
                    statements.append((start, head, True))
                depth = 1
            elif ch == "}":                       # the `}` closing extern "C"
                start, buf = None, []
            elif ch == ";":
                if start is not None:
                    statements.append((start, " ".join("".join(buf).split()), False))
                start, buf = None, []
            else:
                if start is None and not ch.isspace():
                    start = k
                buf.append(ch)
        elif ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0 and body_is_function:
                start, buf, body_is_function = None, [], False
    found, unparsed = [], []
    for start, stmt, _ in statements:
        if "(" not in stmt or stmt.startswith("typedef") or "=" in stmt:
            continue
        m = FUNCTION.match(stmt)
        if m is None:
            unparsed.append(stmt)
            continue
        above = [c for s, e, c in comments if e <= start and not text[e:start].strip()]
        found.append(Declaration(m.group("name"), " ".join(m.group("ret").split()),
                                 _param_names(m.group("params")), above[-1] if above else None))
    return found, unparsed


def named_params(comment: str) -> set:
    return {n.strip() for group in PARAM.findall(comment) for n in group.split(",")}


def problems_of(decl: Declaration) -> List[str]:
    """What the block above ``decl`` lacks (empty: a complete Doxygen block)."""
    c = decl.comment
    if c is None:
        return ["no comment right above the prototype"]
    if not c.startswith("/**") or c.startswith("/***"):
        return ["a plain /* ... */ comment, not a Doxygen /** ... */ block"]
    out = [] if "@brief" in c else ["no @brief"]
    out += [f"no @param naming {p}" for p in decl.params if p not in named_params(c)]
    if not (decl.returns.split()[-1] == "void" and "*" not in decl.returns) and "@return" not in c:
        out.append("no @return for a non-void function")
    return out


# ----------------------------------------------------------------------------- the parser itself

SAMPLE = """/* file comment */
#ifndef X_H
#define X_H
#define X_KERNEL(NAME) \\
    float NAME(float x) \\
    { return x; }
#ifdef __cplusplus
extern "C" {
#endif
typedef float (*x_fn)(float v);
typedef struct { float z; } x_state_t;
/* plain */
float x_plain(float v);
/**
 * @brief Good.
 * @param[in] a, b two; @param[out] out written.
 * @return a float.
 */
float x_good(float a, float b,
             float *out);
/** @brief Void, nothing else. @param[in,out] s the state. */
void x_void(x_state_t *s);
/** @brief Forgets the return. @param[in] a it. */
int x_no_return(int a);
/** @brief No parameters. @return 1. */
int x_none(void);
/** @brief Names one of two. @param[in] s one. @return 0. */
float x_half(const x_state_t *s, float *out);
/** @brief Inline. @param[in] a it. @return a. */
static inline float x_inline(float a)
{
    if (a > 0.0f) { return a; }
    return -a;
}

/** @brief Separated by a macro. @return 0. */
#define X_Y 1
int x_separated(void);
#ifdef __cplusplus
}
#endif
#endif
"""


def test_the_parser_finds_each_function_and_the_comment_above_it():
    found, unparsed = declarations(SAMPLE)
    assert unparsed == []
    by_name = {d.name: d for d in found}
    assert list(by_name) == ["x_plain", "x_good", "x_void", "x_no_return", "x_none", "x_half",
                             "x_inline", "x_separated"]
    assert by_name["x_good"].params == ("a", "b", "out") and by_name["x_none"].params == ()
    assert by_name["x_inline"].returns == "static inline float"
    verdicts = {d.name: problems_of(d) for d in found}
    assert verdicts == {
        "x_plain": ["a plain /* ... */ comment, not a Doxygen /** ... */ block"],
        "x_good": [], "x_void": [], "x_none": [], "x_inline": [], "x_half": ["no @param naming out"],
        "x_no_return": ["no @return for a non-void function"],
        "x_separated": ["no comment right above the prototype"]}


# ----------------------------------------------------------------------------- the emitted headers

def cogging_model():
    """A rotary grey-box axis with a cogging map (tests/test_anticogging.py's model, its map
    written down instead of identified from a simulated calibration)."""
    law = fit_law(np.array([0.5, 1.0, 2.0]), np.array([0.02, 0.021, 0.022]))
    base = FrictionModel.from_directions(law.direction(), name="axis_c", training={"units": "rotary"})
    cogging = CoggingMap(period=2 * np.pi, harmonics=(1, 24), sine=(0.5, 0.1), cosine=(0.0, 0.02),
                         sine_se=(0.01, 0.01), cosine_se=(0.01, 0.01))
    return replace(base, cogging_map=cogging)


def load_temperature_model():
    """The same axis with friction that depends on the load and the temperature (written down
    instead of trained as in tests/test_load_temperature.py)."""
    inputs = LoadTemperature(LoadDependence(driving=0.01, back_driving=0.005, largest=50.0),
                             TemperatureDependence(reference=30.0, levels=0.005, viscous=0.03,
                                                   span=(20.0, 60.0)))
    return replace(cogging_model(), name="lt", cogging_map=None, inputs=inputs)


@pytest.fixture(scope="module")
def variants(tmp_path_factory, bench, model10, axis2_model):
    root = tmp_path_factory.mktemp("doxygen")
    folders = emit_every_variant(root, bench, model10, axis2_model)
    for variant, model, name in (("cogging", cogging_model(), "axis_c"),
                                 ("load_temperature", load_temperature_model(), "lt")):
        folders[variant] = root / variant
        codegen.emit(model, folders[variant], name)
    return folders


@pytest.fixture(scope="module")
def headers(variants):
    """{"variant/file.h": [Declaration]} of every header of every variant."""
    out, unparsed = {}, {}
    for variant, folder in sorted(variants.items()):
        for path in sorted(folder.glob("*.h")):
            found, blind = declarations(path.read_text())
            out[f"{variant}/{path.name}"] = found
            if blind:
                unparsed[f"{variant}/{path.name}"] = blind
    assert not unparsed, f"file-scope statements the test cannot read as a function: {unparsed}"
    return out


def test_the_headers_of_every_variant_declare_the_functions_looked_for(headers):
    names = {d.name for found in headers.values() for d in found}
    assert {"fm_force", "fm_aim", "fm_force_q15", "fm_force_q31", "fa_aim_negative", "fx_force_xv",
            "sl_compensation", "sl_reset", "sl_step", "axis_c_cogging", "axis_c_cogging_q15",
            "axis_c_cogging_q31", "lt_force_lt", "fm_regressor", "fm_adapt_default_params",
            "fric_sigmoid_fast_f32", "fric_elm_sigmoid_fast_f32", "fric_exp_neg_fast_f32",
            "fric_exp_neg_inline_f32", "fric_exp_neg_f32", "fric_elm_sigmoid_f32", "fric_elm_sine_f32",
            "fric_elm_rbf_f32", "fric_elm_multiquadric_f32", "fric_sqrt_f32", "fric_ctrl_step",
            "fric_adapt_export"} <= names


def test_every_public_function_has_a_doxygen_block(headers):
    failures = []
    for header, found in headers.items():
        for decl in found:
            failures += [f"{header}: {decl.name}: {p}" for p in problems_of(decl)]
    assert not failures, "\n".join(["functions without a complete Doxygen block:", *failures])
