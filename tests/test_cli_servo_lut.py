"""`armtool servo-lut`: fit/export/apply end to end, and bad input as exit 2 with row and field."""

from __future__ import annotations

import csv
import io
import json
import os
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError

FIXTURE = Path(__file__).resolve().parents[1] / "fixtures" / "servo" / "lut" / "ax12a_meas.csv"
runner = CliRunner()


def invoke(*args: str, stdin: str | None = None) -> tuple[int, str, str]:
    """Exit code, stdout and the error text the way `armtool.cli.main` reports it."""
    result = runner.invoke(app, ["servo-lut", *args], input=stdin)
    if isinstance(result.exception, ArmtoolError):
        return 2, result.stdout, str(result.exception)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.stdout, result.stderr


def fit(tmp_path: Path, *extra: str) -> Path:
    lut = tmp_path / "lut.json"
    code, _out, err = invoke("fit", str(FIXTURE), "-o", str(lut), *extra)
    assert code == 0, err
    return lut


def test_fit_writes_table_and_reports_before_after(tmp_path: Path) -> None:
    lut = tmp_path / "lut.json"
    code, out, err = invoke("fit", str(FIXTURE), "-o", str(lut))
    assert code == 0 and out == ""
    assert "held out" in err and "nominal map" in err and "non-linearity" in err
    doc = json.loads(lut.read_text())
    assert doc["servo"] == {
        "id": 1,
        "model": "AX-12A",
        "model_number": 12,
        "max_tick": 1023,
        "deg_per_tick": 300 / 1023,
    }
    assert doc["method"] == "pchip" and doc["approach"] == "up" and doc["fit"]["holdout"] == 10
    assert doc["fit"]["holdout_lut"]["max_deg"] <= doc["fit"]["holdout_nominal"]["max_deg"] / 3


def test_fit_to_stdout_with_options() -> None:
    code, out, _ = invoke(
        "fit", str(FIXTURE), "--method", "poly", "--degree", "5", "--holdout", "0.3", "--seed", "2", "--grid-step", "5"
    )
    assert code == 0
    doc = json.loads(out)
    assert doc["method"] == "poly" and doc["poly"]["degree"] == 5 and doc["grid"]["step_deg"] == 5


def test_export_formats(tmp_path: Path) -> None:
    lut = fit(tmp_path)
    code, out, _ = invoke("export", str(lut), "--format", "c", "--name", "elbow_lut", "--step", "0.5")
    assert code == 0 and "static const uint16_t elbow_lut[ELBOW_LUT_LEN] PROGMEM" in out
    assert "#define ELBOW_LUT_STEP_CDEG 50L" in out
    code, out, _ = invoke("export", str(lut), "--format", "csv")
    assert code == 0 and out.startswith("angle_deg,command_ticks\n")
    header = tmp_path / "lut.h"
    code, _, _err = invoke("export", str(lut), "--format", "c", "-o", str(header))
    assert code == 0 and header.read_text().startswith("/* servo_lut:")
    code, out, _ = invoke("export", str(lut), "--format", "yaml")
    assert code == 0 and "kind: armtool-servo-lut" in out


def test_apply_list_csv_and_stdin(tmp_path: Path) -> None:
    lut = fit(tmp_path)
    code, out, _ = invoke("apply", str(lut), "--angles", "60,150,240")
    assert code == 0
    ticks = [int(r["command_ticks"]) for r in csv.DictReader(io.StringIO(out))]
    assert ticks == sorted(ticks) and len(ticks) == 3
    traj = tmp_path / "traj.csv"
    traj.write_text("time_s,shoulder_rad\n0,0\n1,0.5\n")
    code, out, _ = invoke("apply", str(lut), str(traj), "--zero-deg", "150", "--direction", "-1")
    assert code == 0 and "shoulder_command_ticks" in out.splitlines()[0]
    code, out2, _ = invoke("apply", str(lut), "-", "--zero-deg", "150", "--direction", "-1", stdin=traj.read_text())
    assert code == 0 and out2 == out
    code, _, err = invoke("apply", str(lut), "--angles", "60,299", "--clip")
    assert code == 0 and "1 of 2 angle(s) clamped" in err


def test_bad_input_is_exit_2_naming_row_or_field(tmp_path: Path) -> None:
    head = "# servo_model: AX-12A\n"
    cases = {
        "missing.csv": (head + "command_ticks,present_ticks\n1,2\n", "missing column reference_deg"),
        "unitless.csv": (head + "command_ticks,reference\n1,2\n", "column 'reference' does not state its unit"),
        "few.csv": (head + "command_ticks,reference_deg\n100,30\n200,60\n300,90\n", "too few points: 3"),
        "nan.csv": (head + "command_ticks,reference_deg\n100,30\n200,nan\n", "nan.csv:4"),
        "dup.csv": (head + "command_ticks,reference_deg,repeat\n100,30,0\n100,30,0\n", "duplicated command 100"),
        "reverse.csv": (head + "command_ticks,reference_deg\n100,30\n200,60\n300,40\n400,120\n500,150\n", "lines 4, 5"),
    }
    for name, (text, needle) in cases.items():
        path = tmp_path / name
        path.write_text(text)
        code, out, err = invoke("fit", str(path))
        assert code == 2 and needle in err and out == "", (name, err)
    lut = fit(tmp_path)
    assert invoke("apply", str(lut), "--angles", "60,x")[0] == 2
    code, _, err = invoke("apply", str(lut))
    assert code == 2 and "give either a CSV or --angles" in err
    code, _, err = invoke("export", str(tmp_path / "none.json"))
    assert code == 2 and "no such file" in err


def test_real_process_exit_2_without_traceback(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("# servo_model: AX-12A\ncommand_ticks,reference_deg\n100,30\n116,inf\n")
    done = subprocess.run(
        [sys.executable, "-m", "armtool", "servo-lut", "fit", str(bad)],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "NO_COLOR": "1"},
    )
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "'reference_deg' is inf" in done.stderr and f"{bad}:4" in done.stderr


def test_fit_warns_about_an_interrupted_run(tmp_path: Path) -> None:
    partial = tmp_path / "m.csv.partial"
    partial.write_text(FIXTURE.read_text().replace("# servo_id: 1", "# servo_id: 1\n# complete: no"))
    code, out, err = invoke("fit", str(partial))
    assert code == 0 and "interrupted run" in err and json.loads(out)["kind"] == "armtool-servo-lut"
