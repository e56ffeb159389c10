"""One validation layer for command-line options: every number finite and inside its documented
range, checked while the command line is parsed, with the flag named in the message.

Why at parse time: a bad value must fail before a file is read, a port opened or a servo
moved, and `nan` must never slip through a comparison (`nan < 0` and `nan > 0` are both
false, so `--margin nan` passed `margin < 0` and wrote a range with no margin).

Use as a typer callback (the flag is taken from the option itself):

    from armtool.cli import options as opt

    margin: float = typer.Option(2.0, "--margin", callback=opt.finite_float(0, 30, unit="degrees"))
    timeout: float = typer.Option(25.0, "--timeout-ms", callback=opt.positive_float(10_000, unit="ms"))
    duration: Optional[float] = typer.Option(None, "--duration", callback=opt.seconds())
    baud: int = typer.Option(1_000_000, "--baud", callback=opt.baud())
    seed: int = typer.Option(0, "--seed", callback=opt.seed())      # any integer; negatives mapped
    ids: Optional[str] = typer.Option(None, "--ids", callback=opt.id_list(0, 252))
    count: int = typer.Option(25, "--n", callback=opt.int_range(1, 10_000))

A callback returns the value unchanged (the seed callback maps a negative seed to a
non-negative one, see `seed_value`); None (an optional option left out) passes through. A bad
value raises `ArmtoolError("--margin must be a finite number of degrees >= 0 and <= 30, got nan")`,
which `armtool.cli.main` prints as `error: ...` with exit code 2, like every other input error.

The same checks without typer, for values that come from elsewhere (a config file, another
option): `check_float(value, flag, ...)`, `check_int(value, flag, lo, hi)`,
`parse_id_list(text, flag, lo, hi)`, `seed_value(value)`.

This module imports nothing heavy (no numpy): `armtool lint --help` stays fast.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

import typer

from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.moveit.package import MoveItPackage

T = TypeVar("T")

MAX_SECONDS = 7 * 24 * 3600.0  # the longest wait any option accepts: a week
MAX_BAUD = 20_000_000  # above every serial servo bus (Dynamixel X: 4.5 Mbps, P series: 10.5 Mbps)
MAX_IDS_TEXT = 10_000  # characters of an --ids list; the IDs themselves are bounded by lo..hi
SEED_MODULUS = 2**64  # negative seeds are taken modulo this (numpy's generators need seeds >= 0)


def _flag(param: typer.CallbackParam) -> str:
    """The option's long name (`--margin`), else its first name."""
    opts = list(getattr(param, "opts", []) or [])
    longs = [o for o in opts if o.startswith("--")]
    return str((longs or opts or [param.name])[0])


def _range_text(lo: float | None, hi: float | None, lo_open: bool, hi_open: bool) -> str:
    parts = []
    if lo is not None:
        parts.append(f"{'>' if lo_open else '≥'} {lo:g}")
    if hi is not None:
        parts.append(f"{'<' if hi_open else '≤'} {hi:g}")
    return " and ".join(parts)


def check_float(
    value: float | str,
    flag: str,
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
) -> float:
    """`value` (a number, or text such as "1.5") as a float if it is finite and inside the range,
    else an ArmtoolError naming `flag`: "--margin must be ≥ 0 and ≤ 90 degrees, got -1"."""
    bounds = _range_text(lo, hi, lo_open, hi_open)
    tail = f"{' ' + bounds if bounds else ''}{' ' + unit if unit else ''}"
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ArmtoolError(f"{flag} must be a number{tail}, got {value!r}") from None
    if not math.isfinite(number):
        raise ArmtoolError(f"{flag} must be a finite number{tail}, got {str(value).strip()}")
    ok = lo is None or (number > lo if lo_open else number >= lo)
    ok = ok and (hi is None or (number < hi if hi_open else number <= hi))
    if not ok:
        raise ArmtoolError(f"{flag} must be{tail}, got {number:g}")
    return number


