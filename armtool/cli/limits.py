"""`armtool limits`: record each joint's real range over a Dynamixel or Feetech bus."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer

from armtool.cli import options as opt
from armtool.errors import ArmtoolError
from armtool.extras import require
from armtool.servo.registry import Protocol, transport_class

if TYPE_CHECKING:
    from armtool.servo.bus import ServoBus
    from armtool.servo.eeprom import EepromWrite
    from armtool.servo.guard import TorqueGuard
    from armtool.servo.limits import AutoParams, Joint, JointRange


class Mode(str, Enum):
    MANUAL = "manual"
    AUTO = "auto"


def limits(
    port: str | None = typer.Option(
        None,
        "--port",
        help="Serial port of the bus adapter (e.g. /dev/ttyUSB0); required unless --from-lerobot converts a file.",
    ),
    mode: Mode | None = typer.Option(
        None,
        "--mode",
        help="manual: you move the joints (torque off); auto: seek each stop at low torque. Required with --port.",
    ),
    protocol: Protocol | None = typer.Option(
        None,
        "--protocol",
        help="dxl1 (AX/MX), dxl2 (X series) or feetech (STS/SCS) [default: the arm file's, else dxl1].",
    ),
    baud: int | None = typer.Option(
        None, "--baud", callback=opt.baud(), help="Baud rate [default: the arm file's, else 1000000]."
    ),
    ids: str | None = typer.Option(
        None, "--ids", callback=opt.id_list(0, 252), help="Servo IDs, e.g. 1,2,3 or 1-6 (or use --arm)."
    ),
    model: str | None = typer.Option(None, "--model", help="With --ids: the model every ID must be (e.g. AX-12A)."),
    arm: Path | None = typer.Option(
        None, "--arm", help="Arm YAML: joints with name, id, model, zero_ticks, direction."
    ),
    output: Path | None = typer.Option(None, "-o", "--output", help="Write the limits YAML here (default: stdout)."),
    margin: float = typer.Option(
        2.0, "--margin", callback=opt.finite_float(0, 90, unit="degrees"), help="Degrees kept inside each recorded end."
    ),
    duration: float | None = typer.Option(
        None, "--duration", callback=opt.seconds(), help="Manual: record this many seconds (default: until Enter)."
    ),
    rate: float = typer.Option(
        50.0, "--rate", callback=opt.positive_float(1000, "samples per second"), help="Manual: samples per second."
    ),
    min_dwell: float = typer.Option(
        0.3,
        "--min-dwell",
        callback=opt.seconds(3600, allow_zero=True),
        help="Manual: seconds a joint must rest at an end to confirm it.",
    ),
    torque_limit: float = typer.Option(
        30.0, "--torque-limit", callback=opt.percent(), help="Auto: torque (or PWM) limit in percent of full."
    ),
    speed: float = typer.Option(
        30.0,
        "--speed",
        callback=opt.positive_float(10_000, "degrees per second"),
        help="Auto: seek speed in degrees per second.",
    ),
    stall_window: float = typer.Option(
        0.12,
        "--stall-window",
        callback=opt.seconds(60),
        help="Auto: seconds without motion that, with high load, mean a stop.",
    ),
    stall_load: float = typer.Option(
        70.0,
        "--stall-load",
        callback=opt.percent(),
        help="Auto: load, in percent of the torque limit, that means a stop.",
    ),
    back_off: float = typer.Option(
        3.0,
        "--back-off",
        callback=opt.finite_float(0, 90, unit="degrees"),
        help="Auto: degrees to back off after each stop.",
    ),
    max_seek: float | None = typer.Option(
        None,
        "--max-seek",
        callback=opt.seconds(3600),
        help="Auto: seconds per direction before giving up [default: range/speed x 1.5 + 2].",
    ),
    first_dir: str = typer.Option("-", "--first-dir", help="Auto: seek the low (-) or high (+) end first."),
    urdf: Path | None = typer.Option(
        None, "--urdf", help="Write <limit lower upper> into this URDF (keeps its text and comments)."
    ),
    in_place: bool = typer.Option(
        False,
        "--in-place",
        help="With --urdf: edit it in place, keeping the previous version "
        "in FILE.bak (or FILE.bak.1, .2 ... when that exists: a backup is never overwritten).",
    ),
    urdf_out: Path | None = typer.Option(None, "--urdf-out", help="With --urdf: write the edited URDF here."),
    allow_widen: bool = typer.Option(
        False, "--allow-widen", help="Write URDF limits even where they are wider than the URDF's."
    ),
    write_eeprom: bool = typer.Option(
        False, "--write-eeprom", help="Also write the safe range into the servos' angle-limit registers."
    ),
    yes: bool = typer.Option(
        False, "--yes", "-y", help="Answer the safety and EEPROM prompts with yes (scripted use)."
    ),
    dry_run: bool = typer.Option(
        False, "--dry-run", help="With --write-eeprom: show the EEPROM writes, do not make them."
    ),
    timeout_ms: float = typer.Option(
        25.0, "--timeout-ms", callback=opt.positive_float(10_000, "milliseconds"), help="Reply timeout per transaction."
    ),
    lerobot_calibration: Path | None = typer.Option(
        None,
        "--lerobot-calibration",
        help="Also write a LeRobot calibration JSON (motor names = the arm file's joint names), with homing offsets that keep every range off the 0/4095 seam.",
    ),
    lerobot_full_turn: str | None = typer.Option(
        None,
        "--lerobot-full-turn",
        help="With --lerobot-calibration: joints that get LeRobot's full-turn range 0..4095 (e.g. wrist_roll).",
    ),
    from_lerobot: Path | None = typer.Option(
        None,
        "--from-lerobot",
        help="Read a LeRobot calibration JSON: without --port, convert its ranges to limits YAML / URDF limits; "
        "with --port and --mode, record the arm and compare each motor's range with the file's (exit 1 when the file reaches past a recorded end).",
    ),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    import sys

    from rich.markup import escape

    from armtool.console import stderr
    from armtool.fileio import backup_path, check_output_path, check_output_paths, rescue_write
    from armtool.servo import limits as L
    from armtool.servo.bus import open_bus
    from armtool.servo.guard import TorqueGuard
    from armtool.servo.models import by_name

    # ---- arguments, before touching the bus
    if from_lerobot is not None or lerobot_calibration is not None or lerobot_full_turn is not None:
        _check_lerobot_options(port, mode, arm, lerobot_calibration, lerobot_full_turn, from_lerobot, write_eeprom)
    elif port is None or mode is None:
        raise ArmtoolError(
            f"{'--port' if port is None else '--mode'} is required",
            hint="e.g. --port /dev/ttyUSB0 --mode manual (or --from-lerobot FILE --arm arm.yaml to convert a LeRobot file)",
        )
    if (ids is None) == (arm is None):
        raise ArmtoolError(
            "give exactly one of --ids or --arm", hint="e.g. --ids 1,2,3 --model AX-12A, or --arm arm.yaml"
        )
    if first_dir not in ("-", "+"):
        raise ArmtoolError(f"--first-dir must be - or +, got '{first_dir}'")
    if urdf is not None and in_place == (urdf_out is not None):
        raise ArmtoolError("with --urdf pass either --in-place or --urdf-out FILE")
    if urdf is None and (in_place or urdf_out is not None):
        raise ArmtoolError("--in-place and --urdf-out need --urdf")
    if dry_run and not write_eeprom:
        raise ArmtoolError("--dry-run applies to --write-eeprom")
    interactive = sys.stdin.isatty()
    if port is not None and mode is Mode.MANUAL and duration is None and not interactive:
        raise ArmtoolError("manual mode ends on Enter, but stdin is not a terminal", hint="pass --duration SECONDS")
    if mode is Mode.AUTO and not yes and not interactive:
        raise ArmtoolError(
            "auto mode moves the arm and needs a confirmation, but stdin is not a terminal",
            hint="pass --yes once the workspace is clear",
        )
    if write_eeprom and not dry_run and not yes and not interactive:
        raise ArmtoolError(
            "--write-eeprom needs a confirmation, but stdin is not a terminal",
            hint="pass --yes, or --dry-run to see the writes",
        )

    if arm is not None:
        arm_file = L.load_arm(arm)
        joints = arm_file.joints
        proto = protocol.value if protocol else (arm_file.protocol or Protocol.DXL1.value)
        baud_rate = baud if baud is not None else (arm_file.baud or 1_000_000)
    else:
        expected = by_name(model) if model else None
        joints = [L.Joint(f"id{i}", i, expected) for i in L.parse_ids(ids or "")]
        proto = protocol.value if protocol else Protocol.DXL1.value
        baud_rate = baud if baud is not None else 1_000_000
    for j in joints:
        if j.model is not None and j.model.protocol != proto:
            raise ArmtoolError(
                f"joint '{j.name}': {j.model.name} speaks {j.model.protocol}, not {proto}",
                hint=f"pass --protocol {j.model.protocol}",
            )
    urdf_text = None
    if urdf is not None:
        try:
            urdf_text = urdf.read_text()
        except OSError as exc:
            raise ArmtoolError(f"cannot read {urdf}: {exc.strerror}") from None
        L.check_urdf_names(urdf_text, [j.name for j in joints], str(urdf))
    # ---- every output checked before the bus is opened (nothing moves for a write that must fail)
    check_output_paths(
        {"-o": output, "--urdf-out": urdf_out, "--lerobot-calibration": lerobot_calibration},
        inputs=[arm, urdf, from_lerobot],
    )
    if in_place and urdf is not None:
        check_output_path(urdf, "--in-place")
        check_output_path(backup_path(urdf), "--in-place (backup)")
    full_turn = _full_turn_names(lerobot_full_turn, joints)
    calibration = None
    if from_lerobot is not None:
        from armtool.servo import lerobot as LR

        calibration = LR.read_calibration(from_lerobot)
        LR.check_against_arm(
            calibration, joints, from_lerobot, {j.name: LR.offset_rule(j.model) for j in joints if j.model is not None}
        )
        if port is None:
            _convert_lerobot(
                calibration, from_lerobot, joints, margin, output, urdf, urdf_text, urdf_out, in_place, allow_widen
            )
            return
    assert port is not None and mode is not None  # checked above

    # ---- the bus
    con = stderr()
    checks = None
    bus = open_bus(port, proto, baud_rate, echo_check_id=joints[0].id, timeout_ms=timeout_ms)
    try:
        for w in bus.warnings:
            con.print(f"[yellow]warning:[/yellow] {w}")
        bus.identify([j.id for j in joints], {j.id: j.model for j in joints if j.model is not None})
        for j in joints:
            j.model = bus.model(j.id)
            _check_motion_options(j, margin, back_off)
        servo_state = _lerobot_state(bus, joints) if (lerobot_calibration or from_lerobot) else {}
        if calibration is not None and from_lerobot is not None:  # offsets against the mode each servo is in
            from armtool.servo import lerobot as LR

            LR.check_against_arm(calibration, joints, from_lerobot, {n: st["rule"] for n, st in servo_state.items()})
        slow = [j.id for j in joints if bus.read(j.id, "return_delay") > 0]
        if slow:
            con.print(
                f"[yellow]warning:[/yellow] ID {', '.join(map(str, slow))}: Return Delay Time > 0 slows every reply; "
                "set it to 0 (register return_delay)"
            )
        if mode is Mode.AUTO and not yes:
            if not typer.confirm(
                "Auto mode drives every joint into its mechanical stops at low torque. "
                "Is the workspace clear and the arm free to move?",
                err=True,
            ):
                raise ArmtoolError("not confirmed; nothing was moved")
        with TorqueGuard(bus) as guard:
            if mode is Mode.MANUAL:
                ranges = _manual(bus, guard, joints, duration, rate, min_dwell, interactive)
            else:
                params = L.AutoParams(
                    torque_limit=torque_limit / 100,
                    speed_deg_s=speed,
                    stall_window_s=stall_window,
                    stall_load=stall_load / 100,
                    back_off_deg=back_off,
                    max_seek_s=max_seek,
                    first_dir=-1 if first_dir == "-" else 1,
                )
                ranges = _auto(bus, guard, joints, params)
        rows = [L.convert(r, margin) for r in ranges]
        unconfirmed = [
            f"{r.joint.name} ({'min' if not r.evidence.get('confirmed_min', True) else 'max'})"
            for r in ranges
            if not r.confirmed and r.method == "manual"
        ]
        # ---- everything computed in memory first: no half-written outputs
        new_urdf = None
        if urdf_text is not None:
            new_urdf = L.patch_urdf(
                urdf_text, {r["name"]: (r["lower_rad"], r["upper_rad"]) for r in rows}, allow_widen, str(urdf)
            )
        for row in rows:
            if row["name"] in servo_state:
                row["homing_offset"] = servo_state[row["name"]]["homing_offset"]
        doc_text = L.dump_yaml(L.limits_document(rows, port, proto, baud_rate))
        lerobot_text, lerobot_error = None, None
        if lerobot_calibration is not None:
            try:
                lerobot_text = _lerobot_document(ranges, rows, servo_state, full_turn)
            except ArmtoolError as exc:  # reported after the limits YAML is written: the recording is kept
                lerobot_error = exc
        checks = _compare_lerobot(calibration, from_lerobot, ranges, servo_state) if calibration is not None else None
        _summary(rows, ranges)
        ends = [
            f"{r.joint.name} ({k[7:]})"
            for r in ranges
            for k in ("reason_min", "reason_max")
            if "range end" in str(r.evidence.get(k, ""))
        ]
        if ends:
            con.print(
                "[yellow]no stop found before the servo's range end[/yellow] (or the travel crosses the encoder seam; "
                "use --mode manual for those): " + ", ".join(ends)
            )
        if unconfirmed:
            con.print(
                f"[yellow]unconfirmed ends[/yellow] (the joint did not rest there {min_dwell:g} s): "
                + ", ".join(unconfirmed)
            )
        _write_outputs(doc_text, output, new_urdf, urdf, urdf_text, urdf_out, in_place)
        if lerobot_error is not None:
            raise ArmtoolError(
                f"{lerobot_error.what} (the limits YAML was written; no LeRobot file)",
                lerobot_error.where,
                lerobot_error.hint,
            )
        if lerobot_text is not None and lerobot_calibration is not None:
            try:
                L.write_atomic(lerobot_calibration, lerobot_text)
            except ArmtoolError as exc:  # keep the recording: a run must not be repeated for a write
                saved = rescue_write(lerobot_calibration, lerobot_text, "armtool-lerobot")
                raise ArmtoolError(
                    f"{exc.what}; the LeRobot calibration was saved to {saved}", exc.where, exc.hint
                ) from None
            con.print(
                escape(
                    f"wrote {lerobot_calibration} (LeRobot calibration; LeRobot offers to write it into "
                    "the servos at the next connect)"
                )
            )
        if write_eeprom:  # after the YAML: a refused EEPROM write must not lose the recording
            _do_eeprom(bus, _eeprom_plan(bus, ranges, rows), yes, dry_run)
    finally:
        bus.close()
    if checks is not None and not all(c.ok(LEROBOT_TOLERANCE_TICKS) for c in checks):
        raise typer.Exit(1)


def _check_motion_options(joint: Any, margin_deg: float, back_off_deg: float) -> None:
    """The options that bound motion against the servo's range, once its model is known."""
    model = joint.model
    if 2 * margin_deg >= model.range_deg:
        raise ArmtoolError(
            f"--margin {margin_deg:g}° leaves nothing of the {model.name}'s {model.range_deg:g}° range "
            f"(joint '{joint.name}')",
            hint="a margin of a few degrees is usual (default 2)",
        )
    if back_off_deg >= model.range_deg / 2:
        raise ArmtoolError(
            f"--back-off {back_off_deg:g}° is half the {model.name}'s {model.range_deg:g}° range or more "
            f"(joint '{joint.name}')",
            hint="a back-off of a few degrees is usual (default 3)",
        )


