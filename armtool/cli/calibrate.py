"""`armtool calibrate check|fit|simulate`: kinematic calibration from images of an AprilTag or a board."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from armtool.calib.choices import Criterion, Quality, ReportFormat, Setup
from armtool.calib.limits import MAX_SIMULATED, TAG_SIZE_M
from armtool.cli import options as opt
from armtool.cli.options import DatasetConfig, PackagePaths, RobotConfig, XacroArgs
from armtool.errors import ExitCode
from armtool.extras import require

if TYPE_CHECKING:
    from armtool.calib.inputs.dataset import Dataset
    from armtool.calib.inputs.observations import Observation
    from armtool.calib.model.camera import CameraModel

HELP = "Fit a real arm's kinematic errors from images (an AprilTag or a board) or measured poses and points; write a corrected URDF. Hand-eye from flange poses: `calibrate handeye`."

app = typer.Typer(
    help=HELP,
    no_args_is_help=True,
    add_completion=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _detect(ds: Dataset, camera: CameraModel) -> dict[str, Observation]:
    """Tag corners of every sample, with a progress bar."""
    from armtool.calib.inputs.observations import observe
    from armtool.console import progress_bar

    with progress_bar() as bar:
        task = bar.add_task("detecting tags" if ds.corners_file is None else "reading corners", total=len(ds.samples))
        return observe(ds, camera, progress=lambda done, total: bar.update(task, completed=done))


@app.command("check")
def check(
    dataset: Path = typer.Argument(..., help="Dataset directory (with dataset.yaml)."),
    detect: bool = typer.Option(True, "--detect/--no-detect", help="Also look for the tag in every image."),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: DatasetConfig = None,
) -> None:
    """Validate a dataset: files, joints, units, images and the tag in every image, or measured poses and points and their conventions."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from rich.markup import escape

    from armtool.calib.check import check_dataset
    from armtool.console import stderr
    from armtool.output.calibrate import print_check_report

    robot = opt.RobotOptions(xacro_arg, package_path, config)  # --xacro-arg wins over the dataset's robot.xacro_args
    ds, note = check_dataset(dataset, robot.given_args, robot.package_paths, _detect if detect else None)
    print_check_report(ds)
    if note:
        stderr().print(f"[dim]conventions:[/dim] {escape(note)}")
    if ds.errors:
        raise typer.Exit(ExitCode.FINDINGS)


