"""The figure of a calibration (`calibrate fit --plot FILE`, PNG, SVG or PDF): what the calibration
changed on every sample, on poses the fit used and on poses it never saw, and how well each fitted
parameter is determined.

- Per measured quantity (corner reprojection in px; or position in mm beside rotation in °), two
  panels on a log scale that stay readable at 1000 samples:
  - every sample, sorted by its hand-eye-only residual (the grey curve), with its calibrated
    residual as a dot: blue fitted, orange held out, a red cross for an outlier (named);
  - the distribution (CDF) of the same residuals: the fitted samples, the held-out ones, and with
    nested cross-validation every fitted sample as it was predicted when its fold was held out.
  A tracked point has no orientation: its rotation panel says so instead of being left out.
- The robot parameters of the fitted set, each value ± σ in mm, ° or %; the ones the data could
  not determine are marked, at the value that puts the flange nearest the nominal arm's.
- The title names the dataset and the headline RMS figures.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from armtool import plotting
from armtool.calib.fit.calibration import CalibrationResult
from armtool.calib.fit.problems import CORNER, POSITION, ROTATION, Block
from armtool.calib.model.params import Parameter, ParamKind
from armtool.calib.model.se3 import Array

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

UNIT_LABEL = {"px": "px", "mm": "mm", "deg": "°"}
_LABELLED_OUTLIERS = 8  # outliers named beside their marker, the largest first
_PARAMETERS_WIDTH = 5.6  # inches: names with their value ± σ


@dataclass(frozen=True)
class Residuals:
    """One block's per-sample residuals (in its unit) of the samples that had a measurement."""

    ids: list[str]
    before: Array  # hand-eye only (the nominal robot)
    after: Array  # calibrated
    cross_validated: Array  # calibrated, predicted while the sample's fold was held out (nan: none)
    held: NDArray[np.bool_]  # kept out of the fit (--holdout, --validation)
    outlier: NDArray[np.bool_]


def residuals(result: CalibrationResult, block: Block) -> Residuals:
    """`calibrate` lists the fitted samples first (`result.fit_samples` of them), then the held-out
    ones, then the rejected ones, which have no residual."""
    rows = [(k, r) for k, r in enumerate(result.residuals) if r.role != "rejected"]

    def values(pick: str) -> Array:
        return np.array([getattr(r, pick).get(block.name, math.nan) for _k, r in rows], dtype=np.float64)

    return Residuals(
        [r.sample_id for _k, r in rows],
        values("before"),
        values("after"),
        values("cross_validated"),
        np.array([k >= result.fit_samples for k, _r in rows], dtype=bool),
        np.array([r.role == "outlier" for _k, r in rows], dtype=bool),
    )


@dataclass(frozen=True)
class ParameterRow:
    name: str
    unit: str  # "mm", "°" or "%"
    value: float  # in `unit`
    sigma: float | None  # None: not determined (dropped by rank), set by the flange gauge
    why_held: str | None


def _display(p: Parameter) -> tuple[float, str]:
    if p.unit == "m":
        return 1e3, "mm"
    if p.unit == "rad":
        return math.degrees(1.0), "°"
    return 100.0, "%"  # a gain error: 0.01 is 1 % of the transmission ratio


def parameter_rows(result: CalibrationResult) -> list[ParameterRow]:
    """The robot parameters of the fitted set, in the model's order: fitted ones with their σ, and
    the ones identifiability dropped with its reason (their value: the flange gauge's)."""
    sigma = dict(zip(result.free, (float(s) for s in result.sigma)))
    out = []
    for i, p in enumerate(result.model.params):
        if p.kind is ParamKind.FRAME or not result.candidate.includes(p):
            continue
        scale, unit = _display(p)
        s = sigma.get(i)
        out.append(
            ParameterRow(
                p.name,
                unit,
                float(result.x[i]) * scale,
                None if s is None else s * scale,
                None if s is not None else result.identifiability.dropped.get(i, "not determined"),
            )
        )
    return out


def calibration_figure(result: CalibrationResult, dataset: str) -> Figure:
    """The figure; `dataset` is how the title names the data (the path the user gave)."""
    columns: list[Block | None] = list(result.blocks)
    if result.blocks == (POSITION,):
        columns.append(None)  # a point: the rotation column says why it is empty
    params = parameter_rows(result)
    widths = [4.6 if block is not None else 2.0 for block in columns]
    height = max(6.4, 1.8 + 0.19 * len(params))
    with plotting.style():
        fig = plotting.figure(sum(widths) + _PARAMETERS_WIDTH, height)
        left, right = fig.subfigures(1, 2, squeeze=False, width_ratios=[sum(widths), _PARAMETERS_WIDTH])[0]
        grid = left.add_gridspec(2, len(columns), width_ratios=widths)
        for c, block in enumerate(columns):
            if block is None:
                _no_rotation(left.add_subplot(grid[:, c]))
                continue
            rows = residuals(result, block)
            _per_sample(left.add_subplot(grid[0, c]), rows, block)
            _distribution(left.add_subplot(grid[1, c]), rows, block)
        _parameters(right, result, params)
        title = _title(result, dataset, params, int(fig.get_figwidth() * 14))
        fig.suptitle(title, fontsize=10, horizontalalignment="left", x=0.01)
    return fig


