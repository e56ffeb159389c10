"""armtool/ik/closed_form/search.py through the `search` solver: every solution of 6R arms with no closed form.

Counts are checked against an independent enumeration: SciPy's least squares (bounded by the limits)
from many random seeds, verified, refined and deduplicated at 1e-6 rad (armtool.ik.solutions).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.ik import make_solver
from armtool.ik.closed_form import search
from armtool.ik.solutions import enumerate_by_least_squares, missing
from armtool.ik.solver import Solver
from armtool.model.chain import Chain, chain_from_xml
from tests.ik.test_analytic import PUMA_RIGHT, check_all_solutions, dh_chain, wrapped_distance

# Rendered arms (DH rows: d, a, α from axis i to axis i+1), hidden behind rotated URDF frames:
# xArm6's kind (axis 6 2 cm off the 4∩5 point) and Gen3 lite's (axes 5, 6 meet 5 cm along axis 5).
OFFSET_WRIST = [*PUMA_RIGHT[:4], (0.0, 0.02, -math.pi / 2), PUMA_RIGHT[5]]
TWO_POINT_WRIST = [*PUMA_RIGHT[:4], (0.05, 0.0, -math.pi / 2), PUMA_RIGHT[5]]

REALWORLD = Path(__file__).resolve().parents[2] / ".." / "shared" / "realworld"


def check_search(chain: Chain, samples: int, enumerated: int, seeds: int = 60) -> None:
    """FK of random in-limit q: every solution exact and in the limits, q among them; on `enumerated`
    targets none of the enumeration's solutions is missing (a finite enumeration may miss some the
    search finds: every one of those is verified above)."""
    solver = make_solver("search", chain)
    assert solver.method.startswith("1-D search")
    rng = np.random.default_rng(3)
    mid = chain.mid()
    for i, q in enumerate(chain.random(rng, samples)):
        target = chain.fk(q)
        result = solver.solve(target, mid)
        check_all_solutions(chain, result, target, mid, most=16)
        assert min(wrapped_distance(x, q) for x in result.solutions) < 1e-7, q
        if i < enumerated:
            found = np.array(result.solutions)
            others = enumerate_by_least_squares(chain, target, chain.random(rng, seeds))
            assert len(others) >= 1 and missing(chain, found, others) == 0


@pytest.mark.parametrize("table", [OFFSET_WRIST, TWO_POINT_WRIST], ids=["offset-wrist", "two-point-wrist"])
def test_rendered_arms_every_solution(table: list[tuple[float, float, float]]) -> None:
    check_search(dh_chain(table, seed=9), samples=150, enumerated=3)


def test_plan_refuses_other_structures() -> None:
    general = [PUMA_RIGHT[0], (0.15, 0.43, 0.3), *PUMA_RIGHT[2:]]  # axes 2∦3
    with pytest.raises(ArmtoolError, match="the 1-D search needs axes 4, 5 intersecting and axes 2∥3"):
        search.plan(dh_chain(general, seed=9))


def test_model_reversed_for_the_pair_at_the_base() -> None:
    """The rendered offset-wrist arm read from its tip: axes 2∩3 and 4∥5, solved reversed (over θ1)."""
    forward = dh_chain(OFFSET_WRIST, seed=9)
    flipped = _reversed_chain(forward)
    assert search.plan(flipped) is True
    check_search(flipped, samples=60, enumerated=1)


def _reversed_chain(chain: Chain) -> Chain:
    """The same arm built from its tip: joint axes in reverse order, q_i turning the other way."""
    from armtool.ik.closed_form.families import reversed_lines
    from armtool.ik.closed_form.geometry import axis_lines

    lines, tip0 = axis_lines(chain)
    flipped, tip = reversed_lines(lines, tip0)
    links = "".join(f'<link name="l{i}"/>' for i in range(7))
    joints = []
    for i, (p, w) in enumerate(flipped):
        prev = np.zeros(3) if i == 0 else flipped[i - 1][0]
        x, y, z = (float(v) for v in p - prev)
        w = [float(v) for v in w]
        j = 5 - i  # the same q: reversed_lines turns each axis around
        lo, hi = float(chain.lower[j]), float(chain.upper[j])
        limit = "" if chain.continuous[j] else f'<limit lower="{lo!r}" upper="{hi!r}" effort="1" velocity="1"/>'
        kind = "continuous" if chain.continuous[j] else "revolute"
        joints.append(
            f'<joint name="r{i + 1}" type="{kind}"><parent link="l{i}"/><child link="l{i + 1}"/>'
            f'<origin xyz="{x!r} {y!r} {z!r}"/><axis xyz="{w[0]!r} {w[1]!r} {w[2]!r}"/>{limit}</joint>'
        )
    R, t = tip[:3, :3], [float(v) for v in tip[:3, 3] - flipped[5][0]]
    rpy = (float(math.atan2(R[2, 1], R[2, 2])), float(math.asin(-R[2, 0])), float(math.atan2(R[1, 0], R[0, 0])))
    joints.append(
        '<link name="tool"/><joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/>'
        f'<origin xyz="{t[0]!r} {t[1]!r} {t[2]!r}" rpy="{rpy[0]!r} {rpy[1]!r} {rpy[2]!r}"/></joint>'
    )
    from lxml import etree

    return chain_from_xml(etree.fromstring(f'<robot name="flipped">{links}{"".join(joints)}</robot>'), "l0", "tool")


# ---- real arms (../shared/realworld) ---------------------------------------------------------------------------


def _realworld(relative: str, args: dict[str, str], base: str, tip: str) -> Chain:
    from armtool.model.load import load_robot_xml

    path = REALWORLD / relative
    if not path.is_file():
        pytest.skip("the realworld corpus is absent")
    return chain_from_xml(load_robot_xml(path, args, [REALWORLD.resolve()]), base, tip)


def test_xarm6() -> None:
    """xarm_ros2's xArm6: axis 6 7.6 cm off the 4∩5 point; EAIK has no decomposition for it."""
    chain = _realworld("xarm_ros2/xarm_description/urdf/xarm_device.urdf.xacro", {"dof": "6"}, "link_base", "link6")
    check_search(chain, samples=100, enumerated=2)


