"""Chains from URDF: FK against Pinocchio's own URDF parser and a hand computation; Jacobians vs
finite differences; the errors users hit (unknown links, no chain, mimic joints)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from armtool.errors import ArmtoolError
from armtool.model.chain import Chain, load_chain, rpy_matrix
from tests.ik.robots import ARMS, PLANAR_2R, erd


def test_rpy_is_fixed_axis_xyz() -> None:
    r, p, y = 0.3, -0.2, 1.1
    Rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    Ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    Rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    assert np.allclose(rpy_matrix(r, p, y), Rz @ Ry @ Rx)


def test_planar_fk_by_hand(tmp_path: Path) -> None:
    path = tmp_path / "planar.urdf"
    path.write_text(PLANAR_2R)
    chain = load_chain(path)
    assert (chain.base, chain.tip, chain.joint_names) == ("base", "tool", ["j1", "j2"])
    q = np.array([0.4, -1.1])
    x = 0.5 * math.cos(q[0]) + 0.3 * math.cos(q[0] + q[1])
    y = 0.5 * math.sin(q[0]) + 0.3 * math.sin(q[0] + q[1])
    for T in (chain.fk(q), chain.fk_batch(q[None])[0], chain.fk_jacobian_batch(q[None])[0][0]):
        assert np.allclose(T[:3, 3], [x, y, 0.1])
        assert math.isclose(math.atan2(T[1, 0], T[0, 0]), q.sum())


@pytest.mark.parametrize("arm", sorted(ARMS))
def test_fk_matches_pinocchio_urdf_parser(arm: str) -> None:
    import pinocchio as pin

    relative, base, tip = ARMS[arm]
    path = erd(relative)
    chain = load_chain(path, base, tip)
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    f_base, f_tip = model.getFrameId(chain.base), model.getFrameId(chain.tip)
    rng = np.random.default_rng(3)
    Q = chain.random(rng, 30)
    batch = chain.fk_batch(Q)
    batch_j, _ = chain.fk_jacobian_batch(Q)
    for q, Tb, Tj in zip(Q, batch, batch_j):
        full = pin.neutral(model)
        for value, name in zip(q, chain.joint_names):
            jid = model.getJointId(name)
            idx = model.idx_qs[jid]
            if model.nqs[jid] == 2:  # continuous joints: (cos, sin)
                full[idx : idx + 2] = [math.cos(value), math.sin(value)]
            else:
                full[idx] = value
        pin.framesForwardKinematics(model, data, full)
        expected = (data.oMf[f_base].inverse() * data.oMf[f_tip]).homogeneous
        assert np.allclose(chain.fk(q), expected, atol=1e-12)
        assert np.allclose(Tb, expected, atol=1e-12)
        assert np.allclose(Tj, expected, atol=1e-12)


@pytest.mark.parametrize("arm", sorted(ARMS))
def test_jacobians_match_finite_differences(arm: str) -> None:
    relative, base, tip = ARMS[arm]
    chain = load_chain(erd(relative), base, tip)
    rng = np.random.default_rng(7)
    for q in chain.random(rng, 5):
        T, J = chain.fk_jacobian(q)
        _, Jb = chain.fk_jacobian_batch(q[None])
        assert np.allclose(J, Jb[0], atol=1e-12)
        h = 1e-6
        for i in range(chain.n):
            dq = np.zeros(chain.n)
            dq[i] = h
            Tp, Tm = chain.fk(q + dq), chain.fk(q - dq)
            v = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
            dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T[:3, :3].T  # = skew(w)
            w = np.array([dR[2, 1], dR[0, 2], dR[1, 0]])
            assert np.allclose(J[:3, i], v, atol=1e-6) and np.allclose(J[3:, i], w, atol=1e-6)


def test_continuous_joints_are_unbounded_and_wrap() -> None:
    chain = load_chain(erd("kinova_description/robots/kinova.urdf"))
    assert chain.continuous.any()
    q = chain.mid()
    q[np.flatnonzero(chain.continuous)[0]] = 7.0
    assert chain.within_limits(q)


def test_unknown_links_list_what_exists(tmp_path: Path) -> None:
    path = tmp_path / "planar.urdf"
    path.write_text(PLANAR_2R)
    with pytest.raises(ArmtoolError) as err:
        load_chain(path, tip="tol")
    assert "did you mean 'tool'" in err.value.what and "base, l1, l2, tool" in (err.value.hint or "")
    with pytest.raises(ArmtoolError, match="not below"):
        load_chain(path, base="tool", tip="base")
    with pytest.raises(ArmtoolError, match="no moving joint"):
        load_chain(path, base="l2", tip="tool")


def test_mimic_joint_in_chain_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "mimic.urdf"
    path.write_text(PLANAR_2R.replace('<origin xyz="0.5 0 0"/>', '<origin xyz="0.5 0 0"/><mimic joint="j1"/>'))
    with pytest.raises(ArmtoolError, match="mimic"):
        load_chain(path, tip="tool")


def test_unparseable_urdf_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "bad.urdf"
    path.write_text("<robot name='x'><link name='a'></robot>")
    with pytest.raises(ArmtoolError) as err:
        load_chain(path)
    assert "not well-formed" in err.value.what and "bad.urdf:1" in (err.value.where or "")


def test_default_chain_stops_before_fingers_and_prefers_a_tool_frame() -> None:
    """Franka-like: the longest chain ends at a finger; the default ends at the arm's TCP instead."""
    from lxml import etree

    from armtool.model.chain import default_base_tip
    from tests.ik.test_group import ARM

    root = etree.fromstring(ARM)
    assert default_base_tip(root) == ("world", "tool_frame")
    no_tool = ARM.replace('"tool_frame"', '"plate"')
    assert default_base_tip(etree.fromstring(no_tool)) == ("world", "plate")  # the deepest link at the arm's end
    # A mimic joint counts as a gripper joint whatever its name (j1, which it mimics, drives the arm below it).
    mimic = ARM.replace('name="finger_joint"', 'name="j4"').replace(
        '<limit lower="0" upper="0.04"', '<mimic joint="j1"/><limit lower="0" upper="0.04"'
    )
    assert default_base_tip(etree.fromstring(mimic))[1] == "tool_frame"
    # ... and so does the joint the fingers mimic (xArm's gripper: drive_joint, followers *_knuckle_joint).
    drive = (
        ARM.replace('name="finger_joint"', 'name="drive_joint"')
        .replace('"tool_frame"', '"plate"')
        .replace(
            "</robot>",
            '<link name="follower"/><joint name="follower_joint" type="revolute"><parent link="finger"/><child link="follower"/>'
            '<mimic joint="drive_joint"/><axis xyz="0 0 1"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint></robot>',
        )
    )
    assert default_base_tip(etree.fromstring(drive))[1] == "plate"


