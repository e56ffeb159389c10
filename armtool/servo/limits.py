"""Record each joint's real range: by hand (torque off, min/max with dwell) or by a torque-limited
seek to each mechanical stop; convert ticks to radians; write the limits YAML and URDF limits.

Stall = the position moved at most `stall_ticks` over `stall_window_s` AND |load| >= `stall_load`
of the torque limit, or the overload alarm (research/servo.md 5.2). Moving = 0 alone is not
used (it stays 1 while pushing a stop), nor load alone (STS load is a PWM duty).
"""

from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, cast

from armtool.errors import ArmtoolError
from armtool.servo.bus import ServoBus
from armtool.servo.models import ServoModel, by_name
from armtool.servo.motion import StallDetector, load_fraction
from armtool.servo.registry import check_protocol, transport_class

SCHEMA = "armtool.limits/1"
LIMITS_VERSION = 1


# ---------------------------------------------------------------- arm description
@dataclass
class Joint:
    name: str
    id: int
    model: ServoModel | None = None  # None: whatever answers (from --ids without --model)
    zero_ticks: int | None = None  # None: the middle of the servo's range
    direction: int = 1


@dataclass
class ArmFile:
    joints: list[Joint]
    protocol: str | None = None
    baud: int | None = None


def load_arm(path: Path) -> ArmFile:
    """`joints: [{name, id, model, zero_ticks, direction}]` plus optional top-level protocol/baud."""
    from armtool.fileio import read_yaml

    data = read_yaml(path, "arm")
    if not isinstance(data, dict) or not isinstance(data.get("joints"), list) or not data["joints"]:
        raise ArmtoolError("arm file needs a 'joints' list", str(path),
                           hint="joints: [{name: shoulder, id: 1, model: AX-12A, zero_ticks: 512, direction: 1}]")
    # cast: YAML is untyped data; the isinstance on the same line checks it (mypy cannot connect the two .get calls)
    bus = cast("dict[str, Any]", data.get("bus")) if isinstance(data.get("bus"), dict) else data
    joints: list[Joint] = []
    seen_ids: set[int] = set()
    seen_names: set[str] = set()
    for k, e in enumerate(data["joints"]):
        where = f"{path}: joints[{k}]"
        if not isinstance(e, dict) or "id" not in e:
            raise ArmtoolError("each joint needs an 'id'", where)
        sid = _whole(e["id"], "id", where)
        direction = _whole(e.get("direction", 1), "direction", where)
        zero = None if e.get("zero_ticks") is None else _whole(e["zero_ticks"], "zero_ticks", where)
        if not 0 <= sid <= 252:
            raise ArmtoolError(f"id {sid} is outside 0..252", where, hint="servo IDs on a bus are 0..252")
        if direction not in (1, -1):
            raise ArmtoolError(f"direction must be 1 or -1, got {direction}", where)
        name = str(e.get("name", f"id{sid}"))
        if sid in seen_ids or name in seen_names:
            raise ArmtoolError(f"joint '{name}' / id {sid} appears twice", where)
        seen_ids.add(sid)
        seen_names.add(name)
        try:
            model = by_name(str(e["model"])) if e.get("model") else None
        except ArmtoolError as exc:
            raise ArmtoolError(exc.what, where, exc.hint) from None
        if model is not None and zero is not None and not 0 <= zero <= model.max_tick:
            raise ArmtoolError(f"zero_ticks {zero} is outside 0..{model.max_tick} of a {model.name}", where)
        joints.append(Joint(name, sid, model, zero, direction))
    baud = bus.get("baud")
    protocol = bus.get("protocol")
    if protocol is not None:
        check_protocol(str(protocol), str(path))
    rate = None if baud is None else _whole(baud, "baud", str(path))
    if rate is not None and not 0 < rate <= 20_000_000:
        raise ArmtoolError(f"baud must be a positive baud rate, got {rate}", str(path), hint="e.g. baud: 1000000")
    return ArmFile(joints, protocol, rate)


def _whole(value: Any, key: str, where: str) -> int:
    """An integer from YAML: 3 or "3", never 1.7 (read as 1) nor `fast`."""
    if isinstance(value, bool) or not isinstance(value, (int, str)):
        if not (isinstance(value, float) and value.is_integer()):
            raise ArmtoolError(f"'{key}' must be a whole number, got {value!r}", where)
    try:
        return int(value)
    except ValueError:
        raise ArmtoolError(f"'{key}' must be a whole number, got {value!r}", where) from None


def parse_ids(text: str) -> list[int]:
    """`--ids` as distinct IDs 0..252, bounded before any range is expanded."""
    from armtool.cli.options import parse_id_list

    return parse_id_list(text, "--ids", 0, 252)


