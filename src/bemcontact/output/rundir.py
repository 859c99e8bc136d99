"""The output directory of a run: at every instant it holds one complete run.

Rules (docs/problem-file.md, "Output directory"):

* A run writes everything into a fresh sibling ``.<name>.tmp-XXXX`` first,
  with a manifest (:data:`MARKER`, the list of the files it wrote); only when
  every file is complete is the whole directory swapped in: renamed into
  place when ``<name>`` does not exist, else ``<name>`` is renamed aside to
  ``.<name>.old-XXXX``, the new one renamed into place and the old one
  removed.  A run killed between the two renames leaves no ``<name>``: the
  next run into it renames the previous run back first (and removes stale
  ``.tmp-`` directories).
* bemcontact never deletes or overwrites a file it did not write: it refuses
  an existing directory without its manifest unless empty, a directory that
  holds files its manifest does not list, the current directory, a
  filesystem root and an empty path, unless ``force`` (then files are moved
  in one by one and nothing else in the directory is touched).
* A lock file ``.<name>.lock`` (the owner's process id) makes a second run
  into the same directory fail at once instead of racing the first; a lock
  whose process is gone is taken over.
"""

from __future__ import annotations

import contextlib
import json
import os
import pathlib
import secrets
import shutil
from collections.abc import Iterator

from .._version import __version__
from ..errors import ConfigError

#: The manifest that marks a bemcontact output directory: JSON with the
#: package version and the files (relative paths) the run wrote.
MARKER = ".bemcontact-run.json"


