"""Corrections folded into <origin> by text edit: same kinematics as the model, comments kept."""

from __future__ import annotations

import numpy as np

from armtool.calib.outputs.urdf import check_reproduces, corrected_text, joint_corrections
from armtool.model.chain import Chain, chain_from_xml
from armtool.model.xmlsource import parse_xml
from tests.calib.conftest import CLEAN_ARM, ROOT, nominal_model


def test_written_urdf_has_the_fitted_kinematics(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    rng = np.random.default_rng(0)
    x = np.zeros(model.size)
    parts = model.split(x)
    parts.origin[:, :3] = rng.normal(scale=0.002, size=(clean_chain.n, 3))
    parts.origin[:, 3:] = rng.normal(scale=0.003, size=(clean_chain.n, 3))
    parts.offset[:] = rng.normal(scale=0.005, size=clean_chain.n)
    text = CLEAN_ARM.read_text()
    new = corrected_text(text, joint_corrections(model, x), "clean_arm.urdf")
    chain2 = chain_from_xml(parse_xml(new.encode()), "base_link", "tool0")
    Q = clean_chain.random(rng, 10)
    F = model.flange(x, Q)
    for q, T in zip(Q, F):
        assert np.allclose(chain2.fk(q), T, atol=1e-9)
    # Only origin values changed: the same comments, the same number of lines.
    assert [line for line in text.splitlines() if "<!--" in line] == [
        line for line in new.splitlines() if "<!--" in line
    ]
    assert len(new.splitlines()) == len(text.splitlines())


def test_joint_without_origin_gets_one(clean_chain: Chain) -> None:
    text = """<robot name="r">
  <link name="a"/><link name="b"/>
  <!-- no origin on purpose -->
  <joint name="j" type="revolute">
    <parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>
"""
    chain = chain_from_xml(parse_xml(text.encode()), "a", "b")
    model = nominal_model(chain)
    x = np.zeros(model.size)
    x[12 + 2] = 0.001  # tz
    x[12 + 6] = 0.01  # zero offset
    new = corrected_text(text, joint_corrections(model, x), "r.urdf")
    assert '<origin xyz="0 0 0.001" rpy="0 0 0.01"/>' in new
    assert "<!-- no origin on purpose -->" in new


def _random_corrections(model, seed: int = 0) -> np.ndarray:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(seed)
    x = np.zeros(model.size)
    parts = model.split(x)
    parts.origin[:, :3] = rng.normal(scale=0.002, size=(model.chain.n, 3))
    parts.origin[:, 3:] = rng.normal(scale=0.003, size=(model.chain.n, 3))
    parts.offset[:] = rng.normal(scale=0.005, size=model.chain.n)
    return x


def test_everything_on_one_line(clean_chain: Chain) -> None:
    # Expanded xacros and generated URDFs often hold many elements per line: each edit must land
    # on its own joint's <origin>, not on the first <origin> of the line.
    one_line = " ".join(CLEAN_ARM.read_text().split())
    model = nominal_model(clean_chain)
    x = _random_corrections(model, 1)
    new = corrected_text(one_line, joint_corrections(model, x), "one_line.urdf")
    check_reproduces(new, model, x, "one_line.urdf")
    assert new.count("<inertial>") == one_line.count("<inertial>")


def test_xacro_input_and_tricky_text() -> None:
    from armtool.model.load import urdf_text

    xacro = ROOT / "fixtures" / "robots" / "xacro_arm" / "urdf" / "xacro_arm.urdf.xacro"
    text = urdf_text(xacro)
    # Comments, CDATA and a transmission's <joint> must not confuse the scanner.
    text = text.replace("<robot", "<!-- <joint name='fake'><origin xyz='9 9 9'/></joint> -->\n<robot", 1)
    root = parse_xml(text.encode())
    chain = chain_from_xml(root)
    model = nominal_model(chain)
    x = _random_corrections(model, 2)
    new = corrected_text(text, joint_corrections(model, x), "xacro_arm")
    check_reproduces(new, model, x, "xacro_arm")
    assert "<!-- <joint name='fake'><origin xyz='9 9 9'/></joint> -->" in new


def test_a_wrong_result_is_refused(clean_chain: Chain) -> None:
    import pytest

    from armtool.errors import ArmtoolError

    model = nominal_model(clean_chain)
    x = _random_corrections(model, 3)
    text = CLEAN_ARM.read_text()
    with pytest.raises(ArmtoolError, match="does not reproduce"):
        check_reproduces(text, model, x, "clean_arm.urdf")  # the nominal text: corrections missing


def test_relocate_meshes_keeps_relative_paths_resolving(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from armtool.calib.outputs.urdf import relocate_meshes

    text = (
        '<robot name="r"><link name="a"><visual><geometry><mesh filename="assets/a.stl" scale="1 1 1"/></geometry></visual>'
        '<collision><geometry><mesh filename="package://pkg/meshes/a.stl"/></geometry></collision>'
        "<visual><geometry><mesh filename='/abs/b.stl'/></geometry></visual>"
        '<visual><geometry><mesh filename="file:///abs/c.stl"/></geometry></visual></link></robot>'
    )
    src, out = tmp_path / "robot", tmp_path / "out" / "calib"
    new = relocate_meshes(text, src, out)
    assert 'filename="../../robot/assets/a.stl" scale="1 1 1"' in new
    assert (
        'filename="package://pkg/meshes/a.stl"' in new
        and "filename='/abs/b.stl'" in new
        and 'filename="file:///abs/c.stl"' in new
    )
    assert relocate_meshes(text, src, src) == text


def _one_joint(text: str) -> str:
    """The text corrected by a shift of tz=0.001 and a zero offset of 0.01 rad on joint 'j'."""
    chain = chain_from_xml(parse_xml(text.encode()), "a", "b")
    model = nominal_model(chain)
    x = np.zeros(model.size)
    x[12 + 2] = 0.001
    x[12 + 6] = 0.01
    return corrected_text(text, joint_corrections(model, x), "r.urdf")


def test_origin_edit_keeps_the_authors_quotes_and_spacing() -> None:
    text = (
        "<robot name='r'>\n  <link name='a'/><link name='b'/>\n  <joint name='j' type='revolute'>\n"
        "    <parent link='a'/><child link='b'/><origin xyz='0 0 0' />\n    <axis xyz='0 0 1'/>\n"
        "    <limit lower='-1' upper='1' effort='1' velocity='1'/>\n  </joint>\n</robot>\n"
    )
    new = _one_joint(text)
    assert new == text.replace("<origin xyz='0 0 0' />", "<origin xyz='0 0 0.001' rpy=\"0 0 0.01\" />")


def test_inserted_origin_follows_the_files_indent_and_line_endings() -> None:
    text = (
        '<robot name="r">\r\n    <link name="a"/><link name="b"/>\r\n    <joint name="j" type="revolute">\r\n'
        '        <parent link="a"/><child link="b"/>\r\n        <axis xyz="0 0 1"/>\r\n'
        '        <limit lower="-1" upper="1" effort="1" velocity="1"/>\r\n    </joint>\r\n</robot>\r\n'
    )
    new = _one_joint(text)
    assert new == text.replace(
        'type="revolute">\r\n', 'type="revolute">\r\n        <origin xyz="0 0 0.001" rpy="0 0 0.01"/>\r\n'
    )
