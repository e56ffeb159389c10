"""Which URDF an SRDF is checked against (armtool/lint/pairing.py and the engine's choice among candidates)."""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from armtool.lint.engine import LintOptions, lint_paths
from armtool.lint.pairing import srdf_names
from tests.lint.helpers import LINK, revolute, robot


def _variant(n_joints: int) -> str:
    links = [LINK.format(name=f"link{i}") for i in range(n_joints + 1)]
    joints = [revolute(f"joint{i}", f"link{i - 1}", f"link{i}") for i in range(1, n_joints + 1)]
    return robot("\n".join(links + joints), name="bot")


def _package(tmp_path: Path, srdf_body: str) -> Path:
    """bot.urdf (2 joints) and bot3.urdf (3 joints), both <robot name="bot">, and srdf/bot.srdf."""
    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "bot.urdf").write_text(_variant(2), encoding="utf-8")
    (tmp_path / "robots" / "bot3.urdf").write_text(_variant(3), encoding="utf-8")
    (tmp_path / "srdf").mkdir()
    srdf = tmp_path / "srdf" / "bot.srdf"
    srdf.write_text(f'<robot name="bot">\n{srdf_body}\n</robot>\n', encoding="utf-8")
    return srdf


def test_srdf_is_checked_against_the_candidate_that_knows_its_names(tmp_path: Path) -> None:
    # bot.srdf names joint3 and link3, which only bot3.urdf has: it describes bot3.urdf, although
    # its file name matches bot.urdf (example-robot-data's solo.srdf beside solo.urdf and solo12.urdf).
    srdf = _package(
        tmp_path, '<group name="arm"><joint name="joint3"/><chain base_link="link0" tip_link="link3"/></group>'
    )
    assert lint_paths([srdf], LintOptions()).findings == []


def test_file_name_still_decides_when_both_candidates_know_every_name(tmp_path: Path) -> None:
    srdf = _package(
        tmp_path,
        '<group name="arm"><joint name="joint1"/></group>\n'
        '<group_state name="home" group="arm"><joint name="joint1" value="2"/></group_state>',
    )
    (finding,) = lint_paths([srdf], LintOptions()).findings
    assert finding.code == "S106" and "bot.urdf" in finding.message and "bot3.urdf" not in finding.message


def test_a_name_no_candidate_knows_is_reported_against_the_first(tmp_path: Path) -> None:
    srdf = _package(tmp_path, '<group name="arm"><joint name="elbow"/></group>')
    (finding,) = lint_paths([srdf], LintOptions()).findings
    assert finding.code == "S101" and "not in bot.urdf" in finding.message


def test_srdf_names_leave_out_virtual_joints() -> None:
    root = etree.fromstring(
        '<robot name="r"><virtual_joint name="root_joint" type="floating" parent_frame="world" child_link="base"/>'
        '<group name="g"><joint name="root_joint"/><joint name="j1"/><link name="l1"/></group>'
        '<end_effector name="e" group="g" parent_link="tool"/>'
        '<disable_collisions link1="a" link2="b" reason="Never"/></robot>'
    )
    assert srdf_names(root) == ({"j1"}, {"l1", "tool", "a", "b"})
