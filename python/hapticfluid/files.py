# SPDX-License-Identifier: GPL-3.0-or-later
"""Writing files so that a crash never leaves a half-written one.

Every output of the package (demo CSV and PNG, bake manifest and checkpoint, benchmark JSON and
plot) goes through :func:`atomic_write`: the data is written to a temporary file in the same
folder, flushed to the disk, given the usual permissions (``mkstemp`` makes 0600), renamed over
the target, and the folder is flushed so the new name survives a power cut.
"""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path
from typing import Any, Callable


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def sync_folder(folder: "str | os.PathLike") -> None:
    """Flush a folder's entries (a rename in it) to the disk, so a power cut after the rename
    cannot bring back the old file or lose the new name. Best effort where folders cannot be
    opened (some file systems); real I/O errors raise."""
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError as exc:
        if exc.errno not in (errno.EINVAL, errno.ENOTSUP, errno.EBADF):  # folder fsync unsupported
            raise
    finally:
        os.close(fd)


def atomic_write(path: "str | os.PathLike", write: Callable[[Any], None], binary: bool = False) -> Path:
    """Call ``write(f)`` on a temporary file next to ``path`` (text: UTF-8, newlines as written;
    ``binary``: bytes), then flush it and rename it into place. On any error the temporary file
    is removed and the old ``path``, if any, is left as it was."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8", "newline": ""})) as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    sync_folder(path.parent)
    return path
