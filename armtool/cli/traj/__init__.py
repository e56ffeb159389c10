"""`armtool traj`: Cartesian paths through IK, time-optimal timing, re-timing, thinning, joining,
a trajectory checker and a plot. One module per group of subcommands, each doing arguments in,
`armtool.traj` core calls, files out; exit 0 / 1 / 2. Shared options live in `common.py`."""

from __future__ import annotations

import typer

from armtool.cli.traj import cartesian, check, edit
from armtool.cli.traj.common import FORMATS_HELP

HELP = "Cartesian lines and circles through IK, time-optimal timing, retime/thin/join, and a trajectory checker."

app = typer.Typer(
    name="traj",
    help=HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)
COMMANDS = (  # name, function, help
    (
        "cartesian",
        cartesian.cartesian,
        "Follow a straight line, a circle/arc, or a list of poses with the tool; write the joint path.",
    ),
    (
        "time",
        edit.time_cmd,
        "Time a joint path time-optimally (TOPP-RA), rest to rest, within velocity and acceleration limits; "
        "with a jerk limit, jerk-limited by smoothing.\n\n" + FORMATS_HELP,
    ),
    (
        "retime",
        edit.retime_cmd,
        "Scale a trajectory's speed exactly: time × 1/S, velocity × S, acceleration × S² "
        "(the lecture's scale_trajectory_speed).",
    ),
    (
        "thin",
        edit.thin_cmd,
        "Drop every K-th point (first and last kept; the lecture: 20 points -> 16 with --every 4), "
        "or points within a tolerance; re-time with --urdf.",
    ),
    (
        "join",
        edit.join_cmd,
        "Join trajectories end to start (each start must meet the previous end) and re-time the whole with --urdf.",
    ),
    (
        "check",
        check.check_cmd,
        "Check a trajectory against a URDF's limits: time, positions, velocity, acceleration, jerk, jumps, "
        "joints, rest. Exit 1 on findings.",
    ),
    (
        "plot",
        check.plot_cmd,
        "Draw positions, velocities and accelerations per joint with their limits (PNG, SVG or PDF); "
        "with --tip also the tool path.",
    ),
)
for name, function, text in COMMANDS:
    app.command(name, help=text)(function)