def test_gen3_lite() -> None:
    """ros2_kortex's Gen3 lite: axes 4∩5 and 5∩6 meet in two points; its rpy 1.5708 leaves axes 2∥3 within 3.7e-6 rad."""
    chain = _realworld("ros2_kortex/kortex_description/robots/gen3_lite.urdf", {}, "base_link", "tool_frame")
    check_search(chain, samples=100, enumerated=2)


def test_ik_bench_row_names_the_search() -> None:
    """`armtool ik-bench` on Gen3 lite: the search row is solved, counts its solutions, and its method
    says how; the analytic row is not applicable (no closed form) and its reason names the search."""
    import json

    from typer.testing import CliRunner

    from armtool.cli import app

    urdf = REALWORLD / "ros2_kortex/kortex_description/robots/gen3_lite.urdf"
    if not urdf.is_file():
        pytest.skip("the realworld corpus is absent")
    args = ["ik-bench", str(urdf), "--solvers", "analytic,search", "--samples", "20", "--no-batch", "--format", "json"]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    rows = {r["solver"]: r for r in json.loads(result.stdout)["solvers"]}
    assert "search" in json.dumps(rows.get("analytic", {})) or "analytic" not in rows
    row = rows["search"]
    assert row["success_rate"] == 1.0 and row["distinct_solutions"] > 1
    assert row["method"].startswith("1-D search over θ6")


# ---- against the closed form, near a wrist singularity -----------------------------------------------------

UR10_DH = [  # UR10's DH rows (d, a, α): axes 2∥3∥4, 4∩5, so both `analytic` and the search solve it
    (0.1273, 0.0, math.pi / 2),
    (0.0, -0.612, 0.0),
    (0.0, -0.5723, 0.0),
    (0.163941, 0.0, math.pi / 2),
    (0.1157, 0.0, -math.pi / 2),
    (0.0922, 0.0, 0.0),
]


def _set_difference(
    solvers: tuple[Solver, Solver], target: np.ndarray, seed: np.ndarray, gap: float = 1e-6
) -> tuple[int, int, int]:
    """(closed-form solutions, those the search lacks, search solutions the closed form lacks), at `gap` rad."""
    closed = np.array(solvers[0].solve(target, seed).solutions).reshape(-1, 6)
    found = np.array(solvers[1].solve(target, seed).solutions).reshape(-1, 6)
    lacking = sum(min((wrapped_distance(a, b) for b in found), default=1.0) > gap for a in closed)
    extra = sum(min((wrapped_distance(b, a) for a in closed), default=1.0) > gap for b in found)
    return len(closed), lacking, extra


def test_ur10_target_near_the_wrist_singularity() -> None:
    """example-robot-data's UR10, bench target 34 of 1000: solutions with θ5 = 0.0003 and θ5 = −0.068. The
    −0.068 pair sits where θ1's reach margin dips below zero between two samples (both reaching): the
    search lost it before the dip was descended."""
    from armtool.ik.bench import BenchConfig, make_targets
    from armtool.model.chain import load_chain
    from tests.ik.robots import erd

    chain = load_chain(erd("ur_description/urdf/ur10_robot.urdf"), "world", "tool0")
    targets = make_targets(chain, BenchConfig(samples=1000))
    solvers = (make_solver("analytic", chain), make_solver("search", chain))
    closed, lacking, extra = _set_difference(solvers, targets.poses[34], targets.seeds[34])
    assert (closed, lacking, extra) == (6, 0, 0)


def test_rendered_ur10_near_the_wrist_singularity() -> None:
    """A rendered UR10 (its DH rows behind rotated URDF frames), 3000 configurations with |θ5| ≤ 0.3 rad:
    every closed-form solution is among the search's and the other way round. Compared at 1e-3 rad: at
    a singular configuration a pose within the tolerance leaves the joints ~√tolerance apart. Where the
    wrist point passes near axis 1, θ1's reach margin rises above zero between two clamped samples for
    ~1e-3 rad only: those solutions were lost before such islands were searched."""
    chain = dh_chain(UR10_DH, seed=5)
    rng = np.random.default_rng(8)
    Q = chain.random(rng, 3000)
    Q[:, 4] = rng.uniform(-0.3, 0.3, len(Q))
    seed = chain.mid()
    solvers = (make_solver("analytic", chain), make_solver("search", chain))
    differences = [(i, *_set_difference(solvers, chain.fk(q), seed, gap=1e-3)) for i, q in enumerate(Q)]
    assert [d for d in differences if d[2] or d[3]] == []
    assert sum(d[1] for d in differences) > 3000 * 4