# ---------------------------------------------------------------- results
@dataclass
class JointRange:
    joint: Joint
    model: ServoModel
    raw_min: int
    raw_max: int
    method: str
    evidence: dict[str, Any] = field(default_factory=dict)

    @property
    def confirmed(self) -> bool:
        return bool(self.evidence.get("confirmed_min", True) and self.evidence.get("confirmed_max", True))

    @property
    def crosses_seam(self) -> bool:
        return self.raw_min < 0 or self.raw_max > self.model.max_tick


# ---------------------------------------------------------------- manual mode
class ManualRecorder:
    """Samples present positions with torque off; unwraps 4096-tick seam crossings."""

    def __init__(self, bus: ServoBus, joints: list[Joint], settle_ticks: int = 2, min_dwell_s: float = 0.3,
                 max_silence_s: float = 1.0) -> None:
        self.bus = bus
        self.joints = joints
        self.settle_ticks = settle_ticks
        self.min_dwell_s = min_dwell_s
        self.max_silence_s = max_silence_s
        self.traces: dict[int, list[tuple[float, int]]] = {j.id: [] for j in joints}
        self.present: dict[int, int] = {}
        self.missed: dict[int, int] = {j.id: 0 for j in joints}
        self._t0 = time.monotonic()
        self._last_reply: dict[int, float] = {j.id: 0.0 for j in joints}

    def sample(self) -> None:
        """One reading per joint. A person records for minutes: a reply lost now and then (noise,
        a loaded machine) skips that joint until the next sample; only an ID silent for more than
        `max_silence_s` ends the session. A lost port ends it at once."""
        from armtool.servo.bus import CommError

        t = time.monotonic() - self._t0
        for j in self.joints:
            try:
                raw = self.bus.read(j.id, "present_position")
            except CommError as exc:
                self.missed[j.id] += 1
                silent = t - self._last_reply[j.id]
                if silent > self.max_silence_s:
                    raise ArmtoolError(f"ID {j.id} ('{j.name}') has not answered for {silent:.1f} s: {exc.what}",
                                       hint="check the cable and power of that servo") from None
                continue
            self._last_reply[j.id] = t
            model = self.bus.model(j.id)
            trace = self.traces[j.id]
            if model.wraps and trace:
                last = trace[-1][1]
                delta = (raw - last) % model.ticks
                if delta > model.ticks // 2:
                    delta -= model.ticks
                value = last + delta
            else:
                value = raw
            trace.append((t, value))
            self.present[j.id] = raw

    def extent(self, sid: int) -> tuple[int, int] | None:
        trace = self.traces[sid]
        if not trace:
            return None
        values = [v for _, v in trace]
        return min(values), max(values)

    def _dwell(self, trace: list[tuple[float, int]], extreme: int) -> float:
        best = 0.0
        start: float | None = None
        for t, v in trace:
            if abs(v - extreme) <= self.settle_ticks:
                start = t if start is None else start
                best = max(best, t - start)
            else:
                start = None
        return best

    def results(self) -> list[JointRange]:
        out: list[JointRange] = []
        for j in self.joints:
            model = self.bus.model(j.id)
            trace = self.traces[j.id]
            if len(trace) < 2:
                raise ArmtoolError(f"joint '{j.name}' (ID {j.id}): no samples were recorded")
            lo, hi = self.extent(j.id)  # type: ignore[misc]
            if lo == hi:
                raise ArmtoolError(f"joint '{j.name}' (ID {j.id}) did not move (always {lo} ticks)",
                                   hint="move every joint to both ends before pressing Enter")
            shift = 0
            if model.wraps and lo < 0:
                shift = model.ticks * math.ceil(-lo / model.ticks)
            dmin, dmax = self._dwell(trace, lo), self._dwell(trace, hi)
            out.append(JointRange(j, model, lo + shift, hi + shift, "manual", {
                "confirmed_min": dmin >= self.min_dwell_s, "confirmed_max": dmax >= self.min_dwell_s,
                "dwell_min_s": round(dmin, 3), "dwell_max_s": round(dmax, 3), "samples": len(trace)}))
        return out


# ---------------------------------------------------------------- auto mode
@dataclass
class AutoParams:
    torque_limit: float = 0.30  # fraction of full torque/PWM
    speed_deg_s: float = 30.0
    stall_window_s: float = 0.12
    stall_ticks: int = 1
    stall_load: float = 0.70  # fraction of the torque limit
    back_off_deg: float = 3.0
    max_seek_s: float | None = None  # per direction; default range/speed*1.5 + 2 s
    first_dir: int = -1


