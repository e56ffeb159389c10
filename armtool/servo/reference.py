"""Angle references for `servo-lut measure` and `check`: what the servo really did, measured outside it.

Why outside: a potentiometer servo reports and regulates its own (non-linear) reading, so
Present Position agrees with the goal while the horn is off by degrees; only an independent
instrument sees that. References, by `--reference` spec:

* `encoder:PORT[@BAUD]`: an encoder on the output shaft behind a microcontroller speaking one
  ASCII line each way: the tool sends `A <id>\\n`, the device answers `<degrees>\\n` (servo-frame
  degrees, a decimal number; a line starting with `E` is an error message). 115200 baud.
* `manual`: a person reads a protractor and types the angle.
* `csv:FILE`: readings taken by other means, keyed by command: `command_ticks,reference_deg`.
* `camera:DEVICE[,tag=ID][,family=NAME][,intrinsics=FILE]`: an AprilTag flat on the horn, seen by
  a camera (the calibrate work's detector, `armtool.calib.targets.apriltag.detect_tag`), aligned to the
  servo's frame by two moves before measuring.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

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
        raise ArmtoolError(
            "the encoder sent an empty line", where, hint="check its baud rate and that it answers 'A <id>'"
        )
    if text[0] in "Ee" and not text[1:2].isdigit():
        raise ArmtoolError(f"the encoder reported an error: {text[1:].strip() or text}", where)
    try:
        value = float(text)
    except ValueError:
        raise ArmtoolError(
            f"the encoder sent {text!r}, not a number of degrees",
            where,
            hint="the device must answer 'A <id>\\n' with '<degrees>\\n'",
        ) from None
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
            raise ArmtoolError(
                f"cannot open the encoder port {port}: {exc}",
                hint="check --reference encoder:PORT (e.g. encoder:/dev/ttyACM1)",
            ) from None
        self.ser.reset_input_buffer()

    def read_deg(self, sid: int, command_ticks: int) -> float:
        where = f"encoder {self.port}"
        for _attempt in range(self.tries):
            self.ser.reset_input_buffer()
            self.ser.write(f"A {sid}\n".encode("ascii"))
            self.ser.flush()
            line = self.ser.readline().decode("ascii", "replace")
            if line.endswith("\n"):
                return parse_angle_line(line, where)
        raise ArmtoolError(
            f"the encoder did not answer 'A {sid}' ({self.tries} tries)",
            where,
            hint="check the port, its baud rate (115200) and that the sketch answers '<degrees>\\n'",
        )

    def close(self) -> None:
        try:
            self.ser.close()
        except Exception:
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
        from armtool.csvrows import csv_rows
        from armtool.fileio import read_text

        text = read_text(path, "reference file")
        numbered = [
            (line, row)
            for line, row in csv_rows(text.splitlines(), str(path), 1, "reference CSV")
            if any(cell.strip() for cell in row) and not row[0].lstrip().startswith("#")
        ]
        header = [h.strip() for h in numbered[0][1]] if numbered else []
        if not {"command_ticks", "reference_deg"} <= set(header):
            raise ArmtoolError(
                "the reference CSV needs columns command_ticks and reference_deg",
                f"{path}:{numbered[0][0]}" if numbered else str(path),
                hint=f"found: {', '.join(header) or 'nothing'}",
            )
        tick_col, deg_col = header.index("command_ticks"), header.index("reference_deg")
        readings: dict[int, list[float]] = {}
        for line, row in numbered[1:]:
            where = f"{path}:{line}"
            try:
                c, a = int(float(row[tick_col])), float(row[deg_col])
            except (IndexError, ValueError):
                raise ArmtoolError("command_ticks/reference_deg is missing or not a number", where) from None
            if not math.isfinite(a):
                raise ArmtoolError(f"reference_deg is {row[deg_col].strip()}", where)
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
    """An AprilTag flat on the horn, seen by a camera: the tag's rotation about its own normal.

    With camera intrinsics the rotation comes from the tag's pose (solvePnP), so the camera may
    look at the horn at an angle; without them it is the tag's in-plane rotation in the image,
    which needs the camera to look along the servo axis. Either way the camera cannot know the
    servo's zero or which way it turns: `align()` sets both from two moves (`servo-lut measure`
    and `check` do this first, at the middle of the range).
    """

    def __init__(
        self,
        device: str,
        capture: Any = None,
        family: str = "tag36h11",
        tag_id: int = 0,
        camera: Any = None,
        size_m: float = 0.03,
        settle_frames: int = 3,
    ) -> None:
        from armtool.calib.targets.apriltag import detect_tag

        self.spec = f"camera:{device}"
        self.detect_tag = detect_tag
        self.family, self.tag_id, self.camera, self.size_m = family, tag_id, camera, size_m
        self.settle_frames = settle_frames
        if capture is None:
            import cv2

            capture = cv2.VideoCapture(int(device) if device.isdigit() else device)
            if not capture.isOpened():
                raise ArmtoolError(
                    f"cannot open camera {device}", hint="pass camera:0 or a device path such as /dev/video0"
                )
        self.cap = capture
        self.sign = 1.0
        self.offset_deg = 0.0
        self._last: float | None = None
        self._r0: Any = None

    def raw_deg(self) -> float:
        """The tag's rotation in the camera's own frame (arbitrary zero and sense), unwrapped."""
        import numpy as np

        frame: Any = None  # the capture's image (cv2 or a test's fake); the loop runs at least once
        for _ in range(max(1, self.settle_frames)):  # drop frames buffered while the servo moved
            ok, frame = self.cap.read()
            if not ok:
                raise ArmtoolError(f"no image from {self.spec}")
        tag = self.detect_tag(frame, self.family, self.tag_id, self.camera)
        if not tag.ok:
            raise ArmtoolError(f"{self.spec}: {tag.reason}", hint="put the tag flat on the horn, in view and in focus")
        corners = np.asarray(tag.corners_px, dtype=np.float64)
        if self.camera is not None:
            from armtool.calib.targets.apriltag import pnp_pose

            cMt, _rms, _ambiguous = pnp_pose(corners, self.size_m, self.camera)
            rot = cMt[:3, :3]
            if self._r0 is None:
                self._r0 = rot
            rel = self._r0.T @ rot
            angle = math.degrees(math.atan2(rel[1, 0], rel[0, 0]))
        else:
            top = (corners[1] - corners[0]) + (corners[2] - corners[3])  # TL->TR plus BL->BR, image y down
            angle = math.degrees(math.atan2(-top[1], top[0]))
        if self._last is not None:
            angle += 360.0 * round((self._last - angle) / 360.0)
        self._last = angle
        return angle

    def align(self, sign: float, offset_deg: float) -> None:
        self.sign, self.offset_deg = sign, offset_deg

    def read_deg(self, sid: int, command_ticks: int) -> float:
        return self.sign * self.raw_deg() + self.offset_deg

    def close(self) -> None:
        release = getattr(self.cap, "release", None)
        if release is not None:
            release()


def _apriltag_detector() -> Callable[..., object] | None:
    """The calibrate work's tag detector, if it has one."""
    try:
        import importlib

        module = importlib.import_module("armtool.calib.targets.apriltag")
    except ImportError:
        return None
    fn = getattr(module, "detect_tag", None)
    return fn if callable(fn) else None


