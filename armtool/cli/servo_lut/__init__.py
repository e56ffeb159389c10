"""`armtool servo-lut`: measure a servo's real angle per command, fit, export and check a
compensation table (wanted angle -> command), and apply it to angles or trajectories. One module
per group of subcommands: `files` (fit, export, apply: no servo) and `move` (measure, check: they
energise one); what both need lives in `common.py`."""

from __future__ import annotations

import typer

from armtool.cli.servo_lut import files, move
from armtool.cli.servo_lut.common import MEAS_FORMAT

HELP = "Build, export and check compensation tables for a servo's non-linear response."

app = typer.Typer(
    name="servo-lut",
    help=HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)
COMMANDS = (  # name, function, help
    ("fit", files.fit, "Fit the table (wanted angle -> command) from a measurement CSV.\n\n" + MEAS_FORMAT),
    ("export", files.export, "Write the table as a C header (uint16_t on a uniform angle grid), CSV, JSON or YAML."),
    ("apply", files.apply, "Turn wanted servo angles (a list, or a CSV column) into compensated commands."),
    (
        "measure",
        move.measure,
        "Step a servo through its range and log command, present position, reference angle, "
        "load, temperature and voltage to a measurement CSV. Energises the servo (asks first).",
    ),
    (
        "check",
        move.check,
        "Command random angles (not table knots) through the table and through the nominal linear "
        "map, measure both with the reference, print both errors; exit 1 above --max-err.",
    ),
)
for name, function, text in COMMANDS:
    app.command(name, help=text)(function)
