"""The bundled robots: the clean arm is clean; every commented defect of the broken ones is found
at its line (the element below each `<!-- defect: ... -->` / `# defect:` comment)."""

from __future__ import annotations

import re
from pathlib import Path

from armtool.lint.engine import LintOptions, lint_paths

ROBOTS = Path(__file__).resolve().parents[2] / "fixtures" / "robots"


def found(*paths: Path, **options: object) -> set[tuple[str, str, int]]:
    result = lint_paths(list(paths), LintOptions(**options))  # type: ignore[arg-type]
    return {(Path(f.path).name, f.code, f.line) for f in result.findings}


def defect_lines(path: Path) -> set[int]:
    """Lines of the elements that follow each defect comment."""
    lines = path.read_text().splitlines()
    out = set()
    for i, line in enumerate(lines):
        if re.search(r"(<!--|#) defect:", line):
            j = i + 1
            while lines[j].strip().startswith(("<!--", "#")) or not lines[j].strip():
                j += 1
            out.add(j + 1)
    return out


def test_clean_arm_is_clean() -> None:
    assert found(ROBOTS / "clean_arm" / "urdf", ROBOTS / "clean_arm" / "config") == set()


def test_broken_arm_every_defect_found() -> None:
    urdf = ROBOTS / "broken_arm" / "broken_arm.urdf"
    expected = {
        ("U401", 10),
        ("U103", 14),
        ("U403", 16),
        ("U404", 20),
        ("U405", 24),
        ("U501", 27),
        ("U102", 32),
        ("U301", 38),
        ("U202", 41),
        ("U302", 48),
        ("U203", 50),
        ("U101", 55),
        ("U303", 58),
        ("U205", 60),
        ("U304", 67),
        ("U204", 69),
        ("U206", 77),
        ("U105", 80),
        ("U106", 83),
        ("U503", 88),
        ("U504", 99),
    }
    assert {(code, line) for _, code, line in found(urdf)} == expected
    # Each commented element has a finding at its line; the comments above joint4 and joint5
    # (lines 63, 72) name defects of their <limit> children.
    assert {line for _, line in expected} >= defect_lines(urdf) - {63, 72}


def test_broken_srdf_and_kinematics_yaml() -> None:
    config = ROBOTS / "clean_arm" / "config_broken"
    assert found(config) == {
        ("clean_arm.srdf", "S109", 7),
        ("clean_arm.srdf", "S101", 11),
        ("clean_arm.srdf", "S102", 13),
        ("clean_arm.srdf", "S104", 17),
        ("clean_arm.srdf", "S107", 29),
        ("clean_arm.srdf", "S106", 30),
        ("clean_arm.srdf", "S105", 34),
        ("clean_arm.srdf", "S105", 36),
        ("clean_arm.srdf", "S108", 38),
        ("kinematics.yaml", "K102", 4),
        ("kinematics.yaml", "K104", 7),
        ("kinematics.yaml", "K101", 9),
        ("kinematics.yaml", "K105", 14),
        ("kinematics.yaml", "K103", 16),
    }


def test_xacro_arm_points_at_call_sites() -> None:
    xacro = ROBOTS / "xacro_arm" / "urdf" / "xacro_arm.urdf.xacro"
    assert found(ROBOTS / "xacro_arm") == {("xacro_arm.urdf.xacro", "U403", 15), ("xacro_arm.urdf.xacro", "U301", 18)}
    assert {15, 18} == defect_lines(xacro)
    assert found(xacro, xacro_args={"prefix": "left_"}) == {
        ("xacro_arm.urdf.xacro", "U403", 15),
        ("xacro_arm.urdf.xacro", "U301", 18),
    }
