"""What the `servo-lut` commands share: the measurement CSV's description, and writing a result to
-o or stdout."""

from __future__ import annotations

from pathlib import Path

from armtool.console import stderr
from armtool.errors import ArmtoolError

MEAS_FORMAT = """Measurement CSV: '# key: value' metadata lines (servo_model: AX-12A, servo_id, reference), then a header
with units in the column names: command_ticks,present_ticks,reference_deg,load_pct,temperature_c,voltage_v,approach,repeat.
command_ticks and reference_deg (or reference_rad, servo frame: 0° at tick 0) are required."""


def write_output(text: str, output: Path | None, what: str, rescue: str | None = None) -> None:
    """To -o or stdout. With `rescue` (the servo has moved), a failed write keeps the text in a spare file."""
    from armtool.console import write_stdout
    from armtool.fileio import rescue_write
    from armtool.servo.lut.csv_format import write_atomic

    if output is None or str(output) == "-":
        write_stdout(text)
        return
    try:
        write_atomic(output, text)
    except ArmtoolError as exc:
        if rescue is None:
            raise
        saved = rescue_write(output, text, rescue)
        raise ArmtoolError(f"{exc.what}; the readings were saved to {saved}", exc.where, exc.hint) from None
    stderr().print(f"wrote {what} {output}")
