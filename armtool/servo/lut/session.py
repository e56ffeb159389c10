"""Setting a servo up for `servo-lut measure` and `check`, the two commands that move one: open
the bus and identify the servo, find the command range to stay inside, plan what to command,
and energise it under a `TorqueGuard` (speed and torque limit set, restored afterwards).

Why one module: both commands need the same range rules (recorded limits, --min/--max, the
servo's own angle-limit registers) and the same energising; the command line only asks and prints.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager
from dataclasses import dataclass
from pathlib import Path

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus
from armtool.servo.lut.choices import MeasureApproach
from armtool.servo.lut.measure import (
    CheckResult,
    Driver,
    Motion,
    check_angles,
    plan_commands,
    speed_register,
    torque_register,
)
from armtool.servo.lut.table import LutTable
from armtool.servo.models import ServoModel
from armtool.servo.reference import CsvReference, Reference
from armtool.servo.registry import transport_class


@dataclass(frozen=True)
class Setup:
    """Where the servo is and how it may be driven (the options `measure` and `check` share)."""

    port: str
    protocol: str
    baud: int
    sid: int
    speed_deg_s: float
    torque_percent: float
    dwell_s: float
    settle_timeout_s: float = 3.0


@dataclass(frozen=True)
class CommandRange:
    lo: int
    hi: int
    source: str  # where the range came from, for the log and the CSV metadata


def connect(setup: Setup, expected_model: str | None = None) -> ServoBus:
    """The bus with the servo identified (and checked to be `expected_model`); closed on failure."""
    from armtool.servo.bus import open_bus
    from armtool.servo.lut.csv_format import model_named

    bus = open_bus(setup.port, setup.protocol, setup.baud, echo_check_id=setup.sid)
    try:
        want = {setup.sid: model_named(expected_model, "--model")} if expected_model else None
        bus.identify([setup.sid], want)
    except BaseException:
        bus.close()
        raise
    return bus


def command_range(
    bus: ServoBus,
    sid: int,
    limits: Path | None,
    lo: int | None,
    hi: int | None,
    fallback: tuple[int, int] | None = None,
) -> CommandRange:
    """The command range to stay inside: recorded limits, --min/--max, or the fallback; never
    wider than the model's ticks or the servo's own angle-limit registers."""
    from armtool.servo.lut.measure import read_limits

    model = bus.model(sid)
    if limits is not None:
        lo_l, hi_l, model_name = read_limits(limits, sid)
        if model_name and model_name.lower() not in (model.name.lower(), *model.aliases):
            raise ArmtoolError(
                f"the limits for ID {sid} were recorded on a {model_name}, the servo is a {model.name}", str(limits)
            )
        lo = lo_l if lo is None else max(lo, lo_l)
        hi = hi_l if hi is None else min(hi, hi_l)
        source = f"limits {limits}"
    elif lo is None or hi is None:
        if fallback is None:
            raise ArmtoolError(
                "no range to measure in",
                hint="pass --limits limits.yaml (from `armtool limits`) or "
                "--min and --max in ticks, inside the joint's mechanical stops",
            )
        lo = fallback[0] if lo is None else lo
        hi = fallback[1] if hi is None else hi
        source = "the table's measured range"
    else:
        source = "--min/--max"
    if not 0 <= lo < hi <= model.max_tick:
        raise ArmtoolError(f"range {lo}..{hi} ticks is not inside 0..{model.max_tick} ({model.name}) with min < max")
    reg_lo, reg_hi = bus.read(sid, "min_limit"), bus.read(sid, "max_limit")
    if transport_class(model.protocol).wheel_mode_when_limits_zero and reg_lo == 0 and reg_hi == 0:
        raise ArmtoolError(f"ID {sid} is in wheel mode (both angle limits 0): it cannot hold a position")
    if lo < reg_lo or hi > reg_hi:
        lo, hi = max(lo, reg_lo), min(hi, reg_hi)
        source += f", narrowed to the servo's angle-limit registers {reg_lo}..{reg_hi}"
        if lo >= hi:
            raise ArmtoolError(f"the servo's angle limits {reg_lo}..{reg_hi} leave nothing of the range")
    return CommandRange(lo, hi, source)


def default_backoff(model: ServoModel) -> int:
    """About 3° of back-off before each approach: past the dead band of every model measured."""
    return max(1, round(3.0 / model.deg_per_tick))


def check_planned(commands: list[int], r: CommandRange, backoff: int) -> None:
    """Every planned command inside the range the user gave: refused before anything moves."""
    outside = [c for c in commands if not r.lo <= c <= r.hi]
    if outside:
        raise ArmtoolError(
            f"planned commands {outside[:5]} lie outside the range {r.lo}..{r.hi} ticks",
            hint=f"with a back-off of {backoff} ticks the points must leave room inside the command range",
        )


def partial_path(output: Path | None) -> Path | None:
    """Where an interrupted run keeps its readings (None when -o is stdout or a device)."""
    if output is None or str(output) == "-" or (output.exists() and not output.is_file()):
        return None
    return output.with_name(output.name + ".partial")


@dataclass(frozen=True)
class MeasurePlan:
    range: CommandRange
    backoff: int
    commands: list[int]
    reads: int  # reference readings per point (a CSV reference has one per command)

    def describe(self, model: ServoModel, setup: Setup, approach: MeasureApproach, ref: Reference) -> str:
        c, r, deg = self.commands, self.range, model.deg_per_tick
        return (
            f"ID {setup.sid}: {model.name} on {setup.port}; {len(c)} points {c[0]}..{c[-1]} ticks "
            f"({c[0] * deg:.1f}..{c[-1] * deg:.1f}°) inside {r.lo}..{r.hi} ({r.source}), "
            f"approach {approach.value}, reference {ref.spec}"
        )

    def metadata(self, model: ServoModel, setup: Setup, ref: Reference) -> dict[str, str]:
        """The measurement CSV's '# key: value' lines."""
        return {
            "servo_id": str(setup.sid),
            "servo_model": model.name,
            "reference": ref.spec,
            "port": setup.port,
            "range_ticks": f"{self.range.lo}..{self.range.hi} ({self.range.source})",
            "backoff_ticks": str(self.backoff),
            "started": time.strftime("%Y-%m-%dT%H:%M:%S"),
        }


