"""Corrections folded into <origin> by text edit: same kinematics as the model, comments kept."""

from __future__ import annotations

import numpy as np

from armtool.calib.urdf_out import corrected_text, joint_corrections
from armtool.ik.chain import Chain, chain_from_xml
from armtool.model.xmlsource import parse_xml
from tests.calib.conftest import CLEAN_ARM, nominal_model


def test_written_urdf_has_the_fitted_kinematics(clean_chain: Chain) -> None:
    model = nominal_model(clean_chain)
    rng = np.random.default_rng(0)
    x = np.zeros(model.size)
    k = x[12:].reshape(clean_chain.n, 8)
    k[:, :3] = rng.normal(scale=0.002, size=(clean_chain.n, 3))
    k[:, 3:6] = rng.normal(scale=0.003, size=(clean_chain.n, 3))
    k[:, 6] = rng.normal(scale=0.005, size=clean_chain.n)
    text = CLEAN_ARM.read_text()
    new = corrected_text(text, joint_corrections(model, x), "clean_arm.urdf")
    chain2 = chain_from_xml(parse_xml(new.encode()), "base_link", "tool0")
    Q = clean_chain.random(rng, 10)
    F = model.flange(x, Q)
    for q, T in zip(Q, F):
        assert np.allclose(chain2.fk(q), T, atol=1e-9)
    # Only origin values changed: the same comments, the same number of lines.
    assert [line for line in text.splitlines() if "<!--" in line] == [line for line in new.splitlines() if "<!--" in line]
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