REALWORLD = Path(__file__).resolve().parents[2] / ".." / "shared" / "realworld"


@pytest.mark.parametrize(
    ("relative", "args", "tip"),
    [
        ("franka_description/robots/fr3/fr3.urdf.xacro", {}, "fr3_hand_tcp"),
        ("ros2_kortex/kortex_description/robots/gen3_lite.urdf", {}, "tool_frame"),
        ("Universal_Robots_ROS2_Description/urdf/ur.urdf.xacro", {"name": "ur", "ur_type": "ur5e"}, "tool0"),
        ("xarm_ros2/xarm_description/urdf/xarm_device.urdf.xacro", {"dof": "6", "add_gripper": "true"}, "link_tcp"),
    ],
)
def test_default_chain_on_real_arms(relative: str, args: dict[str, str], tip: str) -> None:
    from armtool.model.chain import default_base_tip
    from armtool.model.load import load_robot_xml

    path = REALWORLD / relative
    if not path.is_file():
        pytest.skip("the realworld corpus is absent")
    root = load_robot_xml(path, args, [REALWORLD.resolve()])
    assert default_base_tip(root)[1] == tip


# Every case of fk_jacobian_soa's plan: a prismatic first joint, revolute axes along -z, y (the
# turned columns 0 and 2, not adjacent), x, and an unaligned one, a continuous joint, and a tip
# offset that is the identity (no tip frame) or a fixed joint.
MIXED_JOINTS = """<robot name="mixed">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/><link name="l5"/>
  <link name="tool"/>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1" rpy="0.2 0 0"/><axis xyz="0 0 1"/><limit lower="-0.2" upper="0.3"/></joint>
  <joint name="yaw" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.1 0 0.1"/><axis xyz="0 0 -1"/><limit lower="-2" upper="2"/></joint>
  <joint name="pitch" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0.1 0.2" rpy="0 0.3 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2"/></joint>
  <joint name="tilted" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.2 0 0"/><axis xyz="0.3 0.5 0.8"/><limit lower="-2" upper="2"/></joint>
  <joint name="roll" type="continuous"><parent link="l4"/><child link="l5"/>
    <origin xyz="0 0 0.1" rpy="0 0 1.0"/><axis xyz="-1 0 0"/></joint>
  <joint name="flange" type="fixed"><parent link="l5"/><child link="tool"/>
    <origin xyz="0 0 0.05" rpy="0.1 0.2 0.3"/></joint>
</robot>
"""


