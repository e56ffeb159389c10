"""Angle references for `servo-lut measure` and `check`: what the servo really did, measured outside it.

Why outside: a potentiometer servo reports and regulates its own (non-linear) reading, so
Present Position agrees with the goal while the horn is off by degrees; only an independent
instrument sees that. References, by `--reference` spec:

* `encoder:PORT[@BAUD]`: an encoder on the output shaft behind a microcontroller speaking one
  ASCII line each way: the tool sends `A <id>\\n`, the device answers `<degrees>\\n` (servo-frame
  degrees, a decimal number; a line starting with `E` is an error message). 115200 baud.
* `manual`: a person reads a protractor and types the angle.
* `csv:FILE`: readings taken by other means, keyed by command: `command_ticks,reference_deg`.
* `camera:DEVICE`: an AprilTag on the horn, seen by a camera (needs the calibrate work's detector).
"""

from __future__ import annotations

import csv
import io
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Protocol

from armtool.errors import ArmtoolError

ENCODER_BAUD = 115200


class Reference(Protocol):
    """One angle source. `read_deg` returns the servo's true angle in servo-frame degrees."""

    spec: str

    def read_deg(self, sid: int, command_ticks: int) -> float: ...

    def close(self) -> None: ...


def parse_angle_line(line: str, where: str) -> float:
    """One answer line of the encoder protocol: `<degrees>` or `E <message>`."""
    text = line.strip()
    if not text:
        raise ArmtoolError("the encoder sent an empty line", where, hint="check its baud rate and that it answers 'A <id>'")
    if text[0] in "Ee" and not text[1:2].isdigit():
        raise ArmtoolError(f"the encoder reported an error: {text[1:].strip() or text}", where)
    try:
        value = float(text)
    except ValueError:
        raise ArmtoolError(f"the encoder sent {text!r}, not a number of degrees", where,
                           hint="the device must answer 'A <id>\\n' with '<degrees>\\n'") from None
    if not math.isfinite(value):
        raise ArmtoolError(f"the encoder sent {text!r}", where)
    return value


class EncoderReference:
    """An external encoder on a serial port (ASCII: `A <id>\\n` -> `<degrees>\\n`)."""

    def __init__(self, port: str, baud: int = ENCODER_BAUD, timeout_s: float = 0.5, tries: int = 3) -> None:
        import serial

        self.spec = f"encoder:{port}"
        self.port = port
        self.tries = tries
        try:
            self.ser = serial.Serial(port, baud, timeout=timeout_s)
        except (serial.SerialException, OSError, ValueError) as exc:
            raise ArmtoolError(f"cannot open the encoder port {port}: {exc}",
                               hint="check --reference encoder:PORT (e.g. encoder:/dev/ttyACM1)") from None
        self.ser.reset_input_buffer()

    def read_deg(self, sid: int, command_ticks: int) -> float:
        where = f"encoder {self.port}"
        for attempt in range(self.tries):
            self.ser.reset_input_buffer()
            self.ser.write(f"A {sid}\n".encode("ascii"))
            self.ser.flush()
            line = self.ser.readline().decode("ascii", "replace")
            if line.endswith("\n"):
                return parse_angle_line(line, where)
        raise ArmtoolError(f"the encoder did not answer 'A {sid}' ({self.tries} tries)", where,
                           hint="check the port, its baud rate (115200) and that the sketch answers '<degrees>\\n'")

    def close(self) -> None:
        try:
            self.ser.close()
        except Exception:  # noqa: BLE001 - closing must not hide the real error
            pass


@dataclass
class ManualReference:
    """A person reads the angle (protractor, laser on a scale) and types it."""

    ask: Callable[[str], str]
    spec: str = "manual"

    def read_deg(self, sid: int, command_ticks: int) -> float:
        while True:
            text = self.ask(f"servo {sid} at command {command_ticks}: angle in degrees (q to stop)").strip()
            if text.lower() in ("q", "quit"):
                raise KeyboardInterrupt
            try:
                value = float(text)
            except ValueError:
                continue
            if math.isfinite(value):
                return value

    def close(self) -> None:
        pass