@app.command("fit")
def fit(
    dataset: Path = typer.Argument(..., help="Dataset directory (with dataset.yaml)."),
    out: Path = typer.Option(..., "--out", "-o", help="Directory for calibrated.urdf and calibration.yaml."),
    params: str | None = typer.Option(
        None,
        "--params",
        help="Kinematic parameter families to fit: origins, offsets, gains; none: hand-eye only, the robot held nominal [default: origins,offsets].",
    ),
    holdout: float = typer.Option(
        0.0,
        "--holdout",
        callback=opt.finite_float(0.0, 0.9),
        help="Fraction of samples kept out of the fit to validate it (0 to 0.9).",
    ),
    validation: Path | None = typer.Option(
        None, "--validation", help="A second dataset of the same setup, used only to validate."
    ),
    seed: int = typer.Option(
        0, "--seed", callback=opt.seed(), help="Random seed for the hold-out split (any integer)."
    ),
    plot: Path | None = typer.Option(None, "--plot", help="Write a figure of residuals and σ's (.png, .svg, .pdf)."),
    output_format: ReportFormat = typer.Option(
        ReportFormat.TEXT, "--format", help="text (report on stderr) or json (summary on stdout)."
    ),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: DatasetConfig = None,
    ur_kinematics: Path | None = typer.Option(
        None,
        "--ur-kinematics",
        help="Universal Robots arm: also write its calibration YAML (default_kinematics.yaml format) here; use it as kinematics_params:=FILE.",
    ),
    ur_kinematics_in: Path | None = typer.Option(
        None,
        "--ur-kinematics-in",
        help="The robot's current UR kinematics YAML, whose hash is kept [default: the dataset's kinematics_params xacro argument].",
    ),
    folds: int = typer.Option(
        5,
        "--folds",
        callback=opt.int_range(0, 20),
        help="k of the k-fold cross-validation that chooses the parameter set and scores it (0 or 1: none).",
    ),
    select: bool = typer.Option(
        True,
        "--select/--no-select",
        help="Fit the parameter set that cross-validation chooses among hand-eye only, zero offsets, "
        "offsets + origin rotations and all of --params; --no-select fits --params as given.",
    ),
    nested: bool = typer.Option(
        True,
        "--nested/--no-nested",
        help="Also score the choice itself on poses it never saw (nested cross-validation, about k times slower).",
    ),
    allow_nominal: bool = typer.Option(
        False,
        "--allow-nominal",
        help="Exit 0 when nothing beats the nominal robot on held-out poses (calibrated.urdf is still not written).",
    ),
    keep_conventions: bool = typer.Option(
        False,
        "--keep-conventions",
        help="Fit measured poses or points as declared even when another reading of the file fits far better.",
    ),
    criterion: Criterion = typer.Option(
        Criterion.COMBINED,
        "--criterion",
        help="What chooses the parameter set on held-out poses: combined (position and rotation, each divided by "
        "its noise) or position (measured poses and points).",
    ),
) -> None:
    """Calibrate: per-joint origin corrections and zero offsets, with the sensor and target frames."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from rich.markup import escape

    from armtool.calib.fit.calibration import FitOptions
    from armtool.calib.outputs.report import json_summary
    from armtool.calib.pipeline import FitRequest, fit_files, observe_samples, prepare_fit, run_fit, write_files
    from armtool.console import stderr, write_stdout
    from armtool.output.calibrate import print_fit_report

    robot = opt.RobotOptions(xacro_arg, package_path, config)
    options = FitOptions.requested(
        params, holdout=holdout, seed=seed, folds=folds, select=select, nested=nested, criterion=criterion
    )
    opt.check_out_dir(out)
    request = FitRequest(
        dataset,
        out,
        options,
        validation=validation,
        plot=plot,
        xacro_args=robot.given_args,
        package_paths=robot.package_paths,
        ur_kinematics=ur_kinematics,
        ur_kinematics_in=ur_kinematics_in,
        keep_conventions=keep_conventions,
    )
    job = prepare_fit(request)
    observed = observe_samples(job, _detect)
    status = stderr().status("fitting")
    with status:
        result = run_fit(job, observed, progress=lambda msg: status.update(msg))
    written = fit_files(job, result)
    if written.truth_warning:
        stderr().print(f"[yellow]warning:[/yellow] {escape(written.truth_warning)}")
    write_files(written.files, out)
    if output_format is ReportFormat.JSON:
        write_stdout(json.dumps(json_summary(written.document), indent=2))
    print_fit_report(job, result, written)
    if not written.verdict.improves and not (allow_nominal or options.hand_eye_only):
        raise typer.Exit(ExitCode.FINDINGS)


@app.command("simulate")
def simulate(
    urdf: Path = typer.Argument(..., help="Nominal URDF (or xacro) of the robot."),
    out: Path = typer.Option(..., "--out", "-o", help="New directory for the dataset (truth goes to OUT/truth/)."),
    base: str | None = typer.Option(None, "--base", help="Base link (default: the root)."),
    flange: str | None = typer.Option(
        None, "--flange", help="Link the tag (or camera) is mounted on (default: end of the longest chain)."
    ),
    samples: int = typer.Option(
        60, "--samples", callback=opt.int_range(3, MAX_SIMULATED), help=f"Images to render (3 to {MAX_SIMULATED})."
    ),
    validation: int = typer.Option(
        30,
        "--validation",
        callback=opt.int_range(1, MAX_SIMULATED),
        help=f"Extra poses kept in truth/ to score a calibration (1 to {MAX_SIMULATED}).",
    ),
    setup: Setup = typer.Option(
        Setup.EYE_TO_HAND, "--setup", help="Camera fixed (eye_to_hand) or on the flange (eye_in_hand)."
    ),
    quality: Quality = typer.Option(Quality.TYPICAL, "--quality", help="Image blur, noise and contrast."),
    tag_size: float = typer.Option(
        0.08,
        "--tag-size",
        callback=opt.finite_float(TAG_SIZE_M[0], TAG_SIZE_M[1], unit="m"),
        help="Edge of the black square, m (0.001 to 2).",
    ),
    bad_samples: int = typer.Option(
        0,
        "--bad-samples",
        callback=opt.int_range(0, MAX_SIMULATED),
        help="Wrong rows to mix in (joint off by 5°, mislabeled image; at most a quarter of --samples).",
    ),
    distortion: bool = typer.Option(False, "--distortion", help="Give the camera lens distortion."),
    target: str | None = typer.Option(
        None,
        "--target",
        help="A board instead of the AprilTag, spelled as for `calibrate camera --board`: chessboard:COLSxROWS:SQUARE, "
        "charuco:COLSxROWS:SQUARE:MARKER[:DICT] or aprilgrid:COLSxROWS:TAG:GAP[:FAMILY] (metres).",
    ),
    seed: int = typer.Option(0, "--seed", callback=opt.seed(), help="Random seed (any integer)."),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    config: RobotConfig = None,
) -> None:
    """Write a synthetic dataset with known injected errors (truth kept apart), to rehearse a pose set."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from armtool.calib.simulation.simulate import SimulationSpec
    from armtool.calib.simulation.simulate import simulate as run
    from armtool.calib.targets.spec import fit_board
    from armtool.console import progress_bar, say

    opt.check_out_dir(out)
    opt.check_chain_ends(base, flange)
    robot = opt.RobotOptions(xacro_arg, package_path, config)
    args = robot.xacro_args(urdf)
    spec = SimulationSpec(
        samples=samples,
        validation=validation,
        setup=setup,
        seed=seed,
        quality=quality,
        tag_size_m=tag_size,
        bad_samples=bad_samples,
        distortion=distortion,
        xacro_args=args,
        package_paths=tuple(robot.package_paths),
        board=fit_board(target, "--target") if target is not None else None,
    )
    with progress_bar() as bar:
        task = bar.add_task("rendering", total=samples)
        summary = run(urdf, out, base, flange, spec, progress=lambda done, total: bar.update(task, completed=done))
    say(f"wrote {samples} images and dataset.yaml to {out}; ground truth in {out / 'truth'}")
    if summary["bad_samples"]:
        say(f"bad samples mixed in: {summary['bad_samples']}")


from armtool.cli import calibrate_apply, calibrate_extra, calibrate_handeye  # noqa: E402  (apply; camera, import-bag; handeye)

calibrate_extra.register(app)
calibrate_handeye.register(app)
calibrate_apply.register(app)
