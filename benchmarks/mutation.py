"""Mutation score of the core: apply one small change at a time, run the module's tests, count.

Each mutant changes one token of a module's code: an arithmetic operator (+ -, * /, ** *), a
comparison (< <=, > >=, == !=), or a number (0 -> 1, n -> n + 1, x.y -> 2 x.y). Python modules
are tokenized (docstrings and comments are never mutated) and limited to the functions listed;
the C templates are scanned line by line (comments and Jinja tags skipped). A mutant is killed
when ``pytest -x -q`` on the module's tests (slow ones too) fails (or runs past --timeout), and
survives when they pass. The file is restored after every mutant, also on Ctrl-C.

    python benchmarks/mutation.py                       # every module, 8 sampled mutants each
    python benchmarks/mutation.py --modules decision outliers --per-module 0   # all of them
    python benchmarks/mutation.py --list                # the mutants, without running tests
    python benchmarks/mutation.py --modules controller adaptation runtime_ctrl runtime_adapt --default-run

Run it from the repository root on a clean tree: it edits the files in place.
"""
from __future__ import annotations

import argparse
import ast
import io
import random
import re
import subprocess
import sys
import time
import tokenize
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

ROOT = Path(__file__).resolve().parents[1]

#: name -> (file, functions mutated (None: the whole file), tests run on each mutant).
MODULES: Dict[str, Tuple[str, Optional[Sequence[str]], Sequence[str]]] = {
    "friction": ("fricgen/friction.py", None,
                 ["tests/test_references.py", "tests/test_friction.py", "tests/test_properties.py"]),
    "model": ("fricgen/model.py",
              ["Direction.network_input", "Direction.stribeck", "Direction.magnitude",
               "FrictionModel.network_input", "FrictionModel.stribeck", "FrictionModel.force"],
              ["tests/test_references.py", "tests/test_properties.py", "tests/test_asymmetric.py::"
               "test_each_direction_saturates_at_its_own_v_sat_in_c_and_the_twin"]),
    "twin": ("fricgen/codegen/twin.py", None,
             ["tests/test_references.py", "tests/test_effects.py", "tests/test_asymmetric.py::"
              "test_each_direction_saturates_at_its_own_v_sat_in_c_and_the_twin"]),
    "fixedpoint": ("fricgen/codegen/fixedpoint.py",
                   ["_frac_for", "_quantize", "ConstMul.of", "ConstMul.apply", "input_range",
                    "FixedSpec.of", "sigmoid_table", "_rshift", "sigmoid_q", "force_q", "error_bound"],
                   ["tests/test_references.py::test_every_c_implementation_of_the_hand_elm_gives_the_hand_values",
                    "tests/test_references.py::test_fixed_point_c_equals_its_twin_with_a_constant_at_the_end_of_its_range",
                    "tests/test_fixedpoint.py"]),
    "outliers": ("fricgen/data/outliers.py", None, ["tests/test_outliers.py"]),
    "decision": ("fricgen/diagnose/decision.py", ["autocorrelation_time", "held_out_p_value"],
                 ["tests/test_decision.py"]),
    "template_float": ("templates/model.c.j2", None,
                       ["tests/test_references.py", "tests/test_asymmetric.py::"
                        "test_each_direction_saturates_at_its_own_v_sat_in_c_and_the_twin"]),
    "controller": ("fricgen/control/backstepping.py",
                   ["_project", "AdaptiveBackstepping.friction_force", "AdaptiveBackstepping.friction_velocity",
                    "AdaptiveBackstepping.compensation_force", "AdaptiveBackstepping.step_with_force"],
                   ["tests/test_control.py", "tests/test_control_faults.py", "tests/test_control_c.py"]),
    "adaptation": ("fricgen/control/adaptation.py",
                   ["FrictionAdapter.force", "FrictionAdapter._gate", "FrictionAdapter.rls",
                    "FrictionAdapter.lyapunov", "FrictionAdapter._clamp", "FrictionAdapter._finish",
                    "FrictionAdapter.gain", "FrictionAdapter.input_limit", "AdaptedController.step"],
                   ["tests/test_adaptation.py", "tests/test_adaptation_c.py"]),
    "runtime_adapt": ("c_runtime/fric_adapt.c", None,
                      ["tests/test_adaptation_c.py", "tests/test_adaptation.py", "tests/test_readback.py"]),
    "runtime_ctrl": ("c_runtime/fric_ctrl.c", None,
                     ["tests/test_control_c.py", "tests/test_control_faults.py"]),
    "template_curve": ("templates/curve.c.j2", None, [
        "tests/test_references.py", "tests/test_hardening.py::"
        "test_grey_box_force_has_defined_behaviour_for_every_input_under_sanitizers"]),
    "template_fixed": ("templates/model_fixed.c.j2", None,
                       ["tests/test_references.py::test_every_c_implementation_of_the_hand_elm_gives_the_hand_values",
                        "tests/test_fixedpoint.py", "tests/test_fixed_table.py", "tests/test_hardening.py::"
                        "test_fixed_point_grey_box_table_is_read_in_bounds_for_every_input_under_sanitizers"]),
    "fixed_table": ("fricgen/codegen/fixed_table.py",
                    ["TableSpec.base_shift", "TableSpec.of", "knots", "_layout", "interpolation_error",
                     "force_table_q", "table_error_bound"],
                    ["tests/test_fixed_table.py"]),
}

