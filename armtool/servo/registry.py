"""Every bus protocol by name. A new protocol is one module plus one line here (imported on use)."""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from armtool.servo.bus import Transport

PROTOCOLS: dict[str, str] = {
    "dxl1": "armtool.servo.protocols.dxl1:Dxl1",
    "dxl2": "armtool.servo.protocols.dxl2:Dxl2",
    "feetech": "armtool.servo.protocols.feetech:Feetech",
}


def protocol_names() -> list[str]:
    return list(PROTOCOLS)


def transport_class(name: str) -> type[Transport]:
    if name not in PROTOCOLS:
        raise ArmtoolError(f"unknown protocol '{name}'", hint="protocols: " + ", ".join(PROTOCOLS))
    module, _, cls = PROTOCOLS[name].partition(":")
    return getattr(importlib.import_module(module), cls)  # type: ignore[no-any-return]
