"""Angle references: the encoder's ASCII protocol, manual entry, readings from a file."""

from __future__ import annotations

import os
import sys
import threading
import tty
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.servo.reference import CsvReference, EncoderReference, ManualReference, open_reference, parse_angle_line


def test_parse_angle_line() -> None:
    assert parse_angle_line("123.4567\r\n", "enc") == pytest.approx(123.4567)
    assert parse_angle_line("-5\n", "enc") == -5.0
    with pytest.raises(ArmtoolError, match="reported an error: bad request"):
        parse_angle_line("E bad request\n", "enc")
    with pytest.raises(ArmtoolError, match="not a number of degrees"):
        parse_angle_line("hello\n", "enc")
    with pytest.raises(ArmtoolError, match="empty line"):
        parse_angle_line("\n", "enc")
    with pytest.raises(ArmtoolError, match="'nan'"):
        parse_angle_line("nan\n", "enc")


@pytest.mark.skipif(sys.platform == "win32", reason="needs a pty")
def test_encoder_talks_the_ascii_protocol_on_a_serial_port() -> None:
    """A fake microcontroller on a pty: answers `A <id>` with a fixed angle per id, once with garbage."""
    master, slave = os.openpty()
    tty.setraw(slave)
    seen: list[bytes] = []

    def device() -> None:
        buf = b""
        while len(seen) < 3:
            buf += os.read(master, 64)
            while b"\n" in buf:
                line, buf = buf.split(b"\n", 1)
                seen.append(line)
                sid = int(line.split()[1])
                os.write(master, b"E no such id\n" if sid == 9 else f"{100 + sid}.25\n".encode())

    thread = threading.Thread(target=device, daemon=True)
    thread.start()
    enc = open_reference(f"encoder:{os.ttyname(slave)}")
    assert isinstance(enc, EncoderReference) and enc.spec == f"encoder:{os.ttyname(slave)}"
    try:
        assert enc.read_deg(1, 500) == pytest.approx(101.25)
        assert enc.read_deg(7, 500) == pytest.approx(107.25)
        with pytest.raises(ArmtoolError, match="no such id"):
            enc.read_deg(9, 500)
    finally:
        enc.close()
        thread.join(timeout=2)
        os.close(master)
        os.close(slave)
    assert seen == [b"A 1", b"A 7", b"A 9"]


@pytest.mark.skipif(sys.platform == "win32", reason="needs a pty")
def test_silent_encoder_times_out_with_a_hint() -> None:
    master, slave = os.openpty()
    tty.setraw(slave)
    try:
        enc = EncoderReference(os.ttyname(slave), timeout_s=0.05, tries=2)
        with pytest.raises(ArmtoolError, match="did not answer 'A 3' \\(2 tries\\)") as info:
            enc.read_deg(3, 0)
        assert "115200" in str(info.value.hint)
        enc.close()
    finally:
        os.close(master)
        os.close(slave)


def test_bad_specs() -> None:
    with pytest.raises(ArmtoolError, match="cannot open the encoder port /nonexistent/tty"):
        open_reference("encoder:/nonexistent/tty")
    with pytest.raises(ArmtoolError, match="without a port"):
        open_reference("encoder:")
    with pytest.raises(ArmtoolError, match="baud rate 'fast'"):
        open_reference("encoder:/dev/null@fast")
    for bad in ("0", "-1", "", "5000000"):  # baud 0 is "hang up" on Linux: the port opens, nothing arrives
        with pytest.raises(ArmtoolError, match="encoder baud rate"):
            open_reference(f"encoder:/dev/null@{bad}")
    with pytest.raises(ArmtoolError, match="without a port"):
        open_reference("encoder:@115200")
    with pytest.raises(ArmtoolError, match="unknown reference 'laser'"):
        open_reference("laser")


def test_manual_asks_until_it_gets_a_number() -> None:
    answers = iter(["", "abc", "inf", " 45.5 "])
    prompts: list[str] = []

    def ask(text: str) -> str:
        prompts.append(text)
        return next(answers)

    ref = open_reference("manual", ask=ask)
    assert isinstance(ref, ManualReference) and ref.read_deg(2, 300) == 45.5
    assert len(prompts) == 4 and "servo 2 at command 300" in prompts[0]
    with pytest.raises(KeyboardInterrupt):
        ManualReference(lambda _: "q").read_deg(1, 1)


def test_csv_reference(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("# from a protractor\ncommand_ticks,reference_deg\n300,88.5\n100,30.1\n300,88.7\n")
    ref = CsvReference.load(path)
    assert ref.commands == [100, 300] and ref.spec == "csv:r.csv"
    assert [ref.read_deg(1, 300), ref.read_deg(1, 300)] == [88.5, 88.7]
    with pytest.raises(ArmtoolError, match="no reading for command 300 left"):
        ref.read_deg(1, 300)
    bad = tmp_path / "bad.csv"
    bad.write_text("command,angle\n1,2\n")
    with pytest.raises(ArmtoolError, match="needs columns command_ticks and reference_deg"):
        CsvReference.load(bad)
    bad.write_text("command_ticks,reference_deg\n1,nan\n")
    with pytest.raises(ArmtoolError) as info:
        CsvReference.load(bad)
    assert info.value.where == f"{bad}:2"