def _manual(
    bus: ServoBus,
    guard: TorqueGuard,
    joints: list[Joint],
    duration: float | None,
    rate: float,
    min_dwell: float,
    interactive: bool,
) -> list[JointRange]:
    import select
    import sys
    import time

    from rich.live import Live

    from armtool.console import stderr
    from armtool.servo.limits import ManualRecorder

    for j in joints:
        guard.touch(j.id)
        if not guard.torque_off(j.id):
            raise ArmtoolError(f"ID {j.id}: torque did not go off")
    rec = ManualRecorder(bus, joints, min_dwell_s=min_dwell)
    how = f"for {duration:g} s" if duration else "until you press Enter"
    stderr().print(f"torque is off: move every joint to both of its ends and hold it there a moment; recording {how}")
    start = time.monotonic()
    with Live(_manual_table(rec), console=stderr(), refresh_per_second=8, transient=False) as live:
        while True:
            rec.sample()
            live.update(_manual_table(rec))
            if duration is not None and time.monotonic() - start >= duration:
                break
            if interactive and select.select([sys.stdin], [], [], 0)[0]:
                sys.stdin.readline()
                if duration is None:
                    break
            time.sleep(max(0.0, 1.0 / rate))
    return rec.results()


def _manual_table(rec: Any) -> Any:
    from rich.table import Table

    table = Table(title="joint ranges (ticks)", title_justify="left")
    for col in ("joint", "id", "present", "min", "max"):
        table.add_column(col, justify="right" if col != "joint" else "left")
    for j in rec.joints:
        ext = rec.extent(j.id)
        table.add_row(
            j.name, str(j.id), str(rec.present.get(j.id, "-")), *(str(v) for v in (ext if ext else ("-", "-")))
        )
    return table


