"""Every bus protocol by name. A new protocol is one module plus one line here (imported on use).

`Protocol` is what the command line offers; `PROTOCOLS` maps it (or its plain string value, as a
config file spells it) to the `Transport` class that frames the bytes and carries the protocol's
facts (re-arm after overload, wheel mode, position mode, EEPROM lock, homing-offset sign).
Numpy-free: command modules import it at start-up.
"""

from __future__ import annotations

import importlib
from enum import Enum
from typing import TYPE_CHECKING

from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.servo.transport import Transport


class Protocol(str, Enum):
    DXL1 = "dxl1"
    DXL2 = "dxl2"
    FEETECH = "feetech"


PROTOCOLS: dict[str, str] = {
    Protocol.DXL1: "armtool.servo.protocols.dxl1:Dxl1",
    Protocol.DXL2: "armtool.servo.protocols.dxl2:Dxl2",
    Protocol.FEETECH: "armtool.servo.protocols.feetech:Feetech",
}


def protocol_names() -> list[str]:
    return [str(getattr(name, "value", name)) for name in PROTOCOLS]


def check_protocol(name: str, where: str | None = None) -> str:
    """`name` if it is a known protocol, else an ArmtoolError that lists them."""
    if name not in PROTOCOLS:
        raise ArmtoolError(f"unknown protocol {name!r}", where, hint="protocols: " + ", ".join(protocol_names()))
    return name


def transport_class(name: str) -> type[Transport]:
    module, _, cls = PROTOCOLS[check_protocol(name)].partition(":")
    return getattr(importlib.import_module(module), cls)  # type: ignore[no-any-return]
