"""The manual: it builds without a warning, documents every option of every command, and its
tutorial commands run as written; the README stays a front page whose links resolve."""
import argparse
import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from fricgen.cli import COMMANDS, build_parser

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"


def _manual() -> str:
    return "\n".join(p.read_text(encoding="utf-8") for p in sorted(DOCS.rglob("*.md")))


def _options(name: str) -> list:
    parser = build_parser([name])
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return [o for a in sub.choices[name]._actions for o in a.option_strings
            if o.startswith("--") and o != "--help"]


def test_every_option_of_every_command_is_in_the_manual():
    text = _manual()
    missing = [f"{name} {opt}" for name in COMMANDS for opt in _options(name)
               if not re.search(rf"(?<![\w-]){re.escape(opt)}(?![\w-])", text)]
    assert not missing, f"options no page of docs/ mentions: {missing}"


def test_the_option_check_sees_a_missing_option():
    assert _options("train") and "--vs-max" in _options("train")
    assert not re.search(r"(?<![\w-])--vs-max(?![\w-])", "--vs-maximum and -vs-max")


@pytest.mark.skipif(not all(importlib.util.find_spec(m) for m in ("mkdocs", "material", "mkdocstrings")),
                    reason="the docs extra (mkdocs, mkdocs-material, mkdocstrings) is not installed")
def test_the_manual_builds_strictly(tmp_path):
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q",
                           "-f", str(ROOT / "mkdocs.yml"), "-d", str(tmp_path / "site")],
                          cwd=ROOT, capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stdout + done.stderr
    assert (tmp_path / "site" / "reference" / "python-api" / "index.html").is_file()


def test_the_readme_is_a_front_page_whose_links_resolve():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 150
    links = re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", text)
    assert links
    assert [link for link in links if not (ROOT / link).exists()] == []
    assert 'pip install -e ".[test,plot]" && fricgen demo' in text
    assert 'pip install -e ".[test,plot]" && python -m pytest -q' in text


def _shell_lines(page: Path) -> list:
    """The command lines of a page's ``sh`` blocks, in order."""
    return _shell_lines_of(page.read_text(encoding="utf-8"))


def _shell_lines_of(text: str) -> list:
    """The command lines of the ``sh`` blocks of a text, in order."""
    blocks = re.findall(r"```sh\n(.*?)```", text, flags=re.S)
    return [line for block in blocks for line in block.splitlines() if line.strip()]


def _run_lines(lines, folder) -> None:
    """Run each shell line in ``folder``, ``fricgen`` as this Python's module (a C compiler's
    lines skipped where there is none); each must exit 0."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    fricgen = f"{shlex.quote(sys.executable)} -m fricgen"
    for line in lines:
        if line.startswith("cc ") and shutil.which("cc") is None:
            continue
        command = re.sub(r"(^|\| )fricgen ", rf"\g<1>{fricgen} ", line)
        done = subprocess.run(command, shell=True, cwd=folder, env=env, capture_output=True, text=True)
        assert done.returncode == 0, f"{line}\n{done.stderr}"


@pytest.mark.slow
def test_the_tutorial_commands_run_as_written(tmp_path):
    lines = _shell_lines(DOCS / "tutorials.md")
    assert len(lines) >= 6
    _run_lines(lines, tmp_path)
    assert (tmp_path / "out" / "fm.h").is_file() and (tmp_path / "diag" / "model.json").is_file()


@pytest.mark.slow
def test_the_readme_tour_runs_as_written_in_order(tmp_path):
    """Every command of the README's five-minute tour, in order, in an empty folder (the
    install lines before it are what CI runs)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    tour = text[text.index("## A five-minute tour"):]
    lines = [line for line in _shell_lines_of(tour) if not line.startswith("pip ")]
    assert len(lines) >= 8
    _run_lines(lines, tmp_path)
    assert (tmp_path / "adapt" / "fm_adapt.c").is_file() and (tmp_path / "log.json").is_file()


@pytest.mark.slow
def test_the_python_tutorial_runs_as_written(tmp_path, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", (DOCS / "python.md").read_text(encoding="utf-8"), flags=re.S)
    assert len(blocks) >= 4
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)
    assert (tmp_path / "out" / "fm.c").is_file() and namespace["same"].model_hash == namespace["model"].model_hash
    assert namespace["d"].summary()["effect"] == "position_ripple"


def test_the_readme_python_example_runs(tmp_path, monkeypatch):
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = re.search(r"```python\n(.*?)```", text, flags=re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    assert (tmp_path / "model.json").is_file() and (tmp_path / "out" / "fm.h").is_file()
