"""`armtool calibrate check|fit|simulate`: kinematic calibration from AprilTag images."""

from __future__ import annotations

import json
import math
from enum import Enum
from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer

from armtool.calib.limits import MAX_SIMULATED, TAG_SIZE_M
from armtool.cli import options as opt
from armtool.errors import ArmtoolError, ExitCode
from armtool.extras import require

if TYPE_CHECKING:
    from armtool.calib.camera import CameraModel
    from armtool.calib.dataset import Dataset
    from armtool.calib.fit import CalibrationResult
    from armtool.calib.model import Family
    from armtool.calib.observations import Observation
    from armtool.model.chain import Chain

app = typer.Typer(
    help="Fit a real arm's kinematic errors from AprilTag images and write a corrected URDF.",
    no_args_is_help=True,
    add_completion=False,
    context_settings={"help_option_names": ["-h", "--help"]},
)


class SetupOption(str, Enum):
    EYE_TO_HAND = "eye_to_hand"
    EYE_IN_HAND = "eye_in_hand"


class QualityOption(str, Enum):
    GOOD = "good"
    TYPICAL = "typical"
    POOR = "poor"


class ReportFormat(str, Enum):
    TEXT = "text"
    JSON = "json"


def _families(text: str) -> tuple[Family, ...]:
    from armtool.calib.model import Family

    out = []
    for part in [p.strip() for p in text.split(",") if p.strip()]:
        try:
            out.append(Family(part))
        except ValueError:
            raise ArmtoolError(
                f"unknown parameter family '{part}' in --params", hint="choose from: origins, offsets, gains"
            ) from None
    if not out:
        raise ArmtoolError("--params is empty", hint="e.g. --params origins,offsets")
    return tuple(dict.fromkeys(out))


XACRO_ARG_HELP = "xacro argument NAME:=VALUE for a .xacro robot (repeatable; overrides the dataset's robot.xacro_args)."
PACKAGE_PATH_HELP = "Directory holding ROS packages for package:// and $(find) (repeatable; searched before the dataset's robot.package_paths)."


def _load(
    dataset: Path, xacro_args: dict[str, str] | None = None, package_paths: list[Path] | None = None
) -> tuple[Dataset, Chain | None, CameraModel | None]:
    """Dataset, chain and camera: the manifest first, then the chain it names, then the samples
    checked against the chain's joints. Command-line xacro arguments and package paths are merged
    over the dataset's own (robot.xacro_args, robot.package_paths)."""
    from armtool.calib.camera import load_intrinsics
    from armtool.calib.dataset import Problem, load_dataset, read_samples
    from armtool.calib.files import unreadable_reason
    from armtool.model.chain import load_chain

    ds = load_dataset(dataset, with_samples=False)
    ds.xacro_args, ds.package_paths = ds.robot_sources(xacro_args, package_paths)
    chain = camera = None
    if ds.base_link and ds.base_link == ds.flange_link:
        ds.problems.append(
            Problem(
                "dataset.yaml",
                f"robot.base_link and robot.flange_link are the same link '{ds.base_link}': the chain between them has no joints",
                "robot.flange_link names the link the tag (or camera) is mounted on, robot.base_link the robot's fixed base",
            )
        )
    elif unreadable_reason(ds.urdf) is None and ds.base_link and ds.flange_link:
        try:
            chain = load_chain(
                ds.urdf, ds.base_link, ds.flange_link, xacro_args=ds.xacro_args, package_paths=ds.package_paths
            )
        except ArmtoolError as exc:
            ds.problems.append(Problem(str(ds.urdf.name), exc.what, exc.hint or ""))
    read_samples(ds, chain.joint_names if chain is not None else None)
    if chain is not None and ds.joints and set(ds.joints) != set(chain.joint_names):
        ds.problems.append(
            Problem(
                "dataset.yaml",
                f"robot.joints {sorted(ds.joints)} differ from the chain's moving joints {chain.joint_names}",
                f"list the joints between {ds.base_link} and {ds.flange_link}",
            )
        )
    if unreadable_reason(ds.intrinsics) is None:
        try:
            camera = load_intrinsics(ds.intrinsics)
            if ds.images_rectified:
                camera = camera.without_distortion()
        except ArmtoolError as exc:
            ds.problems.append(
                Problem(Path(exc.where).name if exc.where else ds.intrinsics.name, exc.what, exc.hint or "")
            )
    return ds, chain, camera


