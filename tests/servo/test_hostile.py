"""Hostile input for servo-sim, limits and servo-lut (issue 14): every numbered finding in their
scope as a plain regression test, then property-based runs over numeric options and mutated files.

The CLI runs in-process (CliRunner); an exception other than ArmtoolError or SystemExit is what
`armtool.cli.main` would report as "internal error", so it fails the test.
"""

from __future__ import annotations

import copy
import json
import math
import os
import stat
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError

FIXTURES = Path(__file__).resolve().parents[2] / "fixtures" / "servo"
MEAS = FIXTURES / "lut" / "ax12a_meas.csv"
runner = CliRunner()
pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="the simulator needs a pty")
HYPO = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def run(*args: str, stdin: str | None = None) -> tuple[int, str, str]:
    """Exit code, stdout, error text, as `armtool.cli.main` would give them; any other exception fails."""
    result = runner.invoke(app, list(args), input=stdin)
    exc = result.exception
    if isinstance(exc, ArmtoolError):
        return 2, result.stdout, str(exc)
    if exc is not None and not isinstance(exc, SystemExit):
        raise exc
    return result.exit_code, result.stdout, result.stderr


def snapshot(*paths: Path) -> dict[Path, bytes]:
    return {p: p.read_bytes() for p in paths}


@pytest.fixture(scope="module")
def table(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("lut") / "lut.json"
    code, _, err = run("servo-lut", "fit", str(MEAS), "-o", str(path))
    assert code == 0, err
    return path


def edited(table: Path, tmp_path: Path, edit: Any) -> Path:
    doc = json.loads(table.read_text())
    edit(doc)
    out = tmp_path / "edited.json"
    out.write_text(json.dumps(doc))
    return out


# ---------------------------------------------------------------- 1. files destroyed


def test_port_file_refuses_a_device_and_never_touches_it() -> None:
    from armtool.fileio import PortFile

    marker = PortFile(Path("/dev/null"))
    assert not PortFile.looks_like_ours(Path("/dev/null"))
    with pytest.raises(ArmtoolError, match="not a port file"):
        marker.claim()
    marker.remove()  # never written: nothing happens
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_servo_sim_port_file_refuses_a_user_file_and_a_fifo(tmp_path: Path) -> None:
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    for target in (notes, fifo):
        code, _, err = run(
            "servo-sim", str(FIXTURES / "ax12_arm.yaml"), "--duration", "0.2", "--port-file", str(target)
        )
        assert code == 2 and "is not a port file written by armtool" in err
    assert notes.read_text() == "my notes\n" and stat.S_ISFIFO(fifo.stat().st_mode)


def test_port_file_is_removed_only_if_still_ours(tmp_path: Path) -> None:
    from armtool.fileio import PortFile

    stale = tmp_path / "port"
    stale.write_text("/dev/pts/99\n")  # left by a killed run: reused
    marker = PortFile(stale)
    marker.claim()
    marker.write("/dev/pts/7")
    assert stale.read_text() == "/dev/pts/7\n"
    stale.write_text("the user's text now\n")
    marker.remove()
    assert stale.read_text() == "the user's text now\n"
    marker = PortFile(stale := tmp_path / "port2")
    marker.claim()
    marker.write("/dev/pts/7")
    marker.remove()
    assert not stale.exists()


def test_servo_sim_writes_and_removes_its_port_file(tmp_path: Path) -> None:
    port_file = tmp_path / "port"
    code, out, err = run(
        "servo-sim", str(FIXTURES / "ax12_arm.yaml"), "--duration", "0.3", "--port-file", str(port_file)
    )
    assert code == 0, err
    assert out.splitlines()[0].startswith("/dev/") and not port_file.exists()


def test_in_place_twice_keeps_the_original(tmp_path: Path) -> None:
    from armtool.fileio import write_with_backup

    urdf = tmp_path / "arm.urdf"
    urdf.write_text("original")
    first = write_with_backup(urdf, "edit 1", urdf.read_text())
    second = write_with_backup(urdf, "edit 2", urdf.read_text())
    assert (first.name, second.name) == ("arm.urdf.bak", "arm.urdf.bak.1")
    assert first.read_text() == "original" and second.read_text() == "edit 1" and urdf.read_text() == "edit 2"


# ---------------------------------------------------------------- 2. safety


@pytest.fixture(scope="module")
def sim() -> Iterator[Any]:
    from armtool.servo.sim import SimBus

    cfg = {
        "protocol": "dxl1",
        "baud": 1000000,
        "return_delay": 0,
        "encoder": {"noise_deg": 0.05},
        "joints": [{"id": 1, "model": "AX-12A", "stops": [92, 914], "start": 503}],
    }
    with SimBus.start(cfg) as bus:
        yield bus


def measure_args(sim: Any, *extra: str) -> list[str]:
    return [
        "servo-lut",
        "measure",
        "--port",
        sim.port_path,
        "--id",
        "1",
        "--reference",
        f"encoder:{sim.encoder_port_path}",
        "--speed",
        "600",
        "--dwell",
        "0.01",
        "--yes",
        *extra,
    ]


def test_negative_backoff_is_refused_before_moving(sim: Any) -> None:
    goal = sim.peek(1, "goal_position")
    code, _, err = run(*measure_args(sim, "--min", "420", "--max", "620", "--backoff", "-50"))
    assert code == 2 and "--backoff" in err
    assert sim.peek(1, "goal_position") == goal and sim.peek(1, "torque_enable") == 0


def test_motion_layer_refuses_a_goal_outside_the_range() -> None:
    from armtool.servo.lut.measure import Driver, plan_commands

    class NoBus:
        def write(self, *args: Any, **kw: Any) -> None:
            raise AssertionError("a goal outside the range reached the bus")

    driver = Driver(NoBus(), None, 1, bounds=(420, 620))
    with pytest.raises(ArmtoolError, match="refusing to command"):
        driver.goto(370)
    with pytest.raises(ArmtoolError, match="--backoff"):
        plan_commands(420, 620, "up", -50)
    assert all(420 <= c <= 620 for c in plan_commands(420, 620, "both", 50, points=5000))


@pytest.mark.parametrize(
    "args, flag",
    [
        (["limits", "--port", "/nonexistent", "--ids", "1", "--mode", "auto", "--yes", "--margin", "nan"], "--margin"),
        (["limits", "--port", "/nonexistent", "--ids", "1", "--mode", "auto", "--yes", "--baud", "0"], "--baud"),
        (
            ["limits", "--port", "/nonexistent", "--ids", "1", "--mode", "auto", "--yes", "--timeout-ms", "nan"],
            "--timeout-ms",
        ),
        (
            ["limits", "--port", "/nonexistent", "--ids", "1", "--mode", "auto", "--yes", "--timeout-ms", "inf"],
            "--timeout-ms",
        ),
        (["limits", "--port", "/nonexistent", "--ids", "1", "--mode", "manual", "--duration", "inf"], "--duration"),
        (["limits", "--port", "/nonexistent", "--ids", "1-100000000000", "--mode", "auto", "--yes"], "--ids"),
        (["limits", "--port", "/nonexistent", "--ids", "1", "--mode", "auto", "--yes", "--speed", "inf"], "--speed"),
        (
            [
                "servo-lut",
                "check",
                "{table}",
                "--port",
                "/nonexistent",
                "--id",
                "1",
                "--reference",
                "manual",
                "--max-err",
                "nan",
            ],
            "--max-err",
        ),
        (
            ["servo-lut", "measure", "--port", "/nonexistent", "--id", "1", "--reference", "manual", "--baud", "0"],
            "--baud",
        ),
        (
            [
                "servo-lut",
                "measure",
                "--port",
                "/nonexistent",
                "--id",
                "1",
                "--reference",
                "manual",
                "--settle-timeout",
                "nan",
            ],
            "--settle-timeout",
        ),
        (["servo-lut", "fit", str(MEAS), "--grid-step", "inf"], "--grid-step"),
        (["servo-lut", "fit", str(MEAS), "--holdout", "nan"], "--holdout"),
        (["servo-lut", "export", "{table}", "--step", "nan"], "--step"),
        (["servo-sim", str(FIXTURES / "ax12_arm.yaml"), "--duration", "inf"], "--duration"),
    ],
)
def test_bad_numbers_are_refused_naming_the_flag(table: Path, args: list[str], flag: str) -> None:
    start = time.monotonic()
    code, _, err = run(*[a.format(table=table) for a in args])
    assert code == 2 and flag in err, err
    assert time.monotonic() - start < 5


def test_torque_limit_that_rounds_to_zero_is_refused(sim: Any) -> None:
    from armtool.servo.lut.measure import torque_register
    from armtool.servo.models import by_name

    with pytest.raises(ArmtoolError, match="less than one step"):
        torque_register(by_name("AX-12A"), 0.01)
    goal = sim.peek(1, "goal_position")
    code, _, err = run(*measure_args(sim, "--min", "420", "--max", "620", "--torque-limit", "0.01"))
    assert code == 2 and "--torque-limit" in err
    assert sim.peek(1, "goal_position") == goal and sim.peek(1, "torque_enable") == 0


def test_encoder_reference_on_the_bus_port_is_refused(sim: Any) -> None:
    code, _, err = run(
        "servo-lut",
        "measure",
        "--port",
        sim.port_path,
        "--id",
        "1",
        "--reference",
        f"encoder:{sim.port_path}",
        "--min",
        "420",
        "--max",
        "620",
        "--yes",
    )
    assert code == 2 and "is the servo bus" in err


def test_manual_reference_without_a_terminal_says_so() -> None:
    code, _, err = run(
        "servo-lut",
        "measure",
        "--port",
        "/nonexistent",
        "--id",
        "1",
        "--reference",
        "manual",
        "--min",
        "420",
        "--max",
        "620",
    )
    assert code == 2 and "stdin is not a terminal" in err and "Aborted" not in err


def test_limits_margin_wider_than_the_servo_range_is_refused() -> None:
    from armtool.servo.limits import Joint
    from armtool.servo.limits.request import check_motion_options
    from armtool.servo.models import by_name

    with pytest.raises(ArmtoolError, match="--margin"):
        check_motion_options(Joint("j", 1, by_name("AX-12A")), 150, 3)
    with pytest.raises(ArmtoolError, match="--back-off"):
        check_motion_options(Joint("j", 1, by_name("AX-12A")), 2, 150)


# ---------------------------------------------------------------- 3. corrupt output


def test_fit_never_writes_non_finite_numbers(tmp_path: Path) -> None:
    out = tmp_path / "lut.json"
    for step in ("inf", "1e-7", "nan", "0", "-1"):
        code, _, err = run("servo-lut", "fit", str(MEAS), "--grid-step", step, "-o", str(out))
        assert code == 2 and "--grid-step" in err, (step, err)
    assert not out.exists()


@pytest.mark.parametrize(
    "edit, what",
    [
        (lambda d: d["knots"]["command_ticks"].__setitem__(0, -5.0), "outside the AX-12A's 0..1023"),
        (lambda d: d.update(approach="*/ #include <evil.h> /*"), "approach must be one of"),
        (lambda d: d["servo"].update(id="1; rm"), "servo.id"),
        (
            lambda d: d.update(method="poly", poly={"degree": 3, "domain_deg": [0, 300], "coef": [500, -100, 0, 0]}),
            "not increasing",
        ),
        (
            lambda d: d.update(method="poly", poly={"degree": 3, "domain_deg": [0, 300], "coef": [500, 100]}),
            "poly.coef",
        ),
    ],
)
def test_table_read_back_is_validated_like_a_fitted_one(table: Path, tmp_path: Path, edit: Any, what: str) -> None:
    bad = edited(table, tmp_path, edit)
    header = tmp_path / "lut.h"
    code, _, err = run("servo-lut", "export", str(bad), "--format", "c", "-o", str(header))
    assert code == 2 and what in err, err
    assert not header.exists()


@pytest.mark.parametrize("value", [".nan", ".inf", "1.5", "-3", "true", "5000"])
def test_limits_file_ticks_are_validated(tmp_path: Path, value: str) -> None:
    from armtool.servo.lut.measure import read_limits

    path = tmp_path / "limits.yaml"
    path.write_text(f"joints:\n  - {{id: 1, safe_min_ticks: {value}, safe_max_ticks: 900}}\n")
    with pytest.raises(ArmtoolError, match="safe_min_ticks"):
        read_limits(path, 1)


def test_table_with_nan_is_refused(table: Path, tmp_path: Path) -> None:
    bad = tmp_path / "nan.json"
    bad.write_text(
        table.read_text().replace('"knots": {\n    "angle_deg": [\n', '"knots": {\n    "angle_deg": [\n      NaN,\n', 1)
    )
    code, _, err = run("servo-lut", "apply", str(bad), "--angles", "150")
    assert code == 2 and "NaN" in err


def test_c_header_cannot_be_injected_through_the_reference(table: Path, tmp_path: Path) -> None:
    bad = edited(table, tmp_path, lambda d: d.update(reference="x */ int evil(void) { return 1; } /* \\\n??/"))
    code, header, err = run("servo-lut", "export", str(bad), "--format", "c")
    assert code == 0, err
    comment = header[: header.index("*/") + 2]
    assert (
        "evil" in comment and header.count("*/") == header.count("/*") and "\\\n" not in header and "??" not in header
    )


# ---------------------------------------------------------------- 4. memory and time


@pytest.mark.parametrize(
    "args",
    [
        ["servo-lut", "fit", str(MEAS), "--grid-step", "1e-7"],
        ["servo-lut", "export", "{table}", "--step", "1e-7"],
        ["servo-lut", "export", "{table}", "--format", "csv", "--step", "0.0001"],
        ["servo-lut", "export", "{table}", "--step", "5e-324"],  # subnormal: range/step overflows to inf
        ["servo-lut", "fit", str(MEAS), "--grid-step", "1e-310"],
    ],
)
def test_huge_tables_are_refused_at_once(table: Path, args: list[str]) -> None:
    start = time.monotonic()
    code, _, err = run(*[a.format(table=table) for a in args])
    assert code == 2 and ("--grid-step" in err or "more than 65536" in err), err
    assert time.monotonic() - start < 5


def test_id_ranges_are_bounded_before_expansion() -> None:
    from armtool.cli.options import parse_id_list

    start = time.monotonic()
    with pytest.raises(ArmtoolError, match="outside 0..252"):
        parse_id_list("1-100000000000")
    with pytest.raises(ArmtoolError, match="listed twice"):
        parse_id_list("1-200,1-200")
    assert parse_id_list("1-3,7") == [1, 2, 3, 7]
    assert time.monotonic() - start < 1


# ---------------------------------------------------------------- 5. internal errors


def test_negative_seed_is_any_integer(tmp_path: Path) -> None:
    code, out, err = run("servo-lut", "fit", str(MEAS), "--seed", "-1")
    assert code == 0, err
    assert json.loads(out)["kind"] == "armtool-servo-lut"


@pytest.mark.parametrize(
    "edit, what",
    [
        ({"person": {"speed_deg_s": 0}}, "speed_deg_s"),
        ({"return_delay": 100000}, "return_delay"),
        ({"overload_time_s": float("inf")}, "overload_time_s"),
        ({"faults": {"p_drop": 2}}, "p_drop"),
        ({"joints": [{"id": 1, "model": "SCS0009"}], "protocol": "feetech"}, "does not support the SCS0009"),
    ],
)
def test_bad_sim_config_is_a_clear_error(tmp_path: Path, edit: dict[str, Any], what: str) -> None:
    cfg = yaml.safe_load((FIXTURES / "ax12_arm.yaml").read_text())
    cfg.update(edit)
    path = tmp_path / "sim.yaml"
    path.write_text(yaml.safe_dump(cfg))
    code, _, err = run("servo-sim", str(path), "--duration", "0.2")
    assert code == 2 and what in err, err


def test_sim_thread_failure_is_reported_not_printed() -> None:
    from armtool.servo.sim import SimBus

    with SimBus.start({"protocol": "dxl1", "joints": [{"id": 1}]}) as sim:

        def boom(*_: Any) -> None:
            raise RuntimeError("physics broke")

        sim.servos[1].step = boom  # type: ignore[method-assign]
        with pytest.raises(ArmtoolError, match="the simulator stopped: RuntimeError: physics broke"):
            sim.wait(2.0)


# ---------------------------------------------------------------- 6. late failures


def test_outputs_are_checked_before_the_bus_is_opened(tmp_path: Path) -> None:
    missing = tmp_path / "no" / "such" / "dir" / "out.yaml"
    arm = FIXTURES / "ax12_arm.yaml"
    for args in (
        ["limits", "--port", "/nonexistent", "--arm", str(arm), "--mode", "auto", "--yes", "-o", str(missing)],
        [
            "servo-lut",
            "measure",
            "--port",
            "/nonexistent",
            "--id",
            "1",
            "--reference",
            "encoder:/nonexistent2",
            "--min",
            "420",
            "--max",
            "620",
            "--yes",
            "-o",
            str(missing),
        ],
    ):
        code, _, err = run(*args)
        assert code == 2 and "does not exist" in err and "/nonexistent" not in err.split("(for")[0], err
    code, _, err = run("limits", "--port", "/nonexistent", "--arm", str(arm), "--mode", "auto", "--yes", "-o", str(arm))
    assert code == 2 and "is also an input" in err


def test_failed_final_write_keeps_the_readings(sim: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import armtool.servo.lut.csv_format as csv_format

    out = tmp_path / "m.csv"
    real = csv_format.write_atomic

    def failing(path: Path, text: str) -> None:
        if path == out:
            raise ArmtoolError("cannot write: disk full", str(path))
        real(path, text)

    monkeypatch.setattr(csv_format, "write_atomic", failing)
    code, _, err = run(
        *measure_args(sim, "--min", "300", "--max", "700", "--points", "5", "--reads", "1", "-o", str(out))
    )
    assert code == 2 and "the readings were saved to" in err, err
    partial = tmp_path / "m.csv.partial"
    assert partial.exists() and partial.read_text().count("\n") > 5
    assert sim.peek(1, "torque_enable") == 0


# ---------------------------------------------------------------- property-based

NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**30), 10**30),
    st.sampled_from(["nan", "inf", "-inf", "1e308", "1e-300", "0", "-0", "abc", ""]),
)