def _auto(bus: ServoBus, guard: TorqueGuard, joints: list[Joint], params: AutoParams) -> list[JointRange]:
    from rich.progress import Progress, TextColumn, TimeElapsedColumn

    from armtool.console import stderr
    from armtool.servo.limits import seek_joint

    ranges = []
    with Progress(TextColumn("{task.description}"), TimeElapsedColumn(), console=stderr(), transient=False) as bar:
        for j in joints:
            task = bar.add_task(f"{j.name} (ID {j.id})")

            def show(joint: Any, label: str, pos: int, load: float, task: Any = task) -> None:
                bar.update(
                    task,
                    description=f"{joint.name} (ID {joint.id}) seeking {label}: {pos} ticks, load {load:.0%} of limit",
                )

            r = seek_joint(bus, guard, j, params, show)
            bar.update(task, description=f"{j.name} (ID {j.id}): {r.raw_min}..{r.raw_max} ticks")
            ranges.append(r)
    return ranges


def _summary(rows: list[dict[str, Any]], ranges: list[Any]) -> None:
    import math

    from rich.table import Table

    from armtool.console import stderr

    table = Table(title="limits", title_justify="left")
    for col in ("joint", "id", "raw ticks", "safe ticks", "lower°", "upper°", "how"):
        table.add_column(col, justify="left" if col in ("joint", "how") else "right", no_wrap=col != "how")
    for row, r in zip(rows, ranges):
        how = (
            r.method
            if r.method != "auto"
            else "auto: " + "/".join(str(r.evidence[k]).split(" (")[0] for k in ("reason_min", "reason_max"))
        )
        if not r.confirmed:
            how += " [yellow](unconfirmed)[/yellow]"
        table.add_row(
            row["name"],
            str(row["id"]),
            f"{row['raw_min_ticks']}..{row['raw_max_ticks']}",
            f"{row['safe_min_ticks']}..{row['safe_max_ticks']}",
            f"{math.degrees(row['lower_rad']):.1f}",
            f"{math.degrees(row['upper_rad']):.1f}",
            how,
        )
    stderr().print(table)


