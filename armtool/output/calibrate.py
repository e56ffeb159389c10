"""The reports of `calibrate check`, `calibrate fit`, `calibrate camera` and `calibrate import-bag` for people, on
stderr (the data goes to files and, with --format json, to stdout)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.markup import escape
from rich.table import Table

from armtool.console import say, stderr

if TYPE_CHECKING:  # each command imports only what it uses
    from armtool.calib.fit.calibration import CalibrationResult
    from armtool.calib.fit.intrinsics import IntrinsicsResult
    from armtool.calib.fit.problems import Block
    from armtool.calib.inputs.bag_import import ImportResult
    from armtool.calib.inputs.dataset import Dataset
    from armtool.calib.pipeline import FitFiles, FitJob
    from armtool.calib.targets.boards import BoardSpec


def print_check_report(ds: Dataset) -> None:
    """`calibrate check`'s report: every problem with where it is and how to fix it, then the counts."""
    out = stderr()
    for p in ds.problems:
        color = "red" if p.severity == "error" else "yellow"
        out.print(f"{escape(p.where)}: [{color}]{p.severity}[/{color}]: {escape(p.what)}")
        if p.hint:
            out.print(f"  [dim]hint:[/dim] {escape(p.hint)}")
    errors = len(ds.errors)
    warnings = len(ds.problems) - errors
    out.print(f"{len(ds.samples)} samples, {errors} error(s), {warnings} warning(s)")


def print_fit_report(job: FitJob, result: CalibrationResult, files: FitFiles) -> None:
    """The fit report on stderr: residuals before and after, noise, cross-validation, the verdict,
    identifiability, zero offsets, outliers, warnings, the files written."""
    con = stderr()
    request, conventions, verdict = job.request, job.conventions, files.verdict
    truth = files.document.get("against_truth")
    ident = result.identifiability
    if conventions is not None:
        con.print(f"[dim]conventions:[/dim] {escape(conventions.message())}")
    con.print(_residual_table(result, truth))
    con.print("estimated noise (σ per coordinate): " + escape(_noise_text(result)))
    if result.crossval is not None:
        con.print(_crossval_table(result))
        nested = _nested_text(result)
        if nested:
            con.print(escape(nested))
    terms = _terms_text(result)
    if terms:
        con.print(escape(terms))
    con.print(_frames_text(result))
    con.print(escape(_identified_text(result)))
    if result.subspace is not None:
        for c in result.subspace.held:
            con.print(f"  [dim]held[/dim] {escape(c.describe(result.model, result.subspace.precision))}")
    gauge = _flange_gauge_text(result)
    if gauge:
        con.print(escape(gauge))
    shown = list(ident.dropped.items())[:6]
    for i, why in shown:
        con.print(f"  [dim]dropped[/dim] {escape(result.model.params[i].name)}: {escape(why)}")
    if len(ident.dropped) > len(shown):
        con.print(f"  [dim]… {len(ident.dropped) - len(shown)} more in calibration.yaml[/dim]")
    if result.zero_offsets:
        con.print(_zero_offset_table(result))
        if not all(z.physical for z in result.zero_offsets if z.identified):
            con.print(
                "  [dim]offsets marked 'no' only balance origin errors the poses cannot separate from them: they are "
                "right inside calibrated.urdf, with the origin corrections, but do not re-zero encoders on them "
                "(calibration.yaml: zero_offsets)[/dim]"
            )
    for sid, why in result.outliers.items():
        con.print(f"[yellow]outlier[/yellow] sample {escape(sid)}: {escape(why)}")
    for sid, why in result.rejected.items():
        con.print(f"[yellow]rejected[/yellow] sample {escape(sid)}: {escape(why)}")
    for w in result.warnings:
        con.print(f"[yellow]warning:[/yellow] {escape(w)}")
    color = "green" if verdict.improves else ("cyan" if request.options.hand_eye_only else "red")
    con.print(f"[{color}]verdict:[/{color}] {escape(verdict.summary)}")
    if verdict.advice:
        con.print(f"  {escape(verdict.advice)}")
    reason = (
        "it would not predict held-out poses better than the nominal URDF"
        if verdict.checked
        else "the fit leaves the robot's URDF as it is"
    )
    for path in files.skipped:
        con.print(f"[yellow]not written:[/yellow] {escape(path)} ({reason})")
        if Path(path).exists():
            con.print(
                f"  [yellow]{escape(path)} already exists from an earlier run: it is not this run's result[/yellow]"
            )
    ur = request.ur_kinematics
    written = [p for p in files.files if p != ur]
    plot = request.plot
    con.print(
        escape(
            "wrote " + " and ".join(str(f) for f in written) + (f" and {plot}" if plot and plot not in written else "")
        )
    )
    if ur is not None and ur in files.files:
        say(f"wrote {ur}: pass it to the UR description as kinematics_params:={ur}")


