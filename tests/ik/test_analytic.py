"""armtool's `analytic` solver: the geometry is detected from the URDF, every solution is found and verified."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from lxml import etree

from armtool.errors import ArmtoolError
from armtool.ik import load_chain, make_solver
from armtool.ik.solver import Array, IKResult, verify
from armtool.model.chain import Chain, chain_from_xml
from tests.ik.robots import ARMS, erd

UR = {
    "ur3": "ur_description/urdf/ur3_robot.urdf",
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "ur10": "ur_description/urdf/ur10_robot.urdf",
    "ur5-limited": "ur_description/urdf/ur5_joint_limited_robot.urdf",
}


def wrapped_distance(a: Array, b: Array) -> float:
    """Largest joint difference modulo 2π."""
    return float(np.max(np.abs((a - b + math.pi) % (2 * math.pi) - math.pi)))


def check_all_solutions(chain: Chain, result: IKResult, target: Array, seed: Array, most: int = 8) -> None:
    """Every solution verifies to ~1e-9, lies in the limits, is geometrically distinct; q is the nearest to the seed."""
    assert result.success and 1 <= len(result.solutions) <= most
    assert result.q is result.solutions[0]
    for x in result.solutions:
        ok, pos, rot = verify(chain, x, target, 1e-5)
        assert ok and pos < 1e-9 and rot < 1e-9
        assert chain.within_limits(x, tol=0.0)
    for i, x in enumerate(result.solutions):
        assert all(wrapped_distance(x, y) > 1e-6 for y in result.solutions[i + 1 :])
    dist = [float(np.sum((x - seed) ** 2)) for x in result.solutions]
    assert dist == sorted(dist)
    ok, pos, rot = verify(chain, result.q, target, 1e-5)
    assert result.position_error_m == pytest.approx(pos, abs=1e-12) and result.orientation_error_rad == pytest.approx(
        rot, abs=1e-9
    )


def assert_finds_random_configurations(chain: Chain, count: int = 200, seed: int = 0) -> float:
    """FK of random in-limit configurations → solve from the middle: the original q is among the solutions."""
    solver = make_solver("analytic", chain)
    rng = np.random.default_rng(seed)
    Q = chain.random(rng, count)
    mid = chain.mid()
    counts = []
    for q, target in zip(Q, chain.fk_batch(Q)):
        result = solver.solve(target, mid)
        check_all_solutions(chain, result, target, mid)
        assert min(wrapped_distance(x, q) for x in result.solutions) < 1e-7, q
        counts.append(len(result.solutions))
    return float(np.mean(counts))


# ---- real robots --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("arm", list(UR))
def test_ur_arms_every_solution(arm: str) -> None:
    chain = load_chain(erd(UR[arm]))
    solver = make_solver("analytic", chain)
    assert solver.geometry.kind == "ur" and solver.geometry.model_error < 1e-12
    assert assert_finds_random_configurations(chain) > 6


def test_kinova_spherical_wrist() -> None:
    chain = load_chain(erd(ARMS["kinova"][0]), tip="j2s6s200_end_effector")
    assert make_solver("analytic", chain).geometry.kind == "spherical-wrist"
    assert_finds_random_configurations(chain)


def test_z1_ur_type_with_wrist_offset() -> None:
    """Unitree Z1: axes 2, 3, 4 parallel but axis 5 passes 7 cm beside axis 4 (a4 ≠ 0); the gripper is cut off."""
    chain = load_chain(erd("z1_description/urdf/z1.urdf"), tip="link06")
    solver = make_solver("analytic", chain)
    assert solver.geometry.kind == "ur" and solver.geometry.joints[3].a == pytest.approx(0.07)
    assert_finds_random_configurations(chain)


@pytest.mark.parametrize(
    "q",
    [
        [0, 0, 0, 0, 0, 0],  # stretched elbow and wrist singularity (axis 6 ∥ axes 2-4)
        [0.3, -1.0, 0.0, 0.5, 0.0, 1.0],
        [0.3, -1.0, 1.2, 0.5, math.pi, 1.0],
        [1.0, -2.0, 3.0, -1.0, 0.7, 2.0],
    ],
)
def test_ur5_singular_and_boundary_configurations(q: list[float]) -> None:
    chain = load_chain(erd(UR["ur5"]))
    solver = make_solver("analytic", chain)
    q_arr = np.array(q, dtype=float)
    target = chain.fk(q_arr)
    for seed in (chain.mid(), q_arr):
        check_all_solutions(chain, solver.solve(target, seed), target, seed)
    # From the configuration itself the free angle of a singularity comes from the seed: q comes back.
    assert wrapped_distance(solver.solve(target, q_arr).q, q_arr) < 1e-7


def test_ur5_wrist_singularity_from_any_seed() -> None:
    """At the wrist singularity θ6 is free only as far as the elbow can follow: a seed's θ6 it cannot is moved."""
    chain = load_chain(erd(UR["ur5"]))
    solver = make_solver("analytic", chain)
    rng = np.random.default_rng(11)
    for q in ([0, 0, 0, 0, 0, 0], [0.3, -1.0, 0.2, 0.5, 0.0, 1.0], [0.3, -1.0, 1.2, 0.5, math.pi, 1.0]):
        target = chain.fk(np.array(q, dtype=float))
        for seed in chain.random(rng, 30):
            check_all_solutions(chain, solver.solve(target, seed), target, seed)


