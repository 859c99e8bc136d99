"""The output directory of a run: at every instant it holds one complete run.

Rules (docs/problem-file.md, "Output directory"):

* A run writes everything into a fresh sibling ``.<name>.tmp-XXXX`` first,
  with a manifest (:data:`MARKER`, the list of the files it wrote); only when
  every file is complete is the whole directory swapped in: renamed into
  place when ``<name>`` does not exist, else exchanged with ``<name>`` in one
  atomic step (Linux ``renameat2(RENAME_EXCHANGE)``) and the old run, now in
  the staging name, removed.  Where the filesystem cannot exchange,
  ``<name>`` is renamed aside to ``.<name>.old-XXXX`` and the new one renamed
  into place: a run killed between those two renames leaves no ``<name>``,
  and the next run into it renames the previous run back first.  Leftover
  ``.tmp-`` and ``.old-`` directories are removed by the next run.
* bemcontact never deletes or overwrites a file it did not write: it refuses
  an existing directory without its manifest unless empty, a directory that
  holds files its manifest does not list, the current directory, a
  filesystem root and an empty path, unless ``force`` (then files are moved
  in one by one and nothing else in the directory is touched).
* ``--out`` naming a symbolic link writes into the directory it points to
  (the link itself is kept); a link to nothing is refused.
* A lock file ``.<name>.lock`` held with ``flock`` (and holding the owner's
  process id, for the message) makes a second run into the same directory
  fail at once instead of racing the first; the kernel releases it when its
  process ends, however it ends, so a killed run never blocks the next.
* Names the filesystem could not hold (the staging sibling is 14 bytes
  longer than ``<name>``; the run's files need 128 bytes of path below it)
  are refused before anything is read.
* :class:`InterruptGuard`: Ctrl-C while the main thread is inside compiled
  code ends the run within ``grace`` seconds, the lock released.
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import json
import os
import pathlib
import secrets
import shutil
import signal
import threading
from collections.abc import Iterator

from .._version import __version__
from ..errors import ConfigError

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: the lock is the file's existence
    fcntl = None

#: The manifest that marks a bemcontact output directory: JSON with the
#: package version and the files (relative paths) the run wrote.
MARKER = ".bemcontact-run.json"

#: Bytes a run's file paths take beyond DIR's (the longest:
#: ``/steps/<64-character body>_interface_<step>.vtu``, with a margin).
_INSIDE = 128


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
        path = pathlib.Path(os.path.normpath(pathlib.Path(text).absolute()))
        if path.is_symlink():
            # the run goes where the link points (swapping the link itself would
            # replace it by a directory and leave the old one behind)
            target = path.resolve()
            if not target.is_dir():
                raise ConfigError(
                    f"{text}: --out: is a symbolic link to {target}, which "
                    f"{'is not a directory' if target.exists() else 'does not exist'}; "
                    "create that directory or name another one"
                )
            path = target
        self.path = path
        self.force = bool(force)
        self.given = text
        self._lock_fd: int | None = None
        self._writing = threading.Lock()
        self.check()

    @property
    def _locked(self) -> bool:
        return self._lock_fd is not None

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
        self._check_length(parent)
        if not os.access(parent if not out.exists() else out, os.W_OK | os.X_OK):
            raise ConfigError(f"{where}: cannot write into {parent if not out.exists() else out}")

    def _check_length(self, existing: pathlib.Path) -> None:
        """Names the run makes beside and inside DIR must fit the filesystem:
        ``.<name>.tmp-XXXXXXXX`` (14 bytes more than the name) and the
        longest file path inside (``steps/<body>_interface_NNN.vtu``, body
        names up to 64 characters: 128 bytes more than DIR's path).  A
        245-character name solved and then failed to write."""
        try:
            name_max = os.pathconf(existing, "PC_NAME_MAX")
            path_max = os.pathconf(existing, "PC_PATH_MAX")
        except (OSError, ValueError):  # pragma: no cover - no limits known
            name_max, path_max = 255, 4096
        name = len(os.fsencode(self.path.name)) + len(".tmp-") + 9
        path = len(os.fsencode(str(self.path))) + _INSIDE
        if name > name_max or path > path_max:
            what = (f"its name is {len(os.fsencode(self.path.name))} bytes, at most "
                    f"{name_max - 14}" if name > name_max else
                    f"its path is {path - _INSIDE} bytes, at most {path_max - _INSIDE}")
            given = self.given if len(self.given) <= 200 else (
                f"{self.given[:80]}...{self.given[-80:]}")
            raise ConfigError(f"{given}: --out: too long for this filesystem ({what}, "
                              "leaving room for the files of a run); name a shorter one")

    def manifest(self) -> list[str] | None:
        """The files the run in the directory wrote, or None (no manifest)."""
        try:
            data = json.loads((self.path / MARKER).read_text())
            return [str(f) for f in data["files"]]
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def foreign_files(self, limit: int = 2) -> list[str]:
        """Up to ``limit`` entries in the directory that its manifest does not
        list (any when there is none), as relative paths: files, links (to
        directories too: the walk does not follow them, a swap would delete
        them) and directories holding no listed file (a user's empty
        folder); the walk stops there, so a large directory of the user's
        costs nothing."""
        listed = set(self.manifest() or ())
        parents = {f.rsplit("/", 1)[0] for f in listed if "/" in f}
        parents |= {q.rsplit("/", 1)[0] for q in list(parents) if "/" in q}
        out: list[str] = []
        for root, dirs, files in os.walk(self.path):
            dirs.sort()
            here = pathlib.Path(root)
            links = [d for d in dirs if (here / d).is_symlink()]
            empty = [d for d in dirs if d not in links
                     and (here / d).relative_to(self.path).as_posix() not in parents
                     and not any((here / d).iterdir())]
            for name in sorted([*files, *links, *empty]):
                rel = (here / name).relative_to(self.path).as_posix()
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
        try:
            self._lock_fd = self._acquire()
        except BaseException:
            self._remove_created()
            raise
        self._recover()
        return self

    def _acquire(self) -> int:
        """The lock's file descriptor, ``flock``-ed; ConfigError if another
        run holds it.  A holder unlinks the file before it lets go, so a lock
        taken on a file no longer at the path is dropped and taken again."""
        for _ in range(100):
            fd = os.open(self._lock, os.O_CREAT | os.O_RDWR, 0o644)
            try:
                _lock_exclusive(fd)
            except BlockingIOError:
                pid = _lock_owner(fd)
                os.close(fd)
                raise ConfigError(
                    f"{self.given}: --out: another bemcontact run"
                    + (f" (process {pid})" if pid is not None else "")
                    + " is writing into it; wait for it or name another directory"
                ) from None
            except BaseException:
                os.close(fd)
                raise
            try:
                st = os.stat(self._lock)
                mine = os.fstat(fd)
                current = (st.st_ino, st.st_dev) == (mine.st_ino, mine.st_dev)
            except FileNotFoundError:
                current = False
            if current:
                os.ftruncate(fd, 0)
                os.write(fd, str(os.getpid()).encode())
                return fd
            os.close(fd)
        raise ConfigError(f"{self.given}: --out: locked by other runs")  # pragma: no cover

    def __exit__(self, *exc: object) -> None:
        if self._lock_fd is not None:
            with contextlib.suppress(FileNotFoundError):
                self._lock.unlink()  # while still held: see _acquire
            os.close(self._lock_fd)
            self._lock_fd = None
        if not self.path.exists():
            self._remove_created()

    def abandon(self) -> bool:
        """For a process about to end at once (:class:`InterruptGuard`):
        release the lock and remove the directories made on the way to DIR,
        unless a run is being written (False: let that finish or fail)."""
        if not self._writing.acquire(blocking=False):
            return False
        if self._lock_fd is not None:
            with contextlib.suppress(OSError):
                self._lock.unlink()
        if not self.path.exists():
            self._remove_created()
        return True

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
        with self._writing:
            tmp = out.parent / f".{out.name}.tmp-{secrets.token_hex(4)}"
            tmp.mkdir()
            try:
                yield tmp
                files = sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*")
                               if p.is_file())
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
        if _exchange(tmp, out):
            shutil.rmtree(tmp, ignore_errors=True)  # the old run, now in the staging name
            return
        old = out.parent / f".{out.name}.old-{secrets.token_hex(4)}"
        out.rename(old)
        tmp.rename(out)
        shutil.rmtree(old, ignore_errors=True)


class InterruptGuard:
    """Ctrl-C inside compiled code (an LU, gmsh, an H-LU holding no Python
    frame) reaches Python only when that code returns, minutes later on a
    large problem.  While entered (from the main thread), a watcher thread
    sees the signal at once (``signal.set_wakeup_fd``); if the main thread
    has not ended ``grace`` seconds after it, the watcher releases ``out``'s
    lock (a :class:`RunDirectory`, set by the caller) and ends the process
    with one line and exit code 130.  While a run is being written it does
    nothing: the write is short and Python code, which the interrupt stops
    the ordinary way (the staged run removed, DIR as it was)."""

    EXIT = 130

    def __init__(self, grace: float = 2.0) -> None:
        self.grace = grace
        self.out: RunDirectory | None = None
        self._done = threading.Event()
        self._said = threading.Lock()
        self._fds: tuple[int, int] | None = None
        self._previous = -1

    def claim(self) -> bool:
        """True for the first caller only: it says 'interrupted'."""
        return self._said.acquire(blocking=False)

    def __enter__(self) -> InterruptGuard:
        if threading.current_thread() is not threading.main_thread():
            return self
        r, w = os.pipe()
        os.set_blocking(w, False)
        try:
            self._previous = signal.set_wakeup_fd(w, warn_on_full_buffer=False)
        except ValueError:  # pragma: no cover - not the main interpreter
            os.close(r)
            os.close(w)
            return self
        self._fds = (r, w)
        threading.Thread(target=self._watch, args=(r,), daemon=True,
                         name="bemcontact-interrupt").start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._done.set()
        if self._fds is not None:
            signal.set_wakeup_fd(self._previous)
            os.close(self._fds[1])  # the watcher's read returns: it ends
            self._fds = None

    def _watch(self, r: int) -> None:
        try:
            while True:
                data = os.read(r, 64)
                if not data:
                    return
                if signal.SIGINT in data:
                    break
            if self._done.wait(self.grace):
                return
            if self.out is not None and not self.out.abandon():
                return
            if self.claim():
                os.write(2, b"bemcontact: interrupted\n")
                os._exit(self.EXIT)
        finally:
            with contextlib.suppress(OSError):
                os.close(r)


def _libc():
    try:
        libc = ctypes.CDLL(None, use_errno=True)
    except OSError:  # pragma: no cover
        return None
    return libc if hasattr(libc, "renameat2") else None


_LIBC = _libc()


def _exchange(a: pathlib.Path, b: pathlib.Path) -> bool:
    """Exchange the directories ``a`` and ``b`` in one atomic step (Linux
    ``renameat2`` with ``RENAME_EXCHANGE``); False where the system or the
    filesystem cannot (then nothing was changed)."""
    if _LIBC is None:
        return False
    at_fdcwd, rename_exchange = -100, 2
    if _LIBC.renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), os.fspath(b))


def _lock_exclusive(fd: int) -> None:
    """flock ``fd`` without waiting (BlockingIOError if held).  Without
    fcntl the file's existence is the lock: held if it names a process."""
    if fcntl is not None:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    elif _lock_owner(fd) is not None:  # pragma: no cover - Windows
        raise BlockingIOError(errno.EAGAIN, "locked")


def _lock_owner(fd: int) -> int | None:
    """The process id written in the lock file ``fd`` (None: not yet written)."""
    try:
        return int(os.pread(fd, 32, 0).decode().strip())
    except (OSError, ValueError):
        return None


__all__ = ["InterruptGuard", "MARKER", "RunDirectory"]
