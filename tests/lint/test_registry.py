"""Every rule: unique code and name, code format, documented sections, a matching module."""

from __future__ import annotations

import re
from pathlib import Path

from armtool.lint.registry import RULES
from armtool.lint.rule import DOC_SECTIONS

RULES_DIR = Path(__file__).resolve().parents[2] / "armtool" / "lint" / "rules"


def test_codes_and_names_are_unique_and_well_formed() -> None:
    codes = [r.code for r in RULES]
    names = [r.name for r in RULES]
    assert len(set(codes)) == len(codes) and len(set(names)) == len(names)
    for rule in RULES:
        assert re.fullmatch(r"[UXSKLPCM]\d{3}", rule.code), rule.code
        assert re.fullmatch(r"[a-z0-9]+(-[a-z0-9]+)*", rule.name), rule.name
        letters = {"U": "urdf", "X": "urdf", "S": "srdf", "K": "kinematics"}
        letters |= {"L": "joint_limits", "P": "pilz", "C": "controllers", "M": "setup_assistant"}
        assert rule.target.value == letters[rule.code[0]]


def test_every_rule_is_documented() -> None:
    for rule in RULES:
        doc = rule.documentation()
        for section in DOC_SECTIONS:
            assert f"{section}:" in doc or section in doc, f"{rule.code} lacks '{section}'"
        assert rule.summary() and len(rule.summary()) > 20


def test_every_rule_module_is_registered() -> None:
    modules = {p.stem for p in RULES_DIR.glob("[a-z][0-9][0-9][0-9]_*.py")}
    registered = {r.__module__.rsplit(".", 1)[-1] for r in RULES}
    assert modules == registered
    for rule in RULES:
        assert rule.__module__.rsplit(".", 1)[-1].startswith(rule.code.lower() + "_")


def test_loader_rules_check_nothing_and_are_the_engines_file_findings() -> None:
    """Rules in LOADER_CODES are not run on loaded files (not even imported by a lint run): each
    must find nothing in check(), and they are exactly the codes the engine reports while loading."""
    import re
    from pathlib import Path

    from armtool.lint import engine, file_findings
    from armtool.lint.registry import LOADER_CODES, checks_for, rule_class, rules_for
    from armtool.lint.rule import Target

    for code in LOADER_CODES:
        assert list(rule_class(code)().check(object())) == []
    source = "".join(Path(m.__file__).read_text(encoding="utf-8") for m in (engine, file_findings))
    reported = set(re.findall(r'(?:file_finding|invalid_yaml)\(\s*"([A-Z]\d{3})"', source))
    reported |= set(file_findings.LOADER_CODE.values())
    assert set(file_findings.LOADER_CODE) == {kind.value for kind in engine.FileKind}  # every kind has one
    assert reported == LOADER_CODES
    for target in Target:
        assert [r.code for r in checks_for(target)] == [r.code for r in rules_for(target) if r.code not in LOADER_CODES]
