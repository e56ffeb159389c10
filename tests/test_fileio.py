"""write_atomic: whole files, kept permissions, devices written in place and never replaced."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.fileio import write_atomic


def test_new_file_and_no_temporary_left(tmp_path: Path) -> None:
    target = tmp_path / "out.yaml"
    write_atomic(target, "a: 1\n")
    assert target.read_text() == "a: 1\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.yaml"]
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~_umask()


def test_existing_file_keeps_its_mode(tmp_path: Path) -> None:
    target = tmp_path / "robot.urdf"
    target.write_text("old")
    target.chmod(0o640)
    write_atomic(target, b"new")
    assert target.read_bytes() == b"new" and stat.S_IMODE(target.stat().st_mode) == 0o640


def test_device_is_written_in_place_not_replaced() -> None:
    write_atomic("/dev/null", "discarded")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_fifo_is_written_in_place(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        write_atomic(fifo, "hello")
        assert os.read(reader, 100) == b"hello"
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(fifo.stat().st_mode)


def test_failed_write_leaves_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "keep.txt"
    target.write_text("old")

    def boom(src: str, dst: str) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(ArmtoolError, match="disk full"):  # an OSError never escapes fileio
        write_atomic(target, "new")
    assert target.read_text() == "old" and [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_symlink_is_followed_and_kept(tmp_path: Path) -> None:
    real = tmp_path / "real.urdf"
    real.write_text("old")
    link = tmp_path / "robot.urdf"
    link.symlink_to(real)
    write_atomic(link, "new")
    assert link.is_symlink() and real.read_text() == "new"


def test_read_yaml_errors_name_the_file_and_line(tmp_path: Path) -> None:
    from armtool.errors import ArmtoolError
    from armtool.fileio import read_yaml

    bad = tmp_path / "arm.yaml"
    bad.write_text("joints:\n  - {id: 1\n  - x\n")
    with pytest.raises(ArmtoolError) as info:
        read_yaml(bad, "arm")
    assert "arm file is not valid YAML" in info.value.what and str(bad) + ":" in (info.value.where or "")
    with pytest.raises(ArmtoolError, match="file not found"):
        read_yaml(tmp_path / "missing.yaml")
    (tmp_path / "latin1.yaml").write_bytes("a: caf\xe9\n".encode("latin-1"))
    with pytest.raises(ArmtoolError, match="not UTF-8"):
        read_yaml(tmp_path / "latin1.yaml")
    good = tmp_path / "ok.yaml"
    good.write_text("a: 1\n")
    assert read_yaml(good) == {"a": 1}
