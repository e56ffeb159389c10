"""Writing user files: atomically when they are regular files, never by replacing a device.

A write goes to a temporary file beside the target, then `os.replace` puts it in place, so a
reader (or a crash) never sees half a file; an existing file keeps its permission bits. A target
that exists but is not a regular file (`/dev/null`, `/dev/stdout`, a FIFO) is written in place:
replacing it would turn the device into a plain file (as root, for every program on the machine).
A symlink is followed: the file it points to is replaced and the link stays.

Every failure (permission, read-only file system, missing directory, a file where a directory
should be, a full disk) becomes an `ArmtoolError` naming the path: no OSError escapes.

The rest of the write path, for commands:

* `check_output_paths(outputs, inputs)`: before any work (above all before moving a servo),
  every output's directory exists and is writable, no output is a directory, and no output is
  one of the run's inputs (writing the result over the file it was computed from).
* `backup_path(path)`: where an in-place edit keeps the previous version: `FILE.bak`, or the
  first free `FILE.bak.N` when that exists, so a second run never loses the original.
* `write_with_backup(path, text)`: that backup, then the new text.
* `PortFile`: a small file that names a resource for as long as a process runs (servo-sim's
  `--port-file`): refused when something else is already there, removed only if it is still
  the regular file this process wrote.
* `rescue_write(path, text)`: the output of a long run (servo readings) when the planned write
  failed: beside it as `.partial`, else in the temporary directory; returns where it went.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

from armtool.errors import ArmtoolError

MAX_BACKUPS = 100  # FILE.bak, FILE.bak.1 .. FILE.bak.99: beyond that, ask the user to clean up


def _os_error(exc: OSError, path: Path | str, doing: str = "write") -> ArmtoolError:
    """An OSError as what / where / how to fix, by its cause."""
    import errno

    reason = exc.strerror or str(exc)
    hints = {
        errno.EACCES: "check the permissions of the file and its directory, or write somewhere else",
        errno.EPERM: "check the permissions of the file and its directory, or write somewhere else",
        errno.EROFS: "the file system is read-only: write somewhere else",
        errno.ENOENT: "the directory does not exist: create it first, or check the path",
        errno.ENOTDIR: "a part of the path is a file, not a directory: check the path",
        errno.EISDIR: "the path is a directory: give a file name",
        errno.ENOSPC: "the disk is full: free some space or write somewhere else",
    }
    return ArmtoolError(f"cannot {doing}: {reason}", str(path), hints.get(exc.errno or 0, "check the path"))


def write_atomic(path: Path | str, data: str | bytes) -> None:
    """Write the whole of `data` to `path` (see the module docstring); ArmtoolError on failure."""
    # Through a symlink, the file it points to is what the user means: replace that, keep the link.
    path = Path(os.path.realpath(path)) if os.path.islink(path) else Path(path)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    try:
        st = os.stat(path)
    except FileNotFoundError:
        st = None
    except OSError as exc:  # ENOTDIR, EACCES on a parent
        raise _os_error(exc, path) from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise ArmtoolError("cannot write: it is a directory", str(path), "give a file name")
    try:
        if st is not None and not stat.S_ISREG(st.st_mode):
            with open(path, "wb") as handle:
                handle.write(payload)
            return
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise _os_error(exc, path) from None
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
        os.chmod(tmp, stat.S_IMODE(st.st_mode) if st is not None else 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as exc:
        _unlink_quietly(tmp)
        raise _os_error(exc, path) from None
    except BaseException:
        _unlink_quietly(tmp)
        raise


def _unlink_quietly(path: str) -> None:
    try:
        if os.path.lexists(path):
            os.unlink(path)
    except OSError:
        pass


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_directory(path: Path | str) -> Iterator[Path]:
    """A new directory written as a whole: the body fills a temporary directory beside `path`,
    which gets the permissions a plain `mkdir` would give and then takes `path`'s place (an
    existing empty directory there is replaced). On any error the temporary directory is removed
    and `path` is left as it was."""
    path = Path(path)
    try:
        tmp = Path(tempfile.mkdtemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp"))
    except OSError as exc:
        raise _os_error(exc, path, "create") from None
    try:
        yield tmp
        os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp makes it private (0700)
        if path.is_dir() and not any(path.iterdir()):
            path.rmdir()
        os.replace(tmp, path)
    except OSError as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        raise _os_error(exc, path) from None
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


# --------------------------------------------------------------------------------------------
# checking outputs before the work


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)


def check_output_path(path: Path | str, flag: str, inputs: Iterable[Path | str] = ()) -> None:
    """One output, checked before any work: not an input of this run, not a directory, and its
    directory exists and is writable. `flag` names the option in the message (e.g. "-o")."""
    path = Path(path)
    label = f"{flag} {path}" if flag else str(path)
    for source in inputs:
        if _same_file(path, Path(source)):
            raise ArmtoolError(
                f"{label} is also an input of this run ({source}): it would be overwritten",
                hint="write the result to another file",
            )
    target = Path(os.path.realpath(path))
    if target.is_dir():
        raise ArmtoolError(f"{label} is a directory", hint="give a file name")
    if target.exists() and not target.is_file():
        return  # a device or FIFO (/dev/stdout, a pipe): written in place
    parent = target.parent
    if not parent.exists():
        raise ArmtoolError(
            f"directory {parent} does not exist (for {label})", hint="create it first, or check the path"
        )
    if not parent.is_dir():
        raise ArmtoolError(f"{parent} is not a directory (for {label})", hint="check the path")
    if target.exists() and not os.access(target, os.W_OK):
        raise ArmtoolError(f"{label} is not writable", hint="check its permissions, or write somewhere else")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ArmtoolError(
            f"directory {parent} is not writable (for {label})", hint="check its permissions, or write somewhere else"
        )


def check_output_paths(outputs: Mapping[str, Path | str | None], inputs: Iterable[Path | str | None] = ()) -> None:
    """Every output (flag -> path; None and "-" = stdout, skipped) checked as `check_output_path`,
    and no two outputs the same file."""
    sources = [Path(p) for p in inputs if p is not None and str(p) != "-"]
    chosen = [(flag, Path(p)) for flag, p in outputs.items() if p is not None and str(p) != "-"]
    for k, (flag, path) in enumerate(chosen):
        check_output_path(path, flag, sources)
        for other_flag, other in chosen[:k]:
            if os.path.realpath(path) == os.path.realpath(other) and not _is_device(path):
                raise ArmtoolError(
                    f"{other_flag} and {flag} name the same file {path}", hint="give each output its own file"
                )


def _is_device(path: Path) -> bool:
    """A character device or FIFO (/dev/stdout, a pipe): many outputs may share it."""
    try:
        return not stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return False


# --------------------------------------------------------------------------------------------
# in-place edits keep the previous version


def backup_path(path: Path | str) -> Path:
    """`FILE.bak`, or the first free `FILE.bak.N`: an existing backup is never overwritten."""
    path = Path(path)
    first = path.with_name(path.name + ".bak")
    if not os.path.lexists(first):
        return first
    for n in range(1, MAX_BACKUPS):
        candidate = path.with_name(f"{path.name}.bak.{n}")
        if not os.path.lexists(candidate):
            return candidate
    raise ArmtoolError(
        f"{path} already has {MAX_BACKUPS} backups ({first.name} .. {path.name}.bak.{MAX_BACKUPS - 1})",
        str(path.parent),
        hint="remove the old .bak files you no longer need",
    )


def write_with_backup(path: Path | str, text: str | bytes, previous: str | bytes) -> Path:
    """Keep `previous` (the file's content as read) in `backup_path(path)`, then write `text`
    to `path`; returns the backup's path. Nothing is changed if the backup cannot be written."""
    backup = backup_path(path)
    write_atomic(backup, previous)
    write_atomic(path, text)
    return backup


# --------------------------------------------------------------------------------------------
# a file that names a resource while a process runs


@dataclass
class PortFile:
    """`--port-file`: one line naming a device, there while the process runs.

    Refused when the path exists and is not a previous port file (a regular file holding one
    line that names a /dev path: left by a run that was killed); removed at the end only if it
    is still the regular file with the content this process wrote.
    """

    path: Path
    content: str = ""
    written: bool = False

    @staticmethod
    def looks_like_ours(path: Path) -> bool:
        try:
            st = os.lstat(path)
            if not stat.S_ISREG(st.st_mode) or st.st_size > 256:
                return False
            text = path.read_text(encoding="ascii")
        except (OSError, UnicodeDecodeError):
            return False
        lines = text.splitlines()
        return len(lines) == 1 and lines[0].startswith("/dev/") and text.endswith("\n")

    def claim(self, flag: str = "--port-file") -> None:
        """Before starting anything: the path is free (or a stale port file) and writable."""
        if os.path.lexists(self.path) and not self.looks_like_ours(self.path):
            raise ArmtoolError(
                f"{flag} {self.path} exists and is not a port file written by armtool",
                hint="name a new file (it is created, and removed at exit)",
            )
        check_output_path(self.path, flag)

    def write(self, device: str) -> None:
        self.content = device + "\n"
        if os.path.lexists(self.path) and not self.looks_like_ours(self.path):  # appeared since claim()
            raise ArmtoolError(f"{self.path} appeared while starting and is not a port file", hint="name a new file")
        write_atomic(self.path, self.content)
        self.written = True

    def remove(self) -> None:
        """Unlink the file only if it is still the regular file with our content."""
        if not self.written:
            return
        try:
            st = os.lstat(self.path)
            if stat.S_ISREG(st.st_mode) and self.path.read_text(encoding="ascii") == self.content:
                os.unlink(self.path)
        except (OSError, UnicodeDecodeError):
            pass
        self.written = False


# --------------------------------------------------------------------------------------------
# keeping the results of a long run


def rescue_write(path: Path | str | None, text: str, stem: str = "armtool") -> Path:
    """Save `text` when the planned write failed: `PATH.partial`, else a new file in the
    temporary directory. Returns where it went; ArmtoolError only if both fail."""
    tried: list[str] = []
    if path is not None and str(path) != "-" and (not os.path.exists(path) or os.path.isfile(path)):
        partial = Path(path).with_name(Path(path).name + ".partial")
        try:
            write_atomic(partial, text)
            return partial
        except ArmtoolError as exc:
            tried.append(f"{partial}: {exc.what}")
    try:
        fd, name = tempfile.mkstemp(prefix=f"{stem}-", suffix=".partial")
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        return Path(name)
    except OSError as exc:
        tried.append(f"{tempfile.gettempdir()}: {exc.strerror or exc}")
    raise ArmtoolError("could not save the results anywhere: " + "; ".join(tried))


class NotRegularFile(OSError):
    """A FIFO, socket or device where a file was expected: reading it could block or never end."""


def read_regular(path: Path | str, limit: int | None = None) -> bytes:
    """The bytes of a regular file (its first `limit` bytes if given). Anything else raises
    NotRegularFile without reading: opened non-blocking and checked with fstat, so a FIFO named
    `package.xml` or a symlink to /dev/zero neither blocks nor fills memory."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise NotRegularFile(0, "not a regular file (a FIFO, socket or device)", str(path))
        with os.fdopen(fd, "rb", closefd=False) as handle:
            return handle.read() if limit is None else handle.read(limit)
    finally:
        os.close(fd)


MAX_TEXT_BYTES = 256 * 1024 * 1024


def read_text(path: Path | str, what: str, limit: int = MAX_TEXT_BYTES, keep_bom: bool = False) -> str:
    """A regular UTF-8 file's text, or an ArmtoolError naming `what` and the file. A FIFO or device
    is refused without blocking (read_regular); a file over `limit` bytes is refused. Line endings
    stay as they are; `keep_bom` keeps a byte-order mark for text that is written back whole."""
    source = str(path)
    try:
        data = read_regular(path, limit + 1)
    except FileNotFoundError:
        raise ArmtoolError(f"{what} not found", source, "check the path") from None
    except NotRegularFile:
        raise ArmtoolError(f"{what} is not a regular file (a FIFO, socket or device)", source, "pass a file") from None
    except OSError as exc:
        raise ArmtoolError(f"cannot read {what}: {exc.strerror or exc}", source) from None
    if len(data) > limit:
        raise ArmtoolError(f"{what} is larger than {limit / (1024 * 1024):g} MB", source) from None
    try:
        return data.decode("utf-8" if keep_bom else "utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ArmtoolError(f"{what} is not UTF-8 text (byte {exc.start})", source, "save it as UTF-8") from None


def read_yaml(path: Path | str, what: str = "") -> object:
    """A YAML file's content, or an ArmtoolError that names the file and line and what it is."""
    import yaml

    from armtool.yamlload import AliasBomb, safe_load

    path = Path(path)
    label = f"{what} " if what else ""
    try:
        text = read_regular(path).decode("utf-8-sig")  # a FIFO or device is refused, not waited on
    except FileNotFoundError:
        raise ArmtoolError(f"{label}file not found", str(path), "check the path") from None
    except OSError as exc:
        raise ArmtoolError(f"cannot read {label}file: {exc.strerror or exc}", str(path)) from None
    except UnicodeDecodeError:
        raise ArmtoolError(f"{label}file is not UTF-8 text", str(path), "save it as UTF-8") from None
    try:
        return safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark is not None else str(path)
        problem = getattr(exc, "problem", None) or exc
        if isinstance(exc, AliasBomb):
            raise ArmtoolError(
                f"{label}file refused: {problem}", where, "write the values out, without aliases"
            ) from None
        raise ArmtoolError(f"{label}file is not valid YAML: {problem}", where) from None
    except RecursionError:
        raise ArmtoolError(f"{label}file is nested too deeply", str(path), "flatten it") from None