def _full_torque(model: ServoModel) -> int:
    reg = model.reg("torque_limit")
    return reg.hi


Progress = Callable[[Joint, str, int, float], None]
RANGE_END = "servo range end"


def seek_joint(bus: ServoBus, guard: Any, joint: Joint, p: AutoParams, progress: Progress | None = None) -> JointRange:
    """Find both mechanical stops of one joint; leaves it holding just inside the last stop."""
    sid = joint.id
    model = bus.model(sid)
    mode = transport_class(model.protocol).position_mode
    if model.has("operating_mode") and mode is not None and bus.read(sid, "operating_mode") != mode:
        raise ArmtoolError(f"ID {sid} is not in position control mode (Operating Mode {mode})",
                           hint=f"set Operating Mode to {mode} (e.g. in Dynamixel Wizard) before `armtool limits --mode auto`")
    cap = max(1, round(p.torque_limit * _full_torque(model)))
    speed = model.speed_register(p.speed_deg_s)
    guard.set_ram(sid, "torque_limit", cap)
    guard.set_ram(sid, "moving_speed", speed)
    guard.torque_on(sid)
    lo_lim, hi_lim = bus.read(sid, "min_limit"), bus.read(sid, "max_limit")
    if lo_lim == hi_lim == 0:
        lo_lim, hi_lim = 0, model.max_tick
    span_deg = (hi_lim - lo_lim) * model.deg_per_tick
    max_seek = p.max_seek_s or span_deg / p.speed_deg_s * 1.5 + 2.0
    back_off = max(2, math.ceil(p.back_off_deg / model.deg_per_tick))
    ends: dict[int, tuple[int, str]] = {}
    max_load = 0.0
    for direction in (p.first_dir, -p.first_dir):
        label = "min" if direction < 0 else "max"
        target = lo_lim if direction < 0 else hi_lim
        bus.write(sid, "goal_position", target, retry=True)
        start = time.monotonic()
        stall = StallDetector(p.stall_window_s, p.stall_ticks)
        reason = ""
        pos = target
        while True:
            now = time.monotonic()
            if now - start > max_seek:
                guard.hold_here(sid)
                raise ArmtoolError(f"joint '{joint.name}' (ID {sid}): no stop found toward {label} within {max_seek:.1f} s",
                                   hint="raise --max-seek or --speed, or check that the joint can move")
            vals = bus.read_many(sid, ["present_position", "present_load"])
            pos, load = vals["present_position"], vals["present_load"]
            load_frac = load_fraction(model, load, cap / _full_torque(model))
            max_load = max(max_load, load_frac)
            if progress is not None:
                progress(joint, label, pos, load_frac)
            if bus.transport.overload(bus.last_error.get(sid, 0)) or bus.transport.alarms(bus.last_error.get(sid, 0)):
                if bus.overloaded(sid):
                    reason = "overload alarm"
                    break
            if stall.add(now, pos):
                if load_frac >= p.stall_load:
                    reason = f"stall (|load| {load_frac:.0%} of limit)"
                    break
                if abs(pos - target) <= model.settle_ticks:
                    reason = f"{RANGE_END} (no stop before it)"
                    break
            time.sleep(0.005)
        ends[direction] = (pos, reason)
        held = guard.hold_here(sid)  # stop pushing at once
        if reason == "overload alarm":
            _rearm(bus, sid, model, cap)
        goal = held - direction * back_off
        goal = min(max(goal, lo_lim), hi_lim)
        bus.write(sid, "goal_position", goal, retry=True)
        deadline = time.monotonic() + 2.0
        while time.monotonic() < deadline and abs(bus.read(sid, "present_position") - goal) > model.settle_ticks:
            time.sleep(0.01)
    (lo, rlo), (hi, rhi) = ends[-1], ends[1]
    # the servo's own range end is not a mechanical stop (no stop, or the seam): never confirmed,
    # so --write-eeprom refuses it (SO-101 wrist_roll recorded 0..604 with 0 being the seam)
    return JointRange(joint, model, lo, hi, "auto", {
        "confirmed_min": not rlo.startswith(RANGE_END), "confirmed_max": not rhi.startswith(RANGE_END),
        "reason_min": rlo, "reason_max": rhi, "torque_limit": cap, "torque_limit_percent": round(100 * p.torque_limit, 1),
        "speed": speed, "speed_deg_s": p.speed_deg_s,
        "max_load_fraction_of_limit": round(max_load, 3)})


