"""`armtool lint PATH...` without options skips Typer (armtool.cli.lint_run.run_plain): same output,
same exit code as the Typer path, the same values for every option, and Typer is never imported."""

from __future__ import annotations

import inspect
import sys
from pathlib import Path

import pytest

from armtool.cli import lint as lint_cmd
from armtool.cli import lint_run, main

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "robots"


def _run(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    monkeypatch.setattr(sys, "argv", ["armtool", *args])
    monkeypatch.setenv("NO_COLOR", "1")
    with pytest.raises(SystemExit) as exited:
        main()
    out, err = capsys.readouterr()
    return int(exited.value.code or 0), out, err


def test_every_option_has_its_default() -> None:
    # The plain path runs LintRequest's defaults; Typer's path runs the command's. They must agree.
    import dataclasses

    params = inspect.signature(lint_cmd.lint).parameters
    renamed = {"xacro_args": "xacro_arg", "package_paths": "package_path"}
    fields = {f.name: f for f in dataclasses.fields(lint_run.LintRequest)}
    assert {renamed.get(name, name) for name in fields} == set(params)
    for name, f in fields.items():
        if name == "paths":
            continue
        default = params[renamed.get(name, name)].default
        default = getattr(default, "default", default)  # typer.Option(default, ...), or an Annotated option's own
        ours = f.default_factory() if f.default_factory is not dataclasses.MISSING else f.default
        # An empty list and None both mean "not given" (Typer gives None for a repeatable option).
        if isinstance(ours, (list, dict)) and not ours:
            ours = None
        assert ours == default, name


@pytest.mark.parametrize(
    "paths",
    [
        [str(FIXTURES / "broken_arm" / "broken_arm.urdf")],  # findings: exit 1
        [str(FIXTURES / "clean_arm")],  # a directory (its config_broken/ has findings)
        [str(FIXTURES / "broken_arm"), str(FIXTURES / "clean_arm" / "urdf")],
        [str(FIXTURES / "nope.urdf")],  # exit 2, message on stderr
    ],
)
@pytest.mark.parametrize("command", ["lint", "lint-urdf"])
def test_plain_paths_match_the_typer_path(
    paths: list[str], command: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    calls = []
    real = lint_run.run_plain
    monkeypatch.setattr(lint_run, "run_plain", lambda args: calls.append(args) or real(args))
    plain = _run(monkeypatch, capsys, command, *paths)
    # --fail-on error is the default: the same run, parsed by Typer.
    typed = _run(monkeypatch, capsys, command, "--fail-on", "error", *paths)
    assert calls == [paths, ["--fail-on", "error", *paths]]
    assert plain == typed
    assert plain[0] in (0, 1, 2) and (plain[1] or plain[2])


def test_anything_but_paths_goes_to_typer(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    assert lint_run.run_plain([]) is None
    assert lint_run.run_plain(["--help"]) is None
    assert lint_run.run_plain(["a.urdf", "--format", "json"]) is None
    code, out, _ = _run(monkeypatch, capsys, "lint", "--help")
    assert code == 0 and "--format" in out
    code, _, err = _run(monkeypatch, capsys, "lint")
    assert code == 2 and "give files or directories to lint" in err


def test_the_plain_path_imports_no_typer(tmp_path: Path) -> None:
    # pre-commit runs `armtool lint PATH...` on every commit: the parser (Typer, ~45 ms) is not built.
    import subprocess

    code = (
        "import sys\n"
        "from armtool.cli import main\n"
        f"sys.argv = ['armtool', 'lint', {str(FIXTURES / 'clean_arm' / 'urdf')!r}]\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('typer', 'click', 'rich')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "[]"