def _eeprom_plan(bus: ServoBus, ranges: list[JointRange], rows: list[dict[str, Any]]) -> list[EepromWrite]:
    from armtool.servo.eeprom import plan_writes

    bad = [r.joint.name for r in ranges if not r.confirmed]
    if bad:
        raise ArmtoolError(
            f"not writing EEPROM limits: unconfirmed ends on {', '.join(bad)} (the limits YAML was written)",
            hint="manual: hold each joint at each end for --min-dwell seconds; auto: an end where no "
            "stop was found is the servo's range end (or the seam), record it with --mode manual",
        )
    seam = [r.joint.name for r in ranges if r.crosses_seam]
    if seam:
        raise ArmtoolError(
            f"not writing EEPROM limits: the range of {', '.join(seam)} crosses the encoder seam",
            hint="set a homing offset that centres the range on 2048, then record again",
        )
    wanted = {row["id"]: {"min_limit": row["safe_min_ticks"], "max_limit": row["safe_max_ticks"]} for row in rows}
    return plan_writes(bus, wanted)


def _do_eeprom(bus: ServoBus, plan: list[EepromWrite], yes: bool, dry_run: bool) -> None:
    from armtool.console import stderr
    from armtool.servo.eeprom import apply_writes

    con = stderr()
    if not plan:
        con.print("EEPROM limits already set; nothing to write")
        return
    for w in plan:
        con.print(("would write " if dry_run else "EEPROM: ") + w.describe())
    if dry_run:
        return
    if not yes and not typer.confirm(f"Write {len(plan)} EEPROM value(s)?", err=True):
        raise ArmtoolError("EEPROM writes not confirmed; nothing written to the servos")
    apply_writes(bus, plan)
    con.print(f"EEPROM: {len(plan)} value(s) written and verified by reading back")


