"""`armtool calibrate camera|import-bag`: camera intrinsics from board images, datasets from ROS bags.

Registered on the `calibrate` Typer app by `register(app)` (see armtool/cli/calibrate.py).
"""

from __future__ import annotations

import json
from pathlib import Path

import typer

from armtool.calib.choices import DistortionModel, ReportFormat, Setup, StillBy
from armtool.calib.limits import MAX_IMAGES, MAX_TAG_ID, TAG_SIZE_M
from armtool.cli import options as opt
from armtool.errors import ArmtoolError
from armtool.extras import require

BOARD_HELP = (
    "The printed board: chessboard:COLSxROWS:SQUARE (squares, not inner corners; metres), "
    "charuco:COLSxROWS:SQUARE:MARKER[:DICT] (squares, metres; DICT default DICT_6X6_250) "
    "or aprilgrid:COLSxROWS:TAG:GAP[:FAMILY] (tags, metres; FAMILY default tag36h11)."
)


def camera(
    images: list[Path] = typer.Argument(..., help="Images of the board (files, or directories of images)."),
    board: str = typer.Option(..., "--board", help=BOARD_HELP),
    out: Path = typer.Option(
        ...,
        "--out",
        "-o",
        help="Intrinsics file to write (OpenCV FileStorage YAML, for dataset.yaml's camera.intrinsics).",
    ),
    distortion: DistortionModel = typer.Option(
        DistortionModel.PLUMB_BOB,
        "--distortion",
        help="Distortion coefficients to fit: none, k1k2 (k1 k2 p1 p2), plumb_bob (+k3), rational (k1..k6 p1 p2).",
    ),
    min_images: int = typer.Option(
        10,
        "--min-images",
        callback=opt.int_range(3, MAX_IMAGES),
        help=f"Fewest images in which the board must be found (3 to {MAX_IMAGES}).",
    ),
    output_format: ReportFormat = typer.Option(
        ReportFormat.TEXT, "--format", help="text (report on stderr) or json (summary on stdout)."
    ),
) -> None:
    """Fit camera intrinsics and lens distortion from images of a chessboard, a ChArUco board or an AprilTag grid."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from armtool.calib.fit.intrinsics import calibrate_images, image_paths, write_intrinsics
    from armtool.calib.targets.boards import parse_board
    from armtool.console import progress_bar, write_stdout
    from armtool.fileio import check_output_paths
    from armtool.output.calibrate import print_camera_report

    spec = parse_board(board)
    paths = image_paths(images)
    check_output_paths({"--out": out}, paths)
    with progress_bar() as bar:
        task = bar.add_task("finding the board", total=len(paths))
        result = calibrate_images(
            paths,
            spec,
            distortion,
            min_images,
            progress=lambda done, total: bar.update(task, completed=done),
        )
    write_intrinsics(result, spec, out)
    if output_format is ReportFormat.JSON:
        write_stdout(json.dumps(result.summary(spec, out), indent=2))
    print_camera_report(result, spec, out)


def import_bag(
    bag: Path = typer.Argument(
        ..., help="ROS 1 .bag file, or ROS 2 bag directory (.db3 or .mcap storage; its metadata.yaml is needed)."
    ),
    image_topic: str = typer.Option(
        ..., "--image-topic", help="sensor_msgs/Image or sensor_msgs/CompressedImage topic."
    ),
    urdf: Path = typer.Option(..., "--urdf", help="The robot's URDF (or xacro), copied into the dataset."),
    out: Path = typer.Option(..., "--out", "-o", help="New dataset directory (armtool-calib-dataset/1)."),
    tag_size: float | None = typer.Option(
        None,
        "--tag-size",
        callback=opt.finite_float(TAG_SIZE_M[0], TAG_SIZE_M[1], unit="m"),
        help="Edge of the tag's black square, metres (measure the print; 0.001 to 2). Required unless --target names a board.",
    ),
    joints_topic: str = typer.Option("/joint_states", "--joints-topic", help="sensor_msgs/JointState topic."),
    base: str | None = typer.Option(None, "--base", help="Base link (default: the URDF's root)."),
    flange: str | None = typer.Option(
        None, "--flange", help="Link the tag (or camera) is mounted on (default: end of the longest chain)."
    ),
    intrinsics: Path | None = typer.Option(
        None,
        "--intrinsics",
        help="Camera intrinsics file to copy in (default: from a CameraInfo topic beside the image topic).",
    ),
    camera_info_topic: str | None = typer.Option(
        None,
        "--camera-info-topic",
        help="sensor_msgs/CameraInfo topic (default: camera_info beside the image topic, if recorded).",
    ),
    setup: Setup = typer.Option(
        Setup.EYE_TO_HAND, "--setup", help="Camera fixed (eye_to_hand) or on the flange (eye_in_hand)."
    ),
    family: str = typer.Option("tag36h11", "--family", help="AprilTag family."),
    tag_id: int = typer.Option(0, "--tag-id", callback=opt.int_range(0, MAX_TAG_ID), help="AprilTag id."),
    still_by: StillBy = typer.Option(
        StillBy.POSITION,
        "--still-by",
        help="Settled means: every joint within --tolerance (position) or below --max-velocity (velocity field of the messages).",
    ),
    tolerance: float = typer.Option(
        0.002,
        "--tolerance",
        callback=opt.positive_float(1.0, unit="rad"),
        help="Largest position change of any joint within a settled window, rad (or m).",
    ),
    max_velocity: float = typer.Option(
        0.01,
        "--max-velocity",
        callback=opt.positive_float(10.0, unit="rad/s"),
        help="With --still-by velocity: largest |velocity| of any joint, rad/s (or m/s).",
    ),
    min_still: float = typer.Option(
        0.5, "--min-still", callback=opt.seconds(3600.0), help="Shortest settled window, seconds."
    ),
    max_image_offset: float = typer.Option(
        0.8,
        "--max-image-offset",
        callback=opt.finite_float(0.0, 1.0),
        help="Farthest the chosen image may be from its settled window's centre, as a fraction of the half-window "
        "(0 = centre, 1 = edge); a window whose images are all farther is skipped (beyond 0.5 a warning).",
    ),
    target: str | None = typer.Option(
        None,
        "--target",
        help="The images show this board instead of an AprilTag (as `calibrate camera --board`; --tag-size, "
        "--family and --tag-id are then not used).",
    ),
    output_format: ReportFormat = typer.Option(
        ReportFormat.TEXT, "--format", help="text (report on stderr) or json (summary on stdout)."
    ),
    xacro_arg: opt.XacroArgs = None,
    package_path: opt.PackagePaths = None,
    config: opt.RobotConfig = None,
) -> None:
    """Turn a ROS bag (images + joint states) into a calibration dataset: one sample per settled pose."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from armtool.calib.inputs.bag_import import ImportOptions
    from armtool.calib.inputs.bag_import import import_bag as run
    from armtool.calib.targets.spec import named_target
    from armtool.console import stderr, write_stdout
    from armtool.output.calibrate import print_bag_report

    opt.check_out_dir(out)
    opt.check_chain_ends(base, flange)
    robot = opt.RobotOptions(xacro_arg, package_path, config)
    if out.exists() and not out.is_dir():
        raise ArmtoolError("--out exists and is not a directory", str(out), "pass a new directory name")
    options = ImportOptions(
        image_topic=image_topic,
        joints_topic=joints_topic,
        base=base,
        flange=flange,
        intrinsics=intrinsics,
        camera_info_topic=camera_info_topic,
        setup=setup,
        target=named_target(target, tag_size, family, tag_id),
        still_by=still_by,
        tolerance=tolerance,
        max_velocity=max_velocity,
        min_still_s=min_still,
        max_image_offset=max_image_offset,
        xacro_args=tuple(robot.xacro_args(urdf).items()),
        package_paths=tuple(robot.package_paths),
    )
    with stderr().status("reading the bag"):
        result = run(bag, urdf, out, options)
    if output_format is ReportFormat.JSON:
        write_stdout(json.dumps(result.summary(), indent=2))
    print_bag_report(result)


def register(app: typer.Typer) -> None:
    """Add `camera` and `import-bag` to the `calibrate` app."""
    app.command("camera")(camera)
    app.command("import-bag")(import_bag)
