"""Control tables: encodings and the registry of models and protocols."""

from __future__ import annotations

import pytest

from armtool.errors import ArmtoolError
from armtool.servo.models import MODELS, Register, by_name, by_number, decode, encode
from armtool.servo.registry import PROTOCOLS, transport_class


def test_sign_magnitude_and_twos_complement() -> None:
    sm10 = Register(40, 2, enc="sm10")
    assert encode(sm10, -300) == (300 | 0x400).to_bytes(2, "little")
    assert decode(sm10, encode(sm10, -300)) == -300
    sm15_be = Register(56, 2, enc="sm15")
    assert encode(sm15_be, -5, big_endian=True) == bytes([0x80, 0x05])
    s32 = Register(132, 4, enc="s")
    assert encode(s32, -1) == b"\xff\xff\xff\xff" and decode(s32, b"\xfe\xff\xff\xff") == -2


def test_tables_are_consistent() -> None:
    for m in MODELS:
        spans = sorted((r.addr, r.addr + r.size, n) for n, r in m.table.items())
        for (_a0, a1, n0), (b0, _b1, n1) in zip(spans, spans[1:]):
            assert a1 <= b0, f"{m.name}: {n0} overlaps {n1}"
        for name in (
            "model_number",
            "id",
            "torque_enable",
            "goal_position",
            "present_position",
            "min_limit",
            "max_limit",
        ):
            assert m.has(name), f"{m.name} lacks {name}"
        assert by_number(m.protocol, m.model_number) is m
    assert by_name("ax12a").model_number == 12 and by_name("STS3215").ticks == 4096
    with pytest.raises(ArmtoolError, match="known models"):
        by_name("MG996R")


def test_every_protocol_module_loads() -> None:
    for name in PROTOCOLS:
        assert transport_class(name).name == name


class _Recorded(Exception):
    pass


class _RecordingGuard:
    """Records the RAM writes `seek_joint` makes and stops it before anything moves."""

    def __init__(self) -> None:
        self.ram: dict[str, int] = {}

    def set_ram(self, sid: int, name: str, value: int) -> None:
        self.ram[name] = value

    def torque_on(self, sid: int) -> None:
        raise _Recorded


class _ModelBus:
    def __init__(self, model: object) -> None:
        self._model = model

    def model(self, sid: int) -> object:
        return self._model

    def read(self, sid: int, name: str) -> int:
        assert name == "operating_mode"
        return 3  # position control


@pytest.mark.parametrize("deg_s", [7.5, 60.0, 200.0])
@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.name)
def test_limits_lut_and_the_simulator_share_one_speed_conversion(model: object, deg_s: float) -> None:
    from armtool.servo import limits as L
    from armtool.servo.lut.measure import speed_register
    from armtool.servo.sim.config import ServoSpec
    from armtool.servo.sim.servo import SimServo

    assert isinstance(model, type(MODELS[0]))
    guard = _RecordingGuard()
    bus = _ModelBus(model)
    if not model.has("torque_limit"):
        pytest.skip("no RAM torque limit: limits --mode auto cannot cap this model")
    with pytest.raises(_Recorded):
        L.seek_joint(bus, guard, L.Joint("j", 1), L.AutoParams(speed_deg_s=deg_s))  # type: ignore[arg-type]
    register = model.speed_register(deg_s)
    assert guard.ram["moving_speed"] == register == speed_register(model, deg_s)
    assert abs(register * model.speed_unit_deg_s - deg_s) <= model.speed_unit_deg_s / 2  # the nearest value
    sim = SimServo(ServoSpec(1, model, 0.0, model.range_deg, model.range_deg / 2))
    sim.set("moving_speed", register)
    if model.protocol == "dxl2":
        sim.set("velocity_limit", model.reg("velocity_limit").hi)
    assert sim.speed_deg_s() == pytest.approx(model.speed_deg_s(register))


def test_ax12a_60_deg_s_is_90_speed_units() -> None:
    """0.111 rpm per unit (ROBOTIS e-manual, AX-12A Moving Speed 32): 60 deg/s = 90.09 units -> 90, not 91."""
    ax = by_name("AX-12A")
    assert ax.speed_register(60) == 90
    assert ax.speed_unit_deg_s == pytest.approx(0.666)
    assert by_name("XM430-W350").load_full_scale == by_name("XM430-W350").reg("current_limit").hi
    assert [m.default_zero for m in (ax, by_name("STS3215"))] == [512, 2048]


def test_xl330_models_of_koch_arms() -> None:
    m288, m077 = by_name("xl330-m288"), by_name("XL330-M077-T")
    assert (m288.name, m288.model_number, m077.model_number) == ("XL330-M288", 1200, 1190)
    assert by_number("dxl2", 1200) is m288 and by_number("dxl2", 1190) is m077
    # e-manual: Present Current in mA up to the 1750 mA Current Limit; 0.229 rpm speed units; 5 V parts
    assert m288.load_full_scale == m077.load_full_scale == 1750
    assert m288.speed_register(60) == 44
    assert (m288.reg("velocity_limit").default, m077.reg("velocity_limit").default) == (445, 1620)
    assert m288.reg("max_voltage").hi == 70 and m288.reg("present_voltage").addr == 144
    assert m288.settle_ticks == 6 and m288.default_zero == 2048
