"""The one URDF text editor: edits land on lxml's element, every other byte stays as written."""

from __future__ import annotations

import pytest

from armtool.model.urdf_edit import UneditableXml, XmlSource, urdf_joints

TRICKY = b"""<?xml version="1.0" encoding="UTF-8"?>
<!DOCTYPE robot [ <!ELEMENT robot ANY> ]>
<!-- <joint name="a" type="revolute"><limit lower="9" upper="9"/></joint> -->
<robot name="r" note='a > b'>
  <link name="x"><visual><![CDATA[ <limit lower="7"/> ]]></visual></link>
  <joint name="a"   type='revolute'>
    <parent link="x"/><child link="y"/>
    <limit upper='1' lower="-1"
           effort="2" />  <!-- </joint> -->
  </joint>
</robot>
"""


def _joint(doc: XmlSource, name: str):  # type: ignore[no-untyped-def]
    return urdf_joints(doc.root)[name]


def test_tags_pair_with_lxml_elements_past_comments_cdata_and_doctype() -> None:
    doc = XmlSource(TRICKY)
    limit = _joint(doc, "a").find("limit")
    tag = doc.tag(limit)
    assert TRICKY[tag.start : tag.end] == b'<limit upper=\'1\' lower="-1"\n           effort="2" />'
    assert tag.self_closing
    joint = doc.tag(_joint(doc, "a"))
    assert TRICKY[joint.close :].startswith(b"</joint>\n</robot>")
    assert [(a.name, TRICKY[a.value_start : a.value_end], a.quote) for a in doc.attributes(limit)] == [
        ("upper", b"1", b"'"),
        ("lower", b"-1", b'"'),
        ("effort", b"2", b'"'),
    ]


def test_set_attributes_keeps_quotes_order_and_layout() -> None:
    doc = XmlSource(TRICKY)
    limit = _joint(doc, "a").find("limit")
    out = doc.apply(doc.set_attributes(limit, {"lower": "-0.5", "upper": "0.5", "velocity": "1.0"}))
    assert out == TRICKY.replace(
        b'<limit upper=\'1\' lower="-1"\n           effort="2" />',
        b'<limit upper=\'0.5\' lower="-0.5"\n           effort="2" velocity="1.0" />',
    )


def test_values_are_escaped_for_their_quotes() -> None:
    doc = XmlSource(b"<r><a x='1' y=\"2\"/></r>")
    a = doc.root.find("a")
    assert doc.apply(doc.set_attributes(a, {"x": "it's <&>", "y": 'say "hi"'})) == (
        b"<r><a x='it&apos;s &lt;&amp;&gt;' y=\"say &quot;hi&quot;\"/></r>"
    )


@pytest.mark.parametrize("newline", [b"\n", b"\r\n"])
def test_insert_child_uses_the_siblings_indent_and_the_files_line_ending(newline: bytes) -> None:
    text = b"<robot>\n\t<joint name='j' type='revolute'>\n\t\t\t<parent link='a'/>\n\t</joint>\n</robot>\n"
    text = text.replace(b"\n", newline)
    doc = XmlSource(text)
    joint = _joint(doc, "j")
    last = doc.apply([doc.insert_child(joint, "limit", {"lower": "0"})])
    assert last == text.replace(b"\t</joint>", b'\t\t\t<limit lower="0"/>' + newline + b"\t</joint>")
    first = doc.apply([doc.insert_child(joint, "origin", {"xyz": "0 0 0"}, first=True)])
    assert first == text.replace(b"type='revolute'>", b"type='revolute'>" + newline + b'\t\t\t<origin xyz="0 0 0"/>')


def test_insert_child_on_one_line() -> None:
    text = b'<robot><joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>'
    doc = XmlSource(text)
    joint = _joint(doc, "j")
    out = doc.apply([doc.insert_child(joint, "origin", {"xyz": "1 2 3"})])
    assert out == text.replace(b"</joint>", b'\n  <origin xyz="1 2 3"/>\n</joint>')
    with pytest.raises(ValueError):
        doc.insert_child(joint.find("child"), "x", {})


def test_elements_at_a_line_as_lxml_numbers_them() -> None:
    doc = XmlSource(b'<r>\n<a n="1"/><a n="2"/>\n<a n="3"\n/><!-- <a n="4"/> -->\n</r>')
    assert [a.get("n") for a in doc.elements_at(2, "a")] == ["1", "2"]
    assert [a.get("n") for a in doc.elements_at(4, "a")] == ["3"]  # libxml2 counts the line where the tag ends
    assert doc.elements_at(3, "a") == []


def test_edits_keep_the_encoding_and_character_offsets() -> None:
    text = '<?xml version="1.0" encoding="ISO-8859-1"?>\n<r><a n="é" x="1"/></r>\n'.encode("latin-1")
    doc = XmlSource(text)
    a = doc.root.find("a")
    assert a.get("n") == "é"
    assert doc.apply(doc.set_attributes(a, {"x": "ü"})) == text.replace(b'x="1"', 'x="ü"'.encode("latin-1"))
    utf8 = XmlSource('<r n="éé"><a x="1"/></r>'.encode())
    (attr,) = utf8.attributes(utf8.root.find("a"))
    assert utf8.char_offset(attr.value_start) == '<r n="éé"><a x="'.__len__()


@pytest.mark.parametrize(
    "data",
    [b"<r><a></r>", "<r/>".encode("utf-16")],
)
def test_uneditable_input_is_refused(data: bytes) -> None:
    with pytest.raises(UneditableXml):
        XmlSource(data)


def test_urdf_joints_are_top_level() -> None:
    doc = XmlSource(
        b'<robot><transmission><joint name="a"/></transmission><joint name="a" type="fixed"/><joint/></robot>'
    )
    assert {n: el.get("type") for n, el in urdf_joints(doc.root).items()} == {"a": "fixed"}