def _identified_text(result: CalibrationResult) -> str:
    """'fitted origins + offsets: 25 of 51 parameters determined (27 identifiable by rank, 2 combinations
    held: σ beyond 1 mm and 0.1°); condition number …'."""
    ident, subspace = result.identifiability, result.subspace
    candidates = len(result.free) + len(ident.dropped)
    text = f"fitted {result.candidate.name}: "
    if subspace is None or not subspace.held:
        text += f"{len(result.free)} of {candidates} parameters identified"
    else:
        held = len(subspace.held)
        text += (
            f"{subspace.dimension} of {candidates} parameters determined ({len(result.free)} identifiable by rank; "
            f"{held} combination{'s' if held > 1 else ''} of them held: not determined to "
            f"{subspace.precision.describe()}, each below with its σ)"
        )
    return (
        text + f"; condition number {ident.condition_number:.1f}, observability index {ident.observability_index:.3g}"
    )


def _flange_gauge_text(result: CalibrationResult) -> str:
    """Where the data leave the geometry free, how near nominal calibrated.urdf's flange was put."""
    gauge = result.flange_gauge
    if gauge is None or not gauge.moved:
        return ""
    return (
        f"{result.model.chain.tip} put nearest the nominal arm's along {gauge.directions} combinations the data do "
        f"not determine (measurements unchanged, χ² {gauge.chi2_change:+.2g}): {gauge.after.describe()} from nominal "
        f"over the fit's poses, against {gauge.before.mean_mm:.2f} mm and {gauge.before.mean_deg:.3f}° on average as "
        "fitted"
    )


def _noise_text(result: CalibrationResult) -> str:
    parts = []
    for b in result.blocks:
        value = result.noise.get(b.name, math.nan)
        parts.append(f"{b.name} {value:.3g} {b.unit}")
    return ", ".join(parts)


def _unit(b: Block) -> str:
    return "°" if b.unit == "deg" else f" {b.unit}"


def _residual_table(result: CalibrationResult, truth: dict[str, Any] | None) -> Table:
    """Residual RMS of fit and held-out samples per block, hand-eye only against calibrated (and against the truth when known)."""
    single = len(result.blocks) == 1 and result.blocks[0].unit == "px"
    table = Table(title="corner reprojection RMS (px)" if single else "residual RMS", title_justify="left")
    table.add_column("")
    table.add_column("hand-eye only", justify="right")
    table.add_column("calibrated", justify="right")
    sets = [("fit samples", result.fit), ("held-out samples", result.holdout)]
    if (
        result.holdout_inliers is not None
        and result.holdout is not None
        and result.holdout_inliers.samples != result.holdout.samples
    ):
        sets.append(("held-out, outliers left out", result.holdout_inliers))
    for label, comparison in sets:
        if comparison is None:
            continue
        for b in result.blocks:
            before, after = comparison.rms[b.name]
            name = label if single else f"{label}: {b.name} ({b.unit})"
            table.add_row(name, f"{before:.3f}", f"{after:.3f}")
    if truth:
        bt, at = truth["hand_eye_only"], truth["calibrated"]
        table.add_row(
            "vs truth: position RMS / max (mm)",
            f"{bt['position_rms_mm']:.3f} / {bt['position_max_mm']:.3f}",
            f"{at['position_rms_mm']:.3f} / {at['position_max_mm']:.3f}",
        )
        table.add_row("vs truth: rotation RMS (°)", f"{bt['rotation_rms_deg']:.4f}", f"{at['rotation_rms_deg']:.4f}")
    return table


