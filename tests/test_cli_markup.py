"""Rich markup must not eat brackets in help texts, hints and messages (issue 10 item 19)."""

from __future__ import annotations

import io
import re

from typer.testing import CliRunner

from armtool.cli import report_error
from armtool.cli.typer_app import build_app
from armtool.errors import ArmtoolError

runner = CliRunner()


def _help(*command: str) -> str:
    result = runner.invoke(
        build_app(), [*command, "--help"], env={"COLUMNS": "400", "NO_COLOR": "1"}, terminal_width=400
    )
    assert result.exit_code == 0, result.output
    return re.sub(r"\s+", " ", result.output)


def test_option_help_keeps_brackets() -> None:
    assert "(needs armtool[peers])" in _help("ik-bench")
    assert "[default: 0.005, or the group's in --kinematics-yaml]" in _help("ik-bench")
    assert "held nominal [default: origins,offsets]" in _help("calibrate", "fit")
    # options declared as Annotated[..., typer.Option(...)] (the robot options, traj's)
    assert "whose [tool.armtool.lint] xacro-args" in _help("tree")
    assert "whose [tool.armtool.lint] xacro-args" in _help("traj", "time")
    assert "whose [tool.armtool.lint] package-paths" in _help("calibrate", "fit")


def test_escaping_is_idempotent() -> None:
    build_app()
    assert "(needs armtool[peers])" in _help("ik-bench")  # a second app does not escape twice


def test_errors_keep_brackets(monkeypatch: object) -> None:
    from rich.console import Console

    import armtool.console as console

    buf = io.StringIO()
    monkeypatch.setattr(console, "_stderr", Console(file=buf, width=300, highlight=False))  # type: ignore[attr-defined]
    report_error(ArmtoolError("joint 'a[1]' is odd", "robot[2].urdf:3", "pip install 'armtool[peers]'"))
    text = buf.getvalue()
    assert "joint 'a[1]' is odd (robot[2].urdf:3)" in text and "pip install 'armtool[peers]'" in text


def test_say_prints_plain_text(monkeypatch: object) -> None:
    from rich.console import Console

    import armtool.console as console

    buf = io.StringIO()
    monkeypatch.setattr(console, "_stderr", Console(file=buf, width=300, highlight=False))  # type: ignore[attr-defined]
    console.say("pip install 'armtool[peers]' for [bold]x[/bold]", label="peer skipped:", style="yellow")
    assert buf.getvalue().strip() == "peer skipped: pip install 'armtool[peers]' for [bold]x[/bold]"
