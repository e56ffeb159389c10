"""The simulator's YAML: which servos, their mechanical stops, the bus, the faults to inject.

    protocol: dxl1            # dxl1 | dxl2 | feetech
    baud: 1000000
    return_delay: 0           # optional: override every servo's Return Delay Time (2 us units)
    overload_time_s: 1.0      # seconds pushing at the torque cap before the overload alarm
    seed: 0
    joints:                   # also readable by `armtool limits --arm` (sim-only keys are ignored there)
      - {name: shoulder, id: 1, model: AX-12A, zero_ticks: 512, direction: 1,
         stops: [92, 914], start: 512}      # stops/start in nominal ticks of the TRUE angle
                                            # (the encoder, before any homing_offset: STS/X only)
    encoder: {noise_deg: 0.05}             # external reference (second pty, always on); noise 1-sigma
    faults: {missing_ids: [3], drop_next: 0, p_drop: 0.0, corrupt_next: 0, p_corrupt: 0.0,
             echo: false, delay_s: 0.0}
    person: {start_s: 0.3, speed_deg_s: 90, dwell_s: 0.6}   # moves torque-off joints to both stops

`stops_deg: [lo, hi]` may replace `stops` (true servo-frame degrees). For the AX-12A the
potentiometer is non-linear near both ends (`nonlinearity`, default 0.010 of the range, ~3°):
the servo reports and regulates the pot reading, so only the encoder sees the true angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from armtool.errors import ArmtoolError
from armtool.servo.models import ServoModel, by_name
from armtool.servo.registry import Protocol, check_protocol, protocol_names, transport_class

# registers the simulated servo drives (armtool/servo/sim/servo.py): a model without one cannot be simulated
SIM_REGISTERS = (
    "torque_enable",
    "torque_limit",
    "goal_position",
    "present_position",
    "moving_speed",
    "min_limit",
    "max_limit",
    "return_delay",
    "status_return_level",
)


@dataclass
class Faults:
    """Injected faults; counters (`*_next`) are consumed one per reply. Mutable from tests."""

    missing_ids: set[int] = field(default_factory=set)
    drop_next: int = 0
    p_drop: float = 0.0
    corrupt_next: int = 0
    p_corrupt: float = 0.0
    echo: bool = False
    delay_s: float = 0.0


@dataclass
class ServoSpec:
    id: int
    model: ServoModel
    stop_lo_deg: float
    stop_hi_deg: float
    start_deg: float
    nonlinearity: float = 0.0
    name: str | None = None
    homing_offset: int = 0


@dataclass
class PersonSpec:
    start_s: float = 0.3
    speed_deg_s: float = 90.0
    dwell_s: float = 0.6
    overshoot_deg: float = 10.0
    ids: list[int] | None = None


@dataclass
class SimConfig:
    protocol: str
    servos: list[ServoSpec]
    baud: int = 1_000_000
    return_delay: int | None = 0
    overload_time_s: float = 1.0
    seed: int = 0
    encoder_noise_deg: float = 0.0
    faults: Faults = field(default_factory=Faults)
    person: PersonSpec | None = None
    source: str = "<config>"


def load_sim_config(path: Path) -> SimConfig:
    from armtool.fileio import read_yaml

    data = read_yaml(path, "simulator config")
    return sim_config_from_dict(data, source=str(path))


def _number(
    d: dict[str, Any],
    key: str,
    default: Any,
    where: str,
    kind: type = float,
    lo: float | None = None,
    hi: float | None = None,
    lo_open: bool = False,
) -> Any:
    """`d[key]` as `kind`, finite and inside lo..hi (lo excluded with lo_open), or an error naming the key."""

    value = d.get(key, default)
    if value is None:
        return default
    if isinstance(value, bool) or (kind is int and isinstance(value, float) and not value.is_integer()):
        raise ArmtoolError(f"'{key}' must be a {'whole ' if kind is int else ''}number, got {value!r}", where)
    try:
        number = kind(value)
    except (TypeError, ValueError, OverflowError):
        raise ArmtoolError(f"'{key}' must be a number, got {value!r}", where) from None
    bad = (
        not math.isfinite(number)
        or (lo is not None and (number <= lo if lo_open else number < lo))
        or (hi is not None and number > hi)
    )
    if bad:
        span = f"{'>' if lo_open else '>='} {lo:g}" if lo is not None else ""
        span += (" and " if span and hi is not None else "") + (f"<= {hi:g}" if hi is not None else "")
        raise ArmtoolError(f"'{key}' must be a finite number{' ' + span if span else ''}, got {value!r}", where)
    return number


def _default_models() -> str:
    """ "AX-12A (dxl1), XL430-W250 (dxl2) or STS3215 (feetech)": each protocol's default model."""
    names = [f"{transport_class(p).default_model} ({p})" for p in protocol_names()]
    return ", ".join(names[:-1]) + " or " + names[-1] if len(names) > 1 else names[0]


