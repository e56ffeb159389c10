"""Bad input in the arm file, the simulator config, the URDF and --id: exit 2 with what, where
and a hint, never an internal error."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from armtool.errors import ArmtoolError
from armtool.servo import limits as L
from armtool.servo.sim import sim_config_from_dict

ARM = "joints:\n  - {name: j1, id: 1, model: AX-12A, zero_ticks: 512, direction: 1}\n"


@pytest.mark.parametrize(
    "text, what, where",
    [
        ("baud: fast\n" + ARM, "'baud' must be a whole number, got 'fast'", "arm.yaml"),
        (ARM.replace("id: 1,", "id: 400,"), "id 400 is outside 0..252", "joints[0]"),
        (ARM.replace("id: 1,", "id: 1.7,"), "'id' must be a whole number, got 1.7", "joints[0]"),
        (ARM.replace("AX-12A", "AX-99"), "unknown servo model 'AX-99'", "joints[0]"),
        (ARM.replace("zero_ticks: 512", "zero_ticks: 5000"), "zero_ticks 5000 is outside 0..1023", "joints[0]"),
    ],
)
def test_arm_file(tmp_path: Path, text: str, what: str, where: str) -> None:
    path = tmp_path / "arm.yaml"
    path.write_text(text)
    with pytest.raises(ArmtoolError) as info:
        L.load_arm(path)
    assert what in info.value.what and where in (info.value.where or "")


@pytest.mark.parametrize(
    "change, what, where",
    [
        ({"stops": ["a", "b"]}, "'stops' must be two numbers", "joints[0]"),
        ({"stops": [1, 2, 3]}, "'stops' must be two numbers", "joints[0]"),
        ({"model": "AX-99"}, "unknown servo model", "joints[0]"),
        ({"faults": {"missing_ids": 3}}, "'missing_ids' must be a list of IDs", "faults"),
        ({"baud": "fast"}, "'baud' must be a number", "sim.yaml"),
        ({"person": {"speed_deg_s": "fast"}}, "'speed_deg_s' must be a number", "person"),
    ],
)
def test_sim_config(change: dict[str, object], what: str, where: str) -> None:
    joint: dict[str, object] = {"id": 1, "model": "AX-12A", "stops": [92, 914]}
    doc: dict[str, object] = {"protocol": "dxl1", "joints": [joint]}
    for k, v in change.items():
        (joint if k in ("stops", "model") else doc)[k] = v
    with pytest.raises(ArmtoolError) as info:
        sim_config_from_dict(doc, source="sim.yaml")
    assert what in info.value.what and where in (info.value.where or ""), (info.value.what, info.value.where)


def test_xacro_expression_in_the_urdf() -> None:
    text = '<robot name="r">\n  <joint name="a" type="revolute">\n    <limit lower="${-pi}" upper="1"/>\n  </joint>\n</robot>\n'
    with pytest.raises(ArmtoolError) as info:
        L.check_urdf_names(text, ["a"], "arm.urdf")
    assert (
        "is not a number" in info.value.what and info.value.where == "arm.urdf:2" and "xacro" in (info.value.hint or "")
    )


@pytest.mark.parametrize(
    "args, what",
    [
        (
            ["limits", "--port", "/dev/null", "--arm", "{arm}", "--mode", "auto", "--yes"],
            "'baud' must be a whole number",
        ),
        (["servo-lut", "measure", "--port", "/dev/null", "--id", "300", "--reference", "manual"], "300"),
        (
            ["servo-lut", "measure", "--port", "/dev/null", "--id", "1", "--reference", "encoder:/dev/ttyS0@0"],
            "encoder baud rate 0 is outside 1..4000000",
        ),
        (
            [
                "servo-lut",
                "check",
                "t.json",
                "--port",
                "/dev/null",
                "--id",
                "1",
                "--reference",
                "encoder:/dev/ttyS0@-9600",
            ],
            "encoder baud rate -9600 is outside",
        ),
        (
            ["servo-lut", "measure", "--port", "/dev/null", "--id", "1", "--reference", "encoder:/dev/ttyS0@"],
            "encoder baud rate '' is not a whole number",
        ),
    ],
)
def test_cli_exit_2_without_internal_error(tmp_path: Path, args: list[str], what: str) -> None:
    arm = tmp_path / "arm.yaml"
    arm.write_text("baud: fast\n" + ARM)
    r = subprocess.run(
        [sys.executable, "-m", "armtool", *[a.format(arm=arm) for a in args]],
        capture_output=True,
        text=True,
        timeout=60,
        stdin=subprocess.DEVNULL,
    )
    assert r.returncode == 2 and what in r.stderr, r.stderr
    assert "internal error" not in r.stderr and "Traceback" not in r.stderr


LUT_FIXTURE = Path(__file__).resolve().parents[2] / "fixtures" / "servo" / "lut" / "ax12a_meas.csv"


def _armtool(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True)


def test_duplicated_command_without_repeat_column(tmp_path: Path) -> None:
    from armtool.servo.lut.csv_format import parse_measurements

    text = "# servo_model: AX-12A\n# reference: csv\ncommand_ticks,reference_deg\n100,30.1\n200,59.2\n100,30.3\n"
    with pytest.raises(ArmtoolError) as info:
        parse_measurements(text, "m.csv")
    assert "duplicated command 100" in info.value.what and "first at line 4" in info.value.what
    assert "m.csv:6" in (info.value.where or "")


def test_negative_monotone_tolerance_is_refused(tmp_path: Path) -> None:
    r = _armtool("servo-lut", "fit", str(LUT_FIXTURE), "-o", str(tmp_path / "t.json"), "--monotone-tol", "-1")
    assert r.returncode == 2 and "--monotone-tol must be ≥ 0" in r.stderr
    assert not (tmp_path / "t.json").exists()


def test_table_with_decreasing_commands_is_refused(tmp_path: Path) -> None:
    import json

    table = tmp_path / "t.json"
    assert _armtool("servo-lut", "fit", str(LUT_FIXTURE), "-o", str(table)).returncode == 0
    doc = json.loads(table.read_text())
    doc["knots"]["command_ticks"] = list(reversed(doc["knots"]["command_ticks"]))
    table.write_text(json.dumps(doc))
    r = _armtool("servo-lut", "apply", str(table), "--angles", "150")
    assert r.returncode == 2 and "knots.command_ticks is not strictly increasing" in r.stderr


@pytest.mark.parametrize("name, what", [("int", "is a C keyword"), ("9lives", "cannot be a C name")])
def test_export_name_must_be_a_c_identifier(tmp_path: Path, name: str, what: str) -> None:
    table = tmp_path / "t.json"
    assert _armtool("servo-lut", "fit", str(LUT_FIXTURE), "-o", str(table)).returncode == 0
    r = _armtool("servo-lut", "export", str(table), "--format", "c", "--name", name, "-o", str(tmp_path / "h.h"))
    assert r.returncode == 2 and what in r.stderr and not (tmp_path / "h.h").exists()