def _ok_codes(code: int, err: str) -> None:
    assert code in (0, 1, 2, 130, 143), err
    assert "Traceback" not in err and "internal error" not in err


@HYPO
@given(step=NUMBERS, holdout=NUMBERS, tol=NUMBERS, seed=st.integers(-(10**20), 10**20))
def test_fit_options(tmp_path_factory: pytest.TempPathFactory, step: Any, holdout: Any, tol: Any, seed: int) -> None:
    before = snapshot(MEAS)
    start = time.monotonic()
    code, out, err = run(
        "servo-lut",
        "fit",
        str(MEAS),
        "--grid-step",
        str(step),
        "--holdout",
        str(holdout),
        "--monotone-tol",
        str(tol),
        "--seed",
        str(seed),
    )
    _ok_codes(code, err)
    if code == 0:
        doc = json.loads(out)
        assert all(isinstance(v, int) and 0 <= v <= 1023 for v in doc["grid"]["command_ticks"])
    assert snapshot(MEAS) == before and time.monotonic() - start < 10


@HYPO
@given(step=NUMBERS, fmt=st.sampled_from(["c", "csv", "json", "yaml"]), name=st.text(max_size=80))
def test_export_options(table: Path, step: Any, fmt: str, name: str) -> None:
    before = snapshot(table)
    start = time.monotonic()
    code, out, err = run("servo-lut", "export", str(table), "--step", str(step), "--format", fmt, "--name", name or "x")
    _ok_codes(code, err)
    if code == 0 and fmt == "json":
        json.loads(out)
    if code == 0 and fmt == "c":
        assert out.count("*/") == out.count("/*")
    assert snapshot(table) == before and time.monotonic() - start < 10