def _crossval_table(result: CalibrationResult) -> Table:
    """Each candidate's k-fold held-out residual and score; the chosen one marked."""
    cv = result.crossval
    assert cv is not None
    table = Table(title=f"parameter sets on held-out poses ({cv.folds}-fold cross-validation)", title_justify="left")
    table.add_column("parameter set")
    table.add_column("fitted", justify="right")
    for b in result.blocks:
        table.add_column(f"{b.name} RMS / max ({b.unit})", justify="right")
    table.add_column("score", justify="right")
    table.add_column("")
    for score in cv.scores:
        cells = [escape(score.candidate.name), "-" if math.isnan(score.parameters) else f"{score.parameters:.0f}"]
        cells += [f"{score.rms[b.name]:.3f} / {score.maximum[b.name]:.3f}" for b in result.blocks]
        cells.append(f"{score.loss:.3g}")
        marks = []
        if score.candidate == cv.chosen:
            marks.append("[green]chosen[/green]")
        terms = result.joint_terms
        fitted = terms.candidate if terms is not None else result.candidate
        if score.candidate == fitted and score.candidate != cv.chosen:
            marks.append("fitted (--no-select)")
        if terms is not None and score.candidate == result.candidate:
            marks.append("calibrated.urdf")
        if score.failed:
            marks.append(f"[yellow]failed on {score.failed} fold(s)[/yellow]")
        cells.append(", ".join(marks))
        table.add_row(*cells)
    return table


def _nested_text(result: CalibrationResult) -> str:
    """The whole procedure's held-out residual (nested cross-validation), against hand-eye only."""
    cv = result.crossval
    if cv is None or cv.nested is None:
        return ""
    n = cv.nested
    dropped = n.samples - n.inliers
    outliers = f"the {dropped} outlier{'s' if dropped != 1 else ''}"
    parts = []
    for b in result.blocks:
        u = _unit(b)
        parts.append(
            f"{b.name} {n.rms[b.name]:.3f}{u} RMS (max {n.maximum[b.name]:.3f}{u}; "
            f"{n.inlier_rms[b.name]:.3f}{u} without {outliers}) against {n.hand_eye_rms[b.name]:.3f}{u} hand-eye only"
        )
    from armtool.calib.fit.crossval import describe_choices

    text = (
        f"whole procedure on held-out poses (nested {cv.folds}-fold, choosing {describe_choices(n.chosen)}): "
        + "; ".join(parts)
    )
    if cv.nested_terms is None:
        return text
    with_terms = ", ".join(f"{b.name} {cv.nested_terms.rms[b.name]:.3f}{_unit(b)} RMS" for b in result.blocks)
    return text + f" for calibrated.urdf (the URDF rung of each choice); with the joint terms {with_terms}"


def _terms_text(result: CalibrationResult) -> str:
    """Why calibrated.urdf is not the chosen set, and where the chosen set is."""
    from armtool.calib.apply import TERMS_URDF

    terms = result.joint_terms
    if terms is None:
        return ""
    cv = result.crossval
    figures = ""
    if cv is not None:
        score = cv.score_of(terms.candidate.name)
        figures = (
            " (k-fold held-out "
            + ", ".join(f"{b.name} {score.rms[b.name]:.3f}{_unit(b)} RMS" for b in result.blocks)
            + ")"
        )
    return (
        f"chosen: {terms.candidate.name}{figures}. A URDF cannot hold its joint terms, so calibrated.urdf "
        f"is {result.candidate.name} fitted alone, right as it is; the chosen set's own geometry is {TERMS_URDF}, "
        "right with calibration.yaml's joint_terms applied to the readings (`armtool calibrate apply`), the arm on "
        "average as it is"
    )


