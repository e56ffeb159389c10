"""`armtool lint PATH...` without options skips Typer (armtool.cli.lint.run_plain): same output,
same exit code as the Typer path, and the same values for every option."""

from __future__ import annotations

import inspect
import sys
from pathlib import Path

import pytest

from armtool.cli import lint as lint_cmd
from armtool.cli import main

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "robots"


def _run(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    monkeypatch.setattr(sys, "argv", ["armtool", *args])
    monkeypatch.setenv("NO_COLOR", "1")
    with pytest.raises(SystemExit) as exited:
        main()
    out, err = capsys.readouterr()
    return int(exited.value.code or 0), out, err


def test_every_option_has_its_default() -> None:
    params = inspect.signature(lint_cmd.lint).parameters
    assert set(lint_cmd._DEFAULTS) == set(params) - {"paths"}
    for name, value in lint_cmd._DEFAULTS.items():
        default = params[name].default
        default = getattr(default, "default", default)  # typer.Option(default, ...), or an Annotated option's own
        assert (list(value) if isinstance(value, tuple) else value) == default, name


@pytest.mark.parametrize(
    "paths",
    [
        [str(FIXTURES / "broken_arm" / "broken_arm.urdf")],  # findings: exit 1
        [str(FIXTURES / "clean_arm")],  # a directory, clean: exit 0
        [str(FIXTURES / "broken_arm"), str(FIXTURES / "clean_arm" / "urdf")],
        [str(FIXTURES / "nope.urdf")],  # exit 2, message on stderr
    ],
)
@pytest.mark.parametrize("command", ["lint", "lint-urdf"])
def test_plain_paths_match_the_typer_path(
    paths: list[str], command: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    calls = []
    real = lint_cmd.run_plain
    monkeypatch.setattr(lint_cmd, "run_plain", lambda args: calls.append(args) or real(args))
    plain = _run(monkeypatch, capsys, command, *paths)
    # --fail-on error is the default: the same run, parsed by Typer.
    typed = _run(monkeypatch, capsys, command, "--fail-on", "error", *paths)
    assert calls == [paths, ["--fail-on", "error", *paths]]
    assert plain == typed
    assert plain[0] in (0, 1, 2) and (plain[1] or plain[2])


def test_anything_but_paths_goes_to_typer(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    assert lint_cmd.run_plain([]) is None
    assert lint_cmd.run_plain(["--help"]) is None
    assert lint_cmd.run_plain(["a.urdf", "--format", "json"]) is None
    code, out, _ = _run(monkeypatch, capsys, "lint", "--help")
    assert code == 0 and "--format" in out
    code, _, err = _run(monkeypatch, capsys, "lint")
    assert code == 2 and "give files or directories to lint" in err
