"""read_regular: files armtool looks into are read only if they are regular files."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from armtool.fileio import NotRegularFile, read_regular


def test_reads_a_regular_file_whole_or_its_head(tmp_path: Path) -> None:
    path = tmp_path / "package.xml"
    path.write_bytes(b"<package><name>arm</name></package>")
    assert read_regular(path) == path.read_bytes()
    assert read_regular(path, 9) == b"<package>"
    link = tmp_path / "link.xml"
    link.symlink_to(path)
    assert read_regular(link, 9) == b"<package>"  # a symlink to a regular file is fine


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "package.xml")  # opening it blocking would wait for a writer forever
    with pytest.raises(NotRegularFile):
        read_regular(tmp_path / "package.xml")


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_a_device_is_refused_without_reading(tmp_path: Path) -> None:
    link = tmp_path / "package.xml"
    link.symlink_to("/dev/zero")  # read_bytes() would never end
    with pytest.raises(NotRegularFile):
        read_regular(link)


def test_a_missing_file_is_an_oserror(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        read_regular(tmp_path / "nothing.xml")
