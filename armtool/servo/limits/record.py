"""`armtool limits` from its checked options to the written files: open the bus, identify the
servos, record each joint's range (by hand or by a torque-limited seek), then write the limits
YAML, the URDF limits, a LeRobot calibration and the EEPROM angle limits, in that order.

Why that order: everything is computed in memory first (no half-written outputs), and the
limits YAML is written before anything that can still be refused, so a recording is never lost.
The command line supplies `Hooks` (questions, notes, live tables); nothing here prints.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus
from armtool.servo.eeprom import EepromWrite
from armtool.servo.guard import TorqueGuard
from armtool.servo.limits.arm_file import Joint, JointRange
from armtool.servo.limits.auto import AutoParams, seek_joint
from armtool.servo.limits.choices import Mode
from armtool.servo.limits.document import convert, dump_yaml, limits_document, summary, write_atomic, write_outputs
from armtool.servo.limits.manual import ManualRecorder
from armtool.servo.limits.request import (
    Request,
    check_motion_options,
    check_outputs,
    check_request,
    full_turn_names,
    read_urdf,
    resolve_arm,
)
from armtool.servo.summary import Cell, Summary


@dataclass(frozen=True)
class Hooks:
    """What a recording asks of the person at the command line."""

    confirm: Callable[[str, str], None]  # (question, what to say on no): returns on yes, raises otherwise
    note: Callable[[Cell], None]  # a line of news for stderr
    table: Callable[[Summary], None]  # a table for stderr
    live: Callable[[Summary], AbstractContextManager[Callable[[Summary], None]]]  # a table redrawn in place
    progress: Callable[[], AbstractContextManager[Callable[[int, str], None]]]  # (key, status) lines
    enter_pressed: Callable[[], bool]  # the person pressed Enter since the last look
    stdout: Callable[[str], None]  # the limits YAML when there is no -o


def _warning(text: str) -> Cell:
    return (("warning:", "yellow"), (f" {text}", ""))


def run(r: Request, hooks: Hooks, interactive: bool) -> bool:
    """Record (or convert) the limits and write every output; False when a LeRobot file reaches
    past a recorded stop (the command exits 1)."""
    from armtool.servo import lerobot as LR
    from armtool.servo.limits import lerobot_files as LF

    check_request(r, interactive)
    arm = resolve_arm(r)
    joints = arm.joints
    urdf_text = read_urdf(r, joints)
    check_outputs(r)
    full_turn = full_turn_names(r.lerobot_full_turn, joints)
    calibration = None
    if r.from_lerobot is not None:
        calibration = LR.read_calibration(r.from_lerobot)
        rules = {j.name: LR.offset_rule(j.model) for j in joints if j.model is not None}
        LR.check_against_arm(calibration, joints, r.from_lerobot, rules)
        if r.port is None:
            ranges, rows = LF.converted_ranges(calibration, r.from_lerobot, joints, r.margin)
            new_urdf = _patched_urdf(r, urdf_text, rows)
            doc = limits_document(rows, "", "", 0)
            doc["bus"] = None  # converted from a file: no bus was used
            doc["source"] = {"lerobot_calibration": str(r.from_lerobot)}
            hooks.table(summary(rows, ranges))
            write_outputs(
                dump_yaml(doc), r.output, r.urdf, urdf_text, new_urdf, r.urdf_out, r.in_place, hooks.note, hooks.stdout
            )
            return True
    assert r.port is not None and r.mode is not None  # check_request saw to it
    from armtool.servo.bus import open_bus

    checks = None
    bus = open_bus(r.port, arm.protocol, arm.baud, echo_check_id=joints[0].id, timeout_ms=r.timeout_ms)
    try:
        for w in bus.warnings:
            hooks.note(_warning(w))
        bus.identify([j.id for j in joints], {j.id: j.model for j in joints if j.model is not None})
        for j in joints:
            j.model = bus.model(j.id)
            check_motion_options(j, r.margin, r.back_off)
        state = LF.servo_states(bus, joints) if (r.lerobot_calibration or r.from_lerobot) else {}
        if calibration is not None and r.from_lerobot is not None:  # offsets against the mode each servo is in
            LR.check_against_arm(calibration, joints, r.from_lerobot, {n: st.rule for n, st in state.items()})
        slow = [j.id for j in joints if bus.read(j.id, "return_delay") > 0]
        if slow:
            hooks.note(
                _warning(
                    f"ID {', '.join(map(str, slow))}: Return Delay Time > 0 slows every reply; "
                    "set it to 0 (register return_delay)"
                )
            )
        if r.mode is Mode.AUTO and not r.yes:
            hooks.confirm(
                "Auto mode drives every joint into its mechanical stops at low torque. "
                "Is the workspace clear and the arm free to move?",
                "not confirmed; nothing was moved",
            )
        with TorqueGuard(bus) as guard:
            if r.mode is Mode.MANUAL:
                ranges = record_manual(bus, guard, joints, r.duration, r.rate, r.min_dwell, hooks)
            else:
                ranges = seek_all(bus, guard, joints, r.auto_params(), hooks)
        rows = [convert(x, r.margin) for x in ranges]
        unconfirmed = [
            f"{x.joint.name} ({'min' if not x.evidence.get('confirmed_min', True) else 'max'})"
            for x in ranges
            if not x.confirmed and x.method == "manual"
        ]
        # ---- everything computed in memory first: no half-written outputs
        new_urdf = _patched_urdf(r, urdf_text, rows)
        for row in rows:
            if row["name"] in state:
                row["homing_offset"] = state[row["name"]].homing_offset
        doc_text = dump_yaml(limits_document(rows, r.port, arm.protocol, arm.baud))
        lerobot_text, lerobot_error = None, None
        if r.lerobot_calibration is not None:
            try:
                lerobot_text = LF.calibration_document(ranges, rows, state, full_turn)
            except ArmtoolError as exc:  # reported after the limits YAML is written: the recording is kept
                lerobot_error = exc
        if calibration is not None and r.from_lerobot is not None:
            checks, comparison = LF.compare_ranges(calibration, r.from_lerobot, ranges, state)
            hooks.table(comparison)
        hooks.table(summary(rows, ranges))
        _report_ends(ranges, unconfirmed, r.min_dwell, hooks)
        write_outputs(doc_text, r.output, r.urdf, urdf_text, new_urdf, r.urdf_out, r.in_place, hooks.note, hooks.stdout)
        if lerobot_error is not None:
            raise ArmtoolError(
                f"{lerobot_error.what} (the limits YAML was written; no LeRobot file)",
                lerobot_error.where,
                lerobot_error.hint,
            )
        if lerobot_text is not None and r.lerobot_calibration is not None:
            _write_lerobot(r.lerobot_calibration, lerobot_text, hooks)
        if r.write_eeprom:  # after the YAML: a refused EEPROM write must not lose the recording
            write_eeprom(bus, eeprom_plan(bus, ranges, rows), r.yes, r.dry_run, hooks)
    finally:
        bus.close()
    return checks is None or all(c.ok(LF.TOLERANCE_TICKS) for c in checks)


def _patched_urdf(r: Request, urdf_text: str | None, rows: list[dict[str, Any]]) -> str | None:
    from armtool.servo.limits.urdf import patch_urdf

    if urdf_text is None:
        return None
    limits = {row["name"]: (row["lower_rad"], row["upper_rad"]) for row in rows}
    return patch_urdf(urdf_text, limits, r.allow_widen, str(r.urdf))


def _report_ends(ranges: list[JointRange], unconfirmed: list[str], min_dwell: float, hooks: Hooks) -> None:
    """Ends that are not mechanical stops, and ends a person did not hold long enough."""
    ends = [
        f"{x.joint.name} ({k[7:]})"
        for x in ranges
        for k in ("reason_min", "reason_max")
        if "range end" in str(x.evidence.get(k, ""))
    ]
    if ends:
        hooks.note(
            (
                ("no stop found before the servo's range end", "yellow"),
                (" (or the travel crosses the encoder seam; use --mode manual for those): " + ", ".join(ends), ""),
            )
        )
    if unconfirmed:
        hooks.note(
            (
                ("unconfirmed ends", "yellow"),
                (f" (the joint did not rest there {min_dwell:g} s): " + ", ".join(unconfirmed), ""),
            )
        )


def _write_lerobot(path: Path, text: str, hooks: Hooks) -> None:
    from armtool.fileio import rescue_write

    try:
        write_atomic(path, text)
    except ArmtoolError as exc:  # keep the recording: a run must not be repeated for a write
        saved = rescue_write(path, text, "armtool-lerobot")
        raise ArmtoolError(f"{exc.what}; the LeRobot calibration was saved to {saved}", exc.where, exc.hint) from None
    hooks.note(f"wrote {path} (LeRobot calibration; LeRobot offers to write it into the servos at the next connect)")


def manual_summary(rec: ManualRecorder) -> Summary:
    """The live table of a manual recording: each joint's present position and extent so far."""
    table = Summary("joint ranges (ticks)", ("joint", "id", "present", "min", "max"), left=("joint",))
    for j in rec.joints:
        ext = rec.extent(j.id)
        table.rows.append(
            (j.name, str(j.id), str(rec.present.get(j.id, "-")), *(str(v) for v in (ext if ext else ("-", "-"))))
        )
    return table


