"""The report of `calibrate handeye` for people, on stderr (the data goes to --out and, with
--format json, to stdout): every method's held-out reprojection and board spread, the frames
written, the images left out and why."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from rich.markup import escape
from rich.table import Table

from armtool.console import stderr

if TYPE_CHECKING:
    from armtool.calib.handeye.run import HandEyeResult

_NAMES = {"refined_intrinsics": "refined+K"}


def _num(value: float | None, digits: int = 2) -> str:
    return "–" if value is None or not math.isfinite(value) else f"{value:.{digits}f}"


def print_handeye_report(result: HandEyeResult, doc: dict[str, Any]) -> None:
    """Methods table, chosen frames with 1σ, noise, outliers and unused images, notes."""
    con = stderr()
    if result.conventions is not None:
        con.print(f"[dim]conventions:[/dim] {escape(result.conventions.message())}")
    folds = doc["heldout"]["folds"]
    con.print(f"{doc['images_used']} of {len(doc['images'])} images used: {escape(doc['target'])}")
    held = f"held out: {folds}-fold over images" if folds else "no held-out images (--folds 0)"
    table = Table(
        title=f"reprojection RMS px ({held}; inliers: without outlier images) and the board's spread",
        title_justify="left",
    )
    for col in ("method", "held out", "inliers", "fit", "spread mm", "spread °"):
        table.add_column(col, justify="left" if col == "method" else "right", no_wrap=True)
    for m in doc["methods"]:
        spread = m.get("board_spread") or {}
        chosen = m["method"] == doc["method"]
        name = _NAMES.get(m["method"], m["method"]) + (" ←" if chosen else "")
        table.add_row(
            f"[bold]{escape(name)}[/bold]" if chosen else escape(name),
            _num(m["heldout_rms_px"], 3),
            _num(m["heldout_rms_px_without_outliers"], 3),
            _num(m["fit_rms_px"], 3),
            _num(spread.get("position_rms_mm")),
            _num(spread.get("rotation_rms_deg"), 3),
            end_section=m["method"] == "li",
        )
    con.print(table)
    x_name, z_name = result.frame_names
    for name in (x_name, z_name):
        pose = doc[name]
        sigma_mm = max((v for v in pose.get("sigma_position_mm", []) if v is not None), default=math.nan)
        sigma_deg = max((v for v in pose.get("sigma_rotation_deg", []) if v is not None), default=math.nan)
        xyz = ", ".join(f"{v * 1000:.2f}" for v in pose["xyz_m"])
        rpy = ", ".join(f"{math.degrees(v):.3f}" for v in pose["rpy_rad"])
        sigma = (
            f"1σ up to {_num(sigma_mm, 3)} mm, {_num(sigma_deg, 4)}°"
            if "sigma_position_mm" in pose
            else f"no 1σ: a closed form's ({doc['method']})"
        )
        con.print(f"{name}: xyz ({xyz}) mm, rpy ({rpy})° (R = Rz·Ry·Rx); {sigma}")
    noise = doc["noise"]
    con.print(
        f"estimated noise: corners {_num(noise['pixel_px'], 3)} px, flange poses {_num(noise['flange_position_mm'], 3)} mm "
        f"and {_num(noise['flange_rotation_deg'], 4)}° per axis"
    )
    if doc["intrinsics"]["refined"]:
        K = doc["intrinsics"]["camera_matrix"]
        con.print(f"intrinsics refined: fx {K[0][0]:.2f} fy {K[1][1]:.2f} cx {K[0][2]:.2f} cy {K[1][2]:.2f} px")
    for image in doc["images"]:
        if not image["used"]:
            con.print(f"[yellow]not used[/yellow] {escape(image['image'])}: {escape(image['reason'])}")
        elif image.get("outlier"):
            con.print(
                f"[yellow]outlier[/yellow] {escape(image['image'])}: reprojection RMS {_num(image['fit_rms_px'])} px "
                "(left out of the fit; check its detection and its pose row)"
            )
        if "turned_deg" in image:
            con.print(f"[dim]turned[/dim] {escape(image['image'])}: its corners relabelled by {image['turned_deg']}°")
    for note in doc["notes"]:
        con.print(f"[dim]note:[/dim] {escape(note)}")