@HYPO
@given(
    angles=st.lists(NUMBERS, min_size=1, max_size=5),
    zero=st.one_of(st.none(), NUMBERS),
    direction=st.sampled_from(["1", "-1", "0", "2"]),
    clip=st.booleans(),
)
def test_apply_options(table: Path, angles: list[Any], zero: Any, direction: str, clip: bool) -> None:
    args = ["servo-lut", "apply", str(table), "--angles", ",".join(map(str, angles)), "--direction", direction]
    if zero is not None:
        args += ["--zero-deg", str(zero)]
    code, _out, err = run(*args, *(["--clip"] if clip else []))
    _ok_codes(code, err)


@settings(max_examples=12, deadline=None)
@given(values=st.lists(NUMBERS, min_size=7, max_size=7), ids=st.text(alphabet="0123456789-,", max_size=12))
def test_limits_options(tmp_path_factory: pytest.TempPathFactory, values: list[Any], ids: str) -> None:
    """Whatever the numbers, the command ends with a message (here: at the missing port at the latest)."""
    flags = ["--margin", "--rate", "--torque-limit", "--speed", "--stall-window", "--back-off", "--timeout-ms"]
    args = [a for flag, v in zip(flags, values) for a in (flag, str(v))]
    start = time.monotonic()
    code, _, err = run("limits", "--port", "/nonexistent/port", "--ids", ids or "1", "--mode", "auto", "--yes", *args)
    _ok_codes(code, err)
    assert code == 2 and time.monotonic() - start < 5


