"""Files out, all or nothing, the shipped resources, and numbers and errors as users see them."""
from __future__ import annotations

import errno
import os
import re
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Dict, Iterator, Optional, Sequence, Union

from .errors import DataError, UsageError

#: A number as fricgen reads one: ASCII digits, '.' decimals, an optional exponent, or nan/inf.
_NUMBER = re.compile(r"\s*[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|nan|inf(?:inity)?)\s*",
                     re.IGNORECASE)
#: An integer as fricgen reads one: ASCII digits with an optional sign.
_INTEGER = re.compile(r"\s*[+-]?[0-9]+\s*")


def plain_float(text: str) -> float:
    """``float(text)`` for a plainly written number only (no '_' separators, no digits of other
    scripts, which Python's float would accept); else ``ValueError``. The minus sign U+2212, as
    numbers copied from documents write it, is a minus."""
    return _plain(text, _NUMBER, float)


def plain_int(text: str) -> int:
    """``int(text)`` for a plainly written integer only, as ``plain_float``."""
    return _plain(text, _INTEGER, int)


def _plain(text: str, pattern, kind):
    text = text.replace("\u2212", "-")
    if not pattern.fullmatch(text):
        raise ValueError(f"not a number: {text!r}")
    return kind(text)


@contextmanager
def named_data(name) -> Iterator[None]:
    """A ``DataError`` raised inside, prefixed with the file (or files) ``name`` it concerns."""
    try:
        yield
    except DataError as exc:
        raise DataError(f"{name}: {exc}") from None


#: Shipped resource folders: where a wheel installs them inside the package, and where a source
#: checkout keeps them (relative to the repository's top).
RESOURCES = {"templates": "templates", "c_runtime": "c_runtime",
             "firmware_sources": "examples/firmware"}


def resource_dir(kind: str) -> Path:
    """The folder of the shipped ``templates``, ``c_runtime`` or ``firmware_sources`` files.

    A wheel installs them inside the package (``fricgen/templates``); a source checkout keeps
    them at the top of the repository, beside ``fricgen/``.
    """
    if kind not in RESOURCES:
        raise ValueError(f"kind must be one of {sorted(RESOURCES)}, got {kind!r}")
    package = Path(__file__).resolve().parent
    for path in (package / kind, package.parent / RESOURCES[kind]):
        if path.is_dir():
            return path
    raise FileNotFoundError(f"fricgen {kind} folder not found beside {package} (broken install?)")


