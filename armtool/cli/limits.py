"""`armtool limits`: record each joint's real range over a Dynamixel or Feetech bus."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import Any, Optional

import typer

from armtool.errors import ArmtoolError
from armtool.extras import require


class Mode(str, Enum):
    MANUAL = "manual"
    AUTO = "auto"


class ProtocolOption(str, Enum):
    DXL1 = "dxl1"
    DXL2 = "dxl2"
    FEETECH = "feetech"


def limits(
    port: str = typer.Option(..., "--port", help="Serial port of the bus adapter (e.g. /dev/ttyUSB0)."),
    mode: Mode = typer.Option(..., "--mode", help="manual: you move the joints (torque off); auto: seek each stop at low torque."),
    protocol: Optional[ProtocolOption] = typer.Option(None, "--protocol", help="dxl1 (AX/MX), dxl2 (X series) or feetech (STS/SCS) [default: the arm file's, else dxl1]."),
    baud: Optional[int] = typer.Option(None, "--baud", help="Baud rate [default: the arm file's, else 1000000]."),
    ids: Optional[str] = typer.Option(None, "--ids", help="Servo IDs, e.g. 1,2,3 or 1-6 (or use --arm)."),
    model: Optional[str] = typer.Option(None, "--model", help="With --ids: the model every ID must be (e.g. AX-12A)."),
    arm: Optional[Path] = typer.Option(None, "--arm", help="Arm YAML: joints with name, id, model, zero_ticks, direction."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write the limits YAML here (default: stdout)."),
    margin: float = typer.Option(2.0, "--margin", help="Degrees kept inside each recorded end."),
    duration: Optional[float] = typer.Option(None, "--duration", help="Manual: record this many seconds (default: until Enter)."),
    rate: float = typer.Option(50.0, "--rate", help="Manual: samples per second."),
    min_dwell: float = typer.Option(0.3, "--min-dwell", help="Manual: seconds a joint must rest at an end to confirm it."),
    torque_limit: float = typer.Option(30.0, "--torque-limit", help="Auto: torque (or PWM) limit in percent of full."),
    speed: float = typer.Option(30.0, "--speed", help="Auto: seek speed in degrees per second."),
    stall_window: float = typer.Option(0.12, "--stall-window", help="Auto: seconds without motion that, with high load, mean a stop."),
    stall_load: float = typer.Option(70.0, "--stall-load", help="Auto: load, in percent of the torque limit, that means a stop."),
    back_off: float = typer.Option(3.0, "--back-off", help="Auto: degrees to back off after each stop."),
    max_seek: Optional[float] = typer.Option(None, "--max-seek", help="Auto: seconds per direction before giving up [default: range/speed x 1.5 + 2]."),
    first_dir: str = typer.Option("-", "--first-dir", help="Auto: seek the low (-) or high (+) end first."),
    urdf: Optional[Path] = typer.Option(None, "--urdf", help="Write <limit lower upper> into this URDF (keeps its text and comments)."),
    in_place: bool = typer.Option(False, "--in-place", help="With --urdf: edit it in place, leaving a .bak copy."),
    urdf_out: Optional[Path] = typer.Option(None, "--urdf-out", help="With --urdf: write the edited URDF here."),
    allow_widen: bool = typer.Option(False, "--allow-widen", help="Write URDF limits even where they are wider than the URDF's."),
    write_eeprom: bool = typer.Option(False, "--write-eeprom", help="Also write the safe range into the servos' angle-limit registers."),
    yes: bool = typer.Option(False, "--yes", "-y", help="Answer the safety and EEPROM prompts with yes (scripted use)."),
    dry_run: bool = typer.Option(False, "--dry-run", help="With --write-eeprom: show the EEPROM writes, do not make them."),
    timeout_ms: float = typer.Option(25.0, "--timeout-ms", help="Reply timeout per transaction."),
) -> None:
    require("servo")  # exit 2 with the install command when the extra is missing
    import sys

    from armtool.console import stderr, write_stdout
    from armtool.servo import limits as L
    from armtool.servo.bus import open_bus
    from armtool.servo.guard import TorqueGuard
    from armtool.servo.models import by_name

    # ---- arguments, before touching the bus
    if (ids is None) == (arm is None):
        raise ArmtoolError("give exactly one of --ids or --arm", hint="e.g. --ids 1,2,3 --model AX-12A, or --arm arm.yaml")
    if margin < 0 or rate <= 0 or speed <= 0 or not 0 < torque_limit <= 100 or not 0 < stall_load <= 100:
        raise ArmtoolError("--margin must be >= 0, --rate/--speed > 0, --torque-limit and --stall-load in (0, 100]")
    if first_dir not in ("-", "+"):
        raise ArmtoolError(f"--first-dir must be - or +, got '{first_dir}'")
    if duration is not None and duration <= 0:
        raise ArmtoolError(f"--duration must be > 0 seconds, got {duration}")
    if urdf is not None and in_place == (urdf_out is not None):
        raise ArmtoolError("with --urdf pass either --in-place or --urdf-out FILE")
    if urdf is None and (in_place or urdf_out is not None):
        raise ArmtoolError("--in-place and --urdf-out need --urdf")
    if dry_run and not write_eeprom:
        raise ArmtoolError("--dry-run applies to --write-eeprom")
    interactive = sys.stdin.isatty()
    if mode is Mode.MANUAL and duration is None and not interactive:
        raise ArmtoolError("manual mode ends on Enter, but stdin is not a terminal", hint="pass --duration SECONDS")
    if mode is Mode.AUTO and not yes and not interactive:
        raise ArmtoolError("auto mode moves the arm and needs a confirmation, but stdin is not a terminal",
                           hint="pass --yes once the workspace is clear")
    if write_eeprom and not dry_run and not yes and not interactive:
        raise ArmtoolError("--write-eeprom needs a confirmation, but stdin is not a terminal", hint="pass --yes, or --dry-run to see the writes")

    if arm is not None:
        arm_file = L.load_arm(arm)
        joints = arm_file.joints
        proto = protocol.value if protocol else (arm_file.protocol or "dxl1")
        baud_rate = baud or arm_file.baud or 1_000_000
    else:
        expected = by_name(model) if model else None
        joints = [L.Joint(f"id{i}", i, expected) for i in L.parse_ids(ids or "")]
        proto = protocol.value if protocol else "dxl1"
        baud_rate = baud or 1_000_000
    for j in joints:
        if j.model is not None and j.model.protocol != proto:
            raise ArmtoolError(f"joint '{j.name}': {j.model.name} speaks {j.model.protocol}, not {proto}",
                               hint=f"pass --protocol {j.model.protocol}")
    urdf_text = None
    if urdf is not None:
        try:
            urdf_text = urdf.read_text()
        except OSError as exc:
            raise ArmtoolError(f"cannot read {urdf}: {exc.strerror}") from None
        L.check_urdf_names(urdf_text, [j.name for j in joints], str(urdf))
    if output is not None and not output.parent.exists():
        raise ArmtoolError(f"directory {output.parent} does not exist (for -o)")

    # ---- the bus
    con = stderr()
    bus = open_bus(port, proto, baud_rate, echo_check_id=joints[0].id, timeout_ms=timeout_ms)
    try:
        for w in bus.warnings:
            con.print(f"[yellow]warning:[/yellow] {w}")
        bus.identify([j.id for j in joints], {j.id: j.model for j in joints if j.model is not None})
        for j in joints:
            j.model = bus.model(j.id)
        slow = [j.id for j in joints if bus.read(j.id, "return_delay") > 0]
        if slow:
            con.print(f"[yellow]warning:[/yellow] ID {', '.join(map(str, slow))}: Return Delay Time > 0 slows every reply; "
                      "set it to 0 (register return_delay)")
        if mode is Mode.AUTO and not yes:
            if not typer.confirm("Auto mode drives every joint into its mechanical stops at low torque. "
                                 "Is the workspace clear and the arm free to move?", err=True):
                raise ArmtoolError("not confirmed; nothing was moved")
        with TorqueGuard(bus) as guard:
            if mode is Mode.MANUAL:
                ranges = _manual(bus, guard, joints, duration, rate, min_dwell, interactive)
            else:
                params = L.AutoParams(torque_limit=torque_limit / 100, speed_deg_s=speed, stall_window_s=stall_window,
                                      stall_load=stall_load / 100, back_off_deg=back_off, max_seek_s=max_seek,
                                      first_dir=-1 if first_dir == "-" else 1)
                ranges = _auto(bus, guard, joints, params)
        rows = [L.convert(r, margin) for r in ranges]
        unconfirmed = [f"{r.joint.name} ({'min' if not r.evidence.get('confirmed_min', True) else 'max'})"
                       for r in ranges if not r.confirmed and r.method == "manual"]
        # ---- everything computed in memory first: no half-written outputs
        new_urdf = None
        if urdf_text is not None:
            new_urdf = L.patch_urdf(urdf_text, {r["name"]: (r["lower_rad"], r["upper_rad"]) for r in rows},
                                    allow_widen, str(urdf))
        doc_text = L.dump_yaml(L.limits_document(rows, port, proto, baud_rate))
        _summary(rows, ranges)
        ends = [f"{r.joint.name} ({k[7:]})" for r in ranges for k in ("reason_min", "reason_max")
                if "range end" in str(r.evidence.get(k, ""))]
        if ends:
            con.print("[yellow]no stop found before the servo's range end[/yellow] (or the travel crosses the encoder seam; "
                      "use --mode manual for those): " + ", ".join(ends))
        if unconfirmed:
            con.print(f"[yellow]unconfirmed ends[/yellow] (the joint did not rest there {min_dwell:g} s): "
                      + ", ".join(unconfirmed))
        if output is not None:
            L.write_atomic(output, doc_text)
            con.print(f"wrote {output}")
        else:
            write_stdout(doc_text)
        if new_urdf is not None and urdf is not None:
            if in_place:
                L.write_atomic(urdf.with_name(urdf.name + ".bak"), urdf_text or "")
                L.write_atomic(urdf, new_urdf)
                con.print(f"wrote {urdf} (previous version in {urdf.name}.bak)")
            elif urdf_out is not None:
                L.write_atomic(urdf_out, new_urdf)
                con.print(f"wrote {urdf_out}")
        if write_eeprom:  # after the YAML: a refused EEPROM write must not lose the recording
            _do_eeprom(bus, _eeprom_plan(bus, ranges, rows), yes, dry_run)
    finally:
        bus.close()


def _manual(bus: Any, guard: Any, joints: list[Any], duration: float | None, rate: float, min_dwell: float,
            interactive: bool) -> list[Any]:
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
        table.add_row(j.name, str(j.id), str(rec.present.get(j.id, "-")),
                      *(str(v) for v in (ext if ext else ("-", "-"))))
    return table


def _auto(bus: Any, guard: Any, joints: list[Any], params: Any) -> list[Any]:
    from rich.progress import Progress, TextColumn, TimeElapsedColumn

    from armtool.console import stderr
    from armtool.servo.limits import seek_joint

    ranges = []
    with Progress(TextColumn("{task.description}"), TimeElapsedColumn(), console=stderr(), transient=False) as bar:
        for j in joints:
            task = bar.add_task(f"{j.name} (ID {j.id})")

            def show(joint: Any, label: str, pos: int, load: float, task: Any = task) -> None:
                bar.update(task, description=f"{joint.name} (ID {joint.id}) seeking {label}: {pos} ticks, load {load:.0%} of limit")

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
        how = r.method if r.method == "manual" else "auto: " + "/".join(
            str(r.evidence[k]).split(" (")[0] for k in ("reason_min", "reason_max"))
        if not r.confirmed:
            how += " [yellow](unconfirmed)[/yellow]"
        table.add_row(row["name"], str(row["id"]), f"{row['raw_min_ticks']}..{row['raw_max_ticks']}",
                      f"{row['safe_min_ticks']}..{row['safe_max_ticks']}", f"{math.degrees(row['lower_rad']):.1f}",
                      f"{math.degrees(row['upper_rad']):.1f}", how)
    stderr().print(table)


def _eeprom_plan(bus: Any, ranges: list[Any], rows: list[dict[str, Any]]) -> list[Any]:
    from armtool.servo.eeprom import plan_writes

    bad = [r.joint.name for r in ranges if not r.confirmed]
    if bad:
        raise ArmtoolError(f"not writing EEPROM limits: unconfirmed ends on {', '.join(bad)} "
                           "(the limits YAML was written)",
                           hint="manual: hold each joint at each end for --min-dwell seconds; auto: an end where no "
                                "stop was found is the servo's range end (or the seam), record it with --mode manual")
    seam = [r.joint.name for r in ranges if r.crosses_seam]
    if seam:
        raise ArmtoolError(f"not writing EEPROM limits: the range of {', '.join(seam)} crosses the encoder seam",
                           hint="set a homing offset that centres the range on 2048, then record again")
    wanted = {row["id"]: {"min_limit": row["safe_min_ticks"], "max_limit": row["safe_max_ticks"]} for row in rows}
    return plan_writes(bus, wanted)


def _do_eeprom(bus: Any, plan: list[Any], yes: bool, dry_run: bool) -> None:
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