# ---------------------------------------------------------------- LeRobot calibration files
LEROBOT_TOLERANCE_TICKS = 2  # how far a file's end may pass a recorded one (the recording finds stops within 2 ticks)


def _check_lerobot_options(
    port: str | None,
    mode: Any,
    arm: Path | None,
    out: Path | None,
    full_turn: str | None,
    source: Path | None,
    write_eeprom: bool,
) -> None:
    if full_turn is not None and out is None:
        raise ArmtoolError("--lerobot-full-turn applies to --lerobot-calibration")
    if arm is None:
        raise ArmtoolError(
            "--lerobot-calibration and --from-lerobot need --arm (its joint names are LeRobot's motor names)",
            hint="joints: [{name: shoulder_pan, id: 1, model: STS3215}, ...]",
        )
    if out is not None and source is not None:
        raise ArmtoolError("give one of --lerobot-calibration (write a file) and --from-lerobot (read one)")
    if out is not None and (port is None or mode is None):
        raise ArmtoolError("--lerobot-calibration writes a recording: it needs --port and --mode")
    if port is None and mode is not None:
        raise ArmtoolError(
            "--mode records the arm: it needs --port", hint="without --port, --from-lerobot converts the file"
        )
    if port is not None and mode is None:
        raise ArmtoolError(
            "--mode is required with --port", hint="--from-lerobot with --port records the arm to compare it"
        )
    if port is None and write_eeprom:
        raise ArmtoolError("--write-eeprom needs --port")


