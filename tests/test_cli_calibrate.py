"""`armtool calibrate simulate|check|fit` end to end on the bundled arm, and bad input."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.model.chain import load_chain

ROOT = Path(__file__).resolve().parents[1]
CLEAN_ARM = ROOT / "fixtures" / "robots" / "clean_arm" / "urdf" / "clean_arm.urdf"
runner = CliRunner()


def armtool(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "armtool", *args], capture_output=True, text=True, cwd=ROOT)


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("calib") / "ds"
    result = runner.invoke(
        app,
        [
            "calibrate",
            "simulate",
            str(CLEAN_ARM),
            "--flange",
            "tool0",
            "-o",
            str(out),
            "--samples",
            "30",
            "--validation",
            "20",
            "--bad-samples",
            "2",
            "--seed",
            "1",
        ],
    )
    assert result.exit_code == 0, result.output
    return out


def test_simulate_writes_a_dataset_and_keeps_the_truth_apart(dataset: Path) -> None:
    assert {p.name for p in dataset.iterdir()} == {
        "dataset.yaml",
        "robot.urdf",
        "camera.yaml",
        "samples.csv",
        "images",
        "truth",
    }
    assert len(list((dataset / "images").glob("*.png"))) == 30
    assert {p.name for p in (dataset / "truth").iterdir()} == {"truth.yaml", "robot_true.urdf", "validation.csv"}
    assert "truth" not in (dataset / "dataset.yaml").read_text()


def test_check_passes_on_a_good_dataset(dataset: Path) -> None:
    result = runner.invoke(app, ["calibrate", "check", str(dataset)])
    assert result.exit_code == 0, result.output


def test_check_of_an_image_dataset_leaves_the_fit_alone(dataset: Path) -> None:
    # Only measured poses or points need the convention check's fits; images do not (SciPy's
    # optimizer doubled check's CPU time when it came in regardless).
    probe = (
        "import sys\nfrom armtool.cli import main\n"
        f"sys.argv = ['armtool', 'calibrate', 'check', {str(dataset)!r}, '--no-detect']\n"
        "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
        "print(sorted(m for m in ('armtool.calib.fit', 'armtool.calib.pipeline', 'scipy.optimize') if m in sys.modules))\n"
    )
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().splitlines()[-1] == "[]"


def test_fit_end_to_end(dataset: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = runner.invoke(
        app,
        [
            "calibrate",
            "fit",
            str(dataset),
            "--out",
            str(out),
            "--holdout",
            "0.2",
            "--format",
            "json",
            "--plot",
            str(tmp_path / "res.png"),
        ],
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    truth = summary["against_truth"]
    assert truth["calibrated"]["position_rms_mm"] < 0.15 and truth["improvement"] > 25
    assert set(truth["bad_samples"]) <= set(summary["outliers"])
    assert summary["identifiability"]["identified"] == 30
    # One bad sample falls in the hold-out here: it is named, the plain hold-out RMS shows it, and
    # the figure without hold-out outliers shows the calibration itself.
    metrics = summary["metrics"]
    assert metrics["holdout_without_outliers_rms_px"]["calibrated"] < 0.3 < metrics["holdout_rms_px"]["calibrated"]
    assert (tmp_path / "res.png").read_bytes()[:4] == b"\x89PNG"
    # The corrected URDF keeps joint names and comments, and has the fitted kinematics.
    text = (out / "calibrated.urdf").read_text()
    assert "<!-- The root carries no inertia (KDL ignores it there). -->" in text
    import yaml

    doc = yaml.safe_load((out / "calibration.yaml").read_text())
    assert doc["format"] == "armtool-calibration/1" and set(doc["joints"]) == {f"joint{i}" for i in range(1, 7)}
    # calibrated.urdf is the calibrated robot: registered on the validation poses it matches the
    # true robot (written by simulate) to the same accuracy as the fitted model.
    from armtool.calib.simulation.truth import registered_errors

    calibrated = load_chain(out / "calibrated.urdf", "base_link", "tool0")
    true = load_chain(dataset / "truth" / "robot_true.urdf", "base_link", "tool0")
    nominal = load_chain(CLEAN_ARM, "base_link", "tool0")
    assert true.joint_names == calibrated.joint_names
    Q = true.random(np.random.default_rng(5), 30)
    F_true = np.stack([true.fk(q) for q in Q])
    after = registered_errors(np.stack([calibrated.fk(q) for q in Q]), F_true)
    before = registered_errors(np.stack([nominal.fk(q) for q in Q]), F_true)
    assert after.position_rms_mm < 0.3 < 2.0 < before.position_rms_mm
    lint = armtool("lint", str(out / "calibrated.urdf"))
    assert "error" not in lint.stdout, lint.stdout


def test_missing_dataset_is_exit_2(tmp_path: Path) -> None:
    result = armtool("calibrate", "fit", str(tmp_path / "nope"), "--out", str(tmp_path / "o"))
    assert result.returncode == 2 and "no dataset.yaml" in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "o").exists()


def test_degrees_in_csv_is_exit_2_and_nothing_written(dataset: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad"
    shutil.copytree(dataset, bad)
    lines = (bad / "samples.csv").read_text().splitlines()
    head, *rows = lines
    rows = [",".join(r.split(",")[:2] + [f"{float(v) * 57.3:.3f}" for v in r.split(",")[2:]]) for r in rows]
    (bad / "samples.csv").write_text("\n".join([head, *rows]) + "\n")
    result = armtool("calibrate", "fit", str(bad), "--out", str(tmp_path / "o"))
    assert result.returncode == 2 and "look like degrees" in result.stderr and "samples.csv:" in result.stderr
    assert not (tmp_path / "o").exists()
    check = armtool("calibrate", "check", str(bad), "--no-detect")
    assert check.returncode == 1 and "look like degrees" in check.stderr


def test_unknown_joint_column(dataset: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad"
    shutil.copytree(dataset, bad)
    text = (bad / "samples.csv").read_text().replace("joint6", "joint_6", 1)
    (bad / "samples.csv").write_text(text)
    result = armtool("calibrate", "check", str(bad))
    assert result.returncode == 1
    assert "joint6" in result.stderr and "samples.csv:1" in result.stderr


def test_missing_image_is_reported_by_check(dataset: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad"
    shutil.copytree(dataset, bad)
    (bad / "images" / "0004.png").write_bytes(b"not a png")
    result = armtool("calibrate", "check", str(bad))
    assert result.returncode == 0  # one unreadable image is a warning: the fit can do without it
    assert "samples.csv:6" in result.stderr and "cannot read image" in result.stderr


def test_tag_never_found_is_an_error(dataset: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad"
    shutil.copytree(dataset, bad)
    text = (bad / "dataset.yaml").read_text().replace("id: 0\n", "id: 5\n", 1)
    (bad / "dataset.yaml").write_text(text)
    check = armtool("calibrate", "check", str(bad))
    assert check.returncode == 1 and "usable in only 0 of 30" in check.stderr and "found ids: 0" in check.stderr
    fit = armtool("calibrate", "fit", str(bad), "--out", str(tmp_path / "o"))
    assert fit.returncode == 2 and "tag 5 not found (found ids: 0)" in fit.stderr
    assert not (tmp_path / "o").exists()


def test_bad_output_paths_fail_before_the_work(dataset: Path, tmp_path: Path) -> None:
    (tmp_path / "file").write_text("x")
    r = armtool("calibrate", "fit", str(dataset), "--out", str(tmp_path / "file" / "sub"))
    assert r.returncode == 2 and "is a file" in r.stderr
    r = armtool(
        "calibrate", "fit", str(dataset), "--out", str(tmp_path / "o"), "--plot", str(tmp_path / "nodir" / "p.png")
    )
    assert r.returncode == 2 and "--plot's directory does not exist" in r.stderr
    assert not (tmp_path / "o").exists()


def test_validation_dataset_of_another_setup_is_refused(dataset: Path, tmp_path: Path) -> None:
    other = tmp_path / "other"
    r = runner.invoke(
        app,
        [
            "calibrate",
            "simulate",
            str(CLEAN_ARM),
            "--flange",
            "tool0",
            "-o",
            str(other),
            "--samples",
            "10",
            "--validation",
            "2",
            "--setup",
            "eye_in_hand",
        ],
    )
    assert r.exit_code == 0, r.output
    fit = armtool("calibrate", "fit", str(dataset), "--out", str(tmp_path / "o"), "--validation", str(other))
    assert fit.returncode == 2 and "setup (eye_in_hand vs eye_to_hand)" in fit.stderr
    # ... refused while the inputs are checked, before any tag detection on the main dataset
    from armtool.calib.fit.calibration import FitOptions
    from armtool.calib.model.params import parse_families
    from armtool.calib.pipeline import FitRequest, prepare_fit
    from armtool.errors import ArmtoolError

    request = FitRequest(dataset, tmp_path / "o", FitOptions(parse_families("origins")), validation=other)
    with pytest.raises(ArmtoolError, match="setup"):
        prepare_fit(request)


def test_empty_params_is_refused(dataset: Path, tmp_path: Path) -> None:
    result = armtool("calibrate", "fit", str(dataset), "--out", str(tmp_path / "o"), "--params", "")
    assert result.returncode == 2 and "--params is empty" in result.stderr


def test_output_paths_with_brackets_are_printed_as_they_are(dataset: Path, tmp_path: Path) -> None:
    out = tmp_path / "run[/b]"
    result = armtool("calibrate", "fit", str(dataset), "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert f"wrote {out / 'calibrated.urdf'}" in " ".join(result.stderr.split())


def test_unknown_params_family(dataset: Path, tmp_path: Path) -> None:
    result = armtool("calibrate", "fit", str(dataset), "--out", str(tmp_path / "o"), "--params", "origins,lengths")
    assert result.returncode == 2 and "unknown parameter family 'lengths'" in result.stderr


def test_simulate_refuses_a_non_empty_directory(tmp_path: Path) -> None:
    (tmp_path / "x").write_text("keep me")
    result = armtool("calibrate", "simulate", str(CLEAN_ARM), "-o", str(tmp_path), "--samples", "5")
    assert result.returncode == 2 and "not empty" in result.stderr
    assert (tmp_path / "x").read_text() == "keep me"


def test_eye_in_hand_simulate_and_fit(tmp_path: Path) -> None:
    ds = tmp_path / "eih"
    result = runner.invoke(
        app,
        [
            "calibrate",
            "simulate",
            str(CLEAN_ARM),
            "--flange",
            "tool0",
            "-o",
            str(ds),
            "--samples",
            "30",
            "--validation",
            "15",
            "--setup",
            "eye_in_hand",
            "--seed",
            "2",
        ],
    )
    assert result.exit_code == 0, result.output
    result = runner.invoke(app, ["calibrate", "fit", str(ds), "--out", str(tmp_path / "o"), "--format", "json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert "camera_in_flange" in summary["frames"] and summary["against_truth"]["calibrated"]["position_rms_mm"] < 0.15


def test_fit_from_pre_detected_corners(dataset: Path, tmp_path: Path) -> None:
    """corners.csv from another detector feeds the same solver; the images are not needed."""
    from armtool.calib.inputs.dataset import load_dataset
    from armtool.calib.inputs.observations import observe
    from armtool.calib.model.camera import load_intrinsics

    ds = load_dataset(dataset)
    observations = observe(ds, load_intrinsics(ds.intrinsics), workers=1)
    copy = tmp_path / "corners_only"
    shutil.copytree(dataset, copy, ignore=shutil.ignore_patterns("images"))
    rows = ["id,tag_id,u0,v0,u1,v1,u2,v2,u3,v3"]
    for sid, ob in observations.items():
        if ob.corners_px is not None:
            rows.append(f"{sid},0," + ",".join(f"{v:.4f}" for v in ob.corners_px.ravel()))
    (copy / "corners.csv").write_text("\n".join(rows) + "\n")
    result = runner.invoke(app, ["calibrate", "fit", str(copy), "--out", str(tmp_path / "o"), "--format", "json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["against_truth"]["calibrated"]["position_rms_mm"] < 0.15


# -- xacro robots, package paths and mesh paths (issue 10 items 15 and 17) ------------------------

REALWORLD = ROOT / ".." / "shared" / "realworld"
UR_XACRO = REALWORLD / "Universal_Robots_ROS2_Description" / "urdf" / "ur.urdf.xacro"


def _xacro_arm(tmp: Path) -> tuple[Path, Path]:
    """clean_arm as a xacro that needs an argument (no default), a package found only through a
    package path (its directory is not named after it), and a relative mesh path."""
    parts = tmp / "parts_dir"
    parts.mkdir(parents=True)
    (parts / "package.xml").write_text("<package><name>calib_test_parts</name></package>\n")
    (parts / "tool.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:property name="tool_z" value="$(arg tool_length)"/></robot>\n'
    )
    robot_dir = tmp / "robot" / "urdf"
    (robot_dir / "meshes").mkdir(parents=True)
    (robot_dir / "meshes" / "base.stl").write_bytes(b"solid base\nendsolid base\n")
    text = CLEAN_ARM.read_text()
    text = text.replace(
        '<robot name="clean_arm">',
        '<robot name="clean_arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:include filename="$(find calib_test_parts)/tool.xacro"/>',
    )
    text = text.replace("package://clean_arm/meshes/base.stl", "meshes/base.stl")
    tool = text.index('<joint name="tool0_joint"')
    origin = text.index("<origin", tool)
    end = text.index("/>", origin)
    text = text[:origin] + '<origin xyz="0 0 ${tool_z}" rpy="0 0 0"' + text[end:]
    xacro = robot_dir / "arm.urdf.xacro"
    xacro.write_text(text)
    return xacro, parts


def test_simulate_takes_xacro_args_and_package_paths(tmp_path: Path) -> None:
    xacro, parts = _xacro_arm(tmp_path)
    out = tmp_path / "ds"
    bare = armtool("calibrate", "simulate", str(xacro), "--flange", "tool0", "-o", str(out), "--samples", "4")
    assert bare.returncode == 2 and "Traceback" not in bare.stderr
    for option in ("--xacro-arg", "--package-path"):  # the hint names options this command has
        if option in bare.stderr:
            assert option in armtool("calibrate", "simulate", "--help").stdout
    ok = runner.invoke(
        app,
        [
            "calibrate",
            "simulate",
            str(xacro),
            "--flange",
            "tool0",
            "-o",
            str(out),
            "--samples",
            "12",
            "--validation",
            "2",
            "--xacro-arg",
            "tool_length:=0.1",
            "--package-path",
            str(parts),
        ],
    )
    assert ok.exit_code == 0, ok.output
    robot = (out / "robot.urdf").read_text()
    assert 'xyz="0 0 0.1"' in robot
    # The dataset's robot.urdf lives elsewhere: its relative mesh path must still find the file.
    import re

    mesh = re.search(r'<mesh filename="([^"]+)"', robot).group(1)  # type: ignore[union-attr]
    assert (out / mesh).resolve() == (xacro.parent / "meshes" / "base.stl").resolve()


def test_check_and_fit_take_xacro_args_from_the_dataset_and_the_command_line(dataset: Path, tmp_path: Path) -> None:
    import yaml

    xacro, parts = _xacro_arm(tmp_path)
    ds = tmp_path / "ds"
    shutil.copytree(dataset, ds)
    manifest = yaml.safe_load((ds / "dataset.yaml").read_text())
    manifest["robot"]["urdf"] = str(Path("..") / xacro.relative_to(tmp_path))
    (ds / "dataset.yaml").write_text(yaml.safe_dump(manifest))
    missing = armtool("calibrate", "check", str(ds), "--no-detect")
    # The package is found only through --package-path: the hint names that option, which check has.
    assert missing.returncode == 1 and "--package-path" in missing.stderr
    help_text = armtool("calibrate", "check", "--help").stdout
    assert "--xacro-arg" in help_text and "--package-path" in help_text
    cli = armtool(
        "calibrate", "check", str(ds), "--no-detect", "--xacro-arg", "tool_length:=0.1", "--package-path", str(parts)
    )
    assert cli.returncode == 0, cli.stderr
    # The dataset names them (package paths relative to the dataset); the command line overrides.
    manifest["robot"]["xacro_args"] = {"tool_length": 0.1}
    manifest["robot"]["package_paths"] = [str(Path("..") / "parts_dir")]
    (ds / "dataset.yaml").write_text(yaml.safe_dump(manifest))
    assert armtool("calibrate", "check", str(ds), "--no-detect").returncode == 0
    out = tmp_path / "out"
    fit = runner.invoke(app, ["calibrate", "fit", str(ds), "--out", str(out), "--xacro-arg", "tool_length:=0.1"])
    assert fit.exit_code == 0, fit.output
    calibrated = load_chain(out / "calibrated.urdf", "base_link", "tool0")
    assert calibrated.n == 6
    import re

    mesh = re.search(r'<mesh filename="([^"]+)"', (out / "calibrated.urdf").read_text()).group(1)  # type: ignore[union-attr]
    assert (out / mesh).resolve() == (xacro.parent / "meshes" / "base.stl").resolve()
    # The command line wins over the dataset: its bad value breaks the expansion that the
    # dataset's 0.1 makes work.
    wrong = armtool("calibrate", "check", str(ds), "--no-detect", "--xacro-arg", "tool_length:=oops")
    assert wrong.returncode != 0


@pytest.mark.skipif(not UR_XACRO.is_file(), reason="shared/realworld corpus absent")
def test_simulate_on_the_ur_xacro_with_its_documented_arguments(tmp_path: Path) -> None:
    out = tmp_path / "ur"
    bare = armtool("calibrate", "simulate", str(UR_XACRO), "--flange", "tool0", "-o", str(out), "--samples", "4")
    assert bare.returncode == 2 and "--xacro-arg" in bare.stderr and not out.exists()
    ok = runner.invoke(
        app,
        [
            "calibrate",
            "simulate",
            str(UR_XACRO),
            "--flange",
            "tool0",
            "-o",
            str(out),
            "--samples",
            "6",
            "--validation",
            "2",
            "--xacro-arg",
            "name:=ur",
            "--xacro-arg",
            "ur_type:=ur5e",
        ],
    )
    assert ok.exit_code == 0, ok.output
    text = (out / "robot.urdf").read_text()
    assert "package://ur_description/meshes/ur5e/" in text  # package:// kept as the source had it


# -- UR calibration YAML (issue 12 part 3) -----------------------------------------------------------

UR_KINEMATICS = REALWORLD / "Universal_Robots_ROS2_Description" / "config" / "ur5e" / "default_kinematics.yaml"


def test_ur_kinematics_on_a_non_ur_arm_is_refused_before_the_work(dataset: Path, tmp_path: Path) -> None:
    given = tmp_path / "kin.yaml"
    given.write_text("kinematics:\n  hash: calib_1\n")
    r = armtool(
        "calibrate",
        "fit",
        str(dataset),
        "--out",
        str(tmp_path / "o"),
        "--ur-kinematics",
        str(tmp_path / "ur.yaml"),
        "--ur-kinematics-in",
        str(given),
    )
    assert r.returncode == 2 and "needs a Universal Robots arm" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "o").exists() and not (tmp_path / "ur.yaml").exists()


@pytest.mark.skipif(not UR_XACRO.is_file(), reason="shared/realworld corpus absent")
def test_ur_kinematics_yaml_reproduces_the_fit_through_the_ur_xacro(tmp_path: Path) -> None:
    import yaml

    from armtool.model.chain import chain_from_xml
    from armtool.model.load import load_robot_xml

    ds = tmp_path / "ur"
    ok = runner.invoke(
        app,
        [
            "calibrate",
            "simulate",
            str(UR_XACRO),
            "--flange",
            "tool0",
            "-o",
            str(ds),
            "--samples",
            "16",
            "--validation",
            "2",
            "--xacro-arg",
            "name:=ur",
            "--xacro-arg",
            "ur_type:=ur5e",
            "--seed",
            "3",
        ],
    )
    assert ok.exit_code == 0, ok.output
    # The dataset names the UR xacro itself, with its arguments: the hash comes from kinematics_params.
    manifest = yaml.safe_load((ds / "dataset.yaml").read_text())
    manifest["robot"]["urdf"] = str(UR_XACRO.resolve())
    manifest["robot"]["xacro_args"] = {
        "name": "ur",
        "ur_type": "ur5e",
        "kinematics_params": str(UR_KINEMATICS.resolve()),
    }
    (ds / "dataset.yaml").write_text(yaml.safe_dump(manifest))
    written = tmp_path / "my_robot_calibration.yaml"
    fit = runner.invoke(
        app, ["calibrate", "fit", str(ds), "--out", str(tmp_path / "o"), "--ur-kinematics", str(written)]
    )
    assert fit.exit_code == 0, fit.output
    doc = yaml.safe_load(written.read_text())["kinematics"]
    assert doc["hash"] == yaml.safe_load(UR_KINEMATICS.read_text())["kinematics"]["hash"]
    assert list(doc) == ["shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3", "hash"]
    assert "kinematics_params:=" in written.read_text()
    # The UR description expanded with the written file is the calibrated robot.
    expanded = chain_from_xml(
        load_robot_xml(UR_XACRO, {"name": "ur", "ur_type": "ur5e", "kinematics_params": str(written)}),
        "base_link",
        "tool0",
        source="ur.urdf.xacro",
    )
    calibrated = load_chain(tmp_path / "o" / "calibrated.urdf", "base_link", "tool0")
    nominal = chain_from_xml(
        load_robot_xml(UR_XACRO, {"name": "ur", "ur_type": "ur5e"}), "base_link", "tool0", source="ur.urdf.xacro"
    )
    Q = calibrated.random(np.random.default_rng(0), 20)
    worst = max(float(np.abs(expanded.fk(q) - calibrated.fk(q)).max()) for q in Q)
    moved = max(float(np.abs(nominal.fk(q) - calibrated.fk(q))[:3, 3].max()) for q in Q)
    assert worst < 1e-9 and moved > 1e-4


def test_simulate_error_is_the_first_line_on_stderr(tmp_path: Path) -> None:
    # Into a pipe, a progress bar started before the chain was checked left an empty line first.
    result = armtool("calibrate", "simulate", str(CLEAN_ARM), "--flange", "nope", "-o", str(tmp_path / "ds"))
    assert result.returncode == 2 and result.stderr.startswith("error: tip link 'nope'"), result.stderr
