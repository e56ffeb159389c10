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


# ---------------------------------------------------------------- issue 14: one write path


def test_os_errors_become_messages_naming_the_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    with pytest.raises(ArmtoolError, match="cannot write") as info:
        write_atomic(tmp_path / "missing" / "out.txt", "x")
    assert "does not exist" in (info.value.hint or "")
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(ArmtoolError, match="cannot write"):
        write_atomic(blocker / "out.txt", "x")
    with pytest.raises(ArmtoolError, match="is a directory"):
        write_atomic(tmp_path, "x")

    def denied(src: str, dst: str) -> None:
        raise PermissionError(13, "Permission denied")

    target = tmp_path / "ro.urdf"
    target.write_text("old")
    monkeypatch.setattr(os, "replace", denied)
    with pytest.raises(ArmtoolError, match="Permission denied") as info:
        write_atomic(target, "new")
    assert "permissions" in (info.value.hint or "") and target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_check_output_paths(tmp_path: Path) -> None:
    from armtool.fileio import check_output_paths

    source = tmp_path / "in.csv"
    source.write_text("data")
    link = tmp_path / "link.csv"
    link.symlink_to(source)
    check_output_paths({"-o": tmp_path / "out.json", "--plot": None, "--log": "-"}, inputs=[source, None])
    with pytest.raises(ArmtoolError, match="is also an input"):
        check_output_paths({"-o": link}, inputs=[source])
    with pytest.raises(ArmtoolError, match="is a directory"):
        check_output_paths({"-o": tmp_path})
    with pytest.raises(ArmtoolError, match="does not exist"):
        check_output_paths({"-o": tmp_path / "nope" / "x"})
    with pytest.raises(ArmtoolError, match="is not a directory"):
        check_output_paths({"-o": source / "x"})
    with pytest.raises(ArmtoolError, match="name the same file"):
        check_output_paths({"-o": tmp_path / "a", "--urdf-out": tmp_path / "a"})
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    check_output_paths({"-o": fifo, "--log": fifo})  # a pipe is written in place, by anyone


def test_check_output_refuses_an_unwritable_directory(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from armtool.fileio import check_output_path

    real_access = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: False if str(p) == str(tmp_path) else real_access(p, mode))
    with pytest.raises(ArmtoolError, match="is not writable"):
        check_output_path(tmp_path / "out.yaml", "-o")


def test_backups_are_numbered_never_overwritten(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import armtool.fileio as fileio

    target = tmp_path / "arm.urdf"
    target.write_text("v0")
    for k in range(3):
        fileio.write_with_backup(target, f"v{k + 1}", target.read_text())
    assert [(tmp_path / n).read_text() for n in ("arm.urdf.bak", "arm.urdf.bak.1", "arm.urdf.bak.2")] == [
        "v0",
        "v1",
        "v2",
    ]
    monkeypatch.setattr(fileio, "MAX_BACKUPS", 3)
    with pytest.raises(ArmtoolError, match="already has 3 backups"):
        fileio.backup_path(target)


def test_rescue_write_falls_back_to_the_temporary_directory(tmp_path: Path) -> None:
    from armtool.fileio import rescue_write

    beside = rescue_write(tmp_path / "m.csv", "readings")
    assert beside == tmp_path / "m.csv.partial" and beside.read_text() == "readings"
    elsewhere = rescue_write(tmp_path / "missing" / "m.csv", "readings", "armtool-test")
    try:
        assert elsewhere.read_text() == "readings" and elsewhere.name.startswith("armtool-test-")
    finally:
        elsewhere.unlink()


def test_port_file_claims_only_free_or_stale_paths(tmp_path: Path) -> None:
    from armtool.fileio import PortFile

    mine = tmp_path / "port"
    mine.write_text("/dev/pts/3\n")
    assert PortFile.looks_like_ours(mine)
    notes = tmp_path / "notes.txt"
    notes.write_text("/dev/pts/3\nand more\n")
    assert not PortFile.looks_like_ours(notes)
    with pytest.raises(ArmtoolError, match="not a port file"):
        PortFile(notes).claim()
    assert notes.read_text() == "/dev/pts/3\nand more\n"


def test_atomic_directory_appears_whole_with_normal_permissions(tmp_path: Path) -> None:
    from armtool.fileio import atomic_directory

    out = tmp_path / "dataset"
    with atomic_directory(out) as d:
        (d / "a.txt").write_text("a")
        assert not out.exists()  # nothing visible until the body is done
    assert (out / "a.txt").read_text() == "a"
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o777 & ~mask  # not mkdtemp's private 0700


def test_atomic_directory_leaves_nothing_on_error(tmp_path: Path) -> None:
    from armtool.fileio import atomic_directory

    out = tmp_path / "dataset"
    with pytest.raises(RuntimeError):
        with atomic_directory(out) as d:
            (d / "a.txt").write_text("a")
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_read_yaml_refuses_a_fifo_without_waiting(tmp_path: Path) -> None:
    from armtool.fileio import read_yaml

    fifo = tmp_path / "limits.yaml"
    os.mkfifo(fifo)  # nobody writes to it: a plain read would block forever
    with pytest.raises(ArmtoolError, match="not a regular file"):
        read_yaml(fifo, "limits")


@pytest.mark.parametrize("reader", ["lerobot", "measurements", "table"])
def test_servo_file_readers_refuse_a_fifo_without_waiting(tmp_path: Path, reader: str) -> None:
    from armtool.servo.lerobot import read_calibration
    from armtool.servo.lut.csv_format import read_measurements
    from armtool.servo.lut.table import read_table

    fifo = tmp_path / "input"
    os.mkfifo(fifo)
    read = {"lerobot": read_calibration, "measurements": read_measurements, "table": read_table}[reader]
    with pytest.raises(ArmtoolError, match="not a regular file"):
        read(fifo)
