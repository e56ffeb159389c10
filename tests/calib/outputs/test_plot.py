"""`calibrate fit --plot`'s figure, read from the matplotlib Figure (not from pixels): residuals per
sample before and after with the held-out ones and the outliers marked, every calibrated sample
visible at 1000 samples, rotation beside position (or why there is none), the parameters with
their σ, and a title with the dataset and the headline figures."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.collections import PathCollection
from matplotlib.container import ErrorbarContainer
from matplotlib.figure import Figure

from armtool.calib.fit.calibration import CalibrationResult, FitOptions, calibrate
from armtool.calib.fit.problems import CORNER, POSITION
from armtool.calib.outputs.plot import calibration_figure, parameter_rows, residuals
from armtool.model.chain import Chain
from tests.calib.synthetic import make_measured, make_problem


@pytest.fixture(scope="module")
def corners(clean_chain: Chain) -> CalibrationResult:
    """40 tag images, a quarter held out, sample 5's joint 3 read 5° off (an outlier), nested 3-fold."""
    p = make_problem(clean_chain, n=40, seed=3)
    samples = list(p.samples)
    q = samples[5].q.copy()
    q[2] += math.radians(5.0)
    samples[5] = replace(samples[5], q=q)
    return calibrate(p.model, p.measurements, samples, FitOptions(folds=3, holdout=0.25))


@pytest.fixture(scope="module")
def poses(clean_chain: Chain) -> CalibrationResult:
    m = make_measured(clean_chain, "pose", n=60, seed=6)
    return calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0))


@pytest.fixture(scope="module")
def points(clean_chain: Chain) -> CalibrationResult:
    m = make_measured(clean_chain, "point", n=1000, seed=5)
    return calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0, holdout=0.2))


def _axes(fig: Figure) -> dict[str, Axes]:
    """Every axes of the figure (its subfigures' too) by title."""
    return {ax.get_title(loc="center") or ax.get_title(loc="left"): ax for ax in fig.get_axes()}


def _scatter(ax: Axes, label: str) -> PathCollection:
    found = [c for c in ax.collections if isinstance(c, PathCollection) and c.get_label() == label]
    assert len(found) == 1, [c.get_label() for c in ax.collections]
    return found[0]


def _legend(ax: Axes) -> list[str]:
    legend = ax.get_legend()
    assert legend is not None
    return [t.get_text() for t in legend.get_texts()]


def test_corner_figure_has_its_panels_labels_and_title(corners: CalibrationResult) -> None:
    fig = calibration_figure(corners, "mycal/")
    axes = _axes(fig)
    per_sample = axes["corner reprojection error per sample"]
    distribution = axes["corner reprojection error distribution"]
    assert per_sample.get_yscale() == "log" and distribution.get_xscale() == "log"
    assert per_sample.get_ylabel() == "corner reprojection error (px)"
    assert per_sample.get_xlabel() == "sample, sorted by its hand-eye-only error (40 samples)"
    assert distribution.get_ylabel() == "fraction of samples at or below"
    assert "rotation error per sample" not in axes and "rotation error" not in axes  # pixels only
    # held out and cross-validated: both in the distribution, with their counts
    assert _legend(distribution) == [
        "hand-eye only, fitted (30)",
        "calibrated, fitted (30)",
        "hand-eye only, held out (10)",
        "calibrated, held out (10)",
        "calibrated, cross-validated (30)",
    ]
    title = fig.get_suptitle()
    assert title.startswith("mycal/: 40 samples (30 fitted, 10 held out, 1 outlier)")
    fit_before, fit_after = corners.fit.rms["corner"]  # type: ignore[union-attr]
    assert f"fitted, outliers left out {fit_before:#.3g} → {fit_after:#.3g}" in title.replace("\n    ", " ")
    assert "cross-validated" in title and "held out" in title


def test_held_out_samples_and_outliers_are_marked_and_named(corners: CalibrationResult) -> None:
    per_sample = _axes(calibration_figure(corners, "d"))["corner reprojection error per sample"]
    rows = residuals(corners, CORNER)
    held = _scatter(per_sample, "calibrated, held out")
    assert len(np.asarray(held.get_offsets())) == int((rows.held & ~rows.outlier).sum()) == 10
    outlier = _scatter(per_sample, "outlier")
    assert len(np.asarray(outlier.get_offsets())) == 1
    assert [t.get_text() for t in per_sample.texts] == ["5"]  # the outlier's sample id beside it
    # the grey curve is every sample's hand-eye-only residual, sorted
    (curve,) = [line for line in per_sample.get_lines() if line.get_label() == "hand-eye only (nominal robot)"]
    assert np.allclose(curve.get_ydata(), np.sort(rows.before))