def _camera_reference(arg: str) -> CameraReference:
    """camera:DEVICE[,tag=ID][,family=NAME][,intrinsics=FILE][,size=METRES]"""
    device, *options = [part.strip() for part in arg.split(",")]
    kw: dict[str, Any] = {}
    for option in options:
        key, sep, value = option.partition("=")
        try:
            if key == "tag" and sep:
                kw["tag_id"] = int(value)
            elif key == "family" and sep:
                kw["family"] = value
            elif key == "size" and sep:
                kw["size_m"] = float(value)
            elif key == "intrinsics" and sep:
                from armtool.calib.model.camera import load_intrinsics

                kw["camera"] = load_intrinsics(Path(value))
            else:
                raise ValueError
        except ValueError:
            raise ArmtoolError(
                f"camera option {option!r} not understood",
                hint="camera:DEVICE[,tag=ID][,family=tag36h11][,intrinsics=cam.yaml][,size=0.03]",
            ) from None
    return CameraReference(device or "0", **kw)


MAX_ENCODER_BAUD = 4_000_000  # above what a microcontroller's USB serial link runs at


def encoder_port_baud(arg: str) -> tuple[str, int]:
    """`PORT[@BAUD]` of `--reference encoder:PORT[@BAUD]`: the port and a baud rate in
    1..MAX_ENCODER_BAUD (115200 when none is given). Baud 0 is refused: on Linux it means "hang
    up", so the port opens and then nothing ever arrives."""
    port, at, baud = arg.partition("@")
    example = "--reference encoder:/dev/ttyACM1@115200"
    if not port.strip():
        raise ArmtoolError("encoder reference without a port", hint=example)
    if not at:
        return port, ENCODER_BAUD
    try:
        rate = int(baud.strip())
    except ValueError:
        raise ArmtoolError(f"encoder baud rate {baud!r} is not a whole number", hint=example) from None
    if not 1 <= rate <= MAX_ENCODER_BAUD:
        raise ArmtoolError(
            f"encoder baud rate {rate} is outside 1..{MAX_ENCODER_BAUD}",
            hint=f"{example} (the rate the encoder's sketch opens its serial port with)",
        )
    return port, rate


