"""The emitted folder as a library: its build files for CMake (a static library target), Zephyr
(a module: zephyr/module.yml, Kconfig, the same CMakeLists.txt) and PlatformIO (library.json),
rewritten with each model written into the folder; and ``emit``, which writes it all."""
from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Union

from .. import __version__
from .._io import write_all_atomic
from ..model import FrictionModel
from .context import PACKAGE_MARKER, template_environment
from .render import check_name_in_folder, check_overwrite, generated_models, render, written_by_fricgen

#: The build files ``package_files`` writes, by file name in the folder.
PACKAGE_FILES = ("CMakeLists.txt", "library.json", "Kconfig", "zephyr/module.yml")
#: Flags of GCC and clang for the library's sources: no contraction into fused multiply-add and
#: no -ffast-math from the project's own flags (fric_float.h states both in the code already and
#: refuses -ffast-math; these keep a project's global -ffast-math from stopping the build).
STRICT_FLOAT_FLAGS = ("-ffp-contract=off", "-fno-fast-math")
#: A call of a libm function in C (after comments are removed): the folder then links libm.
LIBM_CALL = re.compile(r"\b(?:exp|exp2|expm1|log|log1p|log2|pow|sqrt|cbrt|hypot|sin|cos|tan|"
                       r"asin|acos|atan|atan2|sinh|cosh|tanh|erf|floor|ceil|round|fmod)f?\s*\(")
_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
#: A quoted #include, and a runtime function's definition or declaration at a line's start
#: (or one a defining macro names first: ``FRIC_ELM_KERNEL(fric_elm_sigmoid_f32, ...)``).
_INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
_RUNTIME_FUNCTION = re.compile(r"^(?:[A-Za-z_][\w \t*]*?\b|[A-Z_]+\(\s*)(fric_\w+)\s*[(,]", re.M)


def library_name(folder: Union[str, Path]) -> str:
    """The library's name: the folder's name as a C identifier (``fricgen_`` before one that
    would begin with a digit), for the CMake target, the Zephyr library and the PlatformIO
    library; its Kconfig symbol is FRICGEN_ and that name in capitals."""
    name = re.sub(r"\W", "_", Path(folder).resolve().name, flags=re.ASCII) or "models"
    return f"fricgen_{name}" if name[0].isdigit() else name


def uses_libm(texts: Iterable[str]) -> bool:
    """Whether any of the C texts calls a libm function (comments aside)."""
    return any(LIBM_CALL.search(_COMMENT.sub(" ", text)) for text in texts)


def reached_files(texts: Dict[str, str]) -> set:
    """The files of a folder's C ``texts`` (by name) that its models' files reach, as the
    compiler and linker would: every file not of the runtime (``fric_*``) is a model's, and the
    controller where a model's emit options ask for it (the loop calls it); a file reaches what
    it #includes, a header its own .c, and a file that calls a runtime function
    (a declaration is no call) the runtime .c that defines it."""
    runtime = {f for f in texts if f.startswith("fric_")}
    defines = {f: set(_RUNTIME_FUNCTION.findall(_COMMENT.sub(" ", texts[f])))
               for f in runtime if f.endswith(".c")}
    reached, todo = set(), [f for f in texts if f not in runtime]
    if "fric_ctrl.h" in texts and any("with_controller=1" in texts[f] for f in todo):
        todo.append("fric_ctrl.h")      # asked for (emit --with-controller): the loop calls it
    while todo:
        f = todo.pop()
        if f in reached:
            continue
        reached.add(f)
        code = _COMMENT.sub(" ", texts[f])
        todo += [g for g in _INCLUDE.findall(code) if g in texts]
        todo += [f[:-2] + ".c"] if f.endswith(".h") and f[:-2] + ".c" in texts else []
        called = set(re.findall(r"\b(fric_\w+)\s*\(", code)) - set(_RUNTIME_FUNCTION.findall(code))
        todo += [c for c, names in defines.items() if names & called]
    return reached


def stale_files(folder: Union[str, Path], name: str, files: Dict[str, str]) -> List[Path]:
    """The files fricgen wrote into ``folder`` before that this emit, ``files``, no longer
    writes and no model left there needs: the model ``name``'s adaptation (NAME_adapt.c and .h)
    and the runtime files that no model's files reach any more (``reached_files``: a model
    emitted again without ``--adapt`` leaves no adaptation runtime behind). Removed with it, so
    that the folder builds nothing a model it holds does not use."""
    return _stale_and_texts(folder, name, files)[0]


def _stale_and_texts(folder: Union[str, Path], name: str, files: Dict[str, str]):
    """``stale_files`` and the C texts of the folder without them (``_folder_texts``), read
    once."""
    folder = Path(folder)
    adapt = [folder / f for f in (f"{name}_adapt.c", f"{name}_adapt.h")
             if f not in files and (folder / f).is_file() and written_by_fricgen(folder / f)]
    texts = _folder_texts(folder, files, adapt)
    reached = reached_files(texts)
    unused = [f for f in sorted(texts) if f.startswith("fric_") and f not in files and f not in reached]
    return adapt + [folder / f for f in unused], {f: t for f, t in texts.items() if f not in unused}


def remove_stale(folder: Union[str, Path], name: str, files: Dict[str, str]) -> List[str]:
    """Remove ``stale_files``; their names."""
    stale = stale_files(folder, name, files)
    for path in stale:
        path.unlink()
    return [path.name for path in stale]


