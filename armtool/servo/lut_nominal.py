"""The datasheet ("nominal") map between command ticks and servo degrees, per servo model.

A compensation table is judged against this map: it is what a driver does when it has no
table. The servo angle frame is the datasheet's: 0° at tick 0, increasing with the ticks
(research/servo.md 1.5). AX-12A/18A: ticks 0..1023 over 0..300°, 300/1023 = 0.2933°/tick,
512 = 150.15°; X series and STS3215: 4096 ticks per turn, 360/4096 = 0.0879°/tick.
"""

from __future__ import annotations

from dataclasses import dataclass

from armtool.errors import ArmtoolError


@dataclass(frozen=True)
class ServoModel:
    """One servo model's resolution and the model number it answers a ping with."""

    name: str
    max_tick: int  # largest valid command (ticks run 0..max_tick)
    span_deg: float  # angle covered by 0..max_tick
    model_number: int | None  # control-table model number; None when a family name is given

    @property
    def deg_per_tick(self) -> float:
        return self.span_deg / self.max_tick

    def ticks_to_deg(self, ticks: float) -> float:
        return ticks * self.deg_per_tick

    def deg_to_ticks(self, deg: float) -> float:
        return deg / self.deg_per_tick


_AX_SPAN = 300.0
_X_SPAN = 360.0 * 4095 / 4096  # 4096 ticks per turn: tick 4095 is one tick short of 360°

MODELS: dict[str, ServoModel] = {
    "AX-12A": ServoModel("AX-12A", 1023, _AX_SPAN, 12),
    "AX-18A": ServoModel("AX-18A", 1023, _AX_SPAN, 18),
    "XL430-W250": ServoModel("XL430-W250", 4095, _X_SPAN, 1060),
    "XM430-W350": ServoModel("XM430-W350", 4095, _X_SPAN, 1020),
    "X-series": ServoModel("X-series", 4095, _X_SPAN, None),
    "STS3215": ServoModel("STS3215", 4095, _X_SPAN, 777),
}

_ALIASES = {"AX12A": "AX-12A", "AX-12": "AX-12A", "AX12": "AX-12A", "AX18A": "AX-18A", "AX-18": "AX-18A",
            "XL430": "XL430-W250", "XM430": "XM430-W350", "X": "X-series", "XSERIES": "X-series", "STS-3215": "STS3215"}


def servo_model(name: str, where: str | None = None) -> ServoModel:
    """The model called `name` (case and dashes forgiven), or an error listing the known ones."""
    key = name.strip()
    for candidate in (key, key.upper(), _ALIASES.get(key.upper().replace(" ", ""), "")):
        for known in MODELS:
            if candidate and candidate.upper() == known.upper():
                return MODELS[known]
    raise ArmtoolError(f"unknown servo model '{name}'", where, hint="known models: " + ", ".join(MODELS))


def model_by_number(number: int) -> ServoModel | None:
    """The model that answers a ping with `number`, if we know it."""
    return next((m for m in MODELS.values() if m.model_number == number), None)
