"""All or nothing on disk: every command checks its destinations first, writes every file or
none, and gives new files the umask's permissions."""
import os
import stat
import subprocess
import sys

import pytest

from conftest import copy_of
from fricgen._io import write_files
from fricgen.cli import main


@pytest.fixture(scope="module")
def workdir(cli_inputs, tmp_path_factory):
    """A sweep, a model trained on it and a short log, shared by the rows below."""
    return copy_of(cli_inputs, tmp_path_factory.mktemp("outputs") / "work")


def _snapshot(folder):
    """Every file below ``folder`` with its bytes and mode (to prove nothing changed)."""
    return {p: (p.read_bytes(), p.stat().st_mode) for p in sorted(folder.rglob("*")) if p.is_file()}


def test_write_files_leaves_nothing_when_one_destination_fails(tmp_path):
    (tmp_path / "old.txt").write_text("before")
    (tmp_path / "blocked").mkdir()                      # a folder in the way of a file
    files = {tmp_path / "new" / "a.txt": "a", tmp_path / "old.txt": "after",
             tmp_path / "blocked": "b"}
    with pytest.raises(OSError) as info:
        write_files(files)
    assert str(tmp_path / "blocked") in str(info.value.filename)   # the user's path, no temp
    assert (tmp_path / "old.txt").read_text() == "before"
    assert not (tmp_path / "new").exists()              # the folder it created is gone too
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocked", "old.txt"]


def test_new_and_overwritten_files_get_the_umask_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        target = tmp_path / "f.txt"
        target.write_text("x")
        os.chmod(target, 0o644)
        write_files({target: "y", tmp_path / "g.txt": b"z"})
        assert stat.S_IMODE(target.stat().st_mode) == 0o644
        assert stat.S_IMODE((tmp_path / "g.txt").stat().st_mode) == 0o644
        os.umask(0o027)
        write_files({tmp_path / "h.txt": "w"})
        assert stat.S_IMODE((tmp_path / "h.txt").stat().st_mode) == 0o640
    finally:
        os.umask(old)


def _fifo(d):
    path = d / "fifo"
    if not path.exists():
        os.mkfifo(path)
    return path


def _symlink(d):
    path = d / "link.json"
    if not path.is_symlink():
        (d / "target.json").write_text("{}")
        path.symlink_to(d / "target.json")
    return path


def _copy(source, target):
    target.write_bytes(source.read_bytes())
    return target


def _c_folder(d, name, edit):
    """The folder ``d/name`` with the C of model.json emitted as fm, then ``edit(folder)``."""
    folder = d / name
    if not folder.exists():
        from fricgen.codegen import emit
        from fricgen.model import FrictionModel
        emit(FrictionModel.load(d / "model.json"), folder, "fm")
        edit(folder)
    return folder


def _hand_written(folder):
    """A fric_elm_sigmoid.c of the user's own, the last file emit writes: the others must not be either."""
    (folder / "fm.h").unlink()
    (folder / "fric_elm_sigmoid.c").write_text("/* my kernel */\n")


def _read_only(folder):
    os.chmod(folder / "fm.c", 0o444)


def _read_only_file(d, name):
    """``d/name``, an existing file no one may write (its folders made)."""
    path = d / name
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("keep me\n")
        os.chmod(path, 0o444)
    return path


LOG = ["--mass", "4", "--force-constant", "20"]