def _frames_text(result: CalibrationResult) -> str:
    """The two fitted placements, position in mm and rpy in degrees, with σ."""
    from armtool.calib.outputs.report import frames_section

    frames = frames_section(result, dict(zip(result.free, result.sigma)))
    lines = []
    for name, pose in frames.items():
        xyz = ", ".join(f"{v * 1e3:.2f}" for v in pose["xyz"])
        sig = pose.get("sigma_xyz_mm") or []
        pm = (
            " ± (" + ", ".join("-" if v is None else f"{v:.2f}" for v in sig) + ") mm"
            if sig and any(v is not None for v in sig)
            else " mm"
        )
        text = f"{name}: xyz ({xyz}){pm}"
        if "rpy" in pose:
            text += ", rpy (" + ", ".join(f"{math.degrees(v):.3f}" for v in pose["rpy"]) + ")°"
        lines.append(text)
    return escape("; ".join(lines))


def _zero_offset_table(result: CalibrationResult) -> Table:
    """Each zero offset and whether it may be used to re-zero the encoder (see calib/fit/zero_offsets.py)."""
    table = Table(title="zero offsets (encoder zero corrections, already in calibrated.urdf)", title_justify="left")
    table.add_column("joint")
    table.add_column("offset °", justify="right")
    table.add_column("± °", justify="right")
    table.add_column("use to re-zero the encoder?")
    for z in result.zero_offsets:
        if not z.identified:
            table.add_row(escape(z.joint), "-", "-", "[dim]not identified (trades with a camera/tag frame)[/dim]")
            continue
        plus = f"{math.degrees(z.uncertainty_rad):.2f}" if z.uncertainty_rad < math.pi else "unbounded"
        verdict = (
            "yes"
            if z.physical
            else "[red]no[/red]: not separable from "
            + escape(", ".join(p.parameter for p in z.partners[:2]) or "other parameters")
        )
        table.add_row(escape(z.joint), f"{math.degrees(z.value_rad):+.3f}", plus, verdict)
    return table


def print_camera_report(result: IntrinsicsResult, spec: BoardSpec, out: Path) -> None:
    """`calibrate camera`'s report on stderr: each image, the intrinsics with 1σ, distortion, warnings."""
    con = stderr()
    table = Table(title=f"board: {escape(spec.describe())}", title_justify="left")
    for col, justify in (
        ("image", "left"),
        ("corners", "right"),
        ("RMS px", "right"),
        ("tilt °", "right"),
        ("", "left"),
    ):
        table.add_column(col, justify=justify)  # type: ignore[arg-type]
    for v in result.views:
        status = "" if v.used else f"[yellow]{escape(v.reason)}[/yellow]"
        table.add_row(
            escape(Path(v.name).name),
            str(v.points),
            "" if math.isnan(v.rms_px) else f"{v.rms_px:.3f}",
            "" if math.isnan(v.tilt_deg) else f"{v.tilt_deg:.0f}",
            status,
        )
    con.print(table)
    K, s = result.camera.K, result.sigma
    con.print(
        f"fx {K[0, 0]:.2f} ± {s['fx']:.2f}  fy {K[1, 1]:.2f} ± {s['fy']:.2f}  cx {K[0, 2]:.2f} ± {s['cx']:.2f}  "
        f"cy {K[1, 2]:.2f} ± {s['cy']:.2f} px (1σ)"
    )
    con.print(f"distortion ({result.model.value}): " + " ".join(f"{d:.5g}" for d in result.camera.dist))
    con.print(f"reprojection RMS {result.rms_px:.3f} px over {len(result.used)} images; coverage {result.coverage:.0%}")
    for w in result.warnings:
        con.print(f"[yellow]warning:[/yellow] {escape(w)}")
    con.print(f"wrote {escape(str(out))}")


def print_bag_report(result: ImportResult) -> None:
    """`calibrate import-bag`'s report on stderr: skipped windows, warnings, what was written."""
    con = stderr()
    for a, b, reason in result.skipped:
        con.print(f"[yellow]skipped[/yellow] settled window {a:.2f}-{b:.2f} s: {escape(reason)}")
    for w in result.warnings:
        con.print(f"[yellow]warning:[/yellow] {escape(w)}")
    con.print(
        f"{len(result.samples)} samples from settled windows ({result.clock}); intrinsics: {escape(result.intrinsics_source)}"
    )
    con.print(f"wrote {escape(str(result.out))}; next: armtool calibrate check {escape(str(result.out))}")
