"""`make demo`'s steps that are meant to report something: announced before they run, and the demo
fails on any exit code but the announced one (a lint step that finds nothing or breaks)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STEP = ROOT / "tools" / "demo_step.py"


def step(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(STEP), *args], capture_output=True, text=True, timeout=60)


def exits(code: int) -> list[str]:
    return [sys.executable, "-c", f"print('one'); print('two'); print('three'); raise SystemExit({code})"]


def test_the_announced_exit_code_passes_and_is_said_before_the_output() -> None:
    done = step("1", "findings", "--", *exits(1))
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "   (expect findings, exit 1)" and lines[-1] == "-- exit 1, as expected"
    assert lines.index("one") > 0


def test_any_other_exit_code_fails_the_step_loudly() -> None:
    for code in (0, 2):
        done = step("1", "findings", "--", *exits(code))
        assert done.returncode == 1
        assert f"demo step FAILED: `{sys.executable} -c" in done.stderr
        assert f"exited {code}, but it is meant to report findings and exit 1" in done.stderr
    missing = step("0", "nothing", "--", "no-such-command-armtool")
    assert missing.returncode == 1 and "cannot run `no-such-command-armtool`" in missing.stderr


def test_head_and_tail_show_part_of_the_output_and_still_check_the_code() -> None:
    done = step("3", "x", "--tail", "2", "--", *exits(3))
    assert done.returncode == 0 and done.stdout.splitlines()[2:] == ["two", "three", "-- exit 3, as expected"]
    done = step("3", "x", "--head", "1", "--", *exits(0))
    assert done.returncode == 1 and done.stdout.splitlines()[2:] == ["one"]


def test_the_demo_ignores_no_failure() -> None:
    """`make demo` printed `make: [Makefile:22: demo] Error 1 (ignored)` and hid exit codes behind
    `| tail` and `|| true`: every step now either must succeed or goes through demo_step."""
    text = (ROOT / "Makefile").read_text()
    recipe = text.split("\ndemo:", 1)[1].split("\n\n", 1)[0].splitlines()[1:]
    assert recipe, "no demo recipe"
    assert not [line for line in recipe if line.startswith("\t-")], "a recipe line whose failure make ignores"
    assert not [line for line in recipe if "|| true" in line and "kill" not in line], "an exit code hidden"
    assert not [line for line in recipe if re.search(r"armtool [^|;]*\| *(head|tail)", line)], "a pipe hides a code"
    assert "every step behaved as expected" in recipe[-1]