@pytest.mark.parametrize("tip", ["tool", "l5"])
def test_soa_kinematics_match_pinocchio_on_every_joint_kind(tmp_path: Path, tip: str) -> None:
    path = tmp_path / "mixed.urdf"
    path.write_text(MIXED_JOINTS)
    chain = load_chain(path, "base", tip)
    Q = chain.random(np.random.default_rng(5), 9)
    R, p, J = chain.fk_jacobian_soa(Q)
    R_only, p_only, none = chain.fk_jacobian_soa(Q, jacobian=False)
    assert J is not None and none is None
    assert np.array_equal(R, R_only) and np.array_equal(p, p_only)
    for k, q in enumerate(Q):
        T, J_pin = chain.fk_jacobian(q)
        assert np.allclose(R[:, :, k], T[:3, :3], atol=1e-12)
        assert np.allclose(p[:, k], T[:3, 3], atol=1e-12)
        assert np.allclose(J[:, :, k], J_pin, atol=1e-12)


# ---- locking joints (a 7-DOF arm at a given value of one joint) ---------------------------------------------


def _panda() -> Chain:
    relative, base, tip = ARMS["panda"]
    return load_chain(erd(relative), base, tip)


@pytest.mark.parametrize(
    "locks",
    [{"panda_joint1": 0.4}, {"panda_joint4": -1.5}, {"panda_joint7": 0.3}, {"panda_joint2": -0.2, "panda_joint6": 1.9}],
)
def test_locked_chain_is_the_full_chain_at_the_locked_values(locks: dict[str, float]) -> None:
    """FK and Jacobian of the locked chain equal the full chain's at expand(q); names, order and limits kept."""
    full = _panda()
    chain = full.locked(locks)
    moving = [name for name in full.joint_names if name not in locks]
    assert chain.joint_names == moving and chain.n == full.n - len(locks)
    index = [full.joint_names.index(name) for name in moving]
    assert np.array_equal(chain.lower, full.lower[index]) and np.array_equal(chain.upper, full.upper[index])
    Q = chain.random(np.random.default_rng(4), 30)
    expanded = chain.expand(Q)
    assert expanded.shape == (30, full.n)
    for name, value in locks.items():
        assert np.all(expanded[:, full.joint_names.index(name)] == value)
    assert np.array_equal(expanded[:, index], Q)
    assert np.allclose(chain.fk_batch(Q), full.fk_batch(expanded), atol=1e-12)
    for q, qf in zip(Q[:5], expanded[:5]):
        assert np.allclose(chain.jacobian(q), full.jacobian(qf)[:, index], atol=1e-12)


def test_locking_twice_is_locking_both() -> None:
    full = _panda()
    once = full.locked({"panda_joint2": -0.2, "panda_joint6": 1.9})
    twice = full.locked({"panda_joint6": 1.9}).locked({"panda_joint2": -0.2})
    q = once.random(np.random.default_rng(1))
    assert twice.joint_names == once.joint_names
    assert np.allclose(twice.fk(q), once.fk(q), atol=1e-12) and np.array_equal(twice.expand(q), once.expand(q))


def test_unlocked_chain_expands_to_itself() -> None:
    chain = _panda()
    q = chain.mid()
    assert np.array_equal(chain.expand(q), q) and chain.locks == ()


@pytest.mark.parametrize(
    ("locks", "message"),
    [
        ({"panda_joint8": 0.0}, "cannot lock joint 'panda_joint8': not a moving joint"),
        ({"panda_joint4": 0.5}, "cannot lock joint 'panda_joint4' at 0.5: outside its limits"),
        ({"panda_joint4": math.nan}, "not a finite number"),
        ({f"panda_joint{i}": 0.0 for i in (1, 2, 3, 5, 6, 7)} | {"panda_joint4": -1.0}, "at least one must move"),
    ],
)
def test_bad_locks_are_clear_errors(locks: dict[str, float], message: str) -> None:
    with pytest.raises(ArmtoolError, match=message):
        _panda().locked(locks)


def test_position_only_chain_cannot_lock() -> None:
    with pytest.raises(ArmtoolError, match="position-only chain cannot lock"):
        _panda().with_free_orientation().locked({"panda_joint7": 0.3})