def _rearm(bus: ServoBus, sid: int, model: ServoModel, cap: int) -> None:
    rearm = transport_class(model.protocol).rearm
    if rearm is not None:
        bus.write(sid, rearm, cap if rearm == "torque_limit" else 1, retry=True)
    else:
        raise ArmtoolError(f"ID {sid} reports an overload hardware error and turned its torque off",
                           hint="lower --torque-limit; reboot the servo (power cycle) to clear the error")


# ---------------------------------------------------------------- conversion and outputs
def convert(r: JointRange, margin_deg: float) -> dict[str, Any]:
    model = r.model
    margin = math.ceil(margin_deg / model.deg_per_tick - 1e-9) if margin_deg > 0 else 0
    safe_min, safe_max = r.raw_min + margin, r.raw_max - margin
    if safe_min >= safe_max:
        raise ArmtoolError(f"joint '{r.joint.name}': range {r.raw_min}..{r.raw_max} ticks is too small for a "
                           f"{margin_deg:g}° margin", hint="lower --margin")
    zero = r.joint.zero_ticks if r.joint.zero_ticks is not None else model.default_zero
    if model.wraps:  # the zero in the turn nearest the middle of the range
        mid = (r.raw_min + r.raw_max) / 2
        zero = zero + model.ticks * round((mid - zero) / model.ticks)
    d = r.joint.direction
    a = d * (safe_min - zero) * model.rad_per_tick
    b = d * (safe_max - zero) * model.rad_per_tick
    evidence = dict(r.evidence)
    if r.crosses_seam:
        evidence["crosses_seam"] = True
    return {
        "name": r.joint.name, "id": r.joint.id, "model": model.name, "model_number": model.model_number,
        "ticks_per_range": model.ticks, "range_deg": model.range_deg, "homing_offset": None, "drive_mode": None,
        "zero_ticks": zero, "direction": d,
        "raw_min_ticks": r.raw_min, "raw_max_ticks": r.raw_max, "safe_min_ticks": safe_min, "safe_max_ticks": safe_max,
        "margin_deg": margin_deg, "lower_rad": round(min(a, b), 6), "upper_rad": round(max(a, b), 6),
        "method": r.method, "evidence": evidence,
    }


def limits_document(joints: list[dict[str, Any]], port: str, protocol: str, baud: int) -> dict[str, Any]:
    from datetime import datetime, timezone

    from armtool import __version__

    return {"schema": SCHEMA, "version": LIMITS_VERSION,
            "created": datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"), "tool": f"armtool {__version__}",
            "bus": {"port": port, "protocol": protocol, "baud": baud}, "joints": joints}


def dump_yaml(doc: dict[str, Any]) -> str:
    import yaml

    return yaml.safe_dump(doc, sort_keys=False, default_flow_style=None, width=120)


def write_atomic(path: Path, text: str) -> None:
    from armtool.fileio import write_atomic as write

    write(path, text)


# ---------------------------------------------------------------- URDF
_JOINT_RE = re.compile(r"<joint\b[^>]*/>|<joint\b[^>]*>.*?</joint\s*>", re.S)
_NAME_RE = re.compile(r"""\bname\s*=\s*(["'])(.*?)\1""")
_TYPE_RE = re.compile(r"""\btype\s*=\s*(["'])(.*?)\1""")
_LIMIT_RE = re.compile(r"<limit\b[^>]*?/?>", re.S)
_ATTR_RE = r"""(\b{}\s*=\s*)(["'])(.*?)\2"""


@dataclass
class UrdfJoint:
    name: str
    type: str
    lower: float | None
    upper: float | None


def urdf_joints(text: str, source: str = "URDF") -> dict[str, UrdfJoint]:
    out: dict[str, UrdfJoint] = {}
    for m in _JOINT_RE.finditer(_blank_comments(text)):
        block = m.group(0)
        head = block[: block.index(">")]
        name, jtype = _NAME_RE.search(head), _TYPE_RE.search(head)
        if not name or not jtype:  # a URDF joint always has a type; a reference to one does not
            continue
        lim = _LIMIT_RE.search(block)
        lower = upper = None
        if lim:
            lo = re.search(_ATTR_RE.format("lower"), lim.group(0))
            hi = re.search(_ATTR_RE.format("upper"), lim.group(0))
            lower = _urdf_float(lo.group(3), "lower", name.group(2), text, m.start(), source) if lo else None
            upper = _urdf_float(hi.group(3), "upper", name.group(2), text, m.start(), source) if hi else None
        out[name.group(2)] = UrdfJoint(name.group(2), jtype.group(2) if jtype else "", lower, upper)
    return out


