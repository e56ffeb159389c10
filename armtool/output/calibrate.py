"""The reports of `calibrate check`, `calibrate fit`, `calibrate camera` and `calibrate import-bag` for people, on
stderr (the data goes to files and, with --format json, to stdout)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.markup import escape
from rich.table import Table

from armtool.console import stderr

if TYPE_CHECKING:  # each command imports only what it uses
    from armtool.calib.bag_import import ImportResult
    from armtool.calib.boards import BoardSpec
    from armtool.calib.dataset import Dataset
    from armtool.calib.fit import CalibrationResult
    from armtool.calib.intrinsics import IntrinsicsResult


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


def print_fit_report(result: CalibrationResult, truth: dict[str, Any] | None, out: Path, plot: Path | None) -> None:
    """The fit report on stderr: residuals before and after, identifiability, zero offsets, outliers, warnings."""
    con = stderr()
    ident = result.identifiability
    con.print(_residual_table(result, truth))
    con.print(
        f"identified {len(result.free)} of {len(result.free) + len(ident.dropped)} parameters; "
        f"condition number {ident.condition_number:.1f}, observability index {ident.observability_index:.3g}"
    )
    shown = list(ident.dropped.items())[:6]
    for i, why in shown:
        con.print(f"  [dim]dropped[/dim] {escape(result.model.params[i].name)}: {escape(why)}")
    if len(ident.dropped) > len(shown):
        con.print(f"  [dim]… {len(ident.dropped) - len(shown)} more in calibration.yaml[/dim]")
    if result.zero_offsets:
        con.print(_zero_offset_table(result))
        if not all(z.physical for z in result.zero_offsets if z.identified):
            con.print(
                "  [dim]offsets marked 'no' only balance origin errors the poses cannot separate from them; "
                "calibrated.urdf is right as a whole, but do not re-zero encoders on them (calibration.yaml: zero_offsets)[/dim]"
            )
    for sid, why in result.outliers.items():
        con.print(f"[yellow]outlier[/yellow] sample {escape(sid)}: {escape(why)}")
    for sid, why in result.rejected.items():
        con.print(f"[yellow]rejected[/yellow] sample {escape(sid)}: {escape(why)}")
    for w in result.warnings:
        con.print(f"[yellow]warning:[/yellow] {escape(w)}")
    con.print(
        escape(f"wrote {out / 'calibrated.urdf'} and {out / 'calibration.yaml'}" + (f" and {plot}" if plot else ""))
    )


def _residual_table(result: CalibrationResult, truth: dict[str, Any] | None) -> Table:
    """Corner RMS of fit and held-out samples, hand-eye only against calibrated (and against the truth when known)."""
    table = Table(title="corner reprojection RMS (px)", title_justify="left")
    table.add_column("")
    table.add_column("hand-eye only", justify="right")
    table.add_column("calibrated", justify="right")
    table.add_row("fit samples", f"{result.fit_rms_px[0]:.3f}", f"{result.fit_rms_px[1]:.3f}")
    if not math.isnan(result.holdout_rms_px[0]):
        table.add_row("held-out samples", f"{result.holdout_rms_px[0]:.3f}", f"{result.holdout_rms_px[1]:.3f}")
        if result.holdout_inlier_rms_px != result.holdout_rms_px and not math.isnan(result.holdout_inlier_rms_px[0]):
            table.add_row(
                "held-out, outliers left out",
                f"{result.holdout_inlier_rms_px[0]:.3f}",
                f"{result.holdout_inlier_rms_px[1]:.3f}",
            )
    if truth:
        b, a = truth["hand_eye_only"], truth["calibrated"]
        table.add_row(
            "vs truth: position RMS / max (mm)",
            f"{b['position_rms_mm']:.3f} / {b['position_max_mm']:.3f}",
            f"{a['position_rms_mm']:.3f} / {a['position_max_mm']:.3f}",
        )
        table.add_row("vs truth: rotation RMS (°)", f"{b['rotation_rms_deg']:.4f}", f"{a['rotation_rms_deg']:.4f}")
    return table


def _zero_offset_table(result: CalibrationResult) -> Table:
    """Each zero offset and whether it may be used to re-zero the encoder (see calib/zero_offsets.py)."""
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