def test_seed_picks_the_representation_and_the_branch() -> None:
    chain = load_chain(erd(UR["ur5"]))
    solver = make_solver("analytic", chain)
    q = np.array([0.4, -1.1, 1.3, -0.7, 1.2, 0.3])
    target = chain.fk(q)
    near = solver.solve(target, q + 0.05)
    assert np.allclose(near.q, q, atol=1e-9)
    shifted = q.copy()
    shifted[[0, 5]] -= 2 * math.pi  # UR joints have ±2π limits: the seed's turn is kept
    result = solver.solve(target, shifted)
    assert np.allclose(result.q, shifted, atol=1e-9)


@pytest.mark.parametrize("arm", ["ur5", "kinova"])
def test_batch_equals_single(arm: str) -> None:
    chain = load_chain(erd(UR["ur5"])) if arm == "ur5" else load_chain(erd(ARMS[arm][0]), *ARMS[arm][1:])
    solver = make_solver("analytic", chain)
    rng = np.random.default_rng(3)
    targets = chain.fk_batch(chain.random(rng, 20))
    seeds = np.tile(chain.mid(), (20, 1))
    for batch, t, s in zip(solver.solve_batch(targets, seeds), targets, seeds):
        single = solver.solve(t, s)
        # the batch runs on the lanes (closed_form/lanes.py: another atan2, cosines from square roots)
        assert batch.success and len(batch.solutions) == len(single.solutions)
        for x, y in zip(batch.solutions, single.solutions):
            assert np.allclose(x, y, rtol=0.0, atol=1e-9)


# ---- failures ------------------------------------------------------------------------------------------------


def test_unreachable_target_fails_with_reason() -> None:
    chain = load_chain(erd(UR["ur5"]))
    solver = make_solver("analytic", chain)
    target = np.eye(4)
    target[:3, 3] = [5.0, 0.0, 0.0]
    result = solver.solve(target, chain.mid())
    assert not result.success and "out of reach" in result.reason and result.solutions == ()
    assert chain.within_limits(result.q) and result.position_error_m > 3.0


def test_solutions_outside_the_limits_are_dropped() -> None:
    """With the elbow narrowed to ±0.1 rad, a target whose every solution bends the elbow more has none."""
    chain = load_chain(erd(UR["ur5"]))
    q = np.array([2.5, -1.0, 1.0, -1.0, 1.0, 0.0])
    target = chain.fk(q)
    free = make_solver("analytic", chain).solve(target, np.zeros(6))
    assert free.success and all(abs(x[2]) > 0.1 for x in free.solutions)
    chain.lower[2], chain.upper[2] = -0.1, 0.1
    result = make_solver("analytic", chain).solve(target, np.zeros(6))
    assert (
        not result.success
        and result.reason == f"{len(free.solutions)} solution(s) of the closed form, none within the joint limits"
    )
    assert chain.within_limits(result.q)


def test_panda_has_no_closed_form() -> None:
    relative, base, tip = ARMS["panda"]
    chain = load_chain(erd(relative), base, tip)
    with pytest.raises(
        ArmtoolError,
        match=r"the chain has 7 joints; closed form needs 6R with a spherical wrist or three parallel axes \(UR-type\)",
    ) as info:
        make_solver("analytic", chain)
    assert "gripper" not in (info.value.hint or ""), "panda_joint7 is an arm joint, not a gripper's"


