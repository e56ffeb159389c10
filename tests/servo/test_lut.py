"""Fitting a compensation table: averaging, the monotone pass, hold-out errors, round trips."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from armtool.errors import ArmtoolError
from armtool.servo.lut.csv_format import Measurements, Sample, parse_measurements, read_measurements
from armtool.servo.lut.table import Approach, Method, fit_table, read_table, table_from_dict
from armtool.servo.models import by_name as servo_model

FIXTURE = Path(__file__).resolve().parents[2] / "fixtures" / "servo" / "lut" / "ax12a_meas.csv"
AX = servo_model("AX-12A")


def curve_deg(ticks: np.ndarray) -> np.ndarray:
    """A smooth, monotone non-linear response: datasheet map plus up to 3° near the ends."""
    u = ticks / 1023.0
    return ticks * AX.deg_per_tick + 3.0 * np.sin(np.pi * (u - 0.5)) * (2 * np.abs(u - 0.5)) ** 2


def measurements(
    commands: np.ndarray, angles: np.ndarray, approach: str = "up", repeats: int = 1, start_line: int = 2
) -> Measurements:
    samples, line = [], start_line
    for c, row in zip(commands, np.atleast_2d(angles.T).T if repeats > 1 else angles[:, None]):
        for r, a in enumerate(np.atleast_1d(row)):
            samples.append(Sample(line, int(c), float(a), approach=approach, repeat=r))
            line += 1
    return Measurements(source="m.csv", model=AX, samples=tuple(samples))


def test_fixture_meets_the_acceptance_numbers() -> None:
    table = fit_table(read_measurements(FIXTURE))
    r = table.report
    assert r is not None and r.holdout == 10 and r.train == 41
    assert r.holdout_lut.max_deg <= r.holdout_nominal.max_deg / 3
    assert r.holdout_lut.rms_deg < 0.3
    assert r.nominal_max_deg > 2.5  # the fixture's model is ~3° off near the ends


@pytest.mark.parametrize("method", list(Method))
def test_every_method_beats_the_nominal_map(method: Method) -> None:
    c = np.arange(100, 925, 16)
    table = fit_table(measurements(c, curve_deg(c)), method, degree=5, holdout=0.25)
    r = table.report
    assert r is not None
    assert r.holdout_lut.rms_deg < r.holdout_nominal.rms_deg / 3
    grid = table.grid(0.5).command_ticks
    assert all(b >= a for a, b in zip(grid, grid[1:]))


def test_pchip_passes_through_its_knots_and_holdout_keeps_the_ends() -> None:
    c = np.arange(100, 925, 16)
    table = fit_table(measurements(c, curve_deg(c)), holdout=0.3, seed=4)
    assert table.command(table.knots_deg) == pytest.approx(table.knots_ticks, abs=1e-9)
    assert table.knots_ticks[0] == c[0] and table.knots_ticks[-1] == c[-1]
    assert table.report is not None and c[0] not in table.report.holdout_commands
    lo, hi = table.valid_range_deg
    assert np.isnan(table.command([lo - 1, hi + 1])).all()


def test_holdout_zero_uses_every_point() -> None:
    c = np.arange(100, 925, 64)
    table = fit_table(measurements(c, curve_deg(c)), holdout=0)
    assert table.report is not None and table.report.holdout == 0 and len(table.knots_deg) == len(c)


def test_repeats_are_averaged() -> None:
    c = np.arange(100, 400, 50)
    angles = np.stack([curve_deg(c) - 0.1, curve_deg(c) + 0.1], axis=1)
    table = fit_table(measurements(c, angles, repeats=2), holdout=0)
    assert table.knots_deg == pytest.approx(curve_deg(c))
    assert table.report is not None and table.report.samples == 2 * len(c)


def test_backward_step_beyond_noise_is_refused_with_rows() -> None:
    c = np.arange(100, 500, 50)
    a = curve_deg(c)
    a[4] -= 20.0  # a reading 20° too low: not noise
    with pytest.raises(ArmtoolError) as info:
        fit_table(measurements(c, a))
    exc = info.value
    assert "goes down while the command goes up" in exc.what and "command 250" in exc.what
    assert exc.where == "m.csv: lines 5, 6"


def test_small_backward_step_is_pooled() -> None:
    c = np.arange(100, 500, 4)
    a = curve_deg(c)
    a[10] = a[11] + 0.2  # steps back 0.2°, under one AX tick (0.29°): noise
    table = fit_table(measurements(c, a), holdout=0)
    assert table.report is not None and table.report.pooled == 1
    assert all(b > a for a, b in zip(table.knots_deg, table.knots_deg[1:]))


def test_too_few_points() -> None:
    c = np.array([100, 200, 300])
    with pytest.raises(ArmtoolError, match="too few points: 3 distinct commands"):
        fit_table(measurements(c, curve_deg(c)))
    c = np.array([100, 200, 300, 400])
    with pytest.raises(ArmtoolError, match="too few points to hold any out"):
        fit_table(measurements(c, curve_deg(c)), holdout=0.2)


def test_wiggly_polynomial_is_refused() -> None:
    c = np.array([100, 110, 120, 130, 600, 610, 620, 900, 910])
    a = np.array([30, 31, 32, 33, 34, 35, 36, 200, 201], dtype=float)  # a plateau then a jump
    with pytest.raises(ArmtoolError, match="polynomial is not increasing"):
        fit_table(measurements(c, a), Method.POLY, degree=5, holdout=0)


def test_approach_both_gives_mean_and_hysteresis() -> None:
    c = np.arange(100, 925, 32)
    up = measurements(c, curve_deg(c) - 0.5, "up")
    down = measurements(c, curve_deg(c) + 0.5, "down", start_line=100)
    both = Measurements("m.csv", AX, up.samples + down.samples)
    table = fit_table(both, holdout=0)
    assert table.approach == "mean" and table.report is not None
    assert table.report.hysteresis_max_deg == pytest.approx(1.0)
    assert table.knots_deg == pytest.approx(curve_deg(c))
    only_up = fit_table(both, holdout=0, approach=Approach.UP)
    assert only_up.approach == "up" and only_up.knots_deg == pytest.approx(curve_deg(c) - 0.5)
    with pytest.raises(ArmtoolError, match="no readings approached 'down'"):
        fit_table(up, approach=Approach.DOWN)


def test_json_round_trip(tmp_path: Path) -> None:
    c = np.arange(100, 925, 16)
    for method in Method:
        table = fit_table(measurements(c, curve_deg(c)), method)
        path = tmp_path / f"{method.value}.json"
        path.write_text(json.dumps(table.to_dict()))
        back = read_table(path)
        x = np.linspace(*table.valid_range_deg, 77)
        assert back.command(x) == pytest.approx(table.command(x), abs=1e-6)
        assert (back.model, back.method, back.approach) == (table.model, method, "up")
    doc = table.to_dict()
    assert doc["schema_version"] == 1 and doc["servo"]["model"] == "AX-12A"
    assert set(doc["fit"]) >= {"train_nominal", "holdout_lut", "nonlinearity_deg"}


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda d: d.update(kind="x"), "not a servo-lut table"),
        (lambda d: d.update(schema_version=9), "schema_version 9"),
        (lambda d: d["knots"].pop("angle_deg"), "missing field 'knots.angle_deg'"),
        (lambda d: d["knots"]["angle_deg"].reverse(), "not strictly increasing"),
        (lambda d: d["servo"].update(model="SG90"), "unknown servo model 'SG90'"),
        (lambda d: d.update(method="spline"), "unknown method 'spline'"),
    ],
)
def test_bad_table_is_refused_naming_the_field(change, message: str) -> None:  # type: ignore[no-untyped-def]
    c = np.arange(100, 925, 64)
    doc = fit_table(measurements(c, curve_deg(c)), holdout=0).to_dict()
    change(doc)
    with pytest.raises(ArmtoolError, match=message):
        table_from_dict(doc, "lut.json")


def test_read_table_errors(tmp_path: Path) -> None:
    with pytest.raises(ArmtoolError, match="no such file"):
        read_table(tmp_path / "nope.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{\n  'x': 1\n}")
    with pytest.raises(ArmtoolError) as info:
        read_table(bad)
    assert info.value.where == f"{bad}:2:3"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**32 - 1),
    step=st.integers(1, 24),
    repeats=st.integers(1, 5),
    noise_ticks=st.floats(0.0, 0.45),
    lo=st.integers(0, 300),
    points=st.integers(8, 60),
)
def test_noisy_repeated_measurements_give_a_monotone_table(
    seed: int, step: int, repeats: int, noise_ticks: float, lo: int, points: int
) -> None:
    """Readings with noise up to ±0.45 tick never step back further than one tick on average,
    so the fit must accept them, and its table must be monotone everywhere."""
    rng = np.random.default_rng(seed)
    c = lo + step * np.arange(points)
    c = c[c <= 1023]
    noise = rng.uniform(-1, 1, size=(len(c), repeats)) * noise_ticks * AX.deg_per_tick
    angles = curve_deg(c)[:, None] + noise
    meas = measurements(c, angles if repeats > 1 else angles[:, 0], repeats=repeats)
    table = fit_table(meas, holdout=0.2, seed=seed)
    assert all(b > a for a, b in zip(table.knots_deg, table.knots_deg[1:]))
    assert all(b >= a for a, b in zip(table.knots_ticks, table.knots_ticks[1:]))
    x = np.linspace(*table.valid_range_deg, 997)
    y = table.command(x)
    assert np.all(np.diff(y) >= -1e-9)
    grid = table.grid(0.25).command_ticks
    assert all(b >= a for a, b in zip(grid, grid[1:]))


def test_gaussian_noise_with_many_repeats_stays_monotone() -> None:
    """σ = 0.3° Gaussian reference noise (larger than a tick), 5 repeats, 8-tick steps."""
    rng = np.random.default_rng(1)
    c = np.arange(60, 964, 8)
    angles = curve_deg(c)[:, None] + rng.normal(0, 0.3, size=(len(c), 5))
    table = fit_table(measurements(c, angles, repeats=5))
    y = table.command(np.linspace(*table.valid_range_deg, 2000))
    assert np.all(np.diff(y) >= -1e-9)
    assert table.report is not None and table.report.holdout_lut.rms_deg < table.report.holdout_nominal.rms_deg / 3


def test_parse_then_fit_names_file_lines() -> None:
    text = "# servo_model: AX-12A\ncommand_ticks,reference_deg\n100,30\n200,60\n300,50\n400,120\n500,150\n"
    with pytest.raises(ArmtoolError) as info:
        fit_table(parse_measurements(text, "own.csv"))
    assert info.value.where == "own.csv: lines 4, 5"