def _umask_mode() -> int:
    """The permissions a new file gets under the process umask (0o666 & ~umask)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def read_only(path: Path) -> bool:
    """Whether the existing file ``path`` has no write permission for anyone (checked by its
    mode, so that it holds for root as well)."""
    return not path.stat().st_mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH)


def _offer(force: Optional[bool], what: str = "--force to do so") -> str:
    """The hint at ``--force`` a refusal ends with; none where the command has no --force."""
    return "" if force is None else f" ({what})"


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return a.resolve() == b.resolve()


@contextmanager
def _named(option: str, path) -> Iterator[None]:
    """An ``OSError`` of looking at ``path`` (a name too long, no permission) as a
    ``UsageError`` naming ``option`` and ``path``."""
    try:
        yield
    except OSError as exc:
        raise UsageError(f"{option} {path}: {exc.strerror or exc}") from None


def check_destination(path: Union[str, Path], inputs: Sequence[Union[str, Path]] = (),
                      force: Optional[bool] = None, option: str = "-o") -> Path:
    """The file a command may write for ``path``, else ``UsageError`` naming ``option`` and it.

    A folder, FIFO or device is never replaced. A symbolic link, a read-only file or one of the
    command's ``inputs`` is refused unless ``force``; with ``force`` a link is written through
    (its target is replaced, the link kept). ``force`` is None where the command has no
    ``--force``: the refusals then do not offer it."""
    if not str(path).strip():
        raise UsageError(f"{option}: empty path")
    if str(path).endswith(("/", os.sep)):
        raise UsageError(f"{option} {path}: names a folder; give a file name")
    with _named(option, path):
        return _check_destination(Path(path), inputs, force, option)


def _check_destination(path: Path, inputs, force: bool, option: str) -> Path:
    if path.is_symlink():
        if not force:
            raise UsageError(f"{option} {path}: is a symbolic link; refusing to replace it"
                             + _offer(force, "--force writes to its target"))
        target = Path(os.path.realpath(path))
        if target.is_symlink():
            raise UsageError(f"{option} {path}: is a symbolic link that loops")
        path = target
    if path.exists() and not path.is_file():
        kind = "a folder" if path.is_dir() else "not a regular file"
        raise UsageError(f"{option} {path}: is {kind}; refusing to replace it")
    _check_writable(path.parent, path, option)
    if not force:
        for source in inputs:
            if source is not None and Path(source).exists() and _same_file(path, Path(source)):
                raise UsageError(f"{option} {path}: is the input {source}; refusing to overwrite "
                                 "it" + _offer(force))
        if path.is_file() and read_only(path):
            raise UsageError(f"{option} {path}: is read-only; refusing to overwrite it" + _offer(force))
    return path


def _check_writable(folder: Path, path: Path, option: str) -> None:
    """``UsageError`` unless a file can be created in ``folder`` (or in its nearest existing
    ancestor, where the missing folders would be made): found before any work is done."""
    existing = next((p for p in [folder, *folder.parents] if p.exists()), Path("/"))
    if not existing.is_dir():
        raise UsageError(f"{option} {path}: {existing} is not a folder")
    try:
        fd, probe = tempfile.mkstemp(prefix=".fricgen-probe.", dir=existing)
    except OSError as exc:
        raise UsageError(f"{option} {path}: cannot write in {existing} ({exc.strerror})") from None
    os.close(fd)
    os.unlink(probe)


def check_folder(folder: Union[str, Path], inputs: Sequence[Union[str, Path]] = (),
                 force: Optional[bool] = None, option: str = "-o") -> Path:
    """``folder`` if a command may write into it: not an existing non-folder nor a broken
    symbolic link, and not the folder of one of ``inputs`` (unless ``force``; None where the
    command has no ``--force``); else ``UsageError`` naming ``option``."""
    if not str(folder).strip():
        raise UsageError(f"{option}: empty path")
    with _named(option, folder):
        return _check_folder(Path(folder), inputs, force, option)


def _check_folder(folder: Path, inputs, force: bool, option: str) -> Path:
    if folder.is_symlink() and not folder.exists():
        raise UsageError(f"{option} {folder}: is a broken symbolic link (its target does not "
                         "exist or loops); give a folder")
    if folder.exists() and not folder.is_dir():
        raise UsageError(f"{option} {folder}: exists and is not a folder")
    _check_writable(folder, folder, option)
    if not force:
        for source in inputs:
            if source is not None and folder.exists() and _same_file(folder, Path(source).parent):
                raise UsageError(f"{option} {folder}: holds the input {source}; refusing to write "
                                 "into it" + _offer(force))
    return folder


def check_files(folder: Union[str, Path], names, inputs: Sequence[Union[str, Path]] = (),
                folder_of: Sequence[Union[str, Path]] = (), force: Optional[bool] = None,
                option: str = "-o") -> Dict[str, Path]:
    """The destinations of ``names`` in ``folder``, by name: the folder checked
    (``check_folder``, not that of one of ``folder_of``) and each file (``check_destination``,
    not one of ``inputs``)."""
    folder = check_folder(folder, folder_of, force, option)
    return {name: check_destination(folder / name, inputs, force, option) for name in names}


def write_files(files: Dict[Union[str, Path], Union[str, bytes]]) -> Dict[str, Path]:
    """Write every file or none: each is written to a temporary file beside its destination,
    and only when all of them are on disk are they renamed into place; on any failure the
    temporaries, the folders created and the files already replaced are restored. Files get the
    permissions the umask gives. Returns the destinations by the keys given."""
    mode = _umask_mode()
    dests = {key: Path(key) for key in files}
    created, temps, backups, placed = [], {}, {}, []
    try:
        for key, dest in dests.items():
            if dest.is_symlink() or (dest.exists() and not dest.is_file()):
                raise OSError(errno.EEXIST, "is not a regular file", str(dest))
            missing = [p for p in [dest.parent, *dest.parent.parents] if not p.exists()]
            for folder in reversed(missing):
                folder.mkdir()
                created.append(folder)
            text = files[key]
            try:
                fd, tmp = tempfile.mkstemp(prefix=".fricgen-", suffix=".tmp", dir=dest.parent)
            except OSError as exc:
                raise OSError(exc.errno, exc.strerror, str(dest)) from None
            temps[key] = Path(tmp)
            try:
                with os.fdopen(fd, "wb" if isinstance(text, bytes) else "w") as fh:
                    fh.write(text)
            except OSError as exc:
                raise OSError(exc.errno, exc.strerror, str(dest)) from None
            os.chmod(tmp, mode)
        for key, dest in dests.items():
            if dest.exists():
                backup = dest.with_name(f".fricgen-{os.getpid()}-{len(backups)}.bak")
                os.link(dest, backup)
                backups[key] = backup
        for key, dest in dests.items():
            os.replace(temps[key], dest)
            placed.append(key)
    except BaseException:
        for key in placed:
            if key in backups:
                os.replace(backups.pop(key), dests[key])
            else:
                dests[key].unlink()
        for path in list(temps.values()) + list(backups.values()):
            if path.exists() and path.name.startswith("."):
                path.unlink()
        for folder in reversed(created):
            try:
                folder.rmdir()
            except OSError:
                pass
        raise
    for backup in backups.values():
        backup.unlink()
    return dests


def write_atomic(path: Union[str, Path], text: Union[str, bytes]) -> Path:
    """Write one file all or nothing (``write_files``)."""
    return write_files({path: text})[path]


def write_all_atomic(folder: Union[str, Path], files: Dict[str, Union[str, bytes]]) -> Dict[str, Path]:
    """Write several files, by name, into ``folder``: all of them or none (``write_files``)."""
    written = write_files({Path(folder) / name: text for name, text in files.items()})
    return {name: written[Path(folder) / name] for name in files}
