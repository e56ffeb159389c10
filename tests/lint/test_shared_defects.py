"""One defect, one finding: a defect in a file several linted xacros include is reported once,
where it is written, naming the files that include it."""

from __future__ import annotations

from pathlib import Path

import pytest

from armtool.lint.engine import LintOptions, lint_paths

X = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
PARTS = f"""<?xml version="1.0"?>
<robot {X}>
  <xacro:macro name="segment" params="name parent">
    <link name="${{name}}">
      <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.01"/></inertial>
    </link>
    <joint name="${{name}}_joint" type="revolute"><parent link="${{parent}}"/><child link="${{name}}"/>
      <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  </xacro:macro>
</robot>
"""


def top(name: str, include: str, body: str = "") -> str:
    return f'<?xml version="1.0"?>\n<robot name="{name}" {X}>\n  <xacro:include filename="{include}"/>\n  <link name="base"/>\n{body}</robot>\n'


def test_a_macro_defect_is_reported_once_at_the_macro(tmp_path: Path) -> None:
    (tmp_path / "parts.xacro").write_text(PARTS)
    for name in ("a", "b", "c"):
        (tmp_path / f"{name}.urdf.xacro").write_text(
            top(name, "parts.xacro", '  <xacro:segment name="l1" parent="base"/>\n')
        )
    (finding,) = lint_paths([tmp_path], LintOptions()).findings
    assert (Path(finding.path).name, finding.line, finding.code) == ("parts.xacro", 5, "U405")
    assert "(in every file that includes it: " in finding.message
    assert all(f"{n}.urdf.xacro" in finding.message for n in "abc")
    # one file alone: at its macro call, as before, with the macro body's place in the message
    (alone,) = lint_paths([tmp_path / "a.urdf.xacro"], LintOptions()).findings
    assert (Path(alone.path).name, alone.line) == ("a.urdf.xacro", 5) and "parts.xacro:5" in alone.message


def test_a_stale_include_is_one_finding_in_the_included_file(tmp_path: Path) -> None:
    (tmp_path / "common.xacro").write_text(
        f'<?xml version="1.0"?>\n<robot {X}>\n  <xacro:include filename="$(find stale_pkg)/urdf/x.xacro"/>\n</robot>\n'
    )
    for name in ("d", "e"):
        (tmp_path / f"{name}.urdf.xacro").write_text(top(name, "common.xacro"))
    (finding,) = lint_paths([tmp_path], LintOptions()).findings
    assert (Path(finding.path).name, finding.line, finding.code) == ("common.xacro", 3, "X001")
    assert "stale_pkg" in finding.message and "d.urdf.xacro" in finding.message and "e.urdf.xacro" in finding.message


@pytest.mark.parametrize(
    ("code", "included", "note"),
    [("U405", "parts.xacro", "from the macro body at {}:5"), ("X001", "common.xacro", "at {}:3")],
)
def test_the_merged_finding_drops_the_note_that_named_its_place(
    tmp_path: Path, code: str, included: str, note: str
) -> None:
    """The note the writer added (the locator's "from the macro body at F:L", xacro's "at F:L") names
    the merged finding's place: it is taken out of the message, the rest of the message stays."""
    (tmp_path / "parts.xacro").write_text(PARTS)
    (tmp_path / "common.xacro").write_text(
        f'<?xml version="1.0"?>\n<robot {X}>\n  <xacro:include filename="$(find stale_pkg)/urdf/x.xacro"/>\n</robot>\n'
    )
    files = [tmp_path / f"{name}.urdf.xacro" for name in ("a", "b")]
    for path in files:
        body = '  <xacro:segment name="l1" parent="base"/>\n' if included == "parts.xacro" else ""
        path.write_text(top(path.name.split(".")[0], included, body))
    (alone,) = lint_paths(files[:1], LintOptions()).findings
    (merged,) = lint_paths(files, LintOptions()).findings
    assert (merged.code, Path(merged.path).name) == (code, included)
    written = f" ({note.format(merged.path)})"
    assert alone.code == code and written in alone.message
    assert merged.message.startswith(alone.message.replace(written, "") + " (in every file that includes it: ")
    assert written not in merged.message