PY_OPS = {"+": "-", "-": "+", "*": "/", "/": "*", "**": "*", "<": "<=", "<=": "<", ">": ">=",
          ">=": ">", "==": "!=", "!=": "==", "//": "/"}
C_OPS = {"+": "-", "-": "+", "*": "/", "/": "*", "<": "<=", "<=": "<", ">": ">=", ">=": ">"}


@dataclass(frozen=True)
class Mutant:
    module: str
    path: str
    line: int            # 1-based
    col: int             # 0-based start within the line
    old: str
    new: str

    def describe(self, text: str) -> str:
        src = text.splitlines()[self.line - 1].strip()
        return f"{self.path}:{self.line}: {self.old!r} -> {self.new!r} in `{src[:90]}`"


def _number_mutation(tok: str) -> Optional[str]:
    body = tok.rstrip("fFjJ")
    suffix = tok[len(body):]
    try:
        value = int(body, 0)
        return f"{value + 1}{suffix}" if value else f"1{suffix}"
    except ValueError:
        pass
    try:
        value = float(body)
    except ValueError:
        return None
    new = repr(2 * value) if value else "1.0"
    return new + suffix


def _function_lines(text: str, names: Sequence[str]) -> List[Tuple[int, int]]:
    """The (first, last) line of each function named (Class.method or function)."""
    tree = ast.parse(text)
    spans = []

    def visit(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.ClassDef)):
                qual = f"{prefix}{child.name}"
                if isinstance(child, ast.FunctionDef) and qual in names:
                    spans.append((child.lineno, child.end_lineno))
                visit(child, qual + ".")
    visit(tree, "")
    if len(spans) < len(names):
        raise SystemExit(f"not every function of {names} is in the module")
    return spans


def python_mutants(module: str, path: str, functions) -> List[Mutant]:
    text = (ROOT / path).read_text()
    spans = _function_lines(text, functions) if functions else None
    out = []
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        (line, col) = tok.start
        if spans is not None and not any(a <= line <= b for a, b in spans):
            continue
        if tok.type == tokenize.OP and tok.string in PY_OPS:
            out.append(Mutant(module, path, line, col, tok.string, PY_OPS[tok.string]))
        elif tok.type == tokenize.NUMBER:
            new = _number_mutation(tok.string)
            if new is not None:
                out.append(Mutant(module, path, line, col, tok.string, new))
    return out


_C_TOKEN = re.compile(r"(?<![\w.])(\d+\.\d*f?|\d+)(?![\w.])|(<=|>=|(?<![<>=!-])[<>](?![<>=])|(?<=\s)[-+*/](?=\s))")


