"""The one YAML loader: documents that aliases blow up are refused where armtool reads YAML."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
import yaml

from armtool.errors import ArmtoolError
from armtool.yamlload import MAX_ALIAS_NODES, AliasBomb, compose, compose_all, safe_load, safe_load_all

LAUGHS = "\n".join(
    [
        'a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]',
        *[f"{x}: &{x} [{', '.join([f'*{p}'] * 9)}]" for p, x in zip("abcdefgh", "bcdefghi")],
        "arm:",
        "  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin",
        "  lol: *i",
        "",
    ]
)


@pytest.mark.parametrize("load", [safe_load, compose, lambda t: safe_load_all(t), lambda t: compose_all(t)])
def test_a_billion_laughs_is_refused_at_its_anchor_at_once(load: object) -> None:
    start = time.monotonic()
    with pytest.raises(AliasBomb) as info:
        load(LAUGHS)  # type: ignore[operator]
    assert "aliases expand the document to 9.26e+08 nodes from 33 written" in str(info.value)
    assert info.value.problem_mark is not None and info.value.problem_mark.line + 1 == 9  # the anchor &i
    assert isinstance(info.value, yaml.YAMLError)  # every caller's "invalid YAML" handling applies
    assert time.monotonic() - start < 1


def test_a_document_that_contains_itself_is_refused() -> None:
    with pytest.raises(AliasBomb, match="contains itself"):
        safe_load("a: &a\n  - 1\n  - *a\n")


def test_ordinary_anchors_and_merge_keys_load_as_pyyaml_loads_them() -> None:
    text = (
        "defaults: &defaults {has_velocity_limits: true, max_velocity: 1.0}\n"
        "joint_limits:\n"
        "  j1: {<<: *defaults, max_acceleration: 2.0}\n"
        "  j2: *defaults\n"
    )
    assert safe_load(text) == yaml.safe_load(text)
    many = "base: &b [" + ", ".join(["1"] * 100) + "]\nuses: [" + ", ".join(["*b"] * 900) + "]\n"
    assert safe_load(many) == yaml.safe_load(many)  # 90,000 nodes added: under the bound
    assert 900 * 101 < MAX_ALIAS_NODES
    assert safe_load("") is None and compose("") is None and safe_load_all("---\n---\n") == []


def test_read_yaml_refuses_it_with_file_and_line(tmp_path: Path) -> None:
    from armtool.fileio import read_yaml

    path = tmp_path / "joint_limits.yaml"
    path.write_text(LAUGHS)
    with pytest.raises(ArmtoolError) as info:
        read_yaml(path, "joint_limits.yaml")
    assert "joint_limits.yaml file refused: aliases expand" in info.value.what
    assert info.value.where == f"{path}:9"


def test_lint_refuses_a_kinematics_yaml_that_aliases_blow_up(tmp_path: Path) -> None:
    from armtool.lint.engine import LintOptions, lint_paths

    path = tmp_path / "kinematics.yaml"
    path.write_text(LAUGHS)
    findings = lint_paths([path], LintOptions()).findings
    assert [(f.code, f.line) for f in findings] == [("K001", 9)]
    assert "billion laughs" in findings[0].message


def test_a_trajectory_that_aliases_blow_up_is_refused(tmp_path: Path) -> None:
    from armtool.traj.formats import read_trajectory

    text = LAUGHS.replace("arm:\n  kinematics_solver: kdl_kinematics_plugin/KDLKinematicsPlugin\n  lol: *i\n", "")
    text += "joint_names: [j1]\npoints: *i\n"
    path = tmp_path / "traj.yaml"
    path.write_text(text)
    with pytest.raises(ArmtoolError, match="aliases expand"):
        read_trajectory(path)