def _full_turn_names(text: str | None, joints: list[Any]) -> set[str]:
    if text is None:
        return set()
    names = {n.strip() for n in text.split(",") if n.strip()}
    unknown = sorted(names - {j.name for j in joints})
    if unknown or not names:
        raise ArmtoolError(
            f"--lerobot-full-turn: {', '.join(unknown) or 'no joint'} not in the arm file",
            hint="joints: " + ", ".join(j.name for j in joints),
        )
    return names


def _lerobot_state(bus: ServoBus, joints: list[Joint]) -> dict[str, dict[str, Any]]:
    """Each joint's offset rule and registers, read before recording (the recording is in ticks
    under the offset the servo holds now); a model without a homing offset is refused here."""
    from armtool.servo import lerobot as LR

    state: dict[str, dict[str, Any]] = {}
    for j in joints:
        model = bus.model(j.id)
        mode = bus.read(j.id, "operating_mode") if transport_class(model.protocol).position_mode is not None else None
        rule = LR.offset_rule(model, mode)
        state[j.name] = {
            "rule": rule,
            "homing_offset": bus.read(j.id, "homing_offset"),
            # Dynamixel: LeRobot compares drive_mode with the Drive Mode register; Feetech: software, 0
            "drive_mode": bus.read(j.id, "drive_mode") if model.has("drive_mode") else 0,
            "min_limit": bus.read(j.id, "min_limit"),
            "max_limit": bus.read(j.id, "max_limit"),
        }
    return state


