"""Writing user files: atomically when they are regular files, never by replacing a device.

A write goes to a temporary file beside the target, then `os.replace` puts it in place, so a
reader (or a crash) never sees half a file; an existing file keeps its permission bits. A target
that exists but is not a regular file (`/dev/null`, `/dev/stdout`, a FIFO) is written in place:
replacing it would turn the device into a plain file (as root, for every program on the machine).
A symlink is followed: the file it points to is replaced and the link stays.
"""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path


def write_atomic(path: Path | str, data: str | bytes) -> None:
    # Through a symlink, the file it points to is what the user means: replace that, keep the link.
    path = Path(os.path.realpath(path)) if os.path.islink(path) else Path(path)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    try:
        st = os.stat(path)
    except FileNotFoundError:
        st = None
    try:
        if st is not None and not stat.S_ISREG(st.st_mode):
            with open(path, "wb") as handle:
                handle.write(payload)
            return
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        from armtool.errors import ArmtoolError

        raise ArmtoolError(f"cannot write: {exc.strerror}", str(path), "check that the directory exists and is writable") from None
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
        os.chmod(tmp, stat.S_IMODE(st.st_mode) if st is not None else 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def read_yaml(path: Path | str, what: str = "") -> object:
    """A YAML file's content, or an ArmtoolError that names the file and line and what it is."""
    import yaml

    from armtool.errors import ArmtoolError

    path = Path(path)
    label = f"{what} " if what else ""
    try:
        text = path.read_bytes().decode("utf-8-sig")
    except FileNotFoundError:
        raise ArmtoolError(f"{label}file not found", str(path), "check the path") from None
    except OSError as exc:
        raise ArmtoolError(f"cannot read {label}file: {exc.strerror or exc}", str(path)) from None
    except UnicodeDecodeError:
        raise ArmtoolError(f"{label}file is not UTF-8 text", str(path), "save it as UTF-8") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark is not None else str(path)
        raise ArmtoolError(f"{label}file is not valid YAML: {getattr(exc, 'problem', None) or exc}", where) from None