def sim_config_from_dict(data: Any, source: str = "<config>") -> SimConfig:
    if not isinstance(data, dict):
        raise ArmtoolError("simulator config must be a mapping with 'protocol' and 'joints'", source)
    protocol = check_protocol(str(data.get("protocol", Protocol.DXL1.value)), source)
    entries = data.get("joints", data.get("servos"))
    if not isinstance(entries, list) or not entries:
        raise ArmtoolError("no 'joints' list", source, hint="joints: [{id: 1, model: AX-12A, stops: [92, 914]}]")
    servos: list[ServoSpec] = []
    seen: set[int] = set()
    for k, e in enumerate(entries):
        where = f"{source}: joints[{k}]"
        if not isinstance(e, dict) or "id" not in e:
            raise ArmtoolError("each joint needs an 'id'", where)
        sid = _number(e, "id", None, where, int)
        if sid is None or not 0 <= sid <= 252 or sid in seen:
            raise ArmtoolError(f"id {sid} is out of range 0..252 or repeated", where)
        seen.add(sid)
        try:
            model = by_name(str(e.get("model", transport_class(protocol).default_model)))
        except ArmtoolError as exc:
            raise ArmtoolError(exc.what, where, exc.hint) from None
        if model.protocol != protocol:
            raise ArmtoolError(f"{model.name} speaks {model.protocol}, the bus is {protocol}", where)
        missing = [name for name in SIM_REGISTERS if not model.has(name)]
        if missing:
            raise ArmtoolError(
                f"the simulator does not support the {model.name} (it has no {', '.join(missing)} register)",
                where,
                hint=f"simulate {_default_models()}",
            )
        deg = model.deg_per_tick
        key = "stops_deg" if "stops_deg" in e else "stops" if "stops" in e else None
        if key is not None:
            pair = e[key]
            try:
                if not isinstance(pair, (list, tuple)) or len(pair) != 2:
                    raise ValueError
                lo, hi = (float(v) * (1.0 if key == "stops_deg" else deg) for v in pair)
                if not (math.isfinite(lo) and math.isfinite(hi)):
                    raise ValueError
            except (TypeError, ValueError):
                raise ArmtoolError(
                    f"'{key}' must be two numbers [low, high], got {pair!r}",
                    where,
                    hint=f"e.g. {key}: [92, 914]" if key == "stops" else f"e.g. {key}: [27, 268]",
                ) from None
        else:
            lo, hi = 0.0, model.max_tick * deg
        if not lo < hi:
            raise ArmtoolError(f"stops must be [low, high] with low < high, got [{lo}, {hi}]", where)
        if lo < -model.range_deg or hi > 2 * model.range_deg:
            raise ArmtoolError(
                f"stops [{lo:g}, {hi:g}]° are far outside the {model.name}'s {model.range_deg:g}° range", where
            )
        start = _number(e, "start", None, where)
        start_deg = (lo + hi) / 2 if start is None else start * deg
        if not lo <= start_deg <= hi:
            raise ArmtoolError("start lies outside the stops", where)
        nl = _number(e, "nonlinearity", 0.010 if model.name.startswith("AX") else 0.0, where, lo=0.0, hi=0.1)
        offset = _number(e, "homing_offset", 0, where, int)
        if offset and not model.has("homing_offset"):
            raise ArmtoolError(f"a {model.name} has no homing offset register", where, hint="remove 'homing_offset'")
        if offset:
            reg = model.reg("homing_offset")
            if not reg.lo <= offset <= reg.hi:
                raise ArmtoolError(
                    f"'homing_offset' {offset} does not fit the {model.name}'s register ({reg.lo}..{reg.hi})", where
                )
        servos.append(ServoSpec(sid, model, lo, hi, start_deg, nl, e.get("name"), offset))
    faults_d = data.get("faults") or {}
    if not isinstance(faults_d, dict):
        raise ArmtoolError(f"'faults' must be a mapping, got {faults_d!r}", source, hint="faults: {missing_ids: [3]}")
    known = {f.name for f in fields(Faults)}
    unknown = set(faults_d) - known
    if unknown:
        raise ArmtoolError(
            f"unknown fault(s): {', '.join(sorted(unknown))}", source, hint="faults: " + ", ".join(sorted(known))
        )
    fwhere = f"{source}: faults"
    ids = faults_d.get("missing_ids") or []
    if not isinstance(ids, list) or not all(isinstance(i, int) and not isinstance(i, bool) for i in ids):
        raise ArmtoolError(f"'missing_ids' must be a list of IDs, got {ids!r}", fwhere, hint="missing_ids: [3]")
    faults = Faults(
        missing_ids=set(ids),
        drop_next=_number(faults_d, "drop_next", 0, fwhere, int, 0),
        p_drop=_number(faults_d, "p_drop", 0.0, fwhere, lo=0.0, hi=1.0),
        corrupt_next=_number(faults_d, "corrupt_next", 0, fwhere, int, 0),
        p_corrupt=_number(faults_d, "p_corrupt", 0.0, fwhere, lo=0.0, hi=1.0),
        echo=bool(faults_d.get("echo", False)),
        delay_s=_number(faults_d, "delay_s", 0.0, fwhere, lo=0.0, hi=10.0),
    )
    enc = data.get("encoder")
    person_d = data.get("person")
    person = None
    if person_d is not None and not isinstance(person_d, dict):
        raise ArmtoolError(f"'person' must be a mapping, got {person_d!r}", source, hint="person: {speed_deg_s: 90}")
    if isinstance(person_d, dict):
        pwhere = f"{source}: person"
        unknown = set(person_d) - {f.name for f in fields(PersonSpec)}
        if unknown:
            raise ArmtoolError(
                f"unknown key(s): {', '.join(sorted(map(str, unknown)))}",
                pwhere,
                hint="start_s, speed_deg_s, dwell_s, overshoot_deg, ids",
            )
        bounds = {
            "start_s": (0.0, 3600.0, False),
            "speed_deg_s": (0.0, 100_000.0, True),
            "dwell_s": (0.0, 3600.0, False),
            "overshoot_deg": (0.0, 360.0, False),
        }
        person = PersonSpec(
            **{
                name: _number(person_d, name, getattr(PersonSpec, name), pwhere, float, lo, hi, lo_open)
                for name, (lo, hi, lo_open) in bounds.items()
                if name in person_d
            }
        )
        if person_d.get("ids") is not None:
            if not isinstance(person_d["ids"], list):
                raise ArmtoolError(f"'ids' must be a list of IDs, got {person_d['ids']!r}", pwhere)
            person.ids = [_number({"ids": i}, "ids", None, pwhere, int, 0, 252) for i in person_d["ids"]]
    rdt = data.get("return_delay", 0)
    return SimConfig(
        protocol=protocol,
        servos=servos,
        baud=_number(data, "baud", 1_000_000, source, int, 1, 20_000_000),
        # Return Delay Time is one register byte: 0..254 (2 us units, 508 us at most)
        return_delay=None if rdt is None else _number(data, "return_delay", 0, source, int, 0, 254),
        overload_time_s=_number(data, "overload_time_s", 1.0, source, float, 0.0, 3600.0, True),
        seed=_number(data, "seed", 0, source, int),
        encoder_noise_deg=_number(enc, "noise_deg", 0.0, f"{source}: encoder", float, 0.0, 90.0)
        if isinstance(enc, dict)
        else 0.0,
        faults=faults,
        person=person,
        source=source,
    )