@settings(max_examples=12, deadline=None)
@given(values=st.lists(NUMBERS, min_size=8, max_size=8))
def test_measure_options(values: list[Any]) -> None:
    flags = ["--min", "--max", "--points", "--backoff", "--speed", "--torque-limit", "--dwell", "--baud"]
    args = [a for flag, v in zip(flags, values) for a in (flag, str(v))]
    start = time.monotonic()
    code, _, err = run(
        "servo-lut",
        "measure",
        "--port",
        "/nonexistent/port",
        "--id",
        "1",
        "--reference",
        "encoder:/nonexistent/enc",
        "--yes",
        *args,
    )
    _ok_codes(code, err)
    assert code == 2 and time.monotonic() - start < 5


@HYPO
@given(
    lo=st.integers(-5000, 5000),
    width=st.integers(-10, 5000),
    margin=st.floats(allow_nan=True, allow_infinity=True),
    zero=st.one_of(st.none(), st.integers(-5000, 5000)),
    direction=st.sampled_from([1, -1]),
    model=st.sampled_from(["AX-12A", "XL430-W250", "STS3215"]),
)
def test_limits_convert(lo: int, width: int, margin: float, zero: int | None, direction: int, model: str) -> None:
    from armtool.cli.options import check_float
    from armtool.servo.limits import Joint, JointRange, convert
    from armtool.servo.models import by_name

    try:
        margin = check_float(margin, "--margin", 0, 90)
    except ArmtoolError:
        return
    m = by_name(model)
    r = JointRange(Joint("j", 1, m, zero, direction), m, lo, lo + width, "manual")
    try:
        row = convert(r, margin)
    except ArmtoolError:
        return
    assert row["raw_min_ticks"] <= row["safe_min_ticks"] < row["safe_max_ticks"] <= row["raw_max_ticks"]
    assert math.isfinite(row["lower_rad"]) and row["lower_rad"] <= row["upper_rad"]


