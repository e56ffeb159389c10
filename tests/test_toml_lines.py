"""Where a TOML key is written: headers, dotted and quoted keys, inline tables, multi-line strings."""

from __future__ import annotations

from armtool.toml_lines import key_lines, line_of

TEXT = '''# comment = 1
[project]
name = "arm"
description = """
tool.armtool = "not a key: inside a string"
"""

[tool.armtool.lint]
"per-file-ignores" = { "urdf/*.urdf" = ["U401"] }
xacro-args.'robots/gen3.xacro' = { dof = "6" }

[[tool.armtool.list]]
a = 1
'''


def test_keys_are_found_at_their_lines() -> None:
    lines = key_lines(TEXT)
    assert lines[("project", "name")] == 3
    assert ("tool", "armtool") not in lines  # inside the multi-line string
    assert lines[("tool", "armtool", "lint")] == 8
    assert lines[("tool", "armtool", "lint", "per-file-ignores")] == 9
    assert lines[("tool", "armtool", "lint", "xacro-args", "robots/gen3.xacro")] == 10
    assert lines[("tool", "armtool", "list", "a")] == 13


def test_a_key_not_written_itself_is_placed_at_the_nearest_written_one() -> None:
    lines = key_lines(TEXT)
    assert line_of(lines, ("tool", "armtool")) == 8  # implied by [tool.armtool.lint]: its first key below
    assert line_of(lines, ("tool", "armtool", "lint", "per-file-ignores", "urdf/*.urdf")) == 9  # inline table
    assert line_of(lines, ("nothing",)) is None