def plan_measure(
    bus: ServoBus,
    setup: Setup,
    ref: Reference,
    r: CommandRange,
    approach: MeasureApproach,
    backoff: int | None,
    points: int | None,
    step: int | None,
    reads: int,
) -> MeasurePlan:
    """The commands to measure: the CSV reference's own, or evenly spaced inside the range."""
    b = backoff if backoff is not None else default_backoff(bus.model(setup.sid))
    if isinstance(ref, CsvReference):
        commands = ref.commands
        outside = [c for c in commands if not r.lo <= c <= r.hi]
        if outside:
            raise ArmtoolError(
                f"the reference file has commands outside the range {r.lo}..{r.hi}: {outside[:5]}", str(ref.path)
            )
        reads = 1
    else:
        commands = plan_commands(r.lo, r.hi, approach, b, points, step)
    check_planned(commands, r, b)
    return MeasurePlan(r, b, commands, reads)


def check_range(
    bus: ServoBus, setup: Setup, table: LutTable, table_path: Path, limits: Path | None, lo: int | None, hi: int | None
) -> CommandRange:
    """The range `check` may move in: the table must be this model's; its measured command range
    stands in for the limits only on the servo it was measured on."""
    model = bus.model(setup.sid)
    if model.name != table.model.name:
        raise ArmtoolError(
            f"{table_path} was made for a {table.model.name}, but ID {setup.sid} is a {model.name}",
            f"{table_path}: servo.model",
            hint="measure and fit a table on this servo",
        )
    knots = (int(min(table.knots_ticks)), int(max(table.knots_ticks)))
    same_servo = table.servo_id is not None and table.servo_id == setup.sid
    if not same_servo and limits is None and (lo is None or hi is None):
        measured_on = f"ID {table.servo_id}" if table.servo_id is not None else "an unnamed servo"
        raise ArmtoolError(
            f"{table_path} was measured on {measured_on}, not ID {setup.sid}: its command range "
            f"{knots[0]}..{knots[1]} says nothing about this joint's stops",
            f"{table_path}: servo.id",
            hint="pass --limits limits.yaml (from `armtool limits`) or --min and --max in ticks",
        )
    torque_register(model, setup.torque_percent)  # a torque limit below one register step: refused before moving
    return command_range(bus, setup.sid, limits, lo, hi, fallback=knots if same_servo else None)


def plan_check(table: LutTable, ref: Reference, r: CommandRange, n: int, seed: int) -> list[float]:
    """The random angles `check` commands, each reachable inside the range through the table."""
    if isinstance(ref, CsvReference):
        raise ArmtoolError("check needs a live reference (encoder, manual or camera), not a file")
    angles = check_angles(table, n, seed, r.lo, r.hi)
    check_planned([int(table.command_ticks([a])[0]) for a in angles], r, 0)
    return angles


@contextmanager
def energised(bus: ServoBus, setup: Setup, r: CommandRange, backoff: int) -> Iterator[Driver]:
    """The servo at the set speed and torque limit, torque on, driven only inside `r`; torque off
    and the registers restored on leaving, however it is left."""
    from armtool.servo.guard import TorqueGuard

    sid, model = setup.sid, bus.model(setup.sid)
    cap = torque_register(model, setup.torque_percent)
    motion = Motion(
        backoff_ticks=backoff,
        settle_timeout_s=setup.settle_timeout_s,
        dwell_s=setup.dwell_s,
        tolerance_ticks=model.settle_ticks,
        torque_cap=cap / model.reg("torque_limit").hi,
    )
    with TorqueGuard(bus) as guard:
        guard.set_ram(sid, "moving_speed", speed_register(model, setup.speed_deg_s))
        guard.set_ram(sid, "torque_limit", cap)
        guard.torque_on(sid)
        yield Driver(bus, guard, sid, motion, bounds=(r.lo, r.hi))


