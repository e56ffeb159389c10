"""`armtool calibrate handeye|handeye-simulate`: the camera's frame from board images and the flange
poses a controller reports, without joint readings.

Registered on the `calibrate` Typer app by `register(app)` (see armtool/cli/calibrate.py).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from armtool.calib.choices import ChessboardDetector, Intrinsics, Quality, ReportFormat, Setup
from armtool.calib.limits import MAX_SIMULATED
from armtool.cli import options as opt
from armtool.errors import ExitCode
from armtool.extras import require

if TYPE_CHECKING:
    from rich.progress import TaskID


def handeye(
    dataset: Path = typer.Argument(..., help="Hand-eye dataset directory (dataset.yaml, poses file, images)."),
    out: Path | None = typer.Option(None, "--out", "-o", help="Write the result here (YAML: frames, scores, images)."),
    folds: int = typer.Option(
        5,
        "--folds",
        callback=opt.int_range(0, 20),
        help="k of the k-fold over images that scores every method on images it never saw (0 or 1: none).",
    ),
    seed: int = typer.Option(0, "--seed", callback=opt.seed(), help="Random seed for dealing images to folds."),
    intrinsics: Intrinsics = typer.Option(
        Intrinsics.AUTO,
        "--intrinsics",
        help="fixed (as the intrinsics file says), refine (with the frames), or auto (whichever predicts held-out images better).",
    ),
    detector: ChessboardDetector = typer.Option(
        ChessboardDetector.CLASSIC,
        "--detector",
        help="Chessboard corners by OpenCV's findChessboardCorners (classic) or findChessboardCornersSB (sb), refined by cornerSubPix.",
    ),
    keep_conventions: bool = typer.Option(
        False,
        "--keep-conventions",
        help="Calibrate as declared even when another reading of the poses fits far better.",
    ),
    max_rms: float | None = typer.Option(
        None,
        "--max-rms",
        callback=opt.positive_float(1000.0, unit="px"),
        help="Exit 1 when the held-out reprojection RMS is above this many pixels.",
    ),
    output_format: ReportFormat = typer.Option(
        ReportFormat.TEXT, "--format", help="text (report on stderr) or json (summary on stdout)."
    ),
) -> None:
    """Hand-eye calibration from images of a board and the flange poses the controller reports (no joints)."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from armtool.calib.handeye.run import HandEyeRequest, document, run_handeye, write_result
    from armtool.console import progress_bar, write_stdout
    from armtool.fileio import check_output_paths
    from armtool.output.handeye import print_handeye_report

    if out is not None:  # never over a file of the dataset (dataset.yaml, the poses, the intrinsics)
        check_output_paths({"--out": out}, [p for p in dataset.glob("*") if p.is_file()] if dataset.is_dir() else [])
    request = HandEyeRequest(dataset, folds, seed, intrinsics, detector, keep_conventions)
    with progress_bar() as bar:
        tasks: dict[str, TaskID] = {}

        def progress(stage: str, done: int, total: int) -> None:
            if stage not in tasks:
                tasks[stage] = bar.add_task(stage, total=total)
            bar.update(tasks[stage], completed=done)

        result = run_handeye(request, progress)
    doc = document(result)
    if out is not None:
        write_result(result, out)
    if output_format is ReportFormat.JSON:
        write_stdout(json.dumps(doc, indent=2))
    print_handeye_report(result, doc)
    heldout = doc["heldout"]["rms_px"]
    if max_rms is not None and (heldout is None or heldout > max_rms):
        raise typer.Exit(ExitCode.FINDINGS)


def handeye_simulate(
    out: Path = typer.Option(..., "--out", "-o", help="New directory for the dataset (truth goes to OUT/truth/)."),
    images: int = typer.Option(
        30, "--images", callback=opt.int_range(3, MAX_SIMULATED), help=f"Images to render (3 to {MAX_SIMULATED})."
    ),
    setup: Setup = typer.Option(
        Setup.EYE_IN_HAND, "--setup", help="Camera on the flange (eye_in_hand) or fixed (eye_to_hand)."
    ),
    target: str = typer.Option(
        "chessboard:10x7:0.025",
        "--target",
        help="The board, spelled as for `calibrate camera --board` (chessboard:COLSxROWS:SQUARE, charuco:..., aprilgrid:...).",
    ),
    flange_noise_mm: float = typer.Option(
        0.2,
        "--flange-noise-mm",
        callback=opt.finite_float(0.0, 100.0, unit="mm"),
        help="The controller's position error, 1σ per axis.",
    ),
    flange_noise_deg: float = typer.Option(
        0.02,
        "--flange-noise-deg",
        callback=opt.finite_float(0.0, 10.0, unit="degrees"),
        help="Its rotation error, 1σ per axis.",
    ),
    bad_rows: int = typer.Option(
        0,
        "--bad-rows",
        callback=opt.int_range(0, MAX_SIMULATED),
        help="Rows whose pose is 3 cm and 3° off (at most a quarter of --images).",
    ),
    quality: Quality = typer.Option(Quality.TYPICAL, "--quality", help="Image blur, noise and contrast."),
    distortion: bool = typer.Option(True, "--distortion/--no-distortion", help="Give the camera lens distortion."),
    seed: int = typer.Option(0, "--seed", callback=opt.seed(), help="Random seed (any integer)."),
) -> None:
    """Write a synthetic hand-eye dataset (board images and flange poses) with known frames, to rehearse."""
    require("calib")
    from armtool.calib.handeye.simulate import HandEyeSimulation, render, write_dataset
    from armtool.calib.targets.boards import parse_board
    from armtool.console import progress_bar, say

    opt.check_out_dir(out)
    spec = HandEyeSimulation(
        images=images,
        setup=setup,
        board=parse_board(target),
        seed=seed,
        quality=quality,
        distortion=distortion,
        flange_noise_mm=flange_noise_mm,
        flange_noise_deg=flange_noise_deg,
        bad_rows=bad_rows,
    )
    with progress_bar() as bar:
        task = bar.add_task("rendering", total=images)
        rendered = render(spec, progress=lambda done, total: bar.update(task, completed=done))
    write_dataset(out, spec, rendered)
    say(f"wrote {images} images, poses.csv and dataset.yaml to {out}; ground truth in {out / 'truth'}")


def register(app: typer.Typer) -> None:
    """Add `handeye` and `handeye-simulate` to the `calibrate` app."""
    app.command("handeye")(handeye)
    app.command("handeye-simulate")(handeye_simulate)