def template_mutants(module: str, path: str) -> List[Mutant]:
    """Operators and numbers of the C code in a template (not in comments, Jinja tags or
    preprocessor lines)."""
    text = (ROOT / path).read_text()
    out, in_comment = [], False
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw
        stripped = line.strip()
        if in_comment or stripped.startswith(("/*", "*", "#", "{%", "{#", "//")):
            opened = in_comment or stripped.startswith(("/*", "{#"))
            in_comment = opened and "*/" not in stripped and "#}" not in stripped
            continue
        code = re.sub(r"{{.*?}}|{%.*?%}|/\*.*?\*/", lambda m: " " * len(m.group(0)), line)
        for m in _C_TOKEN.finditer(code):
            tok = m.group(0)
            new = C_OPS.get(tok) if m.group(2) else _number_mutation(tok)
            if new is not None and new != tok:
                out.append(Mutant(module, path, number, m.start(), tok, new))
    return out


def mutants_of(module: str) -> List[Mutant]:
    path, functions, _ = MODULES[module]
    if path.endswith(".py"):
        return python_mutants(module, path, functions)
    return template_mutants(module, path)


def apply(m: Mutant, text: str) -> str:
    lines = text.splitlines(keepends=True)
    line = lines[m.line - 1]
    assert line[m.col:m.col + len(m.old)] == m.old, (m, line)
    lines[m.line - 1] = line[:m.col] + m.new + line[m.col + len(m.old):]
    return "".join(lines)


def run_tests(tests: Sequence[str], timeout: float, default_run: bool = False) -> str:
    marks = "not slow" if default_run else "slow or not slow"
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "-m", marks, *tests]
    try:
        proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout"
    if proc.returncode == 5:
        raise SystemExit(f"no test collected by {' '.join(cmd)}")
    return "survived" if proc.returncode == 0 else "killed"   # a failure, or a mutant that breaks import


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modules", nargs="+", choices=sorted(MODULES), default=list(MODULES))
    ap.add_argument("--per-module", type=int, default=8,
                    help="mutants sampled per module (seeded); 0 runs all of them")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per test run")
    ap.add_argument("--list", action="store_true", help="list the mutants and stop")
    ap.add_argument("--default-run", action="store_true",
                    help="run the tests of the default run only (no slow ones): what CI's first "
                    "run catches")
    args = ap.parse_args(argv)
    status = subprocess.run(["git", "status", "--porcelain", "--", *(MODULES[m][0] for m in args.modules)],
                            cwd=ROOT, capture_output=True, text=True).stdout
    if status.strip() and not args.list:
        print(f"the files to mutate have uncommitted changes:\n{status}", file=sys.stderr)
        return 2
    rows, survivors = [], []
    for module in args.modules:
        path, _, tests = MODULES[module]
        every = mutants_of(module)
        chosen = every if args.per_module <= 0 or args.per_module >= len(every) else \
            sorted(random.Random(f"{args.seed}:{module}").sample(every, args.per_module),
                   key=lambda m: (m.line, m.col))
        original = (ROOT / path).read_text()
        if args.list:
            for m in chosen:
                print(m.describe(original))
            continue
        counts = {"killed": 0, "survived": 0, "timeout": 0}
        start = time.perf_counter()
        for m in chosen:
            try:
                (ROOT / path).write_text(apply(m, original))
                outcome = run_tests(tests, args.timeout, args.default_run)
            finally:
                (ROOT / path).write_text(original)
            counts[outcome] += 1
            print(f"  {outcome:8s} {m.describe(original)}", flush=True)
            if outcome == "survived":
                survivors.append(m.describe(original))
        n = len(chosen)
        score = (counts["killed"] + counts["timeout"]) / n if n else float("nan")
        rows.append((module, len(every), n, counts["killed"], counts["timeout"], counts["survived"],
                     score, time.perf_counter() - start))
    if args.list:
        return 0
    print(f"\n{'module':16s} {'mutants':>7s} {'run':>4s} {'killed':>6s} {'timeout':>7s} "
          f"{'survived':>8s} {'score':>6s} {'seconds':>7s}")
    for module, total, n, k, t, s, score, secs in rows:
        print(f"{module:16s} {total:7d} {n:4d} {k:6d} {t:7d} {s:8d} {score:6.0%} {secs:7.0f}")
    if survivors:
        print("\nsurviving mutants:")
        for line in survivors:
            print(f"  {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
