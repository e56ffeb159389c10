"""traj cartesian's default start: the SRDF's home/ready state (a .srdf.xacro expanded), else
mid-range when it is not singular, else a well-conditioned configuration near it; never a singular
one. Its chain with --moveit-config is the planning group's."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.model.chain import load_chain
from armtool.traj.cartesian import sigma_min
from armtool.traj.start import WELL_CONDITIONED_SIGMA, default_start, home_states, read_srdf, srdf_beside
from tests.ik.robots import erd

from .helpers import CLEAN_URDF, START


@pytest.mark.parametrize("arm", ["ur_description/urdf/ur5_robot.urdf", "kinova_description/robots/kinova.urdf"])
def test_arms_whose_mid_range_is_singular_start_well_conditioned(arm: str) -> None:
    urdf = erd(arm)
    chain = load_chain(urdf)
    assert sigma_min(chain, chain.mid()) < 1e-10  # all zeros: UR stretched flat, Jaco folded
    start = default_start(chain, urdf, robot=chain.name)
    assert sigma_min(chain, start.q) >= WELL_CONDITIONED_SIGMA and chain.within_limits(start.q)
    assert start.how.startswith("the middle of the joint ranges is singular")
    assert np.array_equal(start.q, default_start(chain, urdf, robot=chain.name).q)  # the same every run


def test_the_srdf_beside_the_urdf_gives_the_start() -> None:
    urdf = erd("panda_description/urdf/panda.urdf")
    chain = load_chain(urdf)
    assert [s.path.name for s in srdf_beside(urdf, chain.name)[0]] == ["panda.srdf"]
    start = default_start(chain, urdf, robot=chain.name)
    assert start.how.startswith("group state 'default' of ") and start.how.endswith("panda.srdf")
    np.testing.assert_allclose(start.q, [0, -0.785398, 0, -2.35619, 0, 1.5707, 0.785398])


def _srdf(path: Path, states: dict[str, list[float]]) -> Path:
    body = "".join(
        f'<group_state name="{name}" group="arm">'
        + "".join(f'<joint name="joint{i + 1}" value="{v}"/>' for i, v in enumerate(values))
        + "</group_state>"
        for name, values in states.items()
    )
    path.write_text(f'<robot name="clean_arm"><group name="arm"/>{body}</robot>')
    return path


def test_home_is_preferred_and_a_singular_or_partial_state_is_passed_over(tmp_path: Path) -> None:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    srdf = _srdf(
        tmp_path / "arm.srdf",
        {"transport": [0.1] * 6, "ready": [0, -0.5, 1.0, 0, 0.8, 0], "home": [0.2, -0.6, 1.2, 0, 0.9, 0]},
    )
    name, q = home_states(read_srdf(srdf).root, chain)[0]
    assert name == "home" and np.allclose(q, [0.2, -0.6, 1.2, 0, 0.9, 0])
    assert default_start(chain, CLEAN_URDF, read_srdf(srdf)).how == f"group state 'home' of {srdf}"
    partial = _srdf(tmp_path / "partial.srdf", {"home": [0.2, -0.6, 1.2]})  # not every chain joint
    assert home_states(read_srdf(partial).root, chain) == []
    singular = _srdf(tmp_path / "straight.srdf", {"home": [0.2, -0.6, 1.2, 0, 0, 0]})  # wrist axes 4 and 6 aligned
    assert sigma_min(chain, np.array([0.2, -0.6, 1.2, 0, 0, 0])) < 1e-10
    start = default_start(chain, CLEAN_URDF, read_srdf(singular))
    assert "group state 'home' of straight.srdf is near a singularity" in start.how
    assert sigma_min(chain, start.q) >= WELL_CONDITIONED_SIGMA


def test_a_singular_home_gives_way_to_ready(tmp_path: Path) -> None:
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    srdf = _srdf(tmp_path / "arm.srdf", {"home": [0.2, -0.6, 1.2, 0, 0, 0], "ready": [0, -0.5, 1.0, 0, 0.8, 0]})
    start = default_start(chain, CLEAN_URDF, read_srdf(srdf))
    assert start.how == f"group state 'ready' of {srdf}"
    np.testing.assert_allclose(start.q, [0, -0.5, 1.0, 0, 0.8, 0])


XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
STATES_MACRO = f"""<robot {XACRO_NS}>
  <xacro:macro name="arm_states" params="pose">
    <group_state name="${{pose}}" group="arm">
      <joint name="joint1" value="0"/><joint name="joint2" value="-0.5"/><joint name="joint3" value="1.0"/>
      <joint name="joint4" value="0"/><joint name="joint5" value="0.8"/><joint name="joint6" value="0"/>
    </group_state>
  </xacro:macro>
</robot>"""


def _srdf_xacro(folder: Path, chain_tip: str = "tool0") -> Path:
    """clean_arm's SRDF as MoveIt 2 configs write it: a .srdf.xacro whose group state comes from an
    included macro, named by an argument, so it exists only after expansion."""
    (folder / "clean_arm_states.xacro").write_text(STATES_MACRO)
    path = folder / "clean_arm.srdf.xacro"
    path.write_text(
        f"""<robot {XACRO_NS} name="clean_arm">
  <xacro:arg name="pose" default="ready"/>
  <xacro:include filename="clean_arm_states.xacro"/>
  <group name="arm"><chain base_link="base_link" tip_link="{chain_tip}"/></group>
  <group name="gripper"><joint name="left_finger_joint"/></group>
  <group_state name="open" group="gripper"><joint name="left_finger_joint" value="0.04"/></group_state>
  <xacro:arm_states pose="$(arg pose)"/>