def _detect(ds: Dataset, camera: CameraModel) -> dict[str, Observation]:
    from armtool.calib.observations import observe
    from armtool.console import progress_bar

    with progress_bar() as bar:
        task = bar.add_task("detecting tags" if ds.corners_file is None else "reading corners", total=len(ds.samples))
        return observe(ds, camera, progress=lambda done, total: bar.update(task, completed=done))


@app.command("check")
def check(
    dataset: Path = typer.Argument(..., help="Dataset directory (with dataset.yaml)."),
    detect: bool = typer.Option(True, "--detect/--no-detect", help="Also look for the tag in every image."),
    xacro_arg: list[str] = typer.Option([], "--xacro-arg", help=XACRO_ARG_HELP),
    package_path: list[Path] = typer.Option([], "--package-path", help=PACKAGE_PATH_HELP),
) -> None:
    """Validate a dataset: files, joints, units, images, and the tag in every image."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from rich.markup import escape

    from armtool.calib.dataset import Problem
    from armtool.cli.lint import _parse_xacro_args
    from armtool.console import stderr

    ds, chain, camera = _load(dataset, _parse_xacro_args(xacro_arg), list(package_path))
    if detect and chain is not None and camera is not None and ds.samples:
        found = 0
        for sid, ob in _detect(ds, camera).items():
            if ob.corners_px is None:
                row = next(s.row for s in ds.samples if s.id == sid)
                ds.problems.append(Problem(f"samples.csv:{row}", f"sample {sid}: {ob.reason}", severity="warning"))
            else:
                found += 1
        if found < max(3, len(ds.samples) // 2):
            ds.problems.append(
                Problem(
                    "dataset.yaml",
                    f"tag {ds.tag_id} ({ds.family}) was usable in only {found} of {len(ds.samples)} samples",
                    "check target.family, target.id and the images (the warnings above say what was seen)",
                )
            )
    out = stderr()
    for p in ds.problems:
        color = "red" if p.severity == "error" else "yellow"
        out.print(f"{escape(p.where)}: [{color}]{p.severity}[/{color}]: {escape(p.what)}")
        if p.hint:
            out.print(f"  [dim]hint:[/dim] {escape(p.hint)}")
    errors = len(ds.errors)
    warnings = len(ds.problems) - errors
    out.print(f"{len(ds.samples)} samples, {errors} error(s), {warnings} warning(s)")
    if errors:
        raise typer.Exit(ExitCode.FINDINGS)


@app.command("fit")
def fit(
    dataset: Path = typer.Argument(..., help="Dataset directory (with dataset.yaml)."),
    out: Path = typer.Option(..., "--out", "-o", help="Directory for calibrated.urdf and calibration.yaml."),
    params: str | None = typer.Option(
        None,
        "--params",
        help="Kinematic parameter families to fit: origins, offsets, gains [default: origins,offsets].",
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
    plot: Path | None = typer.Option(None, "--plot", help="Write a PNG of per-sample residuals before and after."),
    output_format: ReportFormat = typer.Option(
        ReportFormat.TEXT, "--format", help="text (report on stderr) or json (summary on stdout)."
    ),
    xacro_arg: list[str] = typer.Option([], "--xacro-arg", help=XACRO_ARG_HELP),
    package_path: list[Path] = typer.Option([], "--package-path", help=PACKAGE_PATH_HELP),
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
) -> None:
    """Calibrate: per-joint origin corrections and zero offsets, with the camera and tag frames."""
    require("calib")  # exit 2 with the install command when the extra is missing
    import numpy as np
    import yaml

    from armtool.calib.dataset import require_ok
    from armtool.calib.fit import FitOptions, calibrate
    from armtool.calib.model import CalibModel
    from armtool.calib.report import calibration_document, residual_plot_png
    from armtool.calib.urdf_out import (
        check_reproduces,
        corrected_text,
        expanded_text,
        joint_corrections,
        relocate_meshes,
    )
    from armtool.cli.lint import _parse_xacro_args
    from armtool.console import stderr, write_stdout
    from armtool.fileio import write_atomic

    explicit = params is not None
    families = _families(params or "origins,offsets")
    cli_args, cli_paths = _parse_xacro_args(xacro_arg), list(package_path)
    _check_out_dir(out)
    if plot is not None and not plot.parent.is_dir():  # at once; the full check follows the dataset's
        raise ArmtoolError("--plot's directory does not exist", str(plot), "create it, or write the plot elsewhere")
    ds, chain, camera = _load(dataset, cli_args, cli_paths)
    require_ok(ds)
    assert chain is not None and camera is not None
    vloaded = _load(validation, cli_args, cli_paths) if validation is not None else None
    ur_joints, ur_hash, ur_source = _ur_inputs(ds, chain, ur_kinematics, ur_kinematics_in)
    _check_fit_outputs(
        out,
        plot,
        ur_kinematics,
        _fit_inputs(ds, vloaded[0] if vloaded else None) + [p for p in (ur_source,) if p is not None],
    )
    observations = _detect(ds, camera)
    samples = list(ds.samples)
    holdout_ids: set[str] | None = None
    if validation is not None and vloaded is not None:
        vds, vchain, vcamera = vloaded
        require_ok(vds)
        _same_setup(ds, chain, camera, vds, vchain, vcamera, validation)
        from dataclasses import replace

        from armtool.calib.observations import Observation

        vobs = _detect(vds, vcamera or camera)  # _same_setup refused a missing or different camera
        for s in vds.samples:
            sid = f"validation:{s.id}"
            samples.append(replace(s, id=sid))
            o = vobs[s.id]
            observations[sid] = Observation(sid, o.corners_px, o.reason)
        holdout_ids = {s.id for s in samples if s.id.startswith("validation:")}
    from armtool.calib.fit import split_holdout

    if holdout and holdout_ids is None:
        usable = [s.id for s in samples if observations[s.id].corners_px is not None]
        holdout_ids = split_holdout(usable, holdout, seed)
    elif holdout and holdout_ids is not None:
        usable = [s.id for s in samples if observations[s.id].corners_px is not None and s.id not in holdout_ids]
        holdout_ids |= split_holdout(usable, holdout, seed)

    model = CalibModel(chain, ds.setup, np.eye(4), np.eye(4))
    status = stderr().status("fitting")
    with status:
        result = calibrate(
            model,
            camera,
            samples,
            observations,
            ds.size_m,
            FitOptions(families=families, families_explicit=explicit, holdout=holdout, seed=seed),
            ds.hints,
            holdout_ids=holdout_ids,
            progress=lambda msg: status.update(msg),
        )
    # Everything computed and checked first; then each file is written atomically.
    text = expanded_text(ds.urdf, ds.xacro_args, ds.package_paths)
    new_urdf = relocate_meshes(
        corrected_text(text, joint_corrections(result.model, result.x), ds.urdf.name), ds.urdf.parent, out
    )
    check_reproduces(new_urdf, result.model, result.x, ds.urdf.name)
    doc = calibration_document(result, str(dataset), ds.urdf.name)
    truth_scores = _truth_scores(dataset, result)
    if truth_scores:
        doc["against_truth"] = truth_scores
    outputs: dict[Path, str | bytes] = {
        out / "calibrated.urdf": new_urdf,
        out / "calibration.yaml": yaml.safe_dump(doc, sort_keys=False, allow_unicode=True),
    }
    if plot is not None:
        outputs[plot] = residual_plot_png(result)
    if ur_kinematics is not None and ur_joints is not None and ur_hash is not None:
        from armtool.calib.ur_kinematics import ur_kinematics_yaml

        outputs[ur_kinematics] = ur_kinematics_yaml(new_urdf, ur_joints, ur_hash, "calibrated.urdf")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ArmtoolError(
            f"cannot create --out: {exc.strerror or exc}", str(out), "check the path and its permissions"
        ) from None
    for path, data in outputs.items():
        write_atomic(path, data)
    if output_format is ReportFormat.JSON:
        summary = {
            k: doc[k]
            for k in (
                "setup",
                "frames",
                "identifiability",
                "zero_offsets",
                "metrics",
                "outliers",
                "rejected",
                "warnings",
            )
        }
        summary["schema_version"] = 1
        if truth_scores:
            summary["against_truth"] = truth_scores
        write_stdout(json.dumps(summary, indent=2))
    _print_report(result, truth_scores, out, plot)
    if ur_kinematics is not None:
        stderr().print(f"wrote {ur_kinematics}: pass it to the UR description as kinematics_params:={ur_kinematics}")


def _ur_inputs(
    ds: Dataset, chain: Chain, out: Path | None, given: Path | None
) -> tuple[dict[str, str] | None, str | None, Path | None]:
    """For --ur-kinematics, checked before the fit: the chain is a UR arm's, and the hash to keep
    (from --ur-kinematics-in, or the file the dataset's kinematics_params xacro argument names)."""
    from armtool.calib.ur_kinematics import kinematics_params_path, read_hash, ur_joint_names

    if out is None:
        if given is not None:
            raise ArmtoolError(
                "--ur-kinematics-in needs --ur-kinematics", hint="add --ur-kinematics FILE for the calibrated file"
            )
        return None, None, None
    if out.parent != Path("") and not out.parent.is_dir():
        raise ArmtoolError(
            "--ur-kinematics's directory does not exist", str(out), "create it, or write the file elsewhere"
        )
    joints = ur_joint_names(chain.joint_names, str(ds.urdf))
    if given is None:
        value = ds.xacro_args.get("kinematics_params")
        if value is None:
            raise ArmtoolError(
                "--ur-kinematics needs the robot's current kinematics file, to keep its hash",
                hint="pass --ur-kinematics-in FILE (the robot's default_kinematics.yaml, or ur_calibration's output), "
                "or --xacro-arg kinematics_params:=FILE",
            )
        given = kinematics_params_path(value, ds.root, ds.package_paths)
    return joints, read_hash(given), given


def _check_out_dir(out: Path, flag: str = "--out") -> None:
    """Before any work: `out` is a directory we may write into, or can be created (its nearest
    existing ancestor is a writable directory)."""
    import os

    for p in (out, *out.absolute().parents):
        if not p.exists():
            continue
        if not p.is_dir():
            what = "is a file" if p.is_file() else "is not a directory"
            raise ArmtoolError(f"{flag} cannot be a directory: {p} {what}", str(out), "pass a directory path")
        if not os.access(p, os.W_OK | os.X_OK):
            raise ArmtoolError(
                f"{flag}: directory {p} is not writable", str(out), "check its permissions, or write somewhere else"
            )
        return


def _check_chain_ends(base: str | None, tip: str | None, base_name: str, tip_name: str, where: str = "") -> None:
    """Base and tip must be two links: the same name twice is a chain of no joints, reported
    here instead of as "no moving joint between 'r' and 'r'"."""
    if base is not None and base == tip:
        raise ArmtoolError(
            f"{base_name} and {tip_name} are the same link '{base}': the chain between them has no joints",
            where or None,
            f"{tip_name} names the link the tag (or camera) is mounted on, {base_name} the robot's fixed base",
        )


def _fit_inputs(*datasets: Dataset | None) -> list[Path]:
    """Every file a fit reads: the outputs must not overwrite any of them."""
    files: list[Path] = []
    for ds in datasets:
        if ds is None:
            continue
        files += [ds.root / "dataset.yaml", ds.urdf, ds.intrinsics]
        files += [p for p in (ds.samples_file, ds.corners_file) if p is not None]
        files += [s.image for s in ds.samples if s.image is not None]
    return files


def _check_fit_outputs(out: Path, plot: Path | None, ur_kinematics: Path | None, inputs: list[Path]) -> None:
    """Every file fit writes, checked against the run's inputs before the work starts."""
    from armtool.fileio import check_output_paths

    outputs: dict[str, Path | None] = {"--plot": plot, "--ur-kinematics": ur_kinematics}
    if out.is_dir():  # else created by the fit: nothing in it can be an input
        outputs = {
            "--out (calibrated.urdf)": out / "calibrated.urdf",
            "--out (calibration.yaml)": out / "calibration.yaml",
            **outputs,
        }
    check_output_paths(outputs, inputs)


def _same_setup(
    ds: Dataset,
    chain: Chain,
    camera: CameraModel,
    vds: Dataset,
    vchain: Chain | None,
    vcamera: CameraModel | None,
    where: Path,
) -> None:
    """A validation dataset must share the robot chain, setup, camera and tag, or its residuals mean nothing."""
    import numpy as np

    differences = []
    if vchain is None or vchain.joint_names != chain.joint_names:
        differences.append("robot chain (joints)")
    if vds.setup != ds.setup:
        differences.append(f"setup ({vds.setup.value} vs {ds.setup.value})")
    if (
        vcamera is None
        or (vcamera.width, vcamera.height) != (camera.width, camera.height)
        or not np.allclose(vcamera.K, camera.K)
        or not np.allclose(np.resize(vcamera.dist, 5), np.resize(camera.dist, 5))
    ):
        differences.append("camera intrinsics")
    if (vds.family, vds.tag_id, vds.size_m) != (ds.family, ds.tag_id, ds.size_m):
        differences.append("target (family, id or size)")
    if differences:
        raise ArmtoolError(
            "the validation dataset differs from the dataset in: " + ", ".join(differences),
            str(where),
            "validate with poses of the same robot, camera and tag (a second session of the same setup)",
        )


def _truth_scores(dataset: Path, result: CalibrationResult) -> dict[str, Any] | None:
    """For simulated datasets only: errors against the known true robot on its validation poses."""
    from rich.markup import escape

    from armtool.calib.truth import load_truth, score

    if not (dataset / "truth" / "truth.yaml").is_file():
        return None
    try:
        truth = load_truth(dataset, result.model)
    except ArmtoolError as exc:  # only a score: never lose the fit for it
        from armtool.console import stderr

        stderr().print(f"[yellow]warning:[/yellow] not scored against the truth: {escape(str(exc))}")
        return None
    before, after = score(result.model, result.x_handeye, truth), score(result.model, result.x, truth)
    named = sorted(set(truth.bad_samples) & set(result.outliers))
    return {
        "validation_poses": int(len(truth.validation)),
        "hand_eye_only": before.__dict__,
        "calibrated": after.__dict__,
        "improvement": before.position_rms_mm / after.position_rms_mm if after.position_rms_mm > 0 else math.inf,
        "bad_samples": truth.bad_samples,
        "bad_samples_named": named,
    }


def _print_report(result: CalibrationResult, truth: dict[str, Any] | None, out: Path, plot: Path | None) -> None:
    from rich.markup import escape
    from rich.table import Table

    from armtool.console import stderr

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
    setup: SetupOption = typer.Option(
        SetupOption.EYE_TO_HAND, "--setup", help="Camera fixed (eye_to_hand) or on the flange (eye_in_hand)."
    ),
    quality: QualityOption = typer.Option(QualityOption.TYPICAL, "--quality", help="Image blur, noise and contrast."),
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
    seed: int = typer.Option(0, "--seed", callback=opt.seed(), help="Random seed (any integer)."),
    xacro_arg: list[str] = typer.Option([], "--xacro-arg", help="xacro argument NAME:=VALUE (repeatable)."),
    package_path: list[Path] = typer.Option(
        [], "--package-path", help="Directory holding ROS packages for package:// and $(find) (repeatable)."
    ),
) -> None:
    """Write a synthetic dataset with known injected errors (truth kept apart), to rehearse a pose set."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from armtool.calib.model import Setup
    from armtool.calib.simulate import SimulationSpec
    from armtool.calib.simulate import simulate as run
    from armtool.cli.lint import _parse_xacro_args
    from armtool.console import progress_bar, stderr
    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml

    _check_out_dir(out)
    _check_chain_ends(base, flange, "--base", "--flange")
    args, paths = _parse_xacro_args(xacro_arg), list(package_path)
    if base is None or flange is None:
        chain = chain_from_xml(load_robot_xml(urdf, args, paths), base, flange, source=urdf.name)
        base, flange = chain.base, chain.tip
    spec = SimulationSpec(
        samples=samples,
        validation=validation,
        setup=Setup(setup.value),
        seed=seed,
        quality=quality.value,
        tag_size_m=tag_size,
        bad_samples=bad_samples,
        distortion=distortion,
        xacro_args=args,
        package_paths=tuple(paths),
    )
    with progress_bar() as bar:
        task = bar.add_task("rendering", total=samples)
        summary = run(urdf, out, base, flange, spec, progress=lambda done, total: bar.update(task, completed=done))
    stderr().print(f"wrote {samples} images and dataset.yaml to {out}; ground truth in {out / 'truth'}")
    if summary["bad_samples"]:
        stderr().print(f"bad samples mixed in: {summary['bad_samples']}")


from armtool.cli import calibrate_extra  # noqa: E402  (`calibrate camera` and `calibrate import-bag`)

calibrate_extra.register(app)
