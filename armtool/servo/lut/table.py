"""Compensation tables: the inverse map wanted angle -> command, fitted from measurements.

Why the inverse map: firmware knows the angle it wants and needs the command that produces
it. Why PCHIP by default: it passes through the measured knots, cannot overshoot between
them and stays monotone when the data are (research/servo.md 4); a linear interpolant is the
same idea with kinks, a polynomial is compact but can wiggle at the ends, where an AX-12A's
potentiometer is least linear, so it is refused when it is not monotone over the range.

Fit errors are in degrees: the command error (fractional ticks, before rounding) times the
measured local slope (degrees per tick) at that point. "nominal" is the datasheet map
(`ServoModel.deg_per_tick`: AX 300/1023, X and STS 360/4096), "lut" the table. A servo takes
whole ticks, so up to half a tick (0.15° on an AX-12A) comes on top of both; `servo-lut check`
measures that too.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from armtool.errors import ArmtoolError
from armtool.servo.lut.choices import Approach, Method
from armtool.servo.lut.csv_format import Measurements, Sample, model_named
from armtool.servo.models import ServoModel
from armtool.servo.summary import Summary

SCHEMA_VERSION = 1
KIND = "armtool-servo-lut"
MIN_POINTS = 4  # distinct commands a table needs (after averaging repeats)
MAX_GRID = 65536  # entries of a uniform grid: the most a 16-bit index addresses (and 128 KiB of uint16)
MAX_KNOTS = 65536  # knots a table read from disk may have (a fit has one per measured command)
MAX_DEGREE = 9  # highest polynomial degree (`servo-lut fit --degree`)


@dataclass(frozen=True)
class Point:
    """One commanded position after averaging its readings."""

    command_ticks: float
    angle_deg: float
    n: int
    std_deg: float  # spread of the readings (0 for one reading)
    lines: tuple[int, ...]


@dataclass(frozen=True)
class ErrorStats:
    rms_deg: float
    max_deg: float
    n: int

    @staticmethod
    def of(errors: NDArray[np.float64]) -> ErrorStats:
        if errors.size == 0:
            return ErrorStats(float("nan"), float("nan"), 0)
        return ErrorStats(float(np.sqrt(np.mean(errors**2))), float(np.max(np.abs(errors))), int(errors.size))

    def cell(self) -> str:
        """`rms / max` in degrees for a report table, `-` when there were no points."""
        return "-" if self.n == 0 else f"{self.rms_deg:.3f} / {self.max_deg:.3f}"


@dataclass(frozen=True)
class FitReport:
    """What the fit saw and how well the table does on the points it did and did not use."""

    samples: int
    points: int
    train: int
    holdout: int
    pooled: int  # points merged by the monotone (isotonic) pass
    monotone_tol_deg: float
    train_nominal: ErrorStats
    train_lut: ErrorStats
    holdout_nominal: ErrorStats
    holdout_lut: ErrorStats
    nominal_max_deg: float  # largest |reference - datasheet map| over all points
    nonlinearity_deg: float  # largest deviation from the best straight line through all points
    line_deg_per_tick: float  # slope of that line (the datasheet's is ServoModel.deg_per_tick)
    hysteresis_max_deg: float | None  # largest |up - down| where both were measured
    holdout_commands: tuple[float, ...] = ()

    def summary(self, table: LutTable) -> Summary:
        """Before/after errors on the train and held-out points, and what the raw data showed."""
        model, (lo, hi) = table.model, table.valid_range_deg
        hyst = "" if self.hysteresis_max_deg is None else f", hysteresis up/down up to {self.hysteresis_max_deg:.2f}°"
        notes = [
            f"raw data: {self.samples} readings at {self.points} commands, off the datasheet map by up to "
            f"{self.nominal_max_deg:.2f}°, non-linearity (deviation from the best straight line) "
            f"{self.nonlinearity_deg:.2f}°, slope {self.line_deg_per_tick:.4f}°/tick "
            f"(datasheet {model.deg_per_tick:.4f}){hyst}"
        ]
        if self.pooled:
            notes.append(
                f"{self.pooled} point(s) pooled with a neighbour: readings stepped back by less than "
                f"{self.monotone_tol_deg:.3f}° (noise)"
            )
        return Summary(
            f"servo-lut fit: {model.name}, method {table.method.value}, approach {table.approach}, {lo:.2f}..{hi:.2f}°",
            ("points", "n", "nominal map RMS / max (°)", "with table RMS / max (°)"),
            [
                ("train (knots)", str(self.train), self.train_nominal.cell(), self.train_lut.cell()),
                ("held out", str(self.holdout), self.holdout_nominal.cell(), self.holdout_lut.cell()),
            ],
            left=("points",),
            notes=notes,
        )


@dataclass(frozen=True)
class Grid:
    """The table sampled on a uniform angle grid, as firmware stores it."""

    start_deg: float
    step_deg: float
    command_ticks: tuple[int, ...]

    @property
    def angles_deg(self) -> NDArray[np.floating[Any]]:  # float64; numpy's stubs widen float * int array
        return self.start_deg + self.step_deg * np.arange(len(self.command_ticks))


@dataclass(frozen=True)
class LutTable:
    model: ServoModel
    method: Method
    knots_deg: tuple[float, ...]
    knots_ticks: tuple[float, ...]
    servo_id: int | None = None
    reference: str = "unknown"
    approach: str = "up"
    poly_degree: int | None = None
    poly_domain: tuple[float, float] | None = None
    poly_coef: tuple[float, ...] | None = None
    report: FitReport | None = None
    source: dict[str, Any] = field(default_factory=dict)
    fit_summary: dict[str, Any] | None = None  # the "fit" block of a table read back from JSON

    @property
    def valid_range_deg(self) -> tuple[float, float]:
        return (self.knots_deg[0], self.knots_deg[-1])

    def command(self, angles_deg: NDArray[np.float64] | Sequence[float]) -> NDArray[np.float64]:
        """Command (fractional ticks) for each wanted angle; NaN outside the valid range."""
        x = np.asarray(angles_deg, dtype=np.float64)
        y = _evaluate(
            self.method, np.asarray(self.knots_deg), np.asarray(self.knots_ticks), x, self.poly_domain, self.poly_coef
        )
        lo, hi = self.valid_range_deg
        return np.where((x >= lo - 1e-9) & (x <= hi + 1e-9), y, np.nan)

    def command_ticks(self, angles_deg: NDArray[np.float64] | Sequence[float]) -> NDArray[np.int64]:
        """Whole-tick commands, clipped to the model's range; refuses angles outside the table."""
        x = np.asarray(angles_deg, dtype=np.float64)
        y = self.command(x)
        bad = np.flatnonzero(~np.isfinite(y))
        if bad.size:
            lo, hi = self.valid_range_deg
            raise ArmtoolError(
                f"angle {x[bad[0]]:g}° is outside the table's range {lo:.2f}..{hi:.2f}°",
                f"value {bad[0] + 1}",
                hint="measure a wider range, or pass --clip to clamp to the range",
            )
        return np.clip(np.rint(y), 0, self.model.max_tick).astype(np.int64)

    def grid(self, step_deg: float, flag: str = "grid step") -> Grid:
        """The table on the angles start, start+step, ... inside the valid range (start a multiple
        of step). `flag` names the option the step came from in messages."""
        if not (math.isfinite(step_deg) and step_deg > 0):
            raise ArmtoolError(f"{flag} must be a finite number of degrees > 0, got {step_deg:g}")
        lo, hi = self.valid_range_deg
        span = (hi - lo) / step_deg  # a subnormal step makes this inf: refuse before ceil() overflows
        if not math.isfinite(span) or span > MAX_GRID:
            raise ArmtoolError(
                f"{flag} {step_deg:g}° gives more than {MAX_GRID} entries over {lo:.2f}..{hi:.2f}°",
                hint=f"use a step of at least {(hi - lo) / (MAX_GRID - 2):.4g}°",
            )
        first, last = math.ceil(lo / step_deg - 1e-9), math.floor(hi / step_deg + 1e-9)
        if last < first:
            raise ArmtoolError(f"{flag} {step_deg:g}° is wider than the table's range {lo:.2f}..{hi:.2f}°")
        if last - first + 1 > MAX_GRID:  # checked before any array is made
            raise ArmtoolError(
                f"{flag} {step_deg:g}° gives {last - first + 1} entries over {lo:.2f}..{hi:.2f}°, more than {MAX_GRID}",
                hint=f"use a step of at least {(hi - lo) / (MAX_GRID - 2):.4g}°",
            )
        angles = np.round(np.arange(first, last + 1) * step_deg, 9)
        ticks = self.command(np.clip(angles, lo, hi))
        if not np.all(np.isfinite(ticks)):
            raise ArmtoolError(
                "the table gives no finite command on its grid", hint="rebuild it with `armtool servo-lut fit`"
            )
        clipped = np.clip(np.rint(ticks), 0, self.model.max_tick).astype(int)
        return Grid(float(angles[0]), float(step_deg), tuple(int(t) for t in clipped))

    def to_dict(self, grid_step_deg: float | None = 1.0, flag: str = "grid step") -> dict[str, Any]:
        doc: dict[str, Any] = {
            "schema_version": SCHEMA_VERSION,
            "kind": KIND,
            "servo": {
                "id": self.servo_id,
                "model": self.model.name,
                "model_number": self.model.model_number,
                "max_tick": self.model.max_tick,
                "deg_per_tick": self.model.deg_per_tick,
            },
            "reference": self.reference,
            "approach": self.approach,
            "method": self.method.value,
            "valid_range_deg": list(self.valid_range_deg),
            "knots": {"angle_deg": list(self.knots_deg), "command_ticks": list(self.knots_ticks)},
            "poly": None
            if self.poly_coef is None
            else {
                "degree": self.poly_degree,
                "domain_deg": list(self.poly_domain or ()),
                "coef": list(self.poly_coef),
                "note": "numpy.polynomial.Polynomial(coef, domain=domain_deg, window=[-1, 1])",
            },
        }
        if grid_step_deg is not None:
            g = self.grid(grid_step_deg, flag)
            doc["grid"] = {"start_deg": g.start_deg, "step_deg": g.step_deg, "command_ticks": list(g.command_ticks)}
        if self.report is not None:
            doc["fit"] = _jsonable(asdict(self.report))
        elif self.fit_summary is not None:
            doc["fit"] = self.fit_summary
        doc["source"] = self.source
        from armtool import __version__

        doc["created_by"] = f"armtool {__version__}"
        return doc


