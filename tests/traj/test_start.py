"""traj cartesian's default start: the SRDF's home/ready state, else mid-range when it is not
singular, else a well-conditioned configuration near it; never a singular one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from armtool.model.chain import load_chain
from armtool.traj.cartesian import sigma_min
from armtool.traj.start import WELL_CONDITIONED_SIGMA, default_start, home_state, srdf_beside
from tests.ik.robots import erd

from .helpers import CLEAN_URDF


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
    assert [p.name for p in srdf_beside(urdf, chain.name)] == ["panda.srdf"]
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
    name, q = home_state(srdf, chain) or ("", np.zeros(0))
    assert name == "home" and np.allclose(q, [0.2, -0.6, 1.2, 0, 0.9, 0])
    assert default_start(chain, CLEAN_URDF, srdf).how == f"group state 'home' of {srdf}"
    partial = _srdf(tmp_path / "partial.srdf", {"home": [0.2, -0.6, 1.2]})  # not every chain joint
    assert home_state(partial, chain) is None
    singular = _srdf(tmp_path / "straight.srdf", {"home": [0.2, -0.6, 1.2, 0, 0, 0]})  # wrist axes 4 and 6 aligned
    assert sigma_min(chain, np.array([0.2, -0.6, 1.2, 0, 0, 0])) < 1e-10
    start = default_start(chain, CLEAN_URDF, singular)
    assert "group state 'home' of straight.srdf is near a singularity" in start.how
    assert sigma_min(chain, start.q) >= WELL_CONDITIONED_SIGMA


def test_cartesian_without_start_on_a_ur5_follows_the_line_and_says_where_it_started(tmp_path: Path) -> None:
    from tests.traj.test_cli import invoke

    out = tmp_path / "line.csv"
    code, _, err = invoke(
        "cartesian", str(erd("ur_description/urdf/ur5_robot.urdf")), "--line", "0.05,0,0", "--relative", "-o", str(out)
    )
    assert code == 0, err  # from the singular all-zero mid-range it stopped at point 0
    text = " ".join(err.split())
    assert "chain: base 'world' -> tip 'tool0', 6 joints" in text
    assert "start: the middle of the joint ranges is singular" in text