ProgressBar = Callable[[bool, str, int], AbstractContextManager[Callable[[int, int], None] | None]]


@dataclass(frozen=True)
class Hooks:
    """What a run asks of the person at the command line (the core itself never prints)."""

    ask: Callable[[str], str]  # a typed answer (the manual reference)
    confirm: Callable[[str], None]  # returns on yes, raises ArmtoolError otherwise
    note: Callable[[str], None]  # one line of news for stderr
    progress: ProgressBar  # (shown, label, total) -> a context giving an update(done, total) function


@dataclass(frozen=True)
class MeasureRequest:
    reference: str
    model: str | None
    limits: Path | None
    lo: int | None
    hi: int | None
    approach: MeasureApproach
    backoff: int | None
    points: int | None
    step: int | None
    reads: int
    sweeps: int
    output: Path | None


def run_measure(setup: Setup, req: MeasureRequest, hooks: Hooks) -> str:
    """`servo-lut measure` from the checked options to the measurement CSV text. Readings taken
    before a failure are saved beside -o (FILE.partial) before the error goes on."""
    from armtool.fileio import rescue_write
    from armtool.servo.lut.csv_format import Sample, render_measurements
    from armtool.servo.lut.measure import align_reference, measure
    from armtool.servo.reference import ManualReference, open_reference

    ref = open_reference(req.reference, ask=hooks.ask)
    samples: list[Sample] = []
    bus, meta = None, {}
    try:
        bus = connect(setup, req.model)
        model = bus.model(setup.sid)
        r = command_range(bus, setup.sid, req.limits, req.lo, req.hi)
        plan = plan_measure(bus, setup, ref, r, req.approach, req.backoff, req.points, req.step, req.reads)
        hooks.note(plan.describe(model, setup, req.approach, ref))
        hooks.confirm(f"Energise servo {setup.sid} and move it through this range? Clear the workspace first.")
        meta, t0 = plan.metadata(model, setup, ref), time.monotonic()
        with energised(bus, setup, r, plan.backoff) as driver:
            note = align_reference(driver, ref, r.lo, r.hi, "down" if req.approach is MeasureApproach.DOWN else "up")
            if note is not None:
                meta["reference_alignment"] = note
                hooks.note(f"{ref.spec} aligned to the servo: {note}")
            with hooks.progress(not isinstance(ref, ManualReference), "measuring", len(plan.commands)) as bar:
                measure(
                    driver, ref, plan.commands, req.approach, r.lo, r.hi, plan.reads, req.sweeps, samples.append, bar
                )
        unsettled = sum(1 for s in samples if s.settled is False)
        hooks.note(
            f"measured {len(samples)} readings at {len(plan.commands)} points in {time.monotonic() - t0:.1f} s"
            + (f"; {unsettled} reading(s) taken before the servo settled" if unsettled else "")
            + "; torque off"
        )
    except BaseException:
        if samples and req.output is not None:
            text = render_measurements({**meta, "complete": "no"}, samples)
            saved = rescue_write(req.output, text, "armtool-measure")
            hooks.note(f"wrote the readings so far to {saved}")
        raise
    finally:
        ref.close()
        if bus is not None:
            bus.close()
    return render_measurements(meta, samples)


def run_check(
    setup: Setup,
    table_path: Path,
    reference: str,
    window: tuple[Path | None, int | None, int | None],
    n: int,
    seed: int,
    reads: int,
    hooks: Hooks,
) -> CheckResult:
    """`servo-lut check`: random angles through the table and through the nominal map, measured.
    `window` is (--limits, --min, --max)."""
    from armtool.servo.lut.measure import align_reference, check
    from armtool.servo.lut.table import read_table
    from armtool.servo.reference import ManualReference, open_reference

    table = read_table(table_path)
    bus, ref = connect(setup), None
    try:
        r = check_range(bus, setup, table, table_path, *window)
        ref = open_reference(reference, ask=hooks.ask)
        angles = plan_check(table, ref, r, n, seed)
        hooks.confirm(f"Energise servo {setup.sid} and move it to {n} angles between ticks {r.lo} and {r.hi}?")
        with energised(bus, setup, r, default_backoff(bus.model(setup.sid))) as driver:
            align_reference(driver, ref, r.lo, r.hi, "down" if table.approach == "down" else "up")
            with hooks.progress(not isinstance(ref, ManualReference), "checking", n) as bar:
                return check(driver, ref, table, angles, r.lo, r.hi, reads=reads, progress=bar)
    finally:
        if ref is not None:
            ref.close()
        bus.close()