def _jsonable(value: Any) -> Any:
    if isinstance(value, float):
        return None if not math.isfinite(value) else round(value, 6)
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value


def _evaluate(
    method: Method,
    kx: NDArray[np.float64],
    ky: NDArray[np.float64],
    x: NDArray[np.float64],
    domain: tuple[float, float] | None,
    coef: tuple[float, ...] | None,
) -> NDArray[np.float64]:
    if method is Method.PCHIP:
        from scipy.interpolate import PchipInterpolator

        return np.asarray(PchipInterpolator(kx, ky, extrapolate=True)(x), dtype=np.float64)
    if method is Method.LINEAR:
        return np.asarray(np.interp(x, kx, ky), dtype=np.float64)
    assert domain is not None and coef is not None
    poly = np.polynomial.Polynomial(coef, domain=domain, window=[-1.0, 1.0])
    return np.asarray(poly(x), dtype=np.float64)


# --------------------------------------------------------------------------------------------
# averaging and the monotone pass


def average_points(meas: Measurements, approach: Approach | None) -> tuple[list[Point], str, float | None]:
    """Readings averaged per command for the chosen approach; also the approach used and the
    largest up/down difference (hysteresis) where both were measured."""
    by: dict[str, dict[int, list[Sample]]] = {"up": {}, "down": {}}
    for s in meas.samples:
        by[s.approach].setdefault(s.command_ticks, []).append(s)
    present = [a for a in ("up", "down") if by[a]]
    hysteresis = None
    common = sorted(set(by["up"]) & set(by["down"]))
    if common:
        diffs = [
            abs(np.mean([s.reference_deg for s in by["up"][c]]) - np.mean([s.reference_deg for s in by["down"][c]]))
            for c in common
        ]
        hysteresis = float(max(diffs))
    if approach is None:
        used = present[0] if len(present) == 1 else "mean"
    else:
        used = approach.value
        if used != "mean" and not by[used]:
            raise ArmtoolError(
                f"no readings approached '{used}'",
                meas.source,
                hint=f"the file has: {', '.join(present)}; pass --approach {present[0]}",
            )
    sides = present if used == "mean" else [used]
    points = []
    for command in sorted(set().union(*(by[a].keys() for a in sides))):
        groups = [by[a][command] for a in sides if command in by[a]]
        means = [float(np.mean([s.reference_deg for s in g])) for g in groups]
        readings = [s.reference_deg for g in groups for s in g]
        points.append(
            Point(
                float(command),
                float(np.mean(means)),
                len(readings),
                float(np.std(readings, ddof=1)) if len(readings) > 1 else 0.0,
                tuple(sorted(s.line for g in groups for s in g)),
            )
        )
    return points, used, hysteresis


