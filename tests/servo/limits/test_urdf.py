"""limits --urdf writes <limit lower upper> through model.urdf_edit: cases the old regexes got wrong."""

from __future__ import annotations

import pytest

from armtool.errors import ArmtoolError
from armtool.servo import limits as L


def test_patch_urdf_keeps_crlf_line_endings() -> None:
    text = '<robot name="r">\r\n  <joint name="b" type="revolute">\r\n    <axis xyz="0 0 1"/>\r\n  </joint>\r\n</robot>\r\n'
    out = L.patch_urdf(text, {"b": (-0.5, 0.5)})
    assert out == text.replace(
        "  </joint>", '    <limit lower="-0.5" upper="0.5" effort="1.0" velocity="1.0"/>\r\n  </joint>'
    )


def test_patch_urdf_indents_like_the_siblings() -> None:
    text = '<robot name="r">\n\t<joint name="b" type="revolute">\n\t\t<axis xyz="0 0 1"/>\n\t</joint>\n</robot>\n'
    out = L.patch_urdf(text, {"b": (-0.5, 0.5)})
    assert (
        '\t\t<axis xyz="0 0 1"/>\n\t\t<limit lower="-0.5" upper="0.5" effort="1.0" velocity="1.0"/>\n\t</joint>' in out
    )


def test_patch_urdf_reads_the_name_attribute_not_one_ending_in_name() -> None:
    text = '<robot name="r">\n  <joint data-name="x" name="a" type="revolute">\n    <limit lower="-1" upper="1"/>\n  </joint>\n</robot>\n'
    assert set(L.urdf_joints(text)) == {"a"}
    out = L.patch_urdf(text, {"a": (-0.5, 0.5)})
    assert '<limit lower="-0.5" upper="0.5" effort="1.0" velocity="1.0"/>' in out


def test_patch_urdf_fills_a_bare_limit_in_order() -> None:
    text = '<robot name="r">\n  <joint name="a" type="prismatic">\n    <limit/>\n  </joint>\n</robot>\n'
    out = L.patch_urdf(text, {"a": (-0.5, 0.5)})
    assert out == text.replace("<limit/>", '<limit lower="-0.5" upper="0.5" effort="1.0" velocity="1.0"/>')


def test_patch_urdf_malformed_is_a_clear_error() -> None:
    with pytest.raises(ArmtoolError) as info:
        L.patch_urdf(
            '<robot name="r">\n  <joint name="a" type="revolute">\n</robot>\n', {"a": (0, 1)}, source="arm.urdf"
        )
    assert (info.value.where or "").startswith("arm.urdf:")
