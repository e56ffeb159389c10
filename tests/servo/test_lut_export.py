"""Exports: the C header compiles and its lookup agrees with the table; CSV, JSON, YAML carry the grid."""

from __future__ import annotations

import csv
import io
import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import yaml

from armtool.errors import ArmtoolError
from armtool.servo.lut.csv_format import read_measurements
from armtool.servo.lut.export import ExportFormat, c_identifier, render
from armtool.servo.lut.table import LutTable, Method, fit_table
from armtool.servo.models import by_name as servo_model

FIXTURE = Path(__file__).resolve().parents[2] / "fixtures" / "servo" / "lut" / "ax12a_meas.csv"
CC = shutil.which("cc")


@pytest.fixture(scope="module")
def table() -> LutTable:
    return fit_table(read_measurements(FIXTURE))


@pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
def test_c_header_compiles_and_lookup_matches(table: LutTable, tmp_path: Path) -> None:
    header = tmp_path / "servo1_lut.h"
    header.write_text(render(table, ExportFormat.C, step_deg=0.5, name="servo1_lut"))
    (tmp_path / "only.c").write_text('#include "servo1_lut.h"\n')
    done = subprocess.run(
        [CC, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-c", "only.c", "-o", "only.o"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    # the inline lookup at grid points and between them, against the table itself
    cdeg = [3300, 3350, 3373, 15000, 15049, 26100, 26123, 100, 99999]
    (tmp_path / "main.c").write_text(
        '#include <stdio.h>\n#include "servo1_lut.h"\nint main(void) {\n'
        f"  static const int32_t q[] = {{{', '.join(map(str, cdeg))}}};\n"
        '  printf("%u %ld %ld\\n", (unsigned)SERVO1_LUT_LEN, (long)SERVO1_LUT_START_CDEG, (long)SERVO1_LUT_STEP_CDEG);\n'
        '  for (unsigned i = 0; i < sizeof q / sizeof q[0]; ++i) printf("%u\\n", (unsigned)servo1_lut_lookup(q[i]));\n'
        "  return 0;\n}\n"
    )
    built = subprocess.run(
        [CC, "-std=c99", "-Wall", "-Werror", "main.c", "-o", "main"], cwd=tmp_path, capture_output=True, text=True
    )
    assert built.returncode == 0, built.stderr
    lines = subprocess.run([str(tmp_path / "main")], capture_output=True, text=True, check=True).stdout.split()
    grid = table.grid(0.5)
    assert (int(lines[0]), int(lines[1]), int(lines[2])) == (len(grid.command_ticks), round(grid.start_deg * 100), 50)
    got = [int(v) for v in lines[3:]]
    lo, hi = table.valid_range_deg
    for q, value in zip(cdeg, got):
        deg = min(max(q / 100, grid.start_deg), float(grid.angles_deg[-1]))
        # linear between whole-tick grid entries: within one tick of the table's own command
        assert abs(value - float(table.command([min(max(deg, lo), hi)])[0])) <= 1.0, (q, value)
    assert got[-2] == grid.command_ticks[0] and got[-1] == grid.command_ticks[-1]


def test_c_header_is_clipped_to_the_tick_range() -> None:
    model = servo_model("AX-12A")
    wide = LutTable(model, Method.LINEAR, (0.0, 100.0, 310.0), (-20.0, 340.0, 1060.0))
    text = render(wide, ExportFormat.C, step_deg=10, name="wide")
    values = [int(v) for v in text.split("PROGMEM = {")[1].split("}")[0].replace(",", " ").split()]
    assert values[0] == 0 and values[-1] == 1023 and len(values) == 32
    assert "#define WIDE_MAX_TICK 1023u" in text


@pytest.mark.skipif(CC is None, reason="no C compiler (cc) on PATH")
def test_c_header_survives_hostile_metadata_and_keeps_fit_numbers(table: LutTable, tmp_path: Path) -> None:
    doc = table.to_dict()
    doc["reference"] = "csv:evil*/ int x = ; /*.csv"
    (tmp_path / "t.json").write_text(json.dumps(doc))
    from armtool.servo.lut.table import read_table

    text = render(read_table(tmp_path / "t.json"), ExportFormat.C, name="t")
    assert "held-out points:" in text  # the fit's numbers survive the JSON round trip
    (tmp_path / "t.h").write_text(text)
    (tmp_path / "t.c").write_text('#include "t.h"\n')
    done = subprocess.run(
        [CC, "-std=c99", "-Wall", "-Werror", "-c", "t.c", "-o", "t.o"], cwd=tmp_path, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr


def test_c_step_must_be_whole_hundredths(table: LutTable) -> None:
    with pytest.raises(ArmtoolError, match="hundredths of a degree"):
        render(table, ExportFormat.C, step_deg=0.333)


def test_c_identifier() -> None:
    assert c_identifier("Servo-1 lut") == "servo_1_lut"
    with pytest.raises(ArmtoolError, match="cannot be a C name"):
        c_identifier("1lut")


def test_csv_json_yaml_carry_the_same_grid(table: LutTable) -> None:
    rows = list(csv.DictReader(io.StringIO(render(table, ExportFormat.CSV, step_deg=2))))
    grid = table.grid(2)
    assert [int(r["command_ticks"]) for r in rows] == list(grid.command_ticks)
    assert float(rows[0]["angle_deg"]) == grid.start_deg and float(rows[1]["angle_deg"]) == grid.start_deg + 2
    doc = json.loads(render(table, ExportFormat.JSON, step_deg=2))
    assert doc["grid"]["command_ticks"] == list(grid.command_ticks) and doc["grid"]["step_deg"] == 2
    assert yaml.safe_load(render(table, ExportFormat.YAML, step_deg=2)) == doc
    ticks = np.array(grid.command_ticks)
    assert np.all(np.diff(ticks) >= 0) and ticks.min() >= 0 and ticks.max() <= 1023


def test_grid_step_wider_than_range(table: LutTable) -> None:
    with pytest.raises(ArmtoolError, match="wider than the table's range"):
        table.grid(500)