def default_monotone_tol(points: Sequence[Point], model: ServoModel) -> float:
    """How far a reading may step backwards and still count as noise: one tick, or four standard
    errors of a point's mean when the repeats say the reference is noisier than that."""
    spread = [p.std_deg**2 / p.n for p in points if p.n > 1]
    sem = math.sqrt(float(np.mean(spread))) if spread else 0.0
    return max(model.deg_per_tick, 4.0 * sem)


def make_monotone(points: list[Point], tol_deg: float, source: str) -> tuple[list[Point], int]:
    """Strictly increasing angles: backward steps within `tol_deg` are pooled (isotonic
    regression, weighted by readings), larger ones are refused with their rows."""
    bad = [(a, b) for a, b in zip(points, points[1:]) if a.angle_deg - b.angle_deg > tol_deg]
    if bad:
        shown = "; ".join(
            f"command {a.command_ticks:g} -> {a.angle_deg:.3f}° (line {a.lines[0]}) then "
            f"{b.command_ticks:g} -> {b.angle_deg:.3f}° (line {b.lines[0]})"
            for a, b in bad[:5]
        )
        more = f" and {len(bad) - 5} more" if len(bad) > 5 else ""
        lines = ", ".join(str(n) for a, b in bad[:5] for n in (a.lines[0], b.lines[0]))
        raise ArmtoolError(
            f"the reference angle goes down while the command goes up: {shown}{more}",
            f"{source}: lines {lines}",
            hint=f"steps back by more than {tol_deg:.3f}° are not noise: check the reference's "
            "direction and zero, re-measure those points, or raise --monotone-tol",
        )
    blocks: list[list[Point]] = []
    values: list[float] = []
    weights: list[float] = []
    for p in points:  # pool adjacent violators
        blocks.append([p])
        values.append(p.angle_deg)
        weights.append(float(p.n))
        while len(values) > 1 and values[-2] >= values[-1]:
            w = weights[-2] + weights[-1]
            values[-2] = (values[-2] * weights[-2] + values[-1] * weights[-1]) / w
            weights[-2] = w
            blocks[-2].extend(blocks[-1])
            del values[-1], weights[-1], blocks[-1]
    out = []
    for block, value in zip(blocks, values):
        n = sum(p.n for p in block)
        command = sum(p.command_ticks * p.n for p in block) / n
        spread = max(p.std_deg for p in block)
        out.append(Point(float(command), float(value), n, spread, tuple(sorted(x for p in block for x in p.lines))))
    return out, len(points) - len(out)


