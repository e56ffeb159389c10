"""The arm file (`joints: [{name, id, model, zero_ticks, direction}]`) and what a recording yields
(`JointRange`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, cast

from armtool.errors import ArmtoolError
from armtool.servo.models import ServoModel, by_name
from armtool.servo.registry import check_protocol


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
        raise ArmtoolError(
            "arm file needs a 'joints' list",
            str(path),
            hint="joints: [{name: shoulder, id: 1, model: AX-12A, zero_ticks: 512, direction: 1}]",
        )
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


@dataclass
class JointRange:
    joint: Joint
    model: ServoModel
    raw_min: int
    raw_max: int
    method: Literal["manual", "auto", "lerobot"]
    evidence: dict[str, Any] = field(default_factory=dict)

    @property
    def confirmed(self) -> bool:
        return bool(self.evidence.get("confirmed_min", True) and self.evidence.get("confirmed_max", True))

    @property
    def crosses_seam(self) -> bool:
        return self.raw_min < 0 or self.raw_max > self.model.max_tick