@HYPO
@given(text=st.text(alphabet="0123456789-, x", max_size=40))
def test_parse_ids(text: str) -> None:
    from armtool.servo.limits import parse_ids

    try:
        ids = parse_ids(text)
    except ArmtoolError:
        return
    assert ids and len(set(ids)) == len(ids) and all(0 <= i <= 252 for i in ids)


JSON_VALUES = st.recursive(
    st.one_of(
        st.none(),
        st.booleans(),
        st.integers(-(10**6), 10**6),
        st.floats(allow_nan=False, allow_infinity=False),
        st.text(max_size=20),
    ),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)),
    max_leaves=10,
)


def _paths(doc: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    out = [prefix] if prefix else []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:6]):
            out += _paths(v, prefix + (i,))
    return out


YAML_VALUES = st.one_of(JSON_VALUES, st.floats(), st.sampled_from([".nan", "1e400", -1, 10**12]))


def _mutate(doc: Any, data: st.DataObject, values: st.SearchStrategy[Any] = JSON_VALUES) -> Any:
    doc = copy.deepcopy(doc)
    paths = _paths(doc)
    for _ in range(data.draw(st.integers(1, 3))):
        path = data.draw(st.sampled_from(paths))
        try:
            parent = doc
            for key in path[:-1]:  # an earlier mutation may have removed or replaced the way there
                parent = parent[key]
            if data.draw(st.booleans()) and isinstance(parent, dict):
                del parent[path[-1]]
            else:
                parent[path[-1]] = data.draw(values)
        except (KeyError, IndexError, TypeError):
            pass
    return doc


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_mutated_tables(table: Path, tmp_path_factory: pytest.TempPathFactory, data: st.DataObject) -> None:
    doc = _mutate(json.loads(table.read_text()), data)
    path = tmp_path_factory.mktemp("mut") / "t.json"
    path.write_text(json.dumps(doc))
    before = snapshot(path)
    for args in (
        ["export", str(path), "--format", "c"],
        ["export", str(path), "--format", "json"],
        ["apply", str(path), "--angles", "100,150,200"],
    ):
        code, out, err = run("servo-lut", *args)
        _ok_codes(code, err)
        if code == 0 and "json" in args:
            json.loads(out)
        if code == 0 and "c" in args:
            assert out.count("*/") == out.count("/*") and "nan" not in out.lower()
    assert snapshot(path) == before


