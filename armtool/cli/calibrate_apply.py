"""`armtool calibrate apply`: joint readings turned into the chosen calibration's joint values and
flange poses, with the joint terms a URDF cannot hold.

Registered on the `calibrate` Typer app by `register(app)` (see armtool/cli/calibrate.py).
"""

from __future__ import annotations

from pathlib import Path

import typer

from armtool.cli import options as opt
from armtool.cli.options import PackagePaths, XacroArgs
from armtool.extras import require


def apply(
    calibration: Path = typer.Argument(
        ..., help="calibration.yaml that `calibrate fit` wrote (calibrated_with_terms.urdf beside it)."
    ),
    readings: Path = typer.Argument(
        ..., help="CSV of joint readings: a header naming the chain's joints, one row each."
    ),
    out: Path = typer.Option(
        ...,
        "--out",
        "-o",
        help="CSV to write: the readings' joint values for calibrated_with_terms.urdf, and the flange pose.",
    ),
    degrees: bool = typer.Option(False, "--degrees", help="The readings (and the values written) are in degrees."),
    dataset: Path | None = typer.Option(
        None,
        "--dataset",
        help="The dataset the calibration was fitted on, if it moved [default: as calibration.yaml records it].",
    ),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
) -> None:
    """Apply a calibration's joint terms to joint readings: each joint's value gain·q + Σ p·f(q) − its mean correction for calibrated_with_terms.urdf, and the flange pose it gives."""
    require("calib")  # exit 2 with the install command when the extra is missing
    from armtool.calib.apply import applied_csv
    from armtool.calib.apply import apply as apply_terms
    from armtool.console import say
    from armtool.fileio import check_output_paths, write_atomic

    given = opt.parse_xacro_args(xacro_arg)
    check_output_paths({"--out": out}, [calibration, readings])
    result = apply_terms(calibration, readings, degrees, dataset, given or None, list(package_path or ()))
    write_atomic(out, applied_csv(result, degrees))
    say(
        f"wrote {out}: {len(result.rows)} readings, the joint values for calibrated_with_terms.urdf and its flange poses"
    )


def register(app: typer.Typer) -> None:
    """Add `apply` to the `calibrate` app."""
    app.command("apply")(apply)
