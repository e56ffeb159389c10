"""`calibrate fit`'s report for people, on stderr (the data goes to files and, with --format json, stdout)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from rich.markup import escape
from rich.table import Table

from armtool.calib.fit import CalibrationResult
from armtool.console import stderr


def print_fit_report(result: CalibrationResult, truth: dict[str, Any] | None, out: Path, plot: Path | None) -> None:
    """The fit report on stderr: residuals before and after, identifiability, zero offsets, outliers, warnings."""
    con = stderr()
    ident = result.identifiability
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
    con.print(table)
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
        zt = Table(title="zero offsets (encoder zero corrections, already in calibrated.urdf)", title_justify="left")
        zt.add_column("joint")
        zt.add_column("offset °", justify="right")
        zt.add_column("± °", justify="right")
        zt.add_column("use to re-zero the encoder?")
        for z in result.zero_offsets:
            if not z.identified:
                zt.add_row(escape(z.joint), "-", "-", "[dim]not identified (trades with a camera/tag frame)[/dim]")
                continue
            plus = f"{math.degrees(z.uncertainty_rad):.2f}" if z.uncertainty_rad < math.pi else "unbounded"
            verdict = (
                "yes"
                if z.physical
                else "[red]no[/red]: not separable from "
                + escape(", ".join(p.parameter for p in z.partners[:2]) or "other parameters")
            )
            zt.add_row(escape(z.joint), f"{math.degrees(z.value_rad):+.3f}", plus, verdict)
        con.print(zt)
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
    con.print(f"wrote {out / 'calibrated.urdf'} and {out / 'calibration.yaml'}" + (f" and {plot}" if plot else ""))