def _lerobot_document(
    ranges: list[Any], rows: list[dict[str, Any]], state: dict[str, dict[str, Any]], full_turn: set[str]
) -> str:
    """The LeRobot JSON for the safe range of every joint (the margin inside each recorded end)."""
    from armtool.servo import lerobot as LR

    bad = [r.joint.name for r in ranges if not r.confirmed and r.joint.name not in full_turn]
    if bad:
        raise ArmtoolError(
            f"not writing the LeRobot calibration: unconfirmed ends on {', '.join(bad)}",
            hint="manual: hold each joint at each end for --min-dwell seconds; a joint that turns "
            "freely can take LeRobot's full-turn range with --lerobot-full-turn",
        )
    out = {}
    for r, row in zip(ranges, rows):
        st = state[r.joint.name]
        out[r.joint.name] = LR.calibrate_joint(
            r.joint.name,
            r.joint.id,
            row["safe_min_ticks"],
            row["safe_max_ticks"],
            st["homing_offset"],
            st["rule"],
            st["drive_mode"],
            r.joint.name in full_turn,
        )
    return LR.document(out)


def _compare_lerobot(calibration: Any, source: Any, ranges: list[Any], state: dict[str, dict[str, Any]]) -> list[Any]:
    """Each motor's file range against the recorded one (in ticks under the servo's present offset),
    as a table on stderr (stdout keeps the limits YAML)."""
    from rich.markup import escape
    from rich.table import Table

    from armtool.console import stderr
    from armtool.servo import lerobot as LR

    checks = []
    table = Table(title=escape(f"LeRobot file {source} against the recorded ranges (ticks)"), title_justify="left")
    for col in ("motor", "file range", "recorded", "past low end", "past high end", "verdict"):
        table.add_column(col, justify="left" if col in ("motor", "verdict") else "right")
    differ = []
    for r in ranges:
        cal = calibration[r.joint.name]
        st = state[r.joint.name]
        shift = LR.frame_shift(cal.homing_offset, st["homing_offset"], st["rule"])
        check = LR.compare(r.joint.name, (cal.range_min + shift, cal.range_max + shift), (r.raw_min, r.raw_max))
        checks.append(check)
        held = (st["homing_offset"], st["min_limit"], st["max_limit"])
        if held != (cal.homing_offset, cal.range_min, cal.range_max):
            differ.append(f"{r.joint.name} (offset {held[0]}, limits {held[1]}..{held[2]})")
        verdict = "ok" if check.ok(LEROBOT_TOLERANCE_TICKS) else "[red]file reaches past the recorded stop[/red]"
        table.add_row(
            r.joint.name,
            f"{check.file_min}..{check.file_max}",
            f"{check.recorded_min}..{check.recorded_max}",
            str(check.past_min),
            str(check.past_max),
            verdict,
        )
    stderr().print(table)
    if differ:
        stderr().print(
            escape(
                "the servos' registers differ from the file on "
                + ", ".join(differ)
                + "; LeRobot will offer to write the file at its next connect"
            )
        )
    return checks