class RunDirectory:
    """An output directory, checked at once (before any solve) and locked
    while the instance is entered (``with RunDirectory(path) as out:``);
    :meth:`staging` writes one run into it, all or nothing.

    ``force``: write into a directory that is not a bemcontact output
    directory (or holds files of the user's), moving the run's files in one
    by one and touching nothing else."""

    def __init__(self, path: str | os.PathLike, *, force: bool = False) -> None:
        text = os.fspath(path)
        if not text.strip():
            raise ConfigError("--out: the output directory is an empty path; name a directory")
        # lexically normalized: "a/new/.." is "a", and creates no "a/new"
        self.path = pathlib.Path(os.path.normpath(pathlib.Path(text).absolute()))
        self.force = bool(force)
        self.given = text
        self._locked = False
        self.check()

    # ------------------------------------------------------------------ checks
    def check(self) -> None:
        """Refuse what a run must not write into (see the module docstring)."""
        out = self.path
        where = f"{self.given}: --out"
        if out.exists() and not out.is_dir():
            raise ConfigError(f"{where}: exists and is not a directory")
        resolved = out.resolve()
        if not self.force:
            if resolved == pathlib.Path(resolved.anchor):
                raise ConfigError(f"{where}: is a filesystem root; name a new directory")
            if resolved == pathlib.Path.cwd().resolve():
                raise ConfigError(f"{where}: is the current directory; name a new directory "
                                  "(bemcontact replaces its output directory as a whole)")
            if resolved == pathlib.Path.home().resolve():
                raise ConfigError(f"{where}: is the home directory; name a new directory")
            if out.is_dir():
                foreign = self.foreign_files()
                if foreign:
                    what = ("is not a bemcontact output directory" if not (out / MARKER).exists()
                            else "holds files bemcontact did not write")
                    raise ConfigError(
                        f"{where}: {what} ({foreign[0]}{' and more' if len(foreign) > 1 else ''}); "
                        "name a new directory, or pass --force to add the results beside them"
                    )
        parent = out.parent
        while not parent.exists():
            parent = parent.parent
        if not os.access(parent if not out.exists() else out, os.W_OK | os.X_OK):
            raise ConfigError(f"{where}: cannot write into {parent if not out.exists() else out}")

    def manifest(self) -> list[str] | None:
        """The files the run in the directory wrote, or None (no manifest)."""
        try:
            data = json.loads((self.path / MARKER).read_text())
            return [str(f) for f in data["files"]]
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def foreign_files(self, limit: int = 2) -> list[str]:
        """Up to ``limit`` files in the directory that its manifest does not
        list (any file when there is none), as relative paths; the walk stops
        there, so a large directory of the user's costs nothing."""
        listed = set(self.manifest() or ())
        out: list[str] = []
        for root, dirs, files in os.walk(self.path):
            dirs.sort()
            for name in sorted(files):
                rel = (pathlib.Path(root) / name).relative_to(self.path).as_posix()
                if rel != MARKER and rel not in listed:
                    out.append(rel)
                    if len(out) >= limit:
                        return out
        return out

    # -------------------------------------------------------------------- lock
    @property
    def _lock(self) -> pathlib.Path:
        return self.path.parent / f".{self.path.name}.lock"

    def __enter__(self) -> RunDirectory:
        parent = self.path.parent
        self._created = []
        missing = []
        while not parent.exists():
            missing.append(parent)
            parent = parent.parent
        for d in reversed(missing):
            d.mkdir()
            self._created.append(d)
        for _ in range(2):
            try:
                fd = os.open(self._lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                pid = _lock_owner(self._lock)
                if pid is not None and _alive(pid):
                    self._remove_created()
                    raise ConfigError(
                        f"{self.given}: --out: another bemcontact run (process {pid}) is "
                        "writing into it; wait for it or name another directory"
                    ) from None
                with contextlib.suppress(FileNotFoundError):
                    self._lock.unlink()  # its process is gone: take it over
                continue
            with os.fdopen(fd, "w") as f:
                f.write(str(os.getpid()))
            self._locked = True
            break
        else:  # pragma: no cover - a third run took the stale lock in between
            self._remove_created()
            raise ConfigError(f"{self.given}: --out: locked by another run")
        self._recover()
        return self

    def __exit__(self, *exc: object) -> None:
        if self._locked:
            with contextlib.suppress(FileNotFoundError):
                self._lock.unlink()
            self._locked = False
        if not self.path.exists():
            self._remove_created()

    def _remove_created(self) -> None:
        for d in reversed(getattr(self, "_created", [])):
            with contextlib.suppress(OSError):
                d.rmdir()
        self._created = []

    def _recover(self) -> None:
        """Leftovers of a run killed while writing or swapping."""
        name = self.path.name
        olds = sorted(self.path.parent.glob(f".{name}.old-*"), key=lambda p: p.stat().st_mtime)
        if olds and not self.path.exists():
            olds.pop().rename(self.path)  # the previous complete run
        for p in [*olds, *self.path.parent.glob(f".{name}.tmp-*")]:
            shutil.rmtree(p, ignore_errors=True)

    # ----------------------------------------------------------------- writing
    @contextlib.contextmanager
    def staging(self) -> Iterator[pathlib.Path]:
        """A fresh directory to write one run into; on success it becomes
        the output directory (module docstring), on failure it is removed
        and the output directory is left as it was."""
        if not self._locked:
            with self:
                with self.staging() as tmp:
                    yield tmp
            return
        out = self.path
        tmp = out.parent / f".{out.name}.tmp-{secrets.token_hex(4)}"
        tmp.mkdir()
        try:
            yield tmp
            files = sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*") if p.is_file())
            (tmp / MARKER).write_text(json.dumps({"bemcontact": __version__, "files": files},
                                                 indent=1) + "\n")
            self._swap(tmp)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise

    def _swap(self, tmp: pathlib.Path) -> None:
        out = self.path
        if not out.exists():
            tmp.rename(out)
            return
        if self.force and self.foreign_files():
            # not all ours: move the run's files in, one by one, touch nothing else
            for f in sorted(p for p in tmp.rglob("*") if p.is_file()):
                target = out / f.relative_to(tmp)
                target.parent.mkdir(parents=True, exist_ok=True)
                os.replace(f, target)
            shutil.rmtree(tmp, ignore_errors=True)
            return
        old = out.parent / f".{out.name}.old-{secrets.token_hex(4)}"
        out.rename(old)
        tmp.rename(out)
        shutil.rmtree(old, ignore_errors=True)


def _lock_owner(path: pathlib.Path) -> int | None:
    try:
        return int(path.read_text().strip())
    except (OSError, ValueError):
        return None


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


__all__ = ["RunDirectory", "MARKER"]