def check_int(value: int, flag: str, lo: int | None = None, hi: int | None = None, unit: str = "") -> int:
    """`value` if it is a whole number inside lo..hi, else an ArmtoolError naming `flag`."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise ArmtoolError(f"{flag} must be a whole number, got {value!r}")
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        span = f"{lo if lo is not None else '...'}..{hi if hi is not None else '...'}"
        raise ArmtoolError(f"{flag} must be in {span}{f' {unit}' if unit else ''}, got {value}")
    return value


def seed_value(value: int) -> int:
    """Any integer as a seed numpy accepts: negatives are taken modulo 2**64 (so -1 works)."""
    return value % SEED_MODULUS if value < 0 else value


def parse_id_list(text: str, flag: str = "--ids", lo: int = 0, hi: int = 252) -> list[int]:
    """`1,2,3`, `1-6` or a mix, as distinct IDs in lo..hi. Every bound is checked before a
    range is expanded, so `1-100000000000` is refused at once instead of filling memory."""
    if len(text) > MAX_IDS_TEXT:
        raise ArmtoolError(f"{flag} is {len(text)} characters long", hint=f"IDs are {lo}..{hi}; use ranges such as 1-6")
    ids: list[int] = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        try:
            if "-" in part:
                a_text, b_text = part.split("-", 1)
                a, b = int(a_text), int(b_text)
            else:
                a = b = int(part)
        except ValueError:
            raise ArmtoolError(f"{flag}: '{part}' is not an ID or a range", hint="e.g. 1,2,3 or 1-6") from None
        if not (lo <= a <= hi and lo <= b <= hi):
            raise ArmtoolError(f"{flag}: '{part}' is outside {lo}..{hi}", hint=f"servo IDs on a bus are {lo}..{hi}")
        if b < a:
            raise ArmtoolError(f"{flag}: range '{part}' runs backwards", hint=f"write it {b}-{a}")
        ids.extend(range(a, b + 1))
        if len(ids) > hi - lo + 1:
            break  # more IDs than exist: a repeat, reported below
    if not ids:
        raise ArmtoolError(f"{flag} lists no ID", hint="e.g. 1,2,3 or 1-6")
    seen: set[int] = set()
    for i in ids:
        if i in seen:
            raise ArmtoolError(f"{flag}: ID {i} is listed twice")
        seen.add(i)
    return ids


# --------------------------------------------------------------------------------------------
# typer callbacks


def _optional(check: Callable[[T, str], T]) -> Callable[[typer.CallbackParam, T | None], T | None]:
    def callback(param: typer.CallbackParam, value: T | None) -> T | None:
        return None if value is None else check(value, _flag(param))

    return callback


def finite_float(
    lo: float | None = None, hi: float | None = None, *, lo_open: bool = False, hi_open: bool = False, unit: str = ""
) -> Callable[[typer.CallbackParam, float | None], float | None]:
    """A finite float inside the range (closed ends unless `lo_open`/`hi_open`)."""
    return _optional(lambda v, flag: check_float(v, flag, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit))


def positive_float(
    hi: float | None = None, unit: str = ""
) -> Callable[[typer.CallbackParam, float | None], float | None]:
    """A finite float > 0 (and <= hi)."""
    return finite_float(0.0, hi, lo_open=True, unit=unit)


def percent(lo_open: bool = True) -> Callable[[typer.CallbackParam, float | None], float | None]:
    """A percentage in (0, 100] (or [0, 100] with lo_open=False)."""
    return finite_float(0.0, 100.0, lo_open=lo_open, unit="percent")


def seconds(
    hi: float = MAX_SECONDS, allow_zero: bool = False
) -> Callable[[typer.CallbackParam, float | None], float | None]:
    """A duration in seconds: finite, > 0 (>= 0 with allow_zero), at most `hi` (a week by default)."""
    return finite_float(0.0, hi, lo_open=not allow_zero, unit="seconds")


def int_range(
    lo: int | None = None, hi: int | None = None, unit: str = ""
) -> Callable[[typer.CallbackParam, int | None], int | None]:
    """A whole number in lo..hi."""
    return _optional(lambda v, flag: check_int(v, flag, lo, hi, unit))


def ticks(lo: int = 0, hi: int = 4095) -> Callable[[typer.CallbackParam, int | None], int | None]:
    """A servo position in register ticks (0..4095 covers every supported model; the command
    checks the servo's own range once it knows the model)."""
    return int_range(lo, hi, "ticks")


def baud() -> Callable[[typer.CallbackParam, int | None], int | None]:
    """A baud rate: a whole number > 0 (0 is refused, never read as "the default")."""
    return int_range(1, MAX_BAUD, "baud")


def seed() -> Callable[[typer.CallbackParam, int | None], int | None]:
    """Any integer; a negative one is mapped by `seed_value`."""
    return _optional(lambda v, flag: seed_value(check_int(v, flag)))


def id_list(lo: int = 0, hi: int = 252) -> Callable[[typer.CallbackParam, str | None], str | None]:
    """An ID list (`1,2,3`, `1-6`), checked by `parse_id_list`; the text is returned unchanged."""

    def check(text: str, flag: str) -> str:
        parse_id_list(text, flag, lo, hi)
        return text

    return _optional(check)


# --------------------------------------------------------------------------------------------
# checks of paths and option pairs, called by a command before any work


def check_out_dir(out: Path, flag: str = "--out") -> None:
    """`out` is a directory we may write into, or can be created (its nearest existing ancestor
    is a writable directory): checked before any work, not after a long fit."""
    for p in (out, *out.absolute().parents):
        if not p.exists():
            continue
        if not p.is_dir():
            what = "is a file" if p.is_file() else "is not a directory"
            raise ArmtoolError(f"{flag} cannot be a directory: {p} {what}", str(out), "pass a directory path")
        if not os.access(p, os.W_OK | os.X_OK):
            raise ArmtoolError(
                f"{flag}: directory {p} is not writable", str(out), "check its permissions, or write somewhere else"
            )
        return


def check_chain_ends(base: str | None, tip: str | None, base_flag: str = "--base", tip_flag: str = "--flange") -> None:
    """Base and tip must be two links: the same name twice is a chain of no joints, reported
    here instead of as "no moving joint between 'r' and 'r'"."""
    if base is not None and base == tip:
        raise ArmtoolError(
            f"{base_flag} and {tip_flag} are the same link '{base}': the chain between them has no joints",
            None,
            f"{tip_flag} names the link the tag (or camera) is mounted on, {base_flag} the robot's fixed base",
        )


# ---- option declarations the servo commands share (the help text stays each command's own)


def servo_port(help_text: str, required: bool = True) -> Any:
    """--port: the serial port of the servo bus."""
    return typer.Option(... if required else None, "--port", help=help_text)


def servo_id() -> Any:
    """--id: one servo ID."""
    return typer.Option(..., "--id", min=0, max=252, help="Servo ID (0..252).")


def servo_protocol(default: object, help_text: str) -> Any:
    """--protocol: dxl1, dxl2 or feetech (the `Protocol` enum of the annotation)."""
    return typer.Option(default, "--protocol", help=help_text)


def bus_baud(default: int | None, help_text: str = "Bus baud rate.") -> Any:
    """--baud: a whole number > 0."""
    return typer.Option(default, "--baud", callback=baud(), help=help_text)


def speed_deg_s(default: float, help_text: str) -> Any:
    """--speed in degrees per second."""
    return typer.Option(default, "--speed", callback=positive_float(10_000, "degrees per second"), help=help_text)


def torque_percent(default: float, help_text: str) -> Any:
    """--torque-limit in percent of full torque."""
    return typer.Option(default, "--torque-limit", callback=percent(), help=help_text)


def tick_bound(flag: str, help_text: str) -> Any:
    """--min or --max: a command in ticks."""
    return typer.Option(None, flag, callback=ticks(), help=help_text)


def yes(help_text: str) -> Any:
    """--yes/-y: answer the safety prompts with yes."""
    return typer.Option(False, "--yes", "-y", help=help_text)


# ---- the robot: one set of options for every command that loads a URDF or xacro


XacroArgs = Annotated[
    list[str] | None,
    typer.Option(
        "--xacro-arg",
        help="xacro argument NAME:=VALUE for a .xacro robot (repeatable; wins over the configuration's).",
    ),
]
PackagePaths = Annotated[
    list[Path] | None,
    typer.Option(
        "--package-path",
        help="Directory holding ROS packages, for package:// and $(find) (repeatable; searched first).",
    ),
]
RobotConfig = Annotated[
    Path | None,
    typer.Option(
        "--config",
        help="armtool.toml or pyproject.toml whose [tool.armtool.lint] xacro-args and package-paths apply "
        "(default: the nearest one).",
    ),
]
# check and fit: the dataset names its robot and the robot's xacro arguments (robot.xacro_args).
DatasetConfig = Annotated[
    Path | None,
    typer.Option(
        "--config",
        help="armtool.toml or pyproject.toml whose [tool.armtool.lint] package-paths apply (default: the nearest "
        "one; the dataset's robot.xacro_args give the xacro arguments, --xacro-arg overrides them).",
    ),
]
MoveItConfig = Annotated[
    Path | None,
    typer.Option(
        "--moveit-config",
        help="MoveIt config package directory: the robot (URDF and xacro arguments from .setup_assistant), "
        "SRDF and YAML files, as its launch files load them.",
    ),
]


def parse_xacro_args(items: list[str] | None) -> dict[str, str]:
    """`--xacro-arg NAME:=VALUE` items as a dict (a malformed item is a usage error)."""
    out: dict[str, str] = {}
    for item in items or ():
        name, sep, value = item.partition(":=")
        if not sep or not name:
            raise typer.BadParameter(f"'{item}' is not NAME:=VALUE", param_hint="--xacro-arg")
        out[name] = value
    return out


class RobotOptions:
    """What the robot options say: xacro arguments (the configuration's for the file, then the
    command line's), package paths (the command line's, then the configuration's)."""

    def __init__(
        self, xacro_arg: list[str] | None, package_path: list[Path] | None, config: Path | None = None
    ) -> None:
        from armtool.lint.config import load_config

        if config is not None and not config.is_file():
            raise ArmtoolError("--config: no such file", str(config))
        self.given_args = parse_xacro_args(xacro_arg)
        self.config = load_config(config)
        self.package_paths = [*(package_path or ()), *self.config.package_paths]

    def moveit_package(self, directory: Path, urdf: Path | None, urdf_option: str) -> tuple[MoveItPackage, Path]:
        """--moveit-config DIR read as its launch files load it, and the robot's URDF: the given one,
        else the package's. The package's xacro arguments (`urdf_xacro_args`, its .setup_assistant's)
        describe its robot and go to a given URDF too (one the file does not declare is ignored, as
        xacro does; --xacro-arg wins). `urdf_option` names how the command takes a URDF, for the hint."""
        from armtool.model.packages import PackageResolver
        from armtool.moveit.package import read_package, stale_entry_error

        pkg = read_package(directory, PackageResolver(self.package_paths))
        chosen = urdf or pkg.urdf
        for what, needed in (("URDF", urdf is None), ("SRDF", True)):
            stale = stale_entry_error(pkg, what) if needed else None
            if stale is not None:
                raise stale
        for what, relative, missing in pkg.stale:
            if what == "SRDF" and pkg.srdf is not None and pkg.srdf != missing:
                from armtool.console import say

                say(
                    f".setup_assistant names {relative}, which does not exist; "
                    f"using {pkg.srdf.relative_to(pkg.root).as_posix()}",
                    label="note:",
                )
        if chosen is None:
            raise ArmtoolError(
                "cannot tell the robot of the MoveIt config: " + "; ".join(pkg.problems),
                str(directory),
                f"pass {urdf_option} too",
            )
        return pkg, chosen

    def xacro_args(self, path: Path, extra: dict[str, str] | None = None) -> dict[str, str]:
        """The arguments for one file: the configuration's for its glob, then `extra` (a MoveIt
        package's .setup_assistant), then --xacro-arg."""
        return {**self.config.xacro_args_for(path), **(extra or {}), **self.given_args}