def open_reference(spec: str, ask: Callable[[str], str] | None = None) -> Reference:
    """The reference named by `spec` (encoder:PORT[@BAUD], manual, csv:FILE, camera:DEVICE)."""
    kind, _, arg = spec.partition(":")
    kind = kind.strip().lower()
    if kind == "encoder":
        return EncoderReference(*encoder_port_baud(arg))
    if kind == "manual":
        if ask is None:
            raise ArmtoolError("the manual reference needs someone at the keyboard")
        return ManualReference(ask)
    if kind == "csv":
        if not arg:
            raise ArmtoolError("csv reference without a file", hint="--reference csv:readings.csv")
        return CsvReference.load(Path(arg))
    if kind == "camera":
        if _apriltag_detector() is None:
            raise ArmtoolError(
                "the camera reference is not available yet: armtool.calib.targets.apriltag has no tag detector",
                hint="use --reference encoder:PORT, manual or csv:FILE for now",
            )
        return _camera_reference(arg)
    raise ArmtoolError(f"unknown reference '{spec}'", hint="encoder:PORT, manual, csv:FILE or camera:DEVICE")


def reference_file(spec: str) -> Path | None:
    """The file a `csv:FILE` reference reads (an input the outputs must not overwrite), else None."""
    kind, _, arg = spec.partition(":")
    return Path(arg) if kind.strip().lower() == "csv" and arg else None


def check_reference_spec(spec: str, bus_port: str, interactive: bool) -> None:
    """Before anything opens: the reference is not the servo bus, and a typed one has a typist."""
    import os

    kind, _, arg = spec.partition(":")
    kind = kind.strip().lower()
    if kind == "encoder":
        enc_port, _ = encoder_port_baud(arg)  # a bad port or baud is refused before anything opens
        if os.path.realpath(enc_port) == os.path.realpath(bus_port):
            raise ArmtoolError(
                f"--reference encoder:{enc_port} is the servo bus (--port {bus_port})",
                hint="the encoder is a separate device on its own port, e.g. encoder:/dev/ttyACM1",
            )
    if kind == "manual" and not interactive:
        raise ArmtoolError(
            "--reference manual asks you to type each angle, but stdin is not a terminal",
            hint="run it in a terminal, or use encoder:PORT or csv:FILE",
        )
