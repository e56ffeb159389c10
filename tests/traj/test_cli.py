"""`armtool traj` end to end: the lecture's three exercises, every output checked by `traj check`,
bad input as exit 2 with nothing written, and the check's output formats."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError

from .helpers import CLEAN_LIMITS, CLEAN_URDF, START

runner = CliRunner()
U, JL = str(CLEAN_URDF), str(CLEAN_LIMITS)
CART = ("cartesian", U, "--base", "base_link", "--tip", "tool0", "--start", START)  # the clean arm from START


def invoke(*args: str, stdin: str | None = None) -> tuple[int, str, str]:
    result = runner.invoke(app, ["traj", *args], input=stdin)
    if isinstance(result.exception, ArmtoolError):
        return 2, result.stdout, str(result.exception)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    return result.exit_code, result.stdout, result.stderr


def passes_check(path: Path) -> None:
    code, out, err = invoke("check", str(path), "--urdf", U, "--joint-limits", JL)
    assert code == 0, out + err


def circle(tmp_path: Path, *extra: str) -> Path:
    out = tmp_path / "circle.csv"
    code, _, err = invoke(
        *CART,
        "--center-offset",
        "0,-0.1,0",
        "--normal",
        "1,0,0",
        "-o",
        str(out),
        *extra,
    )
    assert code == 0, err
    return out


def test_circle_time_check_plot(tmp_path: Path) -> None:
    path = circle(tmp_path)
    passes_check(path)
    timed = tmp_path / "circle.yaml"
    code, _, err = invoke("time", str(path), "--urdf", U, "--joint-limits", JL, "-o", str(timed))
    assert code == 0, err
    assert "sec:" in timed.read_text() and "nanosec:" in timed.read_text()  # .yaml: ROS 2 JointTrajectory
    passes_check(timed)
    png = tmp_path / "circle.png"
    code, _, err = invoke(
        "plot", str(timed), "--urdf", U, "--joint-limits", JL, "--base", "base_link", "--tip", "tool0", "-o", str(png)
    )
    assert code == 0, err
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
    assert width > 1000 and height > 1000  # 6 joints x 3 quantities and the tool path


def test_time_follows_a_shape_preserving_cubic_where_the_spline_would_leave_the_limits(tmp_path: Path) -> None:
    path = tmp_path / "near_limit.csv"
    rows = ["joint1_rad,joint2_rad,joint3_rad,joint4_rad,joint5_rad,joint6_rad"]
    rows += [f"{a},{b},0,0,0,0" for a, b in [(0, 0), (0.05, 1.9), (0.3, 1.999), (1.5, 1.0)]]  # joint2's limit: 2
    path.write_text("\n".join(rows) + "\n")
    timed = tmp_path / "timed.csv"
    code, _, err = invoke("time", str(path), "--urdf", U, "--joint-limits", JL, "-o", str(timed))
    assert code == 0, err  # refused before: "the smooth path ... leaves joint 'joint2' limits"
    assert "interpolation: shape-preserving cubic (PCHIP) for 'joint2'" in " ".join(err.split())
    passes_check(timed)


def test_thin_retime_and_join_outputs_pass_check(tmp_path: Path) -> None:
    path = circle(tmp_path)
    thinned = tmp_path / "thin.csv"
    assert invoke("thin", str(path), "--every", "4", "--urdf", U, "--joint-limits", JL, "-o", str(thinned))[0] == 0
    passes_check(thinned)
    slow = tmp_path / "slow.json"
    code, _, err = invoke("retime", str(thinned), "--scale", "0.25", "--urdf", U, "--joint-limits", JL, "-o", str(slow))
    assert code == 0, err
    passes_check(slow)
    line = tmp_path / "line.csv"
    last = thinned.read_text().splitlines()[-1].split(",")[1:7]
    code, _, err = invoke(
        "cartesian",
        U,
        "--base",
        "base_link",
        "--tip",
        "tool0",
        "--start",
        ",".join(last),
        "--line",
        "0,0,-0.05",
        "--relative",
        "-o",
        str(line),
    )
    assert code == 0, err
    joined = tmp_path / "joined.csv"
    code, _, err = invoke(
        "join", str(thinned), str(line), "--urdf", U, "--joint-limits", JL, "-o", str(joined), "--to", "ros1"
    )
    assert code == 0, err
    assert "secs:" in joined.read_text()
    passes_check(joined)


def test_pipe_through_stdin(tmp_path: Path) -> None:
    text = circle(tmp_path).read_text()
    code, out, err = invoke("time", "-", "--urdf", U, "--acc-limit", "5", stdin=text)
    assert code == 0, err
    assert out.startswith("time_s,joint1_rad,")


@pytest.mark.parametrize(
    "args, what",
    [
        (
            [*CART, "--center-offset", "0,0,0"],
            "radius",
        ),
        ([*CART, "--radius", "0"], "radius"),
        (
            [*CART, "--line", "3,0,0"],
            "nothing written",
        ),
        (["retime", "PATH", "--scale", "0"], "--scale must be > 0"),
        (["retime", "PATH", "--scale", "-2"], "--scale must be > 0"),
        (["retime", "PATH", "--scale", "inf"], "finite"),
        (["thin", "PATH", "--tolerance", "nan"], "finite"),
        (["join", "PATH", "PATH", "--tolerance", "-1"], "≥ 0"),
        (["time", "PATH", "--urdf", U, "--joint-limits", JL, "--velocity-scaling", "1.5"], "≤ 1"),
        (["time", "ONE", "--urdf", U, "--joint-limits", JL], "at least two points"),
        (["time", "NAN", "--urdf", U, "--joint-limits", JL], "nan"),
        (["time", "PATH", "--urdf", U], "acceleration limit"),
        (["join", "PATH", "OTHER", "--urdf", U, "--joint-limits", JL], "away from where"),
    ],
)
def test_bad_input_exits_2_and_writes_nothing(tmp_path: Path, args: list[str], what: str) -> None:
    path = circle(tmp_path)
    files = {"PATH": str(path)}
    one = tmp_path / "one.csv"
    one.write_text("joint1_rad,joint2_rad\n0,0\n")
    nan = tmp_path / "nan.csv"
    nan.write_text("joint1_rad,joint2_rad\n0,0\nnan,1\n")
    other = tmp_path / "other.csv"
    other.write_text(path.read_text().replace("\n0.0,-0.6,", "\n0.3,-0.6,", 1))
    files.update(ONE=str(one), NAN=str(nan), OTHER=str(other))
    out = tmp_path / "out.csv"
    code, _, err = invoke(*[files.get(a, a) for a in args], "-o", str(out))
    assert code == 2
    assert what in err.lower() or what in err
    assert not out.exists()


@pytest.mark.parametrize("fmt", ["text", "json", "sarif", "github"])
def test_check_formats_and_exit_code(tmp_path: Path, fmt: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text("time_s,joint1_rad\n0,0\n0.1,1.0\n0.2,0.0\n")
    code, out, _ = invoke("check", str(path), "--urdf", U, "--joint-limits", JL, "--format", fmt)
    assert code == 1
    assert "T301" in out
    if fmt in ("json", "sarif"):
        doc = json.loads(out)
        if fmt == "sarif":
            assert doc["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["region"]["startLine"] == 3
    assert invoke("check", str(path), "--urdf", U, "--joint-limits", JL, "--exit-zero")[0] == 0


def test_check_unknown_joint(tmp_path: Path) -> None:
    path = tmp_path / "bad.csv"
    path.write_text("time_s,elbow_rad\n0,0\n1,0.1\n")
    code, out, _ = invoke("check", str(path), "--urdf", U)
    assert code == 1 and "T601" in out


def test_waypoints_and_arc(tmp_path: Path) -> None:
    start = [float(v) for v in START.split(",")]
    from armtool.model.chain import load_chain

    p = load_chain(CLEAN_URDF, "base_link", "tool0").fk(__import__("numpy").array(start))[:3, 3]
    wp = tmp_path / "poses.csv"
    wp.write_text("x_m,y_m,z_m\n" + f"{p[0]},{p[1] - 0.05},{p[2]}\n{p[0]},{p[1] - 0.05},{p[2] - 0.05}\n")
    out = tmp_path / "wp.csv"
    png = tmp_path / "wp.png"
    code, _, err = invoke(
        *CART,
        "--waypoints",
        str(wp),
        "-o",
        str(out),
        "--plot",
        str(png),
    )
    assert code == 0, err
    assert png.read_bytes()[:4] == b"\x89PNG"
    assert len(out.read_text().splitlines()) >= 11
    arc = tmp_path / "arc.json"
    code, _, err = invoke(
        *CART,
        "--arc-via",
        f"{p[0]},{p[1] - 0.05},{p[2] + 0.05}",
        "--arc-to",
        f"{p[0]},{p[1] - 0.1},{p[2]}",
        "-o",
        str(arc),
    )
    assert code == 0, err
    assert json.loads(arc.read_text())["joint_names"][0] == "joint1"
    bad = tmp_path / "bad_poses.csv"
    bad.write_text("x_m,y_m,z_m\n0.1,nan,0.2\n")
    code, _, err = invoke(
        *CART,
        "--waypoints",
        str(bad),
        "-o",
        str(out),
    )
    assert code == 2 and "bad_poses.csv:2" in err


def test_trajectory_pipes_into_servo_lut_apply(tmp_path: Path) -> None:
    from .helpers import ROOT

    lut = tmp_path / "lut.json"
    result = runner.invoke(app, ["servo-lut", "fit", str(ROOT / "fixtures/servo/lut/ax12a_meas.csv"), "-o", str(lut)])
    assert result.exit_code == 0
    code, timed, err = invoke("time", str(circle(tmp_path)), "--urdf", U, "--joint-limits", JL)
    assert code == 0, err
    result = runner.invoke(
        app, ["servo-lut", "apply", str(lut), "-", "--column", "joint1_rad", "--zero-deg", "150"], input=timed
    )
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[0].endswith(",joint1_command_ticks")


def test_cartesian_plot_of_an_unknown_format_is_refused_before_the_path(tmp_path: Path) -> None:
    out = tmp_path / "line.csv"
    code, _, err = invoke(*CART, "--line", "0,-0.05,0", "--relative", "-o", str(out), "--plot", str(tmp_path / "p.bmp"))
    assert code == 2 and "--plot names a file with '.bmp'" in err and "PNG, SVG or PDF" in err, err
    assert not out.exists()


def test_plot_of_an_untimed_path(tmp_path: Path) -> None:
    path = circle(tmp_path)
    for name, signature in (("path.png", b"\x89PNG\r\n\x1a\n"), ("path.svg", b"<?xml"), ("path.pdf", b"%PDF-")):
        code, _, err = invoke("plot", str(path), "--urdf", U, "-o", str(tmp_path / name))
        assert code == 0, err
        assert (tmp_path / name).read_bytes().startswith(signature)
    code, _, err = invoke("plot", str(path), "--urdf", U, "-o", str(tmp_path / "x.jpg"))
    assert code == 2 and "-o names a file with '.jpg'" in err and "PNG, SVG or PDF" in err
    assert not (tmp_path / "x.jpg").exists()


def test_retime_over_the_limits_with_urdf_writes_nothing(tmp_path: Path) -> None:
    timed = tmp_path / "timed.csv"
    assert invoke("time", str(circle(tmp_path)), "--urdf", U, "--joint-limits", JL, "-o", str(timed))[0] == 0
    out = tmp_path / "fast.csv"
    code, _, err = invoke("retime", str(timed), "--scale", "2", "--urdf", U, "--joint-limits", JL, "-o", str(out))
    assert code == 2 and "smaller --scale" in err and not out.exists()
    assert invoke("retime", str(timed), "--scale", "2", "-o", str(out))[0] == 0  # unchecked without --urdf
    code, text, _ = invoke("check", str(out), "--urdf", U, "--joint-limits", JL)
    assert code == 1 and "T301" in text


def test_time_with_jerk_limits_plans_them_and_passes_check_with_them(tmp_path: Path) -> None:
    jl = tmp_path / "jl.yaml"
    jl.write_text(
        CLEAN_LIMITS.read_text().replace(
            "has_acceleration_limits: true", "has_jerk_limits: true, max_jerk: 50, has_acceleration_limits: true"
        )
    )
    path = circle(tmp_path)
    plain, jerky = tmp_path / "plain.csv", tmp_path / "jerky.csv"
    assert invoke("time", str(path), "--urdf", U, "--joint-limits", JL, "-o", str(plain))[0] == 0
    code, _, err = invoke("time", str(path), "--urdf", U, "--joint-limits", str(jl), "-o", str(jerky))
    assert code == 0 and "jerk-limited" in err, err
    # The time-optimal timing breaks the jerk limit; the jerk-limited one passes check with it.
    code, out, _ = invoke("check", str(plain), "--urdf", U, "--joint-limits", str(jl))
    assert code == 1 and "T303" in out
    code, out, err = invoke("check", str(jerky), "--urdf", U, "--joint-limits", str(jl))
    assert code == 0, out + err
    # The same from --jerk-limit on the command line.
    code, _, err = invoke("time", str(path), "--urdf", U, "--joint-limits", JL, "--jerk-limit", "50", "-o", str(jerky))
    assert code == 0 and "jerk-limited" in err
    assert invoke("check", str(jerky), "--urdf", U, "--joint-limits", str(jl))[0] == 0


def test_output_that_is_an_input_is_refused_and_the_input_kept(tmp_path: Path) -> None:
    path = circle(tmp_path)
    before = path.read_bytes()
    timed = tmp_path / "timed.yaml"
    assert invoke("time", str(path), "--urdf", U, "--joint-limits", JL, "-o", str(timed))[0] == 0
    timed_before = timed.read_bytes()
    for args in (
        ["thin", str(path), "--every", "4", "-o", str(path)],
        ["retime", str(timed), "--scale", "0.5", "-o", str(timed)],
        ["time", str(path), "--urdf", U, "--joint-limits", JL, "-o", str(path)],
        ["join", str(timed), str(path), "-o", str(path)],
        ["plot", str(path), "--urdf", U, "-o", str(path)],
    ):
        code, _, err = invoke(*args)
        assert code == 2 and "input" in err, (args, err)
    assert path.read_bytes() == before and timed.read_bytes() == timed_before
    urdf = tmp_path / "arm.urdf"
    urdf.write_bytes(CLEAN_URDF.read_bytes())
    code, _, err = invoke(
        "cartesian",
        str(urdf),
        "--base",
        "base_link",
        "--tip",
        "tool0",
        "--start",
        START,
        "--center-offset",
        "0,-0.1,0",
        "--plot",
        str(urdf),
    )
    assert code == 2 and urdf.read_bytes() == CLEAN_URDF.read_bytes()


def test_bad_output_path_is_refused_before_the_work(tmp_path: Path) -> None:
    out = tmp_path / "path.csv"
    code, stdout, err = invoke(
        *CART,
        "--center-offset",
        "0,-0.1,0",
        "-o",
        str(out),
        "--plot",
        str(tmp_path / "missing" / "p.png"),
    )
    assert code == 2 and "missing" in err
    assert not out.exists() and stdout == ""
    code, _, err = invoke("thin", str(circle(tmp_path)), "--every", "4", "-o", str(tmp_path))
    assert code == 2 and "director" in err


def _finishes(*args: str) -> tuple[int, str, str]:
    """invoke() in a daemon thread: a read that blocks fails the test instead of hanging it."""
    import threading

    box: list[tuple[int, str, str]] = []
    worker = threading.Thread(target=lambda: box.append(invoke(*args)), daemon=True)
    worker.start()
    worker.join(60)
    assert box, f"traj {args[0]} blocked on a FIFO"
    return box[0]


def test_fifo_inputs_are_refused_without_blocking(tmp_path: Path) -> None:
    import os

    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    code, _, err = _finishes("check", str(fifo), "--urdf", U)
    assert code == 2 and "not a regular file" in err and "fifo.csv" in err
    code, _, err = _finishes(*CART, "--waypoints", str(fifo))
    assert code == 2 and "not a regular file" in err
    code, _, err = _finishes("check", str(circle(tmp_path)), "--urdf", U, "--joint-limits", str(fifo))
    assert code == 2 and "not a regular file" in err


def test_waypoints_that_are_not_utf8_are_an_input_error(tmp_path: Path) -> None:
    wp = tmp_path / "latin1.csv"
    wp.write_bytes("# posé\nx_m,y_m,z_m\n0.1,0.2,0.3\n".encode("latin-1"))
    code, _, err = invoke(*CART, "--waypoints", str(wp))
    assert code == 2 and "UTF-8" in err and "latin1.csv" in err


def test_stdin_output_keeps_the_input_format(tmp_path: Path) -> None:
    timed = tmp_path / "timed.yaml"
    assert invoke("time", str(circle(tmp_path)), "--urdf", U, "--joint-limits", JL, "-o", str(timed))[0] == 0
    code, out, err = invoke("retime", "-", "--scale", "0.5", stdin=timed.read_text())
    assert code == 0, err
    assert "joint_names:" in out and "nanosec:" in out  # ROS 2 YAML in, ROS 2 YAML out (as --help says)


def test_check_sarif_documents_each_code(tmp_path: Path) -> None:
    from armtool.traj.check import CODES

    path = tmp_path / "bad.csv"
    path.write_text("time_s,joint1_rad\n0,0\n0.1,1.0\n0.2,0.0\n")
    doc = json.loads(invoke("check", str(path), "--urdf", U, "--joint-limits", JL, "--format", "sarif")[1])
    driver = doc["runs"][0]["tool"]["driver"]
    assert driver["name"] == "armtool traj check"
    assert [r["id"] for r in driver["rules"]] == list(CODES)
    assert all(r["helpUri"].startswith("https://") for r in driver["rules"])
    result = doc["runs"][0]["results"][0]
    assert driver["rules"][result["ruleIndex"]]["id"] == result["ruleId"] == "T301"


@pytest.mark.parametrize(
    "option, value, what",
    [
        ("--angle", "inf", "finite"),
        ("--angle", "nan", "finite"),
        ("--eef-step", "inf", "finite"),
        ("--precision", "0", "> 0"),
        ("--min-fraction", "2", "≤ 1"),
        ("--solver", "nope", "lm"),
    ],
)
def test_cartesian_numbers_and_solver_checked_at_parse_time(option: str, value: str, what: str) -> None:
    result = runner.invoke(app, ["traj", "cartesian", U, "--center-offset", "0,-0.1,0", option, value])
    text = (str(result.exception) if isinstance(result.exception, ArmtoolError) else "") + result.output
    assert result.exit_code == 2 or isinstance(result.exception, ArmtoolError)
    assert what in text and option in text and "non-zero" not in text


def test_help_shows_brackets_and_solver_choices() -> None:
    # The options are typer Annotated declarations (cli/traj/common.py): their help must still show
    # the brackets rich could take for markup, and --solver lists the solvers.
    wide = {"COLUMNS": "250"}
    time_help = runner.invoke(app, ["traj", "time", "--help"], env=wide).stdout
    assert "JOINT=VALUE[,..]" in time_help and "--jerk-limit" in time_help
    cart_help = runner.invoke(app, ["traj", "cartesian", "--help"], env=wide).stdout
    assert "x_m,y_m,z_m[,roll_rad,pitch_rad,yaw_rad]" in cart_help
    assert "lm|dls|kdl-nr-jl|kdl-lma|trac|analytic" in cart_help


MOVEIT_PACKAGE = Path(__file__).resolve().parents[2] / "fixtures" / "robots" / "clean_arm_moveit_config"


def test_moveit_config_gives_robot_limits_and_scaling(tmp_path: Path) -> None:
    path = circle(tmp_path)
    out = tmp_path / "timed.csv"
    code, _, err = invoke("time", str(path), "--moveit-config", str(MOVEIT_PACKAGE), "-o", str(out))
    assert code == 0, err
    assert "velocity scaling 0.5, acceleration scaling 0.25" in err
    code, out_text, err = invoke("check", str(out), "--moveit-config", str(MOVEIT_PACKAGE))
    assert code == 0, out_text + err


def test_xacro_robot_takes_its_arguments(tmp_path: Path) -> None:
    """traj's hint said "pass --xacro-arg", an option traj did not have."""
    text = CLEAN_URDF.read_text().replace(
        '<robot name="clean_arm">',
        '<robot name="clean_arm" xmlns:xacro="http://www.ros.org/wiki/xacro">',
    )
    xacro = tmp_path / "arm.urdf.xacro"
    xacro.write_text(text.replace('velocity="2.0"', 'velocity="$(arg velocity)"', 1))
    path = circle(tmp_path)
    out = str(tmp_path / "t.csv")
    code, _, err = invoke("time", str(path), "--urdf", str(xacro), "--joint-limits", JL, "-o", out)
    assert code == 2 and "--xacro-arg" in err
    code, _, err = invoke(
        "time", str(path), "--urdf", str(xacro), "--joint-limits", JL, "--xacro-arg", "velocity:=1.5", "-o", out
    )
    assert code == 0, err