@dataclass
class CsvReference:
    """Readings taken by other means: for each command, the angle(s) measured there, used in order."""

    path: Path
    readings: dict[int, list[float]] = field(default_factory=dict)
    spec: str = ""

    @classmethod
    def load(cls, path: Path) -> CsvReference:
        try:
            text = path.read_text(encoding="utf-8-sig")
        except OSError as exc:
            raise ArmtoolError(f"cannot read the reference file {path}: {exc.strerror or exc}") from None
        lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
        reader = csv.DictReader(io.StringIO("\n".join(lines)))
        if not {"command_ticks", "reference_deg"} <= {f.strip() for f in reader.fieldnames or []}:
            raise ArmtoolError("the reference CSV needs columns command_ticks and reference_deg", str(path),
                               hint=f"found: {', '.join(reader.fieldnames or []) or 'nothing'}")
        readings: dict[int, list[float]] = {}
        for k, row in enumerate(reader, start=2):
            row = {key.strip(): value for key, value in row.items() if key is not None}
            try:
                c, a = int(float(row["command_ticks"])), float(row["reference_deg"])
            except (TypeError, ValueError):
                raise ArmtoolError("command_ticks/reference_deg is not a number", f"{path}: row {k}") from None
            if not math.isfinite(a):
                raise ArmtoolError(f"reference_deg is {row['reference_deg'].strip()}", f"{path}: row {k}")
            readings.setdefault(c, []).append(a)
        if not readings:
            raise ArmtoolError("the reference CSV has no rows", str(path))
        return cls(path, readings, f"csv:{path.name}")

    @property
    def commands(self) -> list[int]:
        return sorted(self.readings)

    def read_deg(self, sid: int, command_ticks: int) -> float:
        values = self.readings.get(command_ticks)
        if not values:
            raise ArmtoolError(f"no reading for command {command_ticks} left in the reference file", str(self.path))
        return values.pop(0)

    def close(self) -> None:
        pass


class CameraReference:
    """An AprilTag on the horn: the tag's in-plane rotation in the image, plus an offset set at a known angle."""

    def __init__(self, device: str, detect: Callable[..., object]) -> None:
        self.spec = f"camera:{device}"
        self.detect = detect
        import cv2

        self.cap = cv2.VideoCapture(int(device) if device.isdigit() else device)
        if not self.cap.isOpened():
            raise ArmtoolError(f"cannot open camera {device}", hint="pass camera:0 or a device path such as /dev/video0")
        self.offset_deg = 0.0

    def _angle(self) -> float:
        ok, frame = self.cap.read()
        if not ok:
            raise ArmtoolError(f"no image from {self.spec}")
        found = self.detect(frame)
        tags = list(found) if isinstance(found, (list, tuple)) else []
        if not tags:
            raise ArmtoolError(f"no AprilTag seen by {self.spec}", hint="put a tag on the horn, facing the camera")
        corners = getattr(tags[0], "corners", None)
        if corners is None:
            raise ArmtoolError("the AprilTag detector returned tags without corners")
        (x0, y0), (x1, y1) = corners[0], corners[1]
        return math.degrees(math.atan2(y1 - y0, x1 - x0))

    def read_deg(self, sid: int, command_ticks: int) -> float:
        time.sleep(0.05)
        return self._angle() + self.offset_deg

    def close(self) -> None:
        self.cap.release()


def _apriltag_detector() -> Callable[..., object] | None:
    """The calibrate work's tag detector, if it has one yet."""
    try:
        import importlib

        module = importlib.import_module("armtool.calib.apriltag")
    except ImportError:
        return None
    for name in ("detect_tags", "detect"):
        fn = getattr(module, name, None)
        if callable(fn):
            return fn  # type: ignore[no-any-return]
    return None


def open_reference(spec: str, ask: Callable[[str], str] | None = None) -> Reference:
    """The reference named by `spec` (encoder:PORT[@BAUD], manual, csv:FILE, camera:DEVICE)."""
    kind, _, arg = spec.partition(":")
    kind = kind.strip().lower()
    if kind == "encoder":
        if not arg:
            raise ArmtoolError("encoder reference without a port", hint="--reference encoder:/dev/ttyACM1")
        port, _, baud = arg.partition("@")
        try:
            rate = int(baud) if baud else ENCODER_BAUD
        except ValueError:
            raise ArmtoolError(f"encoder baud rate {baud!r} is not a number", hint="encoder:/dev/ttyACM1@115200") from None
        return EncoderReference(port, rate)
    if kind == "manual":
        if ask is None:
            raise ArmtoolError("the manual reference needs someone at the keyboard")
        return ManualReference(ask)
    if kind == "csv":
        if not arg:
            raise ArmtoolError("csv reference without a file", hint="--reference csv:readings.csv")
        return CsvReference.load(Path(arg))
    if kind == "camera":
        detect = _apriltag_detector()
        if detect is None:
            raise ArmtoolError("the camera reference is not available yet: armtool.calib.apriltag has no tag detector",
                               hint="use --reference encoder:PORT, manual or csv:FILE for now")
        return CameraReference(arg or "0", detect)
    raise ArmtoolError(f"unknown reference '{spec}'", hint="encoder:PORT, manual, csv:FILE or camera:DEVICE")