_NOT_JOINTS_RE = re.compile(r"<!--.*?-->|<(transmission|ros2_control|gazebo)\b.*?</\1\s*>", re.S)


def _urdf_float(value: str, attr: str, joint: str, text: str, offset: int, source: str) -> float:
    try:
        return float(value)
    except ValueError:
        line = text.count("\n", 0, offset) + 1
        raise ArmtoolError(f"joint '{joint}': <limit {attr}=\"{value}\"> is not a number", f"{source}:{line}",
                           hint="run xacro first (xacro arm.urdf.xacro > arm.urdf) and pass the URDF it writes") from None


def _blank_comments(text: str) -> str:
    """Comments, and the blocks whose <joint name> only refers to a joint (<transmission>,
    <ros2_control>, <gazebo>), replaced by spaces of the same length, so offsets stay valid."""
    text = re.sub(r"<!--.*?-->", lambda m: " " * len(m.group(0)), text, flags=re.S)
    return _NOT_JOINTS_RE.sub(lambda m: " " * len(m.group(0)), text)


def check_urdf_names(text: str, names: list[str], source: str) -> dict[str, UrdfJoint]:
    joints = urdf_joints(text, source)
    missing = [n for n in names if n not in joints]
    if missing:
        raise ArmtoolError(f"joint(s) {', '.join(missing)} not in {source}",
                           hint="available: " + ", ".join(sorted(joints)) + "; the arm file's joint names must match the URDF")
    bad = [n for n in names if joints[n].type not in ("revolute", "prismatic")]
    if bad:
        raise ArmtoolError(f"joint(s) {', '.join(bad)} in {source} are not revolute (continuous/fixed joints have no limits)")
    return joints


def patch_urdf(text: str, limits: dict[str, tuple[float, float]], allow_widen: bool = False, source: str = "URDF") -> str:
    """New URDF text with `<limit lower upper>` set per joint; everything else kept byte for byte."""
    existing = check_urdf_names(text, list(limits), source)
    if not allow_widen:
        wider = [f"{n}: measured {lo:.4f}..{hi:.4f}, URDF {existing[n].lower:.4f}..{existing[n].upper:.4f}"
                 for n, (lo, hi) in limits.items()
                 if existing[n].lower is not None and existing[n].upper is not None
                 and (lo < existing[n].lower - 1e-6 or hi > existing[n].upper + 1e-6)]  # type: ignore[operator]
        if wider:
            raise ArmtoolError("measured limits lie outside the URDF's: " + "; ".join(wider),
                               hint="check zero_ticks/direction in the arm file, or pass --allow-widen to write them anyway")
    blanked = _blank_comments(text)
    edits: list[tuple[int, int, str]] = []
    for m in _JOINT_RE.finditer(blanked):
        head = m.group(0)[: m.group(0).index(">")]
        name = _NAME_RE.search(head)
        if not name or not _TYPE_RE.search(head) or name.group(2) not in limits:
            continue
        lo, hi = limits[name.group(2)]
        lim = _LIMIT_RE.search(m.group(0))
        if lim:
            tag = text[m.start() + lim.start(): m.start() + lim.end()]
            for attr, value in (("lower", lo), ("upper", hi)):
                pattern = re.compile(_ATTR_RE.format(attr))
                if pattern.search(tag):
                    tag = pattern.sub(lambda mm: f"{mm.group(1)}{mm.group(2)}{value:.6g}{mm.group(2)}", tag, count=1)  # noqa: B023 (runs at once)
                else:
                    tag = re.sub(r"<limit\b", f'<limit {attr}="{value:.6g}"', tag, count=1)
            for attr, default in (("effort", "1.0"), ("velocity", "1.0")):
                if not re.search(_ATTR_RE.format(attr), tag):
                    tag = re.sub(r"\s*/?>$", lambda mm: f' {attr}="{default}"{mm.group(0)}', tag, count=1)  # noqa: B023 (runs at once)
            edits.append((m.start() + lim.start(), m.start() + lim.end(), tag))
        else:
            close = m.group(0).rfind("</joint")
            if close < 0:
                raise ArmtoolError(f"joint '{name.group(2)}' in {source} is an empty element; cannot add a <limit>")
            line_start = text.rfind("\n", 0, m.start() + close) + 1
            indent = re.match(r"[ \t]*", text[line_start:]).group(0)  # type: ignore[union-attr]
            new = f'  <limit lower="{lo:.6g}" upper="{hi:.6g}" effort="1.0" velocity="1.0"/>\n{indent}'
            edits.append((m.start() + close, m.start() + close, new))
    for start, end, new in sorted(edits, reverse=True):
        text = text[:start] + new + text[end:]
    return text