def _positive(values: Array, floor: float) -> Array:
    """A log axis cannot show 0: exact zeros sit on the axis' floor."""
    return np.maximum(values, floor)


def _floor(rows: Residuals) -> float:
    every = np.concatenate([rows.before, rows.after, rows.cross_validated])
    positive = every[np.isfinite(every) & (every > 0)]
    return float(positive.min()) / 2 if positive.size else 1e-6


def _per_sample(ax: Axes, rows: Residuals, block: Block) -> None:
    n = len(rows.ids)
    order = np.argsort(np.where(np.isfinite(rows.before), rows.before, np.inf), kind="stable")
    rank = np.arange(1, n + 1)
    floor = _floor(rows)
    before, after = _positive(rows.before[order], floor), _positive(rows.after[order], floor)
    held, outlier = rows.held[order], rows.outlier[order]
    size = 14.0 if n <= 100 else (7.0 if n <= 400 else 4.0)
    ax.plot(rank, before, color=plotting.NOMINAL, linewidth=1.4, label="hand-eye only (nominal robot)")
    fitted = ~held & ~outlier
    ax.scatter(rank[fitted], after[fitted], s=size, color=plotting.CALIBRATED, linewidths=0, label="calibrated")
    if (held & ~outlier).any():
        ax.scatter(
            rank[held & ~outlier],
            after[held & ~outlier],
            s=size * 1.6,
            marker="^",
            color=plotting.HELD_OUT,
            linewidths=0,
            label="calibrated, held out",
        )
    if outlier.any():
        ax.scatter(
            rank[outlier], after[outlier], s=28, marker="x", color=plotting.OUTLIER, linewidths=1.2, label="outlier"
        )
        worst = sorted(np.flatnonzero(outlier), key=lambda k: -after[k])[:_LABELLED_OUTLIERS]
        for k in worst:
            ax.annotate(
                rows.ids[order[k]],
                (rank[k], after[k]),
                xytext=(3, 3),
                textcoords="offset points",
                fontsize=7,
                color=plotting.OUTLIER,
            )
    ax.set_yscale("log")
    ax.set_xlim(0, n + 1)
    ax.set_title(f"{block.describe()} error per sample")
    ax.set_xlabel(f"sample, sorted by its hand-eye-only error ({n} samples)")
    ax.set_ylabel(f"{block.describe()} error ({UNIT_LABEL[block.unit]})")
    ax.legend(loc="upper left")


def _cdf(ax: Axes, values: Array, floor: float, **style: object) -> None:
    v = np.sort(values[np.isfinite(values)])
    if v.size:
        fraction = np.arange(1, v.size + 1) / v.size
        ax.step(_positive(v, floor), fraction, where="post", **style)  # type: ignore[arg-type]


def _distribution(ax: Axes, rows: Residuals, block: Block) -> None:
    floor = _floor(rows)
    fit = ~rows.held
    nf, nh = int(fit.sum()), int(rows.held.sum())
    _cdf(ax, rows.before[fit], floor, color=plotting.NOMINAL, label=f"hand-eye only, fitted ({nf})")
    _cdf(ax, rows.after[fit], floor, color=plotting.CALIBRATED, label=f"calibrated, fitted ({nf})")
    if nh:
        _cdf(
            ax,
            rows.before[rows.held],
            floor,
            color=plotting.NOMINAL,
            linestyle="--",
            label=f"hand-eye only, held out ({nh})",
        )
        _cdf(ax, rows.after[rows.held], floor, color=plotting.HELD_OUT, label=f"calibrated, held out ({nh})")
    if np.isfinite(rows.cross_validated).any():
        _cdf(
            ax,
            rows.cross_validated,
            floor,
            color=plotting.CROSS_VALIDATED,
            linestyle=":",
            linewidth=1.6,
            label=f"calibrated, cross-validated ({int(np.isfinite(rows.cross_validated).sum())})",
        )
    ax.set_xscale("log")
    ax.set_ylim(0, 1.02)
    ax.set_title(f"{block.describe()} error distribution")
    ax.set_xlabel(f"{block.describe()} error ({UNIT_LABEL[block.unit]})")
    ax.set_ylabel("fraction of samples at or below")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.17), ncols=2, fontsize=7)  # below: never over a curve


def _no_rotation(ax: Axes) -> None:
    ax.axis("off")
    ax.set_title(f"{ROTATION.describe()} error")
    ax.text(
        0.5,
        0.5,
        "not measured:\nthe data are points\n(a tracker's reflector,\na mocap marker),\nwhich have no "
        "orientation;\nthe flange's orientation\nis not observed",
        transform=ax.transAxes,
        horizontalalignment="center",
        verticalalignment="center",
        color=plotting.NOMINAL,
    )