def record_manual(
    bus: ServoBus,
    guard: TorqueGuard,
    joints: list[Joint],
    duration: float | None,
    rate: float,
    min_dwell: float,
    hooks: Hooks,
) -> list[JointRange]:
    """Torque off; sample until `duration` passes or (without one) the person presses Enter."""
    for j in joints:
        guard.touch(j.id)
        if not guard.torque_off(j.id):
            raise ArmtoolError(f"ID {j.id}: torque did not go off")
    rec = ManualRecorder(bus, joints, min_dwell_s=min_dwell)
    how = f"for {duration:g} s" if duration else "until you press Enter"
    hooks.note(f"torque is off: move every joint to both of its ends and hold it there a moment; recording {how}")
    start = time.monotonic()
    with hooks.live(manual_summary(rec)) as show:
        while True:
            rec.sample()
            show(manual_summary(rec))
            if duration is not None and time.monotonic() - start >= duration:
                break
            if hooks.enter_pressed() and duration is None:
                break
            time.sleep(max(0.0, 1.0 / rate))
    return rec.results()


def seek_all(
    bus: ServoBus, guard: TorqueGuard, joints: list[Joint], params: AutoParams, hooks: Hooks
) -> list[JointRange]:
    """Each joint's stops in turn, with a status line per joint."""
    ranges = []
    with hooks.progress() as status:
        for j in joints:
            status(j.id, f"{j.name} (ID {j.id})")

            def show(joint: Joint, label: str, pos: int, load: float) -> None:
                status(joint.id, f"{joint.name} (ID {joint.id}) seeking {label}: {pos} ticks, load {load:.0%} of limit")

            found = seek_joint(bus, guard, j, params, show)
            status(j.id, f"{j.name} (ID {j.id}): {found.raw_min}..{found.raw_max} ticks")
            ranges.append(found)
    return ranges


