"""Where `traj cartesian` starts when no --start is given: never at a singularity.

The middle of every joint's range is all zeros for most arms, and all zeros is singular on many:
UR arms stretched out flat (σ_min of the Jacobian 1e-17), Kinova's Jaco folded onto itself
(3e-14). A path started there stops at its first step. So the default start is, in order:

1. the SRDF's home/ready state: a `<group_state>` named home, ready or default (or a name
   containing home or ready) that gives every joint of the chain, within the limits and not
   singular. The SRDF is --srdf (or the --moveit-config package's), else one beside the URDF that
   describes the same robot: in the URDF's folder, its parent's or its package's `srdf/` and
   `config/`, or a sibling `*moveit_config*/config/` or `srdf/`. A `.srdf.xacro` is expanded as
   `armtool lint` expands it (`armtool.model.load.load_srdf_xml`, with the robot's xacro
   arguments and package paths): its group states often come from macros and includes;
2. the middle of the ranges, when it is not singular;
3. else the best-conditioned of a fixed sample of configurations in the middle half of the
   ranges (largest σ_min: as far from a singularity as that neighbourhood allows).

"Not singular" is σ_min ≥ WELL_CONDITIONED_SIGMA; `traj cartesian` calls a stop a singularity
below SINGULAR_SIGMA, ten times less.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.model.chain import Chain
from armtool.traj.cartesian import SINGULAR_SIGMA, sigma_min
from armtool.traj.trajectory import Array

WELL_CONDITIONED_SIGMA = 10 * SINGULAR_SIGMA
STATE_NAMES = ("home", "ready", "default")
SRDF_PATTERNS = ("*.srdf", "*.srdf.xacro")
_SAMPLES = 512


@dataclass(frozen=True)
class Start:
    q: Array
    how: str  # where the start came from, for the user


@dataclass(frozen=True)
class Srdf:
    """An SRDF as MoveIt reads it: its path and its <robot> element (a .srdf.xacro expanded)."""

    path: Path
    root: etree._Element


def read_srdf(path: Path, xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[Path] = ()) -> Srdf:
    """The SRDF at `path`, a .srdf.xacro expanded; an ArmtoolError (file:line, hint) when it cannot be read."""
    from armtool.model.load import load_srdf_xml

    return Srdf(path, load_srdf_xml(path, xacro_args, package_paths))


def srdf_beside(
    urdf: Path, robot: str | None, xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[Path] = ()
) -> tuple[list[Srdf], list[str]]:
    """SRDFs near the URDF that describe robot `robot` (beside it, in srdf/ and config/ of its
    parent folder and of its package, and in sibling MoveIt config packages' config/ and srdf/;
    .srdf and .srdf.xacro files, the URDF's stem first), and a note for each one found that
    could not be read (a xacro that needs arguments)."""
    from armtool.model.packages import package_root

    here = urdf.resolve().parent
    bases = list(dict.fromkeys([here.parent, package_root(here) or here.parent]))  # urdf/.. and the package
    folders = [here] + [base / sub for base in bases for sub in ("srdf", "config", ".")]
    for base in bases:
        folders += sorted(
            p / sub for p in base.parent.glob("*moveit_config*") if p.is_dir() for sub in ("config", "srdf")
        )
    found = [
        f
        for folder in dict.fromkeys(folders)
        if folder.is_dir()
        for pattern in SRDF_PATTERNS
        for f in sorted(folder.glob(pattern))
        if f.is_file()
    ]
    same: list[Srdf] = []
    notes: list[str] = []
    for path in dict.fromkeys(found):
        try:
            srdf = read_srdf(path, xacro_args, package_paths)
        except ArmtoolError as exc:
            notes.append(f"{path.name} beside it was not read: {exc.what}")
            continue
        if robot is None or srdf.root.get("name") == robot:
            same.append(srdf)
    stem = urdf.name.split(".")[0]
    return sorted(same, key=lambda s: s.path.name.split(".")[0] != stem), notes


def home_states(srdf: etree._Element, chain: Chain) -> list[tuple[str, Array]]:
    """The SRDF's home/ready group states that give every joint of the chain, as (name, q), best
    name first (home, ready, default, then names containing home or ready; file order within)."""
    states: list[tuple[int, int, str, Array]] = []
    for index, state in enumerate(srdf.iter("group_state")):
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
            states.append((rank, index, name, np.array([values[n] for n in chain.joint_names])))
    return [(name, q) for _, _, name, q in sorted(states, key=lambda s: (s[0], s[1]))]


def state_list(srdf: etree._Element) -> str:
    """The group states an SRDF defines, for a message: "home (group arm), open (group gripper)"."""
    states = [f"{s.get('name') or '(unnamed)'} (group {s.get('group') or '?'})" for s in srdf.iter("group_state")]
    return ", ".join(states) if states else "none"


def default_start(
    chain: Chain,
    urdf: Path,
    srdf: Srdf | None = None,
    robot: str | None = None,
    xacro_args: Mapping[str, str] | None = None,
    package_paths: Sequence[Path] = (),
) -> Start:
    """The start configuration when --start is not given (see the module docstring)."""
    notes: list[str] = []
    candidates = [srdf] if srdf is not None else []
    if srdf is None:
        candidates, notes = srdf_beside(urdf, robot, xacro_args, package_paths)
    for candidate in candidates:
        states = home_states(candidate.root, chain)
        for name, q in states:
            if not chain.within_limits(q):
                notes.append(f"group state '{name}' of {candidate.path.name} is outside the joint limits")
            elif sigma_min(chain, q) < WELL_CONDITIONED_SIGMA:
                notes.append(f"group state '{name}' of {candidate.path.name} is near a singularity")
            else:
                return Start(q, f"group state '{name}' of {candidate.path}")
        if states:
            break
    else:
        if srdf is not None:
            notes.append(
                f"{srdf.path.name} has no home or ready group state for joints {', '.join(chain.joint_names)}; "
                f"its group states: {state_list(srdf.root)}"
            )
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
