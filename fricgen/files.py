"""Atomic file output: a reader never sees a half-written file, a failure leaves none."""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Dict, Union


def write_atomic(path: Union[str, Path], text: Union[str, bytes]) -> Path:
    """Write ``text`` (str, or bytes for binary files) to ``path`` through a temporary file in
    the same folder and a rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb" if isinstance(text, bytes) else "w") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def write_all_atomic(folder: Union[str, Path], files: Dict[str, Union[str, bytes]]) -> Dict[str, Path]:
    """Write several files (all content already rendered) into ``folder``, each atomically."""
    return {name: write_atomic(Path(folder) / name, text) for name, text in files.items()}