def _folder_texts(folder: Path, files: Dict[str, str], stale: List[Path]) -> Dict[str, str]:
    """The C files of the folder once ``files`` are written and ``stale`` removed: those fricgen
    wrote before, then ``files``, by name."""
    texts = {}
    if folder.is_dir():
        for path in sorted(folder.glob("*.[ch]")):
            if path.is_file() and written_by_fricgen(path) and path not in stale:
                texts[path.name] = path.read_text(errors="replace")
    texts.update({fname: text for fname, text in files.items() if fname.endswith((".c", ".h"))})
    return texts


def package_files(folder: Union[str, Path], files: Dict[str, str], name: str) -> Dict[str, str]:
    """The build files of ``folder`` once ``files`` (the model ``name``'s NAME.h, NAME.c and
    runtime, by file name) are written into it, by file name (PACKAGE_FILES): they build every C
    source fricgen wrote there, so that a second model emitted into the folder joins the first
    in one library.

    Parameters
    ----------
    folder : str or pathlib.Path
        The emitted folder (it may hold models emitted before).
    files : dict of str to str
        The files about to be written, by file name (``render``).
    name : str
        The model's name.

    Returns
    -------
    dict of str to str
        CMakeLists.txt, library.json, Kconfig and zephyr/module.yml, by file name.

    Examples
    --------
    >>> import fricgen
    >>> from fricgen.codegen import package_files, render
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0),
    ...                                   name="axis_x")
    >>> build = package_files(tmp / "axes", render(model), "axis_x")
    >>> sorted(build), "axis_x.c" in build["CMakeLists.txt"]
    (['CMakeLists.txt', 'Kconfig', 'library.json', 'zephyr/module.yml'], True)
    """
    folder = Path(folder)
    stale, texts = _stale_and_texts(folder, name, files)
    names = (set(generated_models(folder)) - {path.stem for path in stale}) | {name}
    models = sorted(m for m in names if not (m.endswith("_adapt") and m[:-len("_adapt")] in names))
    lib = library_name(folder)
    ctx = {"lib": lib, "LIB": lib.upper(), "kconfig": f"FRICGEN_{lib.upper()}",
           "marker": PACKAGE_MARKER, "fricgen_version": __version__, "models": models,
           "sources": sorted(f for f in texts if f.endswith(".c")),
           "libm": uses_libm(texts.values()), "flags": list(STRICT_FLOAT_FLAGS)}
    env = template_environment()
    out = {fname: env.get_template(f"package_{Path(fname).name}.j2").render(ctx)
           for fname in PACKAGE_FILES if fname != "library.json"}
    out["library.json"] = json.dumps(platformio_manifest(ctx), indent=2) + "\n"
    return out


def platformio_manifest(ctx: dict) -> dict:
    """library.json: the PlatformIO library of the folder (its sources and headers in the folder
    itself, the strict float flags, and ``-lm``, which PlatformIO passes on to the program's
    link, when a source calls libm). Its description carries PACKAGE_MARKER (JSON has no
    comments)."""
    return {
        "name": ctx["lib"],
        "description": (f"{PACKAGE_MARKER} {ctx['fricgen_version']}: the friction models "
                        f"{', '.join(ctx['models'])} and the fricgen C runtime. Do not edit: "
                        "`fricgen emit` rewrites it."),
        "version": ctx["fricgen_version"],
        "keywords": ["friction", "fricgen", "motion control"],
        "frameworks": "*",
        "platforms": "*",
        "build": {"srcDir": ".", "includeDir": ".",
                  "srcFilter": ["-<*>"] + [f"+<{src}>" for src in ctx["sources"]],
                  "flags": ctx["flags"] + (["-lm"] if ctx["libm"] else [])},
    }


def emit(model: FrictionModel, out_dir: Union[str, Path], name: Optional[str] = None,
         activation_impl: str = "libm", dtype: str = "float",
         with_controller: bool = False, force: bool = False,
         v_max: Optional[float] = None, sample_time: Optional[float] = None) -> Dict[str, Path]:
    """Write the C of a model into a folder: render everything first (the model, its runtime and
    the folder's build files), check the folder's models and that every file it replaces is
    fricgen's own and writable (``check_overwrite``, skipped with ``force``), then write each
    file atomically.

    Parameters
    ----------
    model : FrictionModel
        The model whose [F3] the C evaluates.
    out_dir : str or pathlib.Path
        The folder (created if missing).
    name, activation_impl, dtype, with_controller, v_max, sample_time
        As for ``render``.
    force : bool
        Overwrite files fricgen did not write.

    Returns
    -------
    dict of str to pathlib.Path
        File name -> path written.

    Examples
    --------
    >>> import fricgen
    >>> data = fricgen.synthesize_benchmark(fricgen.preset("paper3"), seed=0).dataset
    >>> model = fricgen.FrictionModel.fit(data, fricgen.ELMRegressor(n_hidden=5, random_state=0),
    ...                                   name="axis_x")
    >>> written = fricgen.emit(model, tmp / "c", dtype="q15")
    >>> sorted(written)[:2], written["axis_x.h"].is_file()
    (['CMakeLists.txt', 'Kconfig'], True)
    """
    name = model.name if name is None else name
    files = render(model, name, activation_impl, dtype, with_controller, v_max,
                   sample_time=sample_time)
    check_name_in_folder(out_dir, name)
    files.update(package_files(out_dir, files, name))
    check_overwrite([Path(out_dir) / fname for fname in files], force)
    written = write_all_atomic(out_dir, files)
    remove_stale(out_dir, name, files)
    return written