# --------------------------------------------------------------------------------------------
# the fit


def _holdout_indices(n: int, fraction: float, min_train: int, seed: int, source: str) -> NDArray[np.int64]:
    if not 0 <= fraction < 1:
        raise ArmtoolError(f"--holdout must be in [0, 1), got {fraction:g}", hint="e.g. --holdout 0.2")
    if fraction == 0:
        return np.zeros(0, dtype=np.int64)
    k = max(1, round(fraction * n))
    k = min(k, n - min_train, n - 2)  # the two ends stay in: a table does not extrapolate
    if k < 1:
        raise ArmtoolError(
            f"too few points to hold any out: {n} distinct commands, need at least {min_train + 1}",
            source,
            hint="measure more points, or pass --holdout 0",
        )
    rng = np.random.default_rng(seed)
    return np.sort(rng.choice(np.arange(1, n - 1), size=k, replace=False))


def _fit_knots(
    method: Method, x: NDArray[np.float64], y: NDArray[np.float64], degree: int, source: str
) -> tuple[tuple[float, float] | None, tuple[float, ...] | None]:
    if method is not Method.POLY:
        return None, None
    poly = np.polynomial.Polynomial.fit(x, y, degree)
    dense = np.linspace(x[0], x[-1], 2001)
    slope = poly.deriv()(dense)
    if np.any(slope <= 0):
        where = dense[int(np.argmax(slope <= 0))]
        raise ArmtoolError(
            f"the degree-{degree} polynomial is not increasing near {where:.1f}°: it would command "
            "the same position for two angles",
            source,
            hint="use --method pchip, or a lower degree",
        )
    dom = (float(poly.domain[0]), float(poly.domain[1]))
    return dom, tuple(float(c) for c in poly.coef)