def _parameters(sub: SubFigure, result: CalibrationResult, params: list[ParameterRow]) -> None:
    units = [u for u in ("mm", "°", "%") if any(p.unit == u for p in params)]
    if not units:
        ax = sub.subplots()
        ax.axis("off")
        ax.set_title("robot parameters")
        ax.text(
            0.5,
            0.5,
            f"{result.candidate.name}:\nno robot parameter fitted,\nthe nominal robot is kept",
            transform=ax.transAxes,
            horizontalalignment="center",
            color=plotting.NOMINAL,
        )
        return
    counts = [sum(p.unit == u for p in params) for u in units]
    axes = sub.subplots(len(units), 1, height_ratios=[max(c, 2) for c in counts], squeeze=False)[:, 0]
    for k, (ax, unit) in enumerate(zip(axes, units)):
        rows = [p for p in params if p.unit == unit]
        y = np.arange(len(rows))
        fitted = [j for j, p in enumerate(rows) if p.sigma is not None]
        held = [j for j, p in enumerate(rows) if p.sigma is None]
        ax.axvline(0.0, color="#999999", linewidth=0.8)
        if fitted:
            ax.errorbar(
                [rows[j].value for j in fitted],
                y[fitted],
                xerr=[rows[j].sigma or 0.0 for j in fitted],
                fmt="o",
                markersize=3.5,
                capsize=2.5,
                color=plotting.CALIBRATED,
                label="fitted: value ± σ",
            )
        if held:
            ax.plot(
                [rows[j].value for j in held],
                y[held],
                "o",
                markersize=4,
                markerfacecolor="white",
                markeredgecolor=plotting.NOMINAL,
                linestyle="none",
                label="not determined: set where the flange is nearest nominal",
            )
        ax.set_yticks(y, [_label(p) for p in rows])
        for j in held:
            ax.get_yticklabels()[j].set_color(plotting.NOMINAL)
        ax.set_ylim(len(rows) - 0.5, -0.5)
        ax.grid(axis="y", visible=False)
        ax.set_xlabel(f"correction ({unit})")
        if k == 0:
            ax.set_title(f"robot parameters of '{result.candidate.name}'")
            ax.legend(loc="best", fontsize=7)
    frames = sum(1 for i in result.free if result.model.params[i].kind is ParamKind.FRAME)
    sensor, target = result.model.frame_names()
    sub.supxlabel(f"also fitted: {frames} parameters of {sensor} and {target} (σ in calibration.yaml)", fontsize=8)


def _label(p: ParameterRow) -> str:
    if p.sigma is None:
        return f"{p.name}  held"
    return f"{p.name}  {p.value:+.3g} ± {p.sigma:.2g}"


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


def _figure(value: float) -> str:
    """Three significant digits, trailing zeros kept (0.700), never a bare point (165, not 165.)."""
    if not math.isfinite(value):
        return "n/a"
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:#.3g}"


def _title(result: CalibrationResult, dataset: str, params: list[ParameterRow], width: int) -> str:
    """Two lines or more, each wrapped to `width` characters."""
    rows = [r for r in result.residuals if r.role != "rejected"]
    held = max(0, len(rows) - result.fit_samples)
    counts = [
        f"{result.fit_samples} fitted",
        f"{held} held out" if held else "",
        _count(len(result.outliers), "outlier"),
    ]
    if result.rejected:
        counts.append(f"{len(result.rejected)} without a measurement")
    fitted = sum(p.sigma is not None for p in params)
    kept = len(params) - fitted
    what = f"'{result.candidate.name}': {fitted} robot parameters fitted" + (f", {kept} held" if kept else "")
    first = f"{dataset}: {len(rows)} samples ({', '.join(c for c in counts if c)}); {what}"
    nested = result.crossval.nested if result.crossval is not None else None
    lines = [first]
    for b in result.blocks:
        unit = UNIT_LABEL[b.unit]
        parts = []
        if result.fit is not None:
            before, after = result.fit.rms[b.name]
            parts.append(f"fitted, outliers left out {_figure(before)} → {_figure(after)}")
        if result.holdout is not None:
            before, after = result.holdout.rms[b.name]
            held_figures = f"held out {_figure(before)} → {_figure(after)}"
            inliers = result.holdout_inliers
            if inliers is not None and inliers.samples < result.holdout.samples:
                clean = inliers.rms[b.name]
                held_figures += f" ({_figure(clean[0])} → {_figure(clean[1])} without its outliers)"
            parts.append(held_figures)
        if nested is not None:
            parts.append(f"cross-validated {_figure(nested.hand_eye_rms[b.name])} → {_figure(nested.rms[b.name])}")
        lines.append(f"{b.describe()} RMS, hand-eye only → calibrated: {'; '.join(parts)} {unit}")
    if result.blocks == (CORNER,):
        lines[-1] += " (per sample: RMS over its corners)"
    return "\n".join(textwrap.fill(line, width, subsequent_indent="    ") for line in lines)
