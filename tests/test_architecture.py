"""The architecture the README draws: imports point one way, none hides inside a function."""
import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "fricgen"
#: Dependencies imported only where they are used, because a user may not have them.
OPTIONAL = {"matplotlib", "cffi", "emlearn", "sklearn"}
#: The layers, bottom first: a module may import only from its own layer or those before it.
LAYERS = ["errors", "unit_sizes", "_lazy", "_validate", "_io", "_json", "_progress", "_plot", "_blas", "metrics", "units", "friction", "c_literal",
          "c_names", "networks", "effects", "axis", "direction", "model", "data", "fit", "codegen", "training", "sim",
          "control", "diagnose", "paper", "firmware", "fleet", "cli"]


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        yield name, path, ast.parse(path.read_text())


def _imported(name, path, node):
    """The fricgen modules (dotted names) and other top-level packages an import names."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if node.level == 0:
        return [node.module]
    base = name.split(".")
    if path.name != "__init__.py":
        base = base[:-1]
    base = base[:len(base) - node.level + 1]
    stem = ".".join(base + ([node.module] if node.module else []))
    return [f"{stem}.{a.name}" for a in node.names] if not node.module else [stem]


def _edges():
    modules = {name for name, _, _ in _modules()}
    edges = {}
    for name, path, tree in _modules():
        targets = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for target in _imported(name, path, node):
                    while target not in modules and "." in target:
                        target = target.rpartition(".")[0]
                    if target in modules and target != name:
                        targets.add(target)
        edges[name] = targets
    return edges


def _layer(module):
    """The layer's index; the package itself sits below everything, ``__main__`` above."""
    parts = module.split(".")
    if len(parts) == 1:
        return -1
    return len(LAYERS) if parts[1] == "__main__" else LAYERS.index(parts[1])


def test_no_import_cycles_among_fricgen_modules():
    edges = _edges()
    state = {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in edges[node]:
            if nxt.startswith(node + ".") or node.startswith(nxt + "."):
                continue      # a package re-exporting its own submodules
            if state.get(nxt) == "open":
                raise AssertionError("import cycle: " + " -> ".join(stack + [node, nxt]))
            if nxt not in state:
                visit(nxt, stack + [node])
        state[node] = "done"

    for node in edges:
        if node not in state:
            visit(node, [])


def test_imports_point_down_the_layers():
    wrong = [f"{a} imports {b}" for a, targets in _edges().items() for b in targets
             if a != "fricgen" and b != "fricgen" and _layer(b) > _layer(a)]
    assert not wrong, wrong


def test_no_import_inside_a_function_except_optional_dependencies():
    found = []
    for name, _, tree in _modules():
        for fn in ast.walk(tree):
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for node in ast.walk(fn):
                    if isinstance(node, ast.Import):
                        roots = {a.name.split(".")[0] for a in node.names}
                    elif isinstance(node, ast.ImportFrom):
                        roots = {"fricgen"} if node.level else {node.module.split(".")[0]}
                    else:
                        continue
                    if not roots <= OPTIONAL:
                        found.append(f"{name}.{fn.name}: {ast.unparse(node)}")
    assert not found, found


def test_every_layer_named_in_the_order_exists():
    names = {p.stem if p.is_file() else p.name for p in PACKAGE.iterdir()
             if (p.suffix == ".py" and p.stem != "__init__" and p.stem != "__main__")
             or (p.is_dir() and (p / "__init__.py").exists())}
    assert names == set(LAYERS)
