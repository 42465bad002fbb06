"""A non-editable install (wheel) must carry the templates and the C runtime and emit working C."""
import os
import shutil
import subprocess
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
CC = shutil.which("gcc") or shutil.which("cc")


@pytest.mark.skipif(CC is None, reason="no C compiler")
def test_wheel_install_emits_c_that_builds(tmp_path):
    env_dir = tmp_path / "venv"
    venv.create(env_dir, system_site_packages=True, with_pip=True)
    py = env_dir / "bin" / "python"
    # --no-deps: numpy & co. come from the system site; the wheel is built in isolation
    proc = subprocess.run([str(py), "-m", "pip", "install", "-q", "--no-deps", str(ROOT)],
                          capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-2000:]
    shutil.rmtree(ROOT / "build", ignore_errors=True)
    fricgen = env_dir / "bin" / "fricgen"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    where = subprocess.run([str(py), "-c", "import fricgen; print(fricgen.__file__)"],
                           capture_output=True, text=True, cwd=tmp_path, env=env)
    assert str(env_dir) in where.stdout, "the venv must import the installed wheel, not the source tree"
    steps = [[str(fricgen), "synth", "-o", "sweep.csv"],
             [str(fricgen), "train", "sweep.csv", "-o", "model.json", "--vs-max", "0.02"],
             [str(fricgen), "emit", "model.json", "-o", "out", "--name", "fm"]]
    for step in steps:
        run = subprocess.run(step, capture_output=True, text=True, cwd=tmp_path, env=env)
        assert run.returncode == 0, run.stderr
    sources = sorted(str(p) for p in (tmp_path / "out").glob("*.c"))
    build = subprocess.run([CC, "-std=c99", "-c", *sources], cwd=tmp_path / "out",
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
