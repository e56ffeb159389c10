"""Where `traj cartesian` starts when no --start is given: never at a singularity.

The middle of every joint's range is all zeros for most arms, and all zeros is singular on many:
UR arms stretched out flat (σ_min of the Jacobian 1e-17), Kinova's Jaco folded onto itself
(3e-14). A path started there stops at its first step. So the default start is, in order:

1. the SRDF's home/ready state: a `<group_state>` named home, ready or default (or a name
   containing home or ready) that gives every joint of the chain, within the limits and not
   singular. The SRDF is --srdf, else one beside the URDF that describes the same robot: in the
   URDF's folder, its parent's or its package's `srdf/` and `config/`, or a sibling
   `*moveit_config*/config/`;
2. the middle of the ranges, when it is not singular;
3. else the best-conditioned of a fixed sample of configurations in the middle half of the
   ranges (largest σ_min: as far from a singularity as that neighbourhood allows).

"Not singular" is σ_min ≥ WELL_CONDITIONED_SIGMA; `traj cartesian` calls a stop a singularity
below SINGULAR_SIGMA, ten times less.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from armtool.model.chain import Chain
from armtool.traj.cartesian import SINGULAR_SIGMA, sigma_min
from armtool.traj.trajectory import Array

WELL_CONDITIONED_SIGMA = 10 * SINGULAR_SIGMA
STATE_NAMES = ("home", "ready", "default")
_SAMPLES = 512


@dataclass(frozen=True)
class Start:
    q: Array
    how: str  # where the start came from, for the user


def srdf_beside(urdf: Path, robot: str | None) -> list[Path]:
    """SRDFs near the URDF that describe robot `robot`: beside it, in srdf/ and config/ of its
    parent folder and of its package, and in sibling MoveIt config packages' config/ (plain .srdf
    files; the URDF's stem first)."""
    from armtool.model.packages import package_root

    here = urdf.resolve().parent
    bases = list(dict.fromkeys([here.parent, package_root(here) or here.parent]))  # urdf/.. and the package
    folders = [here] + [base / sub for base in bases for sub in ("srdf", "config", ".")]
    for base in bases:
        folders += sorted(p / "config" for p in base.parent.glob("*moveit_config*") if p.is_dir())
    found = [f for folder in dict.fromkeys(folders) if folder.is_dir() for f in sorted(folder.glob("*.srdf"))]
    same = [f for f in found if robot is None or _robot_name(f) == robot]
    stem = urdf.name.split(".")[0]
    return sorted(dict.fromkeys(same), key=lambda f: f.name.split(".")[0] != stem)


def _robot_name(path: Path) -> str | None:
    from armtool.model.xmlsource import XmlSyntaxProblem, parse_xml

    try:
        name = parse_xml(path.read_bytes()).get("name")
    except (OSError, XmlSyntaxProblem, ValueError):
        return None
    return str(name) if name is not None else None


def home_state(srdf: Path, chain: Chain) -> tuple[str, Array] | None:
    """The SRDF's home/ready group state that gives every joint of the chain, as (name, q)."""
    from armtool.model.xmlsource import XmlSyntaxProblem, parse_xml

    try:
        root = parse_xml(srdf.read_bytes())
    except (OSError, XmlSyntaxProblem, ValueError):
        return None
    states: list[tuple[int, str, Array]] = []
    for state in root.iter("group_state"):
        name = state.get("name") or ""
        low = name.lower()
        rank = STATE_NAMES.index(low) if low in STATE_NAMES else 3 if ("home" in low or "ready" in low) else -1
        if rank < 0:
            continue
        values: dict[str, float] = {}
        for joint in state.iter("joint"):
            try:
                values[joint.get("name") or ""] = float((joint.get("value") or "").split()[0])
            except (ValueError, IndexError):
                continue
        if all(n in values for n in chain.joint_names):
            states.append((rank, name, np.array([values[n] for n in chain.joint_names])))
    if not states:
        return None
    rank, name, q = min(states, key=lambda s: s[0])
    return name, q


def default_start(chain: Chain, urdf: Path, srdf: Path | None = None, robot: str | None = None) -> Start:
    """The start configuration when --start is not given (see the module docstring)."""
    notes: list[str] = []
    for candidate in [srdf] if srdf is not None else srdf_beside(urdf, robot):
        state = home_state(candidate, chain)
        if state is None:
            continue
        name, q = state
        if not chain.within_limits(q):
            notes.append(f"group state '{name}' of {candidate.name} is outside the joint limits")
        elif sigma_min(chain, q) < WELL_CONDITIONED_SIGMA:
            notes.append(f"group state '{name}' of {candidate.name} is near a singularity")
        else:
            return Start(q, f"group state '{name}' of {candidate}")
        break
    else:
        if srdf is not None:
            notes.append(f"{srdf.name} has no home or ready group state for joints {', '.join(chain.joint_names)}")
    suffix = f" ({'; '.join(notes)})" if notes else ""
    mid = chain.mid()
    sigma = sigma_min(chain, mid)
    if sigma >= WELL_CONDITIONED_SIGMA:
        return Start(mid, f"the middle of the joint ranges{suffix}")
    lower = np.where(np.isfinite(chain.lower), chain.lower, -math.pi)
    upper = np.where(np.isfinite(chain.upper), chain.upper, math.pi)
    rng = np.random.default_rng(0)
    samples = mid + (upper - lower) / 4 * rng.uniform(-1.0, 1.0, size=(_SAMPLES, chain.n))
    _, jacobians = chain.fk_jacobian_batch(samples)
    assert jacobians is not None
    sigmas = np.linalg.svd(jacobians, compute_uv=False)[:, -1]
    best = int(np.argmax(sigmas))
    return Start(
        samples[best],
        f"the middle of the joint ranges is singular (σ_min = {sigma:.2e}): the best-conditioned of "
        f"{_SAMPLES} configurations in the middle half of the ranges (σ_min = {sigmas[best]:.3g}){suffix}",
    )
