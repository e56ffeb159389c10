"""A MoveIt config package is read once per lint run: its SRDF (expanded once for the YAML files
that look it up, once paired with its URDF), its controllers files and its .setup_assistant;
every YAML file of the package needs them, and a .srdf.xacro costs a xacro expansion."""

from __future__ import annotations

import shutil
from collections import Counter
from pathlib import Path

import pytest

from armtool.lint import engine
from armtool.lint.engine import LintOptions, lint_paths
from tests.lint.helpers import LINK, revolute, robot

ROBOTS = Path(__file__).resolve().parents[2] / "fixtures" / "robots"


@pytest.fixture
def package(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A copy of the clean MoveIt 2 package (and its description), linted in one process."""
    shutil.copytree(ROBOTS / "clean_arm", tmp_path / "clean_arm")
    shutil.copytree(ROBOTS / "clean_arm_moveit_config", tmp_path / "clean_arm_moveit_config")
    monkeypatch.setattr(engine, "PARALLEL_MIN_FILES", 10**6)  # counts from every file, not from workers
    return tmp_path / "clean_arm_moveit_config"


def _srdf_xacro(package: Path) -> Path:
    """The package's SRDF as a .srdf.xacro (a xacro property in it), named by .setup_assistant."""
    srdf = package / "config" / "clean_arm.srdf"
    text = srdf.read_text(encoding="utf-8").replace(
        '<robot name="clean_arm">',
        '<robot name="clean_arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:property name="home" value="0"/>',
    )
    srdf.unlink()
    xacro = srdf.with_name("clean_arm.srdf.xacro")
    xacro.write_text(text, encoding="utf-8")
    setup = package / ".setup_assistant"
    setup.write_text(setup.read_text(encoding="utf-8").replace("clean_arm.srdf", "clean_arm.srdf.xacro"))
    return xacro


def test_a_package_srdf_xacro_is_expanded_once_for_lookups_and_once_paired(
    package: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from armtool.model import xacro_source

    xacro = _srdf_xacro(package)
    expanded: Counter[Path] = Counter()
    real = xacro_source.expand

    def counting(path: Path, *args: object, **kwargs: object) -> object:
        expanded[Path(path).resolve()] += 1
        return real(path, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(xacro_source, "expand", counting)
    result = lint_paths([package], LintOptions())
    assert result.findings == []
    yaml_files = [p for p in result.files if p.suffix == ".yaml"]
    assert len(yaml_files) >= 4  # kinematics, joint_limits and the controllers files each look the SRDF up
    # Before the cache: once per YAML file that looks the SRDF up, once more for its own lint.
    assert expanded[xacro.resolve()] == 2


def test_a_package_srdf_is_loaded_once_per_way_of_asking(package: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from armtool.lint import srdf_context

    loads: Counter[tuple[Path, bool]] = Counter()
    real = srdf_context.SrdfContext.__init__

    def counting(self: srdf_context.SrdfContext, path: Path, root: object, locator: object, urdf: object) -> None:
        loads[(Path(path).resolve(), urdf is not None)] += 1
        real(self, path, root, locator, urdf)  # type: ignore[arg-type]

    monkeypatch.setattr(srdf_context.SrdfContext, "__init__", counting)
    assert lint_paths([package], LintOptions()).findings == []
    srdf = (package / "config" / "clean_arm.srdf").resolve()
    assert loads == Counter({(srdf, False): 1, (srdf, True): 1})


def test_an_srdf_linked_under_another_name_is_linted_under_each_name(tmp_path: Path) -> None:
    """The SRDF cache keys on the path as findings show it too: a symlink to an SRDF is linted as
    the file it is written as, as before the cache (one resolved path, two files reported)."""
    body = LINK.format(name="base") + LINK.format(name="tip") + revolute("j1", "base", "tip")
    (tmp_path / "arm.urdf").write_text(robot(body), encoding="utf-8")
    srdf = '<robot name="arm">\n<group name="arm">\n<joint name="j1"/>\n<joint name="nope"/>\n</group>\n</robot>\n'
    (tmp_path / "arm.srdf").write_text(srdf, encoding="utf-8")
    (tmp_path / "copy.srdf").symlink_to(tmp_path / "arm.srdf")
    found = lint_paths([tmp_path], LintOptions()).findings
    assert sorted(Path(f.path).name for f in found if f.code == "S101") == ["arm.srdf", "copy.srdf"]


def test_each_yaml_file_of_a_package_is_parsed_once(package: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A controllers file is read for the package's controllers (C102, C103 compare the files)
    and when it is linted itself: one parse serves both."""
    from armtool.moveit import params

    parsed: Counter[str] = Counter()
    real = params.parse

    def counting(text: str) -> object:
        parsed[text] += 1
        return real(text)

    monkeypatch.setattr(params, "parse", counting)
    assert lint_paths([package], LintOptions()).findings == []
    controllers = sorted((package / "config").glob("*controllers.yaml"))
    assert len(controllers) == 2
    for path in controllers:
        assert parsed[path.read_text(encoding="utf-8")] == 1, path.name  # was 2
    assert set(parsed.values()) == {1}


def test_the_setup_assistant_is_parsed_once(package: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every file of the package asks for .setup_assistant (pairing, SRDF lookup, the package's
    controllers, the xacro arguments of the URDF): 12 parses in one lint of this package before, one now."""
    from armtool import yamlload
    from armtool.lint import pairing

    text = (package / ".setup_assistant").read_text(encoding="utf-8")
    parsed: list[str] = []
    real = yamlload.safe_load

    def counting(source: str) -> object:
        parsed.append(source)
        return real(source)

    monkeypatch.setattr(yamlload, "safe_load", counting)
    pairing._setup_fields.cache_clear()  # parsed by earlier tests (the same text)
    assert lint_paths([package], LintOptions()).findings == []
    assert parsed.count(text) == 1