def test_gripper_hint_only_for_gripper_joints() -> None:
    """A 6R arm with a finger joint after it: the hint names the finger joint (item 12 of issue 10)."""
    from armtool.model.chain import ChainJoint

    chain = dh_chain(UR_LIKE, name="with_finger")
    finger = ChainJoint("finger_joint", "prismatic", np.eye(4), np.array([1.0, 0.0, 0.0]), 0.0, 0.04)
    with_finger = Chain(chain.name, chain.base, chain.tip, [*chain.joints, finger], chain.tip_offset)
    with pytest.raises(ArmtoolError, match="the chain has 7 joints") as info:
        make_solver("analytic", with_finger)
    assert "finger_joint look like a gripper's" in (info.value.hint or "")


def test_general_6r_names_the_failed_checks() -> None:
    chain = dh_chain(GENERAL_6R, name="skew")
    with pytest.raises(ArmtoolError) as info:
        make_solver("analytic", chain)
    text = str(info.value)
    assert "the chain (6R) has no supported closed form" in text
    assert "UR-type: axis 2∥3: no" in text and "spherical wrist: axes 4,5 intersect: no" in text


def test_no_options() -> None:
    chain = load_chain(erd(UR["ur5"]))
    with pytest.raises(ArmtoolError, match="no option"):
        make_solver("analytic", chain, free_joint=5)


# ---- synthetic arms: geometry given as DH, hidden behind rotated URDF frames ------------------------------------

# (d, a, alpha) of joints 1..6 in standard DH; the URDF adds joint-zero offsets, flipped axes and unaligned frames.
PUMA_LIKE = [
    (0.30, 0.05, 1.3),
    (0.12, 0.43, 0.0),
    (-0.04, 0.02, 1.5708),
    (0.43, 0.0, -1.2),
    (0.0, 0.0, 1.9),
    (0.06, 0.0, 0.0),
]
UR_LIKE = [
    (0.10, 0.04, 1.4),
    (0.05, 0.40, 0.0),
    (-0.03, 0.35, 0.0),
    (0.11, 0.03, 1.2),
    (0.09, 0.0, -1.75),
    (0.08, 0.0, 0.0),
]
PUMA_RIGHT = [
    (0.0, 0.0, math.pi / 2),
    (0.15, 0.43, 0.0),
    (0.0, 0.02, -math.pi / 2),
    (0.43, 0.0, math.pi / 2),
    (0.0, 0.0, -math.pi / 2),
    (0.06, 0.0, 0.0),
]
GENERAL_6R = [(0.3, 0.1, 1.2), (0.1, 0.4, 0.3), (0.0, 0.3, 1.4), (0.2, 0.05, -1.0), (0.1, 0.02, 0.9), (0.1, 0.0, 0.0)]


def _rpy(R: Array) -> tuple[float, float, float]:
    return math.atan2(R[2, 1], R[2, 2]), math.asin(-R[2, 0]), math.atan2(R[1, 0], R[0, 0])


def _origin(T: Array) -> str:
    xyz = " ".join(repr(float(v)) for v in T[:3, 3])
    return f'<origin xyz="{xyz}" rpy="{" ".join(repr(v) for v in _rpy(T[:3, :3]))}"/>'


def _random_rotation(rng: np.random.Generator) -> Array:
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q