def eeprom_plan(bus: ServoBus, ranges: list[JointRange], rows: list[dict[str, Any]]) -> list[EepromWrite]:
    """The angle-limit writes for the safe ranges; refused for unconfirmed ends and seam crossings."""
    from armtool.servo.eeprom import plan_writes

    bad = [x.joint.name for x in ranges if not x.confirmed]
    if bad:
        raise ArmtoolError(
            f"not writing EEPROM limits: unconfirmed ends on {', '.join(bad)} (the limits YAML was written)",
            hint="manual: hold each joint at each end for --min-dwell seconds; auto: an end where no "
            "stop was found is the servo's range end (or the seam), record it with --mode manual",
        )
    seam = [x.joint.name for x in ranges if x.crosses_seam]
    if seam:
        raise ArmtoolError(
            f"not writing EEPROM limits: the range of {', '.join(seam)} crosses the encoder seam",
            hint="set a homing offset that centres the range on 2048, then record again",
        )
    wanted = {row["id"]: {"min_limit": row["safe_min_ticks"], "max_limit": row["safe_max_ticks"]} for row in rows}
    return plan_writes(bus, wanted)


def write_eeprom(bus: ServoBus, plan: list[EepromWrite], yes: bool, dry_run: bool, hooks: Hooks) -> None:
    from armtool.servo.eeprom import apply_writes

    if not plan:
        hooks.note("EEPROM limits already set; nothing to write")
        return
    for w in plan:
        hooks.note(("would write " if dry_run else "EEPROM: ") + w.describe())
    if dry_run:
        return
    if not yes:
        hooks.confirm(
            f"Write {len(plan)} EEPROM value(s)?", "EEPROM writes not confirmed; nothing written to the servos"
        )
    apply_writes(bus, plan)
    hooks.note(f"EEPROM: {len(plan)} value(s) written and verified by reading back")