#: (name, argv given the work folder, the words of the one error line)
REFUSED = [
    ("train -o a read-only file", lambda d: ["train", str(d / "sweep.csv"), "-o",
                                             str(_read_only_file(d, "ro.json"))],
     "-o WORK/ro.json: is read-only; refusing to overwrite it (--force to do so)"),
    ("synth -o a read-only file", lambda d: ["synth", "-o", str(_read_only_file(d, "ro.csv"))],
     "-o WORK/ro.csv: is read-only"),
    ("synth-log -o a read-only file", lambda d: ["synth-log", "--duration", "1", "-o",
                                                 str(_read_only_file(d, "ro_log.csv"))],
     "-o WORK/ro_log.csv: is read-only"),
    ("diagnose -o over a read-only report", lambda d: [
        "diagnose", str(d / "log.csv"), "--model", str(d / "model.json"), *LOG, "-o",
        str(_read_only_file(d, "diag/report.md").parent)], "-o WORK/diag/report.md: is read-only"),
    ("simulate --plot over a read-only figure", lambda d: [
        "simulate", "--model", str(d / "model.json"), "--duration", "0.1", "--plot",
        str(_read_only_file(d, "plots/simulate_none.png").parent)],
     "--plot WORK/plots/simulate_none.png: is read-only; refusing to overwrite it\n"),   # no --force
    ("reproduce -o over a read-only report", lambda d: [
        "reproduce", "--quick", "-o", str(_read_only_file(d, "paper/report.md").parent)],
     "-o WORK/paper/report.md: is read-only; refusing to overwrite it (--force to do so)"),
    ("train -o the input", lambda d: ["train", str(d / "sweep.csv"), "-o", str(d / "sweep.csv")],
     "is the input"),
    ("train -o a folder", lambda d: ["train", str(d / "sweep.csv"), "-o", str(d)], "is a folder"),
    ("train -o a FIFO", lambda d: ["train", str(d / "sweep.csv"), "-o", str(_fifo(d))],
     "not a regular file"),
    ("train -o a symlink", lambda d: ["train", str(d / "sweep.csv"), "-o", str(_symlink(d))],
     "symbolic link"),
    ("synth -o a device", lambda d: ["synth", "-o", "/dev/null"], "not a regular file"),
    ("emit -o a file", lambda d: ["emit", str(d / "model.json"), "-o", str(d / "sweep.csv")],
     "is not a folder"),
    ("emit over its input", lambda d: ["emit", str(_copy(d / "model.json", d / "fm.c")), "-o",
                                        str(d), "--name", "fm"], "is the input"),
    ("diagnose -o the model's folder", lambda d: ["diagnose", str(d / "log.csv"), "--model",
                                                   str(d / "model.json"), "--mass", "4",
                                                   "--force-constant", "20", "-o", str(d)],
     "holds the input"),
    ("reproduce -o a file", lambda d: ["reproduce", "--quick", "-o", str(d / "sweep.csv")],
     "is not a folder"),
    ("simulate --plot a file", lambda d: ["simulate", "--duration", "0.1", "--plot",
                                           str(d / "sweep.csv")], "is not a folder"),
    ("emit over a file fricgen did not write", lambda d: [
        "emit", str(d / "model.json"), "-o", str(_c_folder(d, "mine", _hand_written)), "--name", "fm"],
     "mine/fric_elm_sigmoid.c: was not written by fricgen (no 'Generated by fricgen' line); refusing to "
     "overwrite it (--force to do so)"),
    ("emit over a read-only file", lambda d: [
        "emit", str(d / "model.json"), "-o", str(_c_folder(d, "ro", _read_only)), "--name", "fm"],
     "ro/fm.c: is read-only; refusing to overwrite it (--force to do so)"),
    ("demo -o over a file fricgen did not write", lambda d: [
        "demo", "--seeds", "1", "-o", str(_c_folder(d, "mine", _hand_written))],
     "mine/fric_elm_sigmoid.c: was not written by fricgen"),
]


@pytest.mark.parametrize("argv, words", [r[1:] for r in REFUSED], ids=[r[0] for r in REFUSED])
def test_unsafe_destinations_are_refused_with_one_line_and_nothing_changes(workdir, capsys, argv, words):
    argv = argv(workdir)
    before = _snapshot(workdir)
    assert main(argv) == 2
    err = capsys.readouterr().err
    words = words.replace("WORK/", f"{workdir}/")
    assert err.count("\n") == 1 and err.startswith("fricgen: error: ") and words in err, err
    assert _snapshot(workdir) == before


def test_force_overwrites_an_input_and_writes_through_a_symlink(workdir, tmp_path, capsys):
    sweep = tmp_path / "sweep.csv"
    sweep.write_bytes((workdir / "sweep.csv").read_bytes())
    assert main(["synth", "--seed", "3", "-o", str(sweep), "--force"]) == 0
    link = tmp_path / "m.json"
    link.symlink_to(tmp_path / "real.json")
    assert main(["train", str(sweep), "-o", str(link), "--vs-max", "0.02", "--force"]) == 0
    assert link.is_symlink() and (tmp_path / "real.json").read_text().startswith("{")


def test_force_replaces_a_read_only_file(workdir, tmp_path, capsys):
    target = _read_only_file(tmp_path, "m.json")
    assert main(["train", str(workdir / "sweep.csv"), "-o", str(target), "--vs-max", "0.02",
                 "--force"]) == 0
    assert target.read_text().startswith("{")


def test_emit_replaces_its_own_files_and_with_force_any(workdir, tmp_path, capsys):
    model, out = str(workdir / "model.json"), tmp_path / "c"
    for _ in range(2):                                  # the second run replaces fricgen's files
        assert main(["emit", model, "-o", str(out), "--name", "fm"]) == 0
    assert main(["emit", model, "-o", str(out), "--name", "fm", "--activation-impl", "fast"]) == 0
    (out / "fm.c").write_text("/* my own fm.c */\n")
    os.chmod(out / "fm.h", 0o444)
    assert main(["emit", model, "-o", str(out), "--name", "fm"]) == 2
    assert "fm.h: is read-only" in capsys.readouterr().err          # the first refused file
    assert main(["emit", model, "-o", str(out), "--name", "fm", "--force"]) == 0
    assert (out / "fm.c").read_text().splitlines()[1].startswith(" * Generated by fricgen ")


def test_train_with_a_full_stdout_writes_no_model(workdir, tmp_path):
    out = tmp_path / "m.json"
    with open("/dev/full", "w") as full:
        proc = subprocess.run([sys.executable, "-m", "fricgen", "train", str(workdir / "sweep.csv"),
                               "-o", str(out), "--vs-max", "0.02"], stdout=full,
                              stderr=subprocess.PIPE, text=True)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and proc.stderr.startswith("fricgen: error: stdout:")
    assert not out.exists()


def test_pinv_models_are_strict_json(workdir, tmp_path):
    out = tmp_path / "m.json"
    assert main(["train", str(workdir / "sweep.csv"), "-o", str(out), "--vs-max", "0.02",
                 "--method", "elm", "--solver", "pinv", "--neurons", "6"]) == 0
    text = out.read_text()
    assert "Infinity" not in text and "NaN" not in text and '"C": null' in text