def fit_table(
    meas: Measurements,
    method: Method = Method.PCHIP,
    degree: int = 3,
    holdout: float = 0.2,
    seed: int = 0,
    approach: Approach | None = None,
    monotone_tol_deg: float | None = None,
) -> LutTable:
    """Average repeats, make the data monotone (or refuse), hold out points, fit the inverse map."""
    model = meas.model
    raw, used, hysteresis = average_points(meas, approach)
    min_train = max(MIN_POINTS, degree + 2) if method is Method.POLY else MIN_POINTS
    if len(raw) < MIN_POINTS:
        raise ArmtoolError(
            f"too few points: {len(raw)} distinct command{'s' if len(raw) != 1 else ''} "
            f"(approach {used}), a table needs at least {MIN_POINTS}",
            meas.source,
            hint="measure more points (armtool servo-lut measure --points 32)",
        )
    tol = default_monotone_tol(raw, model) if monotone_tol_deg is None else monotone_tol_deg
    points, pooled = make_monotone(raw, tol, meas.source)
    if len(points) < min_train:
        raise ArmtoolError(
            f"too few distinct points after pooling readings that go backwards: {len(points)}, need {min_train}",
            meas.source,
            hint="measure more points over a wider range",
        )
    c = np.array([p.command_ticks for p in points])
    a = np.array([p.angle_deg for p in points])
    held = _holdout_indices(len(points), holdout, min_train, seed, meas.source)
    train = np.setdiff1d(np.arange(len(points)), held)
    domain, coef = _fit_knots(method, a[train], c[train], degree, meas.source)
    samples = meas.samples
    temps = [s.temperature_c for s in samples if s.temperature_c is not None]
    volts = [s.voltage_v for s in samples if s.voltage_v is not None]
    source: dict[str, Any] = {
        "file": Path(meas.source).name,
        "samples": len(samples),
        "temperature_c": [min(temps), max(temps)] if temps else None,
        "voltage_v": [min(volts), max(volts)] if volts else None,
    }
    table = LutTable(
        model=model,
        method=method,
        knots_deg=tuple(float(v) for v in a[train]),
        knots_ticks=tuple(float(v) for v in c[train]),
        servo_id=meas.servo_id,
        reference=meas.reference,
        approach=used,
        poly_degree=degree if method is Method.POLY else None,
        poly_domain=domain,
        poly_coef=coef,
        source=source,
    )
    slope = np.gradient(a, c) if len(c) > 1 else np.full(1, model.deg_per_tick)

    def errors(idx: NDArray[np.int64], commands: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray((commands[idx] - c[idx]) * slope[idx], dtype=np.float64)

    nominal_cmd = np.clip(a / model.deg_per_tick, 0, model.max_tick)
    lut_cmd = np.clip(table.command(np.clip(a, *table.valid_range_deg)), 0, model.max_tick)
    gain, offset = np.polyfit(c, a, 1)
    report = FitReport(
        samples=len(samples),
        points=len(points),
        train=int(train.size),
        holdout=int(held.size),
        pooled=pooled,
        monotone_tol_deg=float(tol),
        train_nominal=ErrorStats.of(errors(train, nominal_cmd)),
        train_lut=ErrorStats.of(errors(train, lut_cmd)),
        holdout_nominal=ErrorStats.of(errors(held, nominal_cmd)),
        holdout_lut=ErrorStats.of(errors(held, lut_cmd)),
        nominal_max_deg=float(np.max(np.abs(a - c * model.deg_per_tick))),
        nonlinearity_deg=float(np.max(np.abs(a - (gain * c + offset)))),
        line_deg_per_tick=float(gain),
        hysteresis_max_deg=hysteresis,
        holdout_commands=tuple(float(v) for v in c[held]),
    )
    return replace(table, report=report)


# --------------------------------------------------------------------------------------------
# reading a table back


def table_from_dict(doc: Any, source: str) -> LutTable:
    """A table from its JSON document, with every field checked and named when wrong."""
    if not isinstance(doc, dict):
        raise ArmtoolError("not a servo-lut table (expected a JSON object)", source)
    if doc.get("kind") != KIND:
        raise ArmtoolError(
            f"not a servo-lut table (kind is {doc.get('kind')!r})",
            source,
            hint="make one with `armtool servo-lut fit meas.csv -o lut.json`",
        )
    if doc.get("schema_version") != SCHEMA_VERSION:
        raise ArmtoolError(
            f"schema_version {doc.get('schema_version')!r} is not supported (this armtool reads {SCHEMA_VERSION})",
            f"{source}: schema_version",
        )

    def need(obj: Any, key: str, path: str) -> Any:
        if not isinstance(obj, dict) or key not in obj:
            raise ArmtoolError(f"missing field '{path}'", source)
        return obj[key]

    servo = need(doc, "servo", "servo")
    model = model_named(str(need(servo, "model", "servo.model")), f"{source}: servo.model")
    try:
        method = Method(need(doc, "method", "method"))
    except ValueError:
        raise ArmtoolError(
            f"unknown method {doc['method']!r}",
            f"{source}: method",
            hint="one of: " + ", ".join(m.value for m in Method),
        ) from None
    knots = need(doc, "knots", "knots")
    try:
        kx = [float(v) for v in need(knots, "angle_deg", "knots.angle_deg")]
        ky = [float(v) for v in need(knots, "command_ticks", "knots.command_ticks")]
    except (TypeError, ValueError):
        raise ArmtoolError("knots must be lists of numbers", f"{source}: knots") from None
    if len(kx) != len(ky) or not 2 <= len(kx) <= MAX_KNOTS or not all(math.isfinite(v) for v in kx + ky):
        raise ArmtoolError(
            f"knots.angle_deg and knots.command_ticks must be equally long finite lists (2..{MAX_KNOTS})",
            f"{source}: knots",
        )
    outside = [v for v in ky if not 0 <= v <= model.max_tick]
    if outside:
        raise ArmtoolError(
            f"knots.command_ticks has {outside[0]:g}, outside the {model.name}'s 0..{model.max_tick} ticks",
            f"{source}: knots.command_ticks",
            "rebuild the table with `armtool servo-lut fit`",
        )
    if any(abs(v) > 3 * model.range_deg for v in kx):
        raise ArmtoolError(
            f"knots.angle_deg is far outside the {model.name}'s {model.range_deg:g}° range",
            f"{source}: knots.angle_deg",
            "angles are servo degrees (0 at tick 0)",
        )
    if any(b <= a for a, b in zip(kx, kx[1:])):
        raise ArmtoolError("knots.angle_deg is not strictly increasing", f"{source}: knots.angle_deg")
    if any(b <= a for a, b in zip(ky, ky[1:])):
        raise ArmtoolError(
            "knots.command_ticks is not strictly increasing: the table would invert commands",
            f"{source}: knots.command_ticks",
            "rebuild the table with `armtool servo-lut fit`",
        )
    domain = coef = None
    degree = None
    if method is Method.POLY:
        poly = need(doc, "poly", "poly")
        try:
            dom = [float(v) for v in need(poly, "domain_deg", "poly.domain_deg")]
            coef = tuple(float(v) for v in need(poly, "coef", "poly.coef"))
            raw_degree = need(poly, "degree", "poly.degree")
            if isinstance(raw_degree, bool) or not isinstance(raw_degree, int):
                raise TypeError
            degree = raw_degree
        except (TypeError, ValueError, OverflowError):
            raise ArmtoolError(
                "poly.domain_deg/coef must be numbers and poly.degree a whole number", f"{source}: poly"
            ) from None
        if len(dom) != 2 or not all(math.isfinite(v) for v in dom) or not dom[0] < dom[1]:
            raise ArmtoolError("poly.domain_deg must be two finite numbers, low < high", f"{source}: poly.domain_deg")
        if not 1 <= degree <= MAX_DEGREE or len(coef) != degree + 1 or not all(math.isfinite(c) for c in coef):
            raise ArmtoolError(
                f"poly.coef must be {degree + 1} finite numbers for degree {degree} (1..{MAX_DEGREE})",
                f"{source}: poly",
            )
        domain = (dom[0], dom[1])
        _check_poly_increasing(domain, coef, (kx[0], kx[-1]), model, source)
    sid = servo.get("id") if isinstance(servo, dict) else None
    if sid is not None and (isinstance(sid, bool) or not isinstance(sid, int) or not 0 <= sid <= 252):
        raise ArmtoolError(f"servo.id must be an ID 0..252 or null, got {sid!r}", f"{source}: servo.id")
    approach = doc.get("approach", "up")
    if approach not in [a.value for a in Approach]:
        raise ArmtoolError(
            f"approach must be one of {', '.join(a.value for a in Approach)}, got {approach!r}", f"{source}: approach"
        )
    reference = doc.get("reference", "unknown")
    if not isinstance(reference, str) or len(reference) > 1000:
        raise ArmtoolError("reference must be a short text", f"{source}: reference")
    return LutTable(
        model=model,
        method=method,
        knots_deg=tuple(kx),
        knots_ticks=tuple(ky),
        servo_id=sid,
        reference=reference,
        approach=str(approach),
        poly_degree=degree,
        poly_domain=domain,
        poly_coef=coef,
        # cast: JSON is untyped data; the isinstance on the same line checks it
        source=cast("dict[str, Any]", doc.get("source")) if isinstance(doc.get("source"), dict) else {},
        fit_summary=doc.get("fit") if isinstance(doc.get("fit"), dict) else None,
    )


def _check_poly_increasing(
    domain: tuple[float, float], coef: tuple[float, ...], span: tuple[float, float], model: ServoModel, source: str
) -> None:
    """A polynomial table must rise over its valid range and stay inside the servo's ticks, as a fitted one does."""
    poly = np.polynomial.Polynomial(coef, domain=domain, window=[-1.0, 1.0])
    dense = np.linspace(span[0], span[1], 2001)
    with np.errstate(all="ignore"):
        values, slope = poly(dense), poly.deriv()(dense)
    if not (np.all(np.isfinite(values)) and np.all(np.isfinite(slope))):
        raise ArmtoolError("the polynomial is not finite over the table's range", f"{source}: poly")
    if np.any(slope <= 0):
        where = dense[int(np.argmax(slope <= 0))]
        raise ArmtoolError(
            f"the polynomial is not increasing near {where:.1f}°: it would command the same position for two angles",
            f"{source}: poly",
            "rebuild the table with `armtool servo-lut fit`",
        )
    if values.min() < -0.5 or values.max() > model.max_tick + 0.5:
        raise ArmtoolError(
            f"the polynomial commands {values.min():.0f}..{values.max():.0f} ticks, outside the "
            f"{model.name}'s 0..{model.max_tick}",
            f"{source}: poly",
        )


def check_table_document(doc: dict[str, Any], source: str) -> LutTable:
    """A table document as it will be written: it must read back as a valid table, and every
    number in it must be finite (JSON has no NaN; a C header none either)."""
    bad = _non_finite(doc)
    if bad is not None:
        raise ArmtoolError(
            f"the table has a non-finite number at {bad}",
            source,
            hint="this is a bug if the options were valid: report it",
        )
    return table_from_dict(doc, source)


def table_json(table: LutTable, grid_step_deg: float) -> str:
    """The table document as `fit` writes it, checked to read back first (never a table that would not)."""
    doc = table.to_dict(grid_step_deg=grid_step_deg, flag="--grid-step")
    check_table_document(doc, "the fitted table")
    return json.dumps(doc, indent=2, allow_nan=False) + "\n"


def _non_finite(value: Any, path: str = "") -> str | None:
    if isinstance(value, float) and not math.isfinite(value):
        return path or "top level"
    if isinstance(value, dict):
        for k, v in value.items():
            found = _non_finite(v, f"{path}.{k}" if path else str(k))
            if found is not None:
                return found
    if isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            found = _non_finite(v, f"{path}[{i}]")
            if found is not None:
                return found
    return None


def read_table(path: Path) -> LutTable:
    from armtool.fileio import read_text

    if not path.exists():
        raise ArmtoolError(
            f"no such file: {path}", hint="make a table with `armtool servo-lut fit meas.csv -o lut.json`"
        )
    text = read_text(path, "table file")
    try:
        doc = json.loads(text, parse_constant=_refuse_constant)
    except json.JSONDecodeError as exc:
        raise ArmtoolError(f"not valid JSON: {exc.msg}", f"{path}:{exc.lineno}:{exc.colno}") from None
    except ValueError as exc:
        raise ArmtoolError(
            f"not valid JSON: {exc}", str(path), "JSON has no NaN or Infinity; rebuild the table"
        ) from None
    except RecursionError:
        raise ArmtoolError("JSON nested too deeply", str(path)) from None
    return table_from_dict(doc, str(path))


def _refuse_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a number JSON allows")


def nominal_command_ticks(model: ServoModel, angles_deg: NDArray[np.float64]) -> NDArray[np.int64]:
    """The datasheet map's command for each angle, whole ticks inside the model's range."""
    return np.clip(np.rint(np.asarray(angles_deg) / model.deg_per_tick), 0, model.max_tick).astype(np.int64)
