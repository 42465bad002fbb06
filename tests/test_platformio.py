"""The emitted folder built by PlatformIO itself: ``pio run`` of a project whose lib/ holds a
folder of two axes, offline. PlatformIO's core package tool-scons is assembled from the SCons
that pip installed, and the development platform is tests/data/pio_host (the host's gcc and
PlatformIO's own program builder), so neither the PlatformIO registry nor GitHub is needed."""
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from test_emit_folder import AXES_MAIN, check_axes_output, two_axes

NOT_INSTALLED = "PlatformIO or SCons not installed (pip install -e .[firmware])"
platformio = pytest.importorskip("platformio", reason=NOT_INSTALLED)
SCons = pytest.importorskip("SCons", reason=NOT_INSTALLED)
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(shutil.which("gcc") is None,
                                 reason="no gcc for the host platform")]

HOST_PLATFORM = Path(__file__).parent / "data" / "pio_host"
#: Launches the SCons package beside it, as PlatformIO runs tool-scons/scons.py.
SCONS_LAUNCHER = """import os, sys
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from SCons.Script import main
main()
"""


def offline_core(core: Path) -> None:
    """A PlatformIO core folder holding tool-scons, made of pip's SCons and stated to be the
    version this PlatformIO requires (``~4.x``), so that ``pio run`` installs nothing."""
    from platformio.dependencies import get_core_dependencies
    version = get_core_dependencies()["tool-scons"].lstrip("~^=")
    package = core / "packages" / "tool-scons"
    shutil.copytree(Path(SCons.__file__).parent, package / "SCons")
    (package / "scons.py").write_text(SCONS_LAUNCHER)
    (package / "package.json").write_text(json.dumps(
        {"name": "tool-scons", "version": version, "description": "SCons (from pip)"}))
    (package / ".piopm").write_text(json.dumps(
        {"type": "tool", "name": "tool-scons", "version": version,
         "spec": {"owner": "platformio", "id": None, "name": "tool-scons",
                  "requirements": None, "uri": None}}))


def pio_run(project: Path, core: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PLATFORMIO_CORE_DIR": str(core),
           "PLATFORMIO_SETTING_ENABLE_TELEMETRY": "no",
           "PLATFORMIO_SETTING_CHECK_PLATFORMIO_INTERVAL": "9999",
           "PLATFORMIO_NO_ANSI": "true"}
    return subprocess.run([sys.executable, "-m", "platformio", "run", "-v", "-d", str(project)],
                          capture_output=True, text=True, env=env, timeout=600)


@pytest.mark.parametrize("build_flags", ["", "-ffast-math"])
def test_pio_run_builds_the_folder_of_two_axes(model10, axis2_model, tmp_path, build_flags):
    """lib/axes (fm with libm and the controller, axis2 fast) and a src/main.c printing both
    forces: PlatformIO finds the library, compiles exactly the sources library.json names with
    its strict float flags (after the project's own, so a project-wide -ffast-math is undone),
    links libm as the manifest asks, and the program's forces are the twins'."""
    core, project = tmp_path / "core", tmp_path / "project"
    offline_core(core)
    two_axes(project / "lib" / "axes", model10, axis2_model)
    (project / "src").mkdir()
    (project / "src" / "main.c").write_text(AXES_MAIN)
    (project / "platformio.ini").write_text(
        f"[env:host]\nplatform = {HOST_PLATFORM.resolve().as_uri()}\nbuild_flags = {build_flags}\n")
    proc = pio_run(project, core)
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, log[-4000:]
    assert "axes @ " in log                                   # the Library Dependency Finder's
    manifest = json.loads((project / "lib" / "axes" / "library.json").read_text())
    sources = [re.fullmatch(r"\+<(.+)>", f).group(1) for f in manifest["build"]["srcFilter"][1:]]
    compiled = {}
    for line in log.splitlines():
        match = re.match(r"gcc -o \S+ -c (.*) (\S+\.c)$", line)
        if match:
            compiled[Path(match.group(2)).name] = match.group(1).split()
    assert sorted(compiled) == sorted(sources + ["main.c"])
    for source in sources:
        flags = compiled[source]
        assert "-ffp-contract=off" in flags and "-fno-fast-math" in flags
        if build_flags:
            assert flags.index("-ffast-math") < flags.index("-fno-fast-math")
    link = next(line for line in log.splitlines()
                if line.startswith("gcc -o") and " -c " not in line)
    assert "-lm" in link.split()
    out = subprocess.run([str(project / ".pio" / "build" / "host" / "program")],
                         capture_output=True, text=True, check=True)
    check_axes_output(out.stdout, model10, axis2_model)


def test_platformios_manifest_schema_accepts_library_json(model10, axis2_model, tmp_path):
    """PlatformIO's own validation (that of ``pio pkg pack`` and the registry) takes the
    manifest as it is, and rejects it with a version that is not semantic, which shows it checks."""
    from platformio.package.exception import ManifestValidationError
    from platformio.package.manifest.parser import ManifestParserFactory
    from platformio.package.manifest.schema import ManifestSchema
    two_axes(tmp_path / "axes", model10, axis2_model)
    text = (tmp_path / "axes" / "library.json").read_text()
    def load(manifest):
        return ManifestSchema().load_manifest(
            ManifestParserFactory.new(manifest, "library.json").as_dict())
    loaded = load(text)
    assert loaded["name"] == "axes" and loaded["version"] == json.loads(text)["version"]
    broken = json.dumps({**json.loads(text), "version": "one"})
    with pytest.raises(ManifestValidationError, match="version"):
        load(broken)
