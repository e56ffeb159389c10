"""`--lock JOINT=VALUE` (`traj cartesian`, `ik-bench`): joints held at a value, so that a 7-DoF arm
becomes the 6-DoF chain left at that value (`Chain.locked`), which has a closed form when it is
one of `analytic`'s families (Panda with any of joints 4 to 7 locked).

The option is repeatable and each occurrence may be a comma list (`--lock a=0.3,b=0`). Values are
rad (m for a prismatic joint). Which joints exist and whether a value is within the joint's
limits is `Chain.locked`'s check (unknown joint: did-you-mean; outside: the limits). Peers that read
a URDF get one where each locked joint is a fixed joint at its value (`locked_urdf`); EAIK takes its
own `fixed_axes` instead (`armtool.ik.peers.eaik_peer`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from lxml import etree

from armtool.errors import ArmtoolError
from armtool.model.chain import Chain

HINT = "write --lock JOINT=VALUE (rad, m for a prismatic joint), e.g. --lock panda_joint7=0.785"


def parse_locks(items: Sequence[str] | None, flag: str = "--lock") -> dict[str, float]:
    """JOINT=VALUE items (each possibly a comma list) as {joint: value}; a joint named twice, an item
    without '=' or a value that is not a finite number is an error naming the item."""
    out: dict[str, float] = {}
    for item in items or ():
        for part in item.split(","):
            text = part.strip()
            if not text:
                continue
            name, eq, value = (s.strip() for s in text.partition("="))
            if not eq or not name:
                raise ArmtoolError(f"{flag} {text!r}: not JOINT=VALUE", hint=HINT)
            try:
                number = float(value)
            except ValueError:
                raise ArmtoolError(f"{flag} {text!r}: {value!r} is not a number", hint=HINT) from None
            if not math.isfinite(number):
                raise ArmtoolError(f"{flag} {text!r}: the value must be finite", hint=HINT)
            if name in out:
                raise ArmtoolError(f"{flag} names joint '{name}' twice", hint="lock each joint once")
            out[name] = number
    if items and not out:
        raise ArmtoolError(f"{flag} {', '.join(items)!r} names no joint", hint=HINT)
    return out


def lock(chain: Chain, locks: Mapping[str, float]) -> Chain:
    """The chain with `locks` held (the chain itself without any)."""
    return chain.locked(locks) if locks else chain


def full_joint_names(chain: Chain) -> list[str]:
    """The joints of the chain a locked chain was locked from, in its order: `chain.expand(q)`'s columns."""
    names: list[str | None] = [None] * (chain.n + len(chain.locks))
    for index, name, _ in chain.locks:
        names[index] = name
    moving = iter(chain.joint_names)
    return [name if name is not None else next(moving) for name in names]


def describe(chain: Chain) -> str:
    """'panda_joint7 = 0.785' for each locked joint, for the report."""
    return ", ".join(f"{name} = {value:g}" for _, name, value in chain.locks)


def locked_urdf(urdf: etree._Element, chain: Chain) -> etree._Element:
    """A copy of a chain's URDF (armtool.ik.peers.path_urdf's) with every locked joint of `chain` made a
    fixed joint whose origin is its origin turned (or moved) to the locked value: the locked chain as a
    peer's URDF reader sees it."""
    import numpy as np

    from armtool.calib.model.se3 import rpy_of
    from armtool.model.chain import axis_angle_batch, origin_matrix

    out: etree._Element = etree.fromstring(etree.tostring(urdf))
    values = {name: value for _, name, value in chain.locks}
    for joint in out.findall("joint"):
        name = joint.get("name", "")
        if name not in values:
            continue
        axis_el = joint.find("axis")
        axis = np.array([float(v) for v in (axis_el.get("xyz") if axis_el is not None else "1 0 0").split()])
        axis /= np.linalg.norm(axis)
        motion = np.eye(4)
        if joint.get("type") == "prismatic":
            motion[:3, 3] = values[name] * axis
        else:
            motion[:3, :3] = axis_angle_batch(axis, np.array([values[name]]))[0]
        T = origin_matrix(joint.find("origin"), f"joint '{name}'") @ motion
        for child in list(joint):
            if child.tag in ("origin", "axis", "limit", "dynamics", "safety_controller", "calibration"):
                joint.remove(child)
        joint.set("type", "fixed")
        origin = etree.Element("origin", xyz=" ".join(repr(float(v)) for v in T[:3, 3]))
        origin.set("rpy", " ".join(repr(float(v)) for v in rpy_of(T[:3, :3])))
        joint.insert(0, origin)
    return out
