"""Atomic file output: write beside the target, then rename, so a crash leaves no half file.

The temporary file is created with mode 0666 and the kernel takes the umask off, so a written
file gets the mode any other tool would give it (0644 under umask 022); tempfile.mkstemp would
make it 0600.
"""
from __future__ import annotations

import contextlib
import os
import secrets
from pathlib import Path

from .errors import Diagnostic, FuzzycError


def _create_beside(path: Path) -> Path:
    """A new empty file next to `path` (O_EXCL: never one that already exists)."""
    while True:
        tmp = path.with_name(f".{path.name}.{secrets.token_hex(6)}{path.suffix}")
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            return tmp
        except FileExistsError:
            continue


@contextlib.contextmanager
def atomic_path(path: str | Path):
    """Yields a temporary path in the target's folder; renamed onto `path` on success.
    An OSError on the way (a full disk, a read-only folder) is a FuzzycError naming `path`."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = _create_beside(path)
    except OSError as exc:
        raise cannot_write(path, exc.strerror or str(exc)) from exc
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    except OSError as exc:
        raise cannot_write(path, exc.strerror or str(exc)) from exc
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def cannot_write(path: str | Path, reason: str) -> FuzzycError:
    return FuzzycError([Diagnostic(None, f"cannot write to {path}: {reason}")])


def write_text(path: str | Path, text: str) -> None:
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def save_figure(fig, path: str | Path, dpi: int = 100) -> Path:
    """A matplotlib figure to PNG (atomically), then closed so long runs do not pile them up."""
    import matplotlib.pyplot as plt
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
    plt.close(fig)
    return path