</robot>"""
    )
    return path


def test_an_srdf_xacro_is_expanded_for_its_group_states(tmp_path: Path) -> None:
    """`traj --srdf x.srdf.xacro` read the xacro unexpanded and said there was no home/ready state."""
    chain = load_chain(CLEAN_URDF, "base_link", "tool0")
    srdf = _srdf_xacro(tmp_path)
    start = default_start(chain, CLEAN_URDF, read_srdf(srdf))
    assert start.how == f"group state 'ready' of {srdf}"
    np.testing.assert_allclose(start.q, [0, -0.5, 1.0, 0, 0.8, 0])
    renamed = default_start(chain, CLEAN_URDF, read_srdf(srdf, {"pose": "transport"}))  # the xacro argument applies
    assert "clean_arm.srdf.xacro has no home or ready group state for joints joint1, joint2" in renamed.how
    assert "its group states: open (group gripper), transport (group arm)" in renamed.how


def test_an_srdf_xacro_beside_the_urdf_is_found(tmp_path: Path) -> None:
    (tmp_path / "urdf").mkdir()
    (tmp_path / "config").mkdir()
    urdf = tmp_path / "urdf" / "clean_arm.urdf"
    urdf.write_bytes(CLEAN_URDF.read_bytes())
    srdf = _srdf_xacro(tmp_path / "config")
    (tmp_path / "config" / "other.srdf.xacro").write_text(f'<robot {XACRO_NS} name="$(arg needed)"/>')
    chain = load_chain(urdf, "base_link", "tool0")
    found, notes = srdf_beside(urdf, chain.name)
    assert [s.path for s in found] == [srdf]
    assert notes == [
        "other.srdf.xacro beside it was not read: xacro failed: undefined substitution argument 'needed' ($(arg needed))"
    ]
    assert default_start(chain, urdf, robot=chain.name).how == f"group state 'ready' of {srdf}"


def _moveit_package(tmp_path: Path, chain_tip: str) -> Path:
    """A copy of the clean arm's MoveIt config package whose SRDF is a .srdf.xacro."""
    import shutil

    fixtures = CLEAN_URDF.parents[2]
    shutil.copytree(fixtures / "clean_arm", tmp_path / "clean_arm")
    package = shutil.copytree(fixtures / "clean_arm_moveit_config", tmp_path / "clean_arm_moveit_config")
    (package / "config" / "clean_arm.srdf").unlink()
    _srdf_xacro(package / "config", chain_tip)
    setup = package / ".setup_assistant"
    setup.write_text(setup.read_text().replace("config/clean_arm.srdf", "config/clean_arm.srdf.xacro"))
    return package


def test_cartesian_with_moveit_config_follows_the_planning_groups_chain(tmp_path: Path) -> None:
    """It followed the default chain (to tool0) and started mid-range, not from the package's SRDF."""
    from tests.traj.test_cli import invoke

    package = _moveit_package(tmp_path, chain_tip="link6")
    out = tmp_path / "line.csv"
    code, _, err = invoke(
        "cartesian", "--moveit-config", str(package), "--line", "0,0,0.02", "--relative", "-o", str(out)
    )
    assert code == 0, err
    text = " ".join(err.split())
    assert (
        "chain: group 'arm' of clean_arm.srdf.xacro (the one group of --moveit-config's kinematics.yaml): "
        "base 'base_link' -> tip 'link6', 6 joints" in text
    )
    assert "start: group state 'ready' of " in text and "clean_arm.srdf.xacro: 0, -0.5, 1, 0, 0.8, 0" in text
    code, _, err = invoke(
        "cartesian", "--moveit-config", str(package), "--group", "arms", "--line", "0,0,0.02", "--relative"
    )
    assert code == 2 and "group 'arms' not in" in err and "did you mean 'arm'" in err, err
    code, _, err = invoke(
        "cartesian", "--moveit-config", str(package), "--base", "base_link", "--tip", "tool0", "--start", START,
        "--line", "0,0,0.02", "--relative", "-o", str(out),
    )  # fmt: skip
    assert code == 0 and "chain: --base/--tip: base 'base_link' -> tip 'tool0'" in " ".join(err.split())
    (package / "config" / "clean_arm.srdf.xacro").unlink()
    setup = package / ".setup_assistant"
    setup.write_text(setup.read_text().replace("relative_path: config/clean_arm.srdf.xacro", "relative_path: ''"))
    code, _, err = invoke("cartesian", "--moveit-config", str(package), "--line", "0,0,0.02", "--relative")
    assert code == 2 and "the --moveit-config package has no SRDF: its planning group's chain is unknown" in err


def test_cartesian_without_start_on_a_ur5_follows_the_line_and_says_where_it_started(tmp_path: Path) -> None:
    from tests.traj.test_cli import invoke

    out = tmp_path / "line.csv"
    code, _, err = invoke(
        "cartesian", str(erd("ur_description/urdf/ur5_robot.urdf")), "--line", "0.05,0,0", "--relative", "-o", str(out)
    )
    assert code == 0, err  # from the singular all-zero mid-range it stopped at point 0
    text = " ".join(err.split())
    assert (
        "chain: the default chain (pass --base/--tip or --group for another): base 'world' -> tip 'tool0', 6 joints"
        in text
    )
    assert "start: the middle of the joint ranges is singular" in text
