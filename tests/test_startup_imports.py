"""`armtool lint` and `armtool --help` start without the heavy libraries (pre-commit runs lint per commit).

Each command runs in a fresh interpreter: `armtool.cli.main()` with `sys.argv` set, then the
top-level names in `sys.modules` are printed. Pinocchio, OpenCV and friends belong to `ik-bench`
and `calib`, imported inside those commands only.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HEAVY = ("pinocchio", "cv2", "scipy", "numpy", "matplotlib", "yourdfpy", "trimesh", "pydantic")

# Runs the CLI in-process, then prints {"exit": code, "modules": [...]} as the last line of stdout.
_PROBE = """\
import json, sys
sys.argv = ["armtool", *json.loads(sys.argv[1])]
from armtool.cli import main
try:
    main()
    code = 0
except SystemExit as exc:
    code = exc.code
sys.stdout.flush()
print()
print(json.dumps({"exit": code, "modules": sorted({name.partition(".")[0] for name in sys.modules})}))
"""

SMALL_URDF = """\
<?xml version="1.0"?>
<robot name="one_joint">
  <link name="base_link"/>
  <link name="arm">
    <inertial>
      <mass value="1.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    </inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/>
    <child link="arm"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1.57" upper="1.57" effort="10" velocity="1.0"/>
  </joint>
</robot>
"""


def _imported_after(*args: str) -> tuple[int, set[str]]:
    result = subprocess.run(
        [sys.executable, "-c", _PROBE, json.dumps(args)],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "NO_COLOR": "1"},
    )
    assert result.returncode == 0, result.stderr
    probe = json.loads(result.stdout.strip().splitlines()[-1])
    return probe["exit"], set(probe["modules"])


@pytest.mark.parametrize("command", ["lint", "help"])
def test_no_heavy_imports(command: str, tmp_path: Path) -> None:
    if command == "lint":
        urdf = tmp_path / "one_joint.urdf"
        urdf.write_text(SMALL_URDF)
        args: tuple[str, ...] = ("lint", str(urdf))
    else:
        args = ("--help",)
    exit_code, modules = _imported_after(*args)
    assert exit_code == 0
    assert "armtool" in modules  # the probe did run the CLI
    # `armtool lint PATH...` (pre-commit's call) never builds the parser; --help does.
    assert ("typer" in modules) == (command == "help")
    assert sorted(modules.intersection(HEAVY)) == []


def test_command_line_start_imports_only_the_option_choices_of_the_servo_commands() -> None:
    # Building the command line reads the servo commands' choices (numpy-free modules); the bus,
    # the models and the motion code come only with a servo command that runs (~60 ms otherwise).
    probe = _PROBE.replace('name.partition(".")[0] for name in sys.modules', "name for name in sys.modules")
    result = subprocess.run(
        [sys.executable, "-c", probe, json.dumps(["--version"])],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "NO_COLOR": "1"},
    )
    assert result.returncode == 0, result.stderr
    modules = set(json.loads(result.stdout.strip().splitlines()[-1])["modules"])
    assert "armtool.servo.limits.choices" in modules  # the probe did build the command line
    loaded = {m for m in modules if m.startswith("armtool.servo.")}
    assert loaded <= {
        "armtool.servo.limits",
        "armtool.servo.limits.choices",
        "armtool.servo.lut",
        "armtool.servo.lut.choices",
        "armtool.servo.registry",
    }, sorted(loaded)