def test_pose_data_shows_rotation_beside_position(poses: CalibrationResult) -> None:
    axes = _axes(calibration_figure(poses, "poses"))
    for quantity, unit in (("position", "mm"), ("rotation", "°")):
        assert axes[f"{quantity} error per sample"].get_ylabel() == f"{quantity} error ({unit})"
        assert axes[f"{quantity} error distribution"].get_xlabel() == f"{quantity} error ({unit})"
    left = {ax.get_title(): ax.get_position().x0 for ax in axes.values()}
    assert left["position error per sample"] < left["rotation error per sample"]  # beside it, to the right


def test_point_data_says_it_has_no_rotation(points: CalibrationResult) -> None:
    fig = calibration_figure(points, "tracker")
    rotation = _axes(fig)["rotation error"]
    assert not rotation.axison
    (note,) = rotation.texts
    assert note.get_text().startswith("not measured") and "no orientation" in note.get_text().replace("\n", " ")
    assert "rotation RMS" not in fig.get_suptitle()


def test_every_calibrated_sample_is_visible_at_1000_samples(points: CalibrationResult) -> None:
    per_sample = _axes(calibration_figure(points, "tracker"))["position error per sample"]
    rows = residuals(points, POSITION)
    assert len(rows.ids) == 1000
    drawn = [c for c in per_sample.collections if isinstance(c, PathCollection)]
    offsets = np.concatenate([np.asarray(c.get_offsets()) for c in drawn])
    assert len(offsets) == 1000  # a marker per sample: fitted, held out or outlier
    assert all(float(c.get_sizes()[0]) >= 4.0 for c in drawn)  # markers, not sub-pixel bars
    low, high = per_sample.get_ylim()
    assert low <= offsets[:, 1].min() and offsets[:, 1].max() <= high
    assert len(np.asarray(_scatter(per_sample, "calibrated, held out").get_offsets())) == int(
        (rows.held & ~rows.outlier).sum()
    )
    assert int(rows.held.sum()) == 200


def test_the_parameters_panel_shows_each_value_with_its_sigma_and_marks_the_held(poses: CalibrationResult) -> None:
    rows = parameter_rows(poses)
    fitted = [p for p in rows if p.sigma is not None]
    held = [p for p in rows if p.sigma is None]
    assert len(fitted) == len([i for i in poses.free if poses.model.params[i].kind.value != "frame"])
    assert held and all(p.why_held for p in held)  # identifiability's reason, kept with the row
    fig = calibration_figure(poses, "poses")
    panels = [ax for ax in fig.get_axes() if ax.get_xlabel().startswith("correction (")]
    assert [ax.get_xlabel() for ax in panels] == ["correction (mm)", "correction (°)"]
    labels = [t.get_text() for ax in panels for t in ax.get_yticklabels()]
    assert len(labels) == len(rows)
    by_name = {p.name: p for p in rows}
    for label in labels:
        name, _, shown = label.partition("  ")
        p = by_name[name]
        assert shown == ("held" if p.sigma is None else f"{p.value:+.3g} ± {p.sigma:.2g}")
    errorbars = [c for ax in panels for c in ax.containers if isinstance(c, ErrorbarContainer)]
    assert [c.get_label() for c in errorbars] == ["fitted: value ± σ"] * len(panels)
    assert sum(len(np.asarray(c.lines[0].get_xdata())) for c in errorbars) == len(fitted)
    translations = [p for p in fitted if p.unit == "mm"]
    index = poses.model.params.index(next(q for q in poses.model.params if q.name == translations[0].name))
    assert translations[0].value == pytest.approx(poses.x[index] * 1e3)  # metres shown as millimetres


def test_hand_eye_only_says_no_robot_parameter_was_fitted(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "pose", n=30, seed=2)
    result = calibrate(m.model, m.measurements, m.samples, FitOptions(folds=0, families=()))
    assert parameter_rows(result) == []
    texts = [t.get_text() for ax in calibration_figure(result, "d").get_axes() for t in ax.texts]
    assert any("no robot parameter fitted" in t for t in texts)