def dh_chain(
    table: list[tuple[float, float, float]], name: str = "synthetic", seed: int = 7, limits: float = math.pi
) -> Chain:
    """A URDF whose joint i turns about z of DH frame i−1, with link frames rotated and shifted along the axis,
    joint-zero offsets, some axes flipped, a rotated base, a fixed joint inside, and a rotated tool."""
    rng = np.random.default_rng(seed)

    def rz(t: float) -> Array:
        T = np.eye(4)
        T[:2, :2] = [[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]]
        return T

    def dh(d: float, a: float, alpha: float) -> Array:
        T = np.eye(4)
        T[:3, 3] = [a, 0.0, d]
        T[1:3, 1:3] = [[math.cos(alpha), -math.sin(alpha)], [math.sin(alpha), math.cos(alpha)]]
        return T

    # Link frame of joint i: J_i = F_{i-1}·Rz(θ_i)·H_i with H_i = Tz(t)·R (origin on the axis), θ_i = offset_i + sign_i·q_i.
    H = []
    for _ in range(6):
        h = np.eye(4)
        h[:3, :3] = _random_rotation(rng)
        h[2, 3] = rng.uniform(-0.1, 0.1)
        H.append(h)
    offsets = rng.uniform(-math.pi, math.pi, 6)
    signs = rng.choice([-1.0, 1.0], 6)
    base = np.eye(4)
    base[:3, :3] = _random_rotation(rng)
    base[:3, 3] = rng.uniform(-0.2, 0.2, 3)
    tool = np.eye(4)
    tool[:3, :3] = _random_rotation(rng)
    tool[:3, 3] = [0.01, -0.02, 0.03]
    links = (
        ['<link name="base"/>']
        + [f'<link name="l{i}"/>' for i in range(1, 7)]
        + ['<link name="mid"/>', '<link name="tool"/>']
    )
    joints = []
    for i in range(6):
        if i == 0:
            origin = base @ rz(offsets[0]) @ H[0]
        else:
            origin = np.linalg.inv(H[i - 1]) @ dh(*table[i - 1]) @ rz(offsets[i]) @ H[i]
        axis = signs[i] * (H[i][:3, :3].T @ np.array([0.0, 0.0, 1.0]))
        parent = "base" if i == 0 else f"l{i}"
        if i == 3:  # split this origin with a fixed joint, which the chain folds in
            half = np.eye(4)
            half[:3, 3] = [0.05, 0.0, 0.0]
            joints.append(
                f'<joint name="fixed_mid" type="fixed"><parent link="l3"/><child link="mid"/>{_origin(half)}</joint>'
            )
            origin, parent = np.linalg.inv(half) @ origin, "mid"
        kind = "continuous" if i == 5 else "revolute"
        limit = "" if kind == "continuous" else f'<limit lower="{-limits}" upper="{limits}" effort="1" velocity="1"/>'
        # a joint turning by +q about `axis` turns the DH frame by sign·q about z: θ = offset + sign·q
        joints.append(
            f'<joint name="j{i + 1}" type="{kind}"><parent link="{parent}"/><child link="l{i + 1}"/>{_origin(origin)}'
            f'<axis xyz="{" ".join(repr(float(v)) for v in axis)}"/>{limit}</joint>'
        )
    last = np.linalg.inv(H[5]) @ dh(*table[5]) @ tool
    joints.append(
        f'<joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/>{_origin(last)}</joint>'
    )
    xml = f'<robot name="{name}">{"".join(links)}{"".join(joints)}</robot>'
    return chain_from_xml(etree.fromstring(xml), "base", "tool")


@pytest.mark.parametrize(("table", "kind"), [(PUMA_LIKE, "spherical-wrist"), (UR_LIKE, "ur")])
def test_synthetic_arms(table: list[tuple[float, float, float]], kind: str) -> None:
    """Shoulder and elbow offsets, non-right twists, joint-zero offsets, flipped axes, rotated base and tool."""
    for seed in (7, 8):
        chain = dh_chain(table, seed=seed)
        solver = make_solver("analytic", chain)
        assert solver.geometry.kind == kind and solver.geometry.model_error < 1e-12
        assert assert_finds_random_configurations(chain, count=100, seed=seed) > 4


def test_spherical_wrist_singularity() -> None:
    """Axis 6 lined up with axis 4 (α4 = ±α5 and θ5 = 0 or π): θ4 comes from the seed and θ6 absorbs the rest."""
    chain = dh_chain(PUMA_RIGHT, seed=9)
    solver = make_solver("analytic", chain)
    j4, j5 = solver.geometry.joints[3:5]
    # cos(angle between axes 4 and 6) = cos α4 cos α5 − sin α4 sin α5 cos θ5: ±1 at θ5 = 0 or π
    theta5 = min(
        (0.0, math.pi),
        key=lambda t: (
            1 - abs(math.cos(j4.alpha) * math.cos(j5.alpha) - math.sin(j4.alpha) * math.sin(j5.alpha) * math.cos(t))
        ),
    )
    rng = np.random.default_rng(4)
    for _ in range(50):
        q = chain.random(rng)
        q[4] = math.remainder((theta5 - j5.offset) / j5.sign, 2 * math.pi)
        target = chain.fk(q)
        for seed in (chain.mid(), q):
            check_all_solutions(chain, solver.solve(target, seed), target, seed)
        assert wrapped_distance(solver.solve(target, q).q, q) < 1e-7