def _convert_lerobot(
    calibration: Any,
    source: Path,
    joints: list[Any],
    margin: float,
    output: Path | None,
    urdf: Path | None,
    urdf_text: str | None,
    urdf_out: Path | None,
    in_place: bool,
    allow_widen: bool,
) -> None:
    """--from-lerobot without a bus: the file's ranges as a limits YAML and URDF limits. The arm
    file's zero_ticks are taken as readings under the file's homing offsets (the offsets LeRobot
    writes into the servos)."""

    from armtool.servo import limits as L

    ranges = []
    for j in joints:
        if j.model is None:
            raise ArmtoolError(
                f"joint '{j.name}' has no model in the arm file",
                str(source),
                hint="give every joint a model (e.g. model: STS3215) to convert ticks to radians",
            )
        _check_motion_options(j, margin, 0.0)
        cal = calibration[j.name]
        ranges.append(
            L.JointRange(
                j,
                j.model,
                cal.range_min,
                cal.range_max,
                "lerobot",
                {
                    "source": str(source),
                    "lerobot_homing_offset": cal.homing_offset,
                    "lerobot_drive_mode": cal.drive_mode,
                },
            )
        )
    rows = [L.convert(r, margin) for r in ranges]
    for row, j in zip(rows, joints):
        row["homing_offset"] = calibration[j.name].homing_offset
    new_urdf = None
    if urdf_text is not None:
        new_urdf = L.patch_urdf(
            urdf_text, {r["name"]: (r["lower_rad"], r["upper_rad"]) for r in rows}, allow_widen, str(urdf)
        )
    doc = L.limits_document(rows, "", "", 0)
    doc["bus"] = None  # converted from a file: no bus was used
    doc["source"] = {"lerobot_calibration": str(source)}
    doc_text = L.dump_yaml(doc)
    _summary(rows, ranges)
    _write_outputs(doc_text, output, new_urdf, urdf, urdf_text, urdf_out, in_place)


def _write_outputs(
    doc_text: str,
    output: Path | None,
    new_urdf: str | None,
    urdf: Path | None,
    urdf_text: str | None,
    urdf_out: Path | None,
    in_place: bool,
) -> None:
    """The limits YAML (to -o or stdout) and the URDF with the new limits. A failed -o keeps the
    limits in a .partial file: a recording must not be repeated for a write."""
    from rich.markup import escape

    from armtool.console import stderr, write_stdout
    from armtool.fileio import rescue_write, write_with_backup
    from armtool.servo import limits as L

    con = stderr()
    if output is not None:
        try:
            L.write_atomic(output, doc_text)
        except ArmtoolError as exc:
            saved = rescue_write(output, doc_text, "armtool-limits")
            raise ArmtoolError(f"{exc.what}; the limits were saved to {saved}", exc.where, exc.hint) from None
        con.print(escape(f"wrote {output}"))
    else:
        write_stdout(doc_text)
    if new_urdf is not None and urdf is not None:
        if in_place:
            backup = write_with_backup(urdf, new_urdf, urdf_text or "")
            con.print(escape(f"wrote {urdf} (previous version in {backup.name})"))
        elif urdf_out is not None:
            L.write_atomic(urdf_out, new_urdf)
            con.print(escape(f"wrote {urdf_out}"))