@HYPO
@given(data=st.data())
def test_mutated_sim_configs(data: st.DataObject) -> None:
    from armtool.servo.sim.config import sim_config_from_dict

    doc = yaml.safe_load((FIXTURES / "ax12_arm.yaml").read_text())
    doc.update({"faults": {"p_drop": 0.0, "delay_s": 0.0}, "person": {"speed_deg_s": 90, "dwell_s": 0.5}})
    try:
        cfg = sim_config_from_dict(_mutate(doc, data, YAML_VALUES), "sim.yaml")
    except ArmtoolError:
        return
    assert cfg.servos and (cfg.person is None or cfg.person.speed_deg_s > 0)
    assert cfg.return_delay is None or 0 <= cfg.return_delay <= 254
    assert all(math.isfinite(s.stop_lo_deg) and s.stop_lo_deg < s.stop_hi_deg for s in cfg.servos)


@HYPO
@given(data=st.data())
def test_mutated_limits_and_arm_files(tmp_path_factory: pytest.TempPathFactory, data: st.DataObject) -> None:
    from armtool.servo.limits import load_arm
    from armtool.servo.lut.measure import read_limits

    limits = {
        "schema": "armtool.limits/1",
        "joints": [{"id": 1, "model": "AX-12A", "safe_min_ticks": 100, "safe_max_ticks": 900}],
    }
    folder = tmp_path_factory.mktemp("yaml")
    lim, arm = folder / "limits.yaml", folder / "arm.yaml"
    lim.write_text(yaml.safe_dump(_mutate(limits, data, YAML_VALUES)))
    arm.write_text(yaml.safe_dump(_mutate(yaml.safe_load((FIXTURES / "ax12_arm.yaml").read_text()), data, YAML_VALUES)))
    try:
        lo, hi, _ = read_limits(lim, 1)
        assert 0 <= lo < hi <= 4095
    except ArmtoolError:
        pass
    try:
        load_arm(arm)
    except ArmtoolError:
        pass