def check_near(chain: Chain, kind: str, samples: int = 40) -> None:
    """A near-closed-form chain: the snapped model solves, Newton polishes, every answer passes our FK check."""
    solver = make_solver("analytic", chain)
    assert solver.geometry.near and solver.geometry.kind == kind and 0 < solver.geometry.model_error < 1e-2
    rng = np.random.default_rng(11)
    solved = 0
    for q in chain.random(rng, samples):
        target = chain.fk(q)
        result = solver.solve(target, chain.mid())
        solved += result.success
        if not result.success:  # only next to a singularity may Newton fail to close the model's gap
            sv = np.linalg.svd(chain.jacobian(q), compute_uv=False)
            assert sv[0] / sv[-1] > 1000, result.reason
        for x in result.solutions:
            ok, _pos, _rot = verify(chain, x, target, 1e-5)
            assert ok and chain.within_limits(x, tol=0.0)
        for i, x in enumerate(result.solutions):
            assert all(wrapped_distance(x, y) > 1e-7 for y in result.solutions[i + 1 :])
    assert solved >= 0.95 * samples


def test_nearly_parallel_axes_are_solved_through_the_nearest_model() -> None:
    """Axes 2 and 3 parallel within 1e-6 rad but not exactly: the model misses by ~1e-7, Newton closes the gap."""
    check_near(dh_chain([UR_LIKE[0], (0.05, 0.40, 5e-7), *UR_LIKE[2:]]), "ur")


def test_near_spherical_wrist_is_solved_through_the_nearest_model() -> None:
    """Axis 6 misses the wrist centre by 0.35 mm and axes 2/3 are 2e-4 rad off parallel (Kinova Gen3 6-DOF's kind of arm)."""
    near = [
        PUMA_RIGHT[0],
        (0.15, 0.43, 2e-4),
        PUMA_RIGHT[2],
        PUMA_RIGHT[3],
        (0.0, 0.00035, -math.pi / 2),
        PUMA_RIGHT[5],
    ]
    check_near(dh_chain(near, seed=9), "spherical-wrist")


def test_exact_arms_stay_exact() -> None:
    assert not make_solver("analytic", dh_chain(PUMA_RIGHT, seed=9)).geometry.near
    assert not make_solver("analytic", dh_chain(UR_LIKE)).geometry.near


def test_far_from_closed_form_is_refused_and_pointed_at_the_search() -> None:
    """Axis 6 2 cm off the wrist: no family even within 1 mm, but axes 4∩5 and 2∥3: analytic refuses
    and its hint names the 1-D search (tests/ik/test_search.py checks that solver)."""
    far = [PUMA_RIGHT[0], PUMA_RIGHT[1], PUMA_RIGHT[2], PUMA_RIGHT[3], (0.0, 0.02, -math.pi / 2), PUMA_RIGHT[5]]
    with pytest.raises(ArmtoolError, match="not even within 0.001 rad / 0.001 m") as info:
        make_solver("analytic", dh_chain(far, seed=9))
    assert "--solvers search" in info.value.hint
    assert make_solver("search", dh_chain(far, seed=9)).method.startswith("1-D search over θ6")


def test_no_closed_form_and_no_search_structure_is_refused_by_both() -> None:
    """Axes 4, 5 apart and 2∦3: neither a family (not even within 1 mm) nor the search's structure."""
    far = [PUMA_RIGHT[0], (0.15, 0.43, 0.3), PUMA_RIGHT[2], (0.43, 0.02, math.pi / 2), PUMA_RIGHT[4], PUMA_RIGHT[5]]
    with pytest.raises(ArmtoolError, match="not even within 0.001 rad / 0.001 m") as info:
        make_solver("analytic", dh_chain(far, seed=9))
    assert "search" not in info.value.hint
    with pytest.raises(ArmtoolError, match="the 1-D search needs axes 4, 5 intersecting"):
        make_solver("search", dh_chain(far, seed=9))


REALWORLD = Path(__file__).resolve().parents[2] / ".." / "shared" / "realworld"


def test_kinova_gen3_6dof_is_near_closed_form() -> None:
    """ros2_kortex's gen3.xacro with dof:=6 (as its README's launch examples pass it): axis 6 misses the wrist by 0.35 mm."""
    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml

    xacro = REALWORLD / "ros2_kortex/kortex_description/robots/gen3.xacro"
    if not xacro.is_file():
        pytest.skip("the realworld corpus is absent")
    root = load_robot_xml(xacro, {"dof": "6"}, [REALWORLD.resolve()])
    check_near(chain_from_xml(root, "base_link", "end_effector_link"), "spherical-wrist", samples=30)


def test_bad_seed_is_a_usage_error() -> None:
    chain = load_chain(erd(UR["ur5"]))
    solver = make_solver("analytic", chain)
    with pytest.raises(ArmtoolError, match="seed must be 6 finite joint values"):
        solver.solve(chain.fk(np.zeros(6)), np.full(6, np.nan))
