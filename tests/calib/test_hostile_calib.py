"""Hostile input for `armtool calibrate` (issue 14): every finding in its scope as a plain
regression test, then property-based runs over the numeric options and mutated dataset files.

Datasets here are tiny and image-free (corners.csv projected from a known robot), so the whole
file runs in well under a minute. The CLI runs in-process (CliRunner); an exception other than
ArmtoolError or SystemExit is what `armtool.cli.main` would report as "internal error", so it
fails the test. `HOSTILE_EXAMPLES=300` runs the mutated-file property longer (about 90 s).
"""

from __future__ import annotations

import json
import os
import shutil
import struct
import time
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from armtool.cli import app
from armtool.errors import ArmtoolError
from tests.calib.conftest import CLEAN_ARM

runner = CliRunner()
# No shrinking: a fit takes seconds, and the failing example is printed as found.
HYPO = settings(
    max_examples=10,
    deadline=None,
    phases=[Phase.explicit, Phase.reuse, Phase.generate],
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0
JOINTS = ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6"]


def run(*args: object) -> tuple[int, str, str]:
    """Exit code, stdout, error text, as `armtool.cli.main` would give them; any other exception fails."""
    result = runner.invoke(app, [str(a) for a in args])
    exc = result.exception
    if isinstance(exc, ArmtoolError):
        return 2, result.stdout, str(exc)
    if exc is not None and not isinstance(exc, SystemExit):
        raise exc
    return result.exit_code, result.stdout, result.stderr


def strict_json(text: str) -> object:
    """JSON as the standard defines it: NaN and Infinity (which Python accepts) are refused."""

    def refuse(constant: str) -> object:
        raise AssertionError(f"{constant} in JSON output")

    return json.loads(text, parse_constant=refuse)


def snapshot(root: Path) -> dict[Path, bytes]:
    return {p: p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def _write_dataset(root: Path, n: int = 12, seed: int = 0) -> Path:
    """A corners.csv dataset of the bundled arm: n poses, corners projected from a perturbed robot."""
    from armtool.calib.model.camera import save_intrinsics
    from armtool.model.chain import load_chain
    from tests.calib.synthetic import make_problem

    chain = load_chain(CLEAN_ARM, "base_link", "tool0")
    prob = make_problem(chain, n=n, seed=seed)
    root.mkdir(parents=True, exist_ok=True)
    shutil.copy(CLEAN_ARM, root / "robot.urdf")
    save_intrinsics(prob.camera, root / "camera.yaml")
    rows = ["id,image," + ",".join(chain.joint_names)]
    rows += [f"{s.id},," + ",".join(f"{v:.9f}" for v in s.q) for s in prob.samples]
    (root / "samples.csv").write_text("\n".join(rows) + "\n")
    corners = ["id,tag_id,u0,v0,u1,v1,u2,v2,u3,v3"]
    for sid, ob in prob.observations.items():
        assert ob.corners_px is not None
        corners.append(f"{sid},0," + ",".join(f"{v:.4f}" for v in ob.corners_px.ravel()))
    (root / "corners.csv").write_text("\n".join(corners) + "\n")
    (root / "dataset.yaml").write_text(
        "format: armtool-calib-dataset/1\nsetup: eye_to_hand\n"
        f"robot: {{urdf: robot.urdf, base_link: base_link, flange_link: tool0, joints: [{', '.join(chain.joint_names)}], joint_units: rad}}\n"
        "camera: {intrinsics: camera.yaml}\n"
        "target: {type: apriltag, family: tag36h11, id: 0, size_m: 0.08}\n"
        "samples: samples.csv\ncorners: corners.csv\n"
    )
    return root


@pytest.fixture(scope="module")
def base_dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _write_dataset(tmp_path_factory.mktemp("hostile") / "ds")


@pytest.fixture()
def dataset(base_dataset: Path, tmp_path: Path) -> Path:
    """A fresh copy per test, so a test may edit it."""
    return Path(shutil.copytree(base_dataset, tmp_path / "ds"))


def test_the_tiny_dataset_fits_with_a_negative_seed(dataset: Path, tmp_path: Path) -> None:
    """The baseline the other tests break (the image-free dataset is good), and `--seed -1`,
    which was an internal error, works like any other seed."""
    code, out, err = run(
        "calibrate", "fit", dataset, "--out", tmp_path / "out", "--format", "json", "--holdout", "0.25", "--seed", "-1"
    )
    assert code == 0, err
    assert strict_json(out)["schema_version"] == 1  # type: ignore[index]
    assert (tmp_path / "out" / "calibrated.urdf").is_file()


# ---------------------------------------------------------------- 1. files destroyed


def test_fit_refuses_to_write_over_its_own_input(dataset: Path) -> None:
    """`fit DATASET --out DATASET` with the nominal URDF named calibrated.urdf overwrote it."""
    (dataset / "robot.urdf").rename(dataset / "calibrated.urdf")
    text = (dataset / "dataset.yaml").read_text().replace("urdf: robot.urdf", "urdf: calibrated.urdf")
    (dataset / "dataset.yaml").write_text(text)
    before = snapshot(dataset)
    code, _, err = run("calibrate", "fit", dataset, "--out", dataset)
    assert code == 2 and "is also an input" in err and "calibrated.urdf" in err
    assert snapshot(dataset) == before


def test_fit_refuses_a_plot_or_ur_file_over_an_input(dataset: Path, tmp_path: Path) -> None:
    before = snapshot(dataset)
    code, _, err = run("calibrate", "fit", dataset, "--out", tmp_path / "o", "--plot", dataset / "samples.csv")
    assert code == 2 and "--plot" in err and "is also an input" in err
    assert snapshot(dataset) == before and not (tmp_path / "o").exists()


def test_camera_refuses_to_write_over_an_image(tmp_path: Path) -> None:
    image = _png(tmp_path / "shot.png", 32, 24)
    before = image.read_bytes()
    code, _, err = run("calibrate", "camera", image, "--board", "charuco:5x4:0.03:0.022", "-o", image)
    assert code == 2 and "is also an input" in err
    assert image.read_bytes() == before


# ---------------------------------------------------------------- validation of options


@pytest.mark.parametrize(
    "args, flag",
    [
        (["simulate", "x.urdf", "-o", "o", "--tag-size", "inf"], "--tag-size"),
        (["simulate", "x.urdf", "-o", "o", "--tag-size", "nan"], "--tag-size"),
        (["simulate", "x.urdf", "-o", "o", "--tag-size", "-0.08"], "--tag-size"),
        (["simulate", "x.urdf", "-o", "o", "--samples", "100000000"], "--samples"),
        (["simulate", "x.urdf", "-o", "o", "--validation", "0"], "--validation"),
        (["simulate", "x.urdf", "-o", "o", "--bad-samples", "-1"], "--bad-samples"),
        (["fit", "ds", "-o", "o", "--holdout", "nan"], "--holdout"),
        (["fit", "ds", "-o", "o", "--holdout", "0.95"], "--holdout"),
        (
            ["import-bag", "b.bag", "--image-topic", "/i", "--urdf", "r.urdf", "-o", "o", "--tag-size", "inf"],
            "--tag-size",
        ),
        (
            [
                "import-bag",
                "b.bag",
                "--image-topic",
                "/i",
                "--urdf",
                "r.urdf",
                "-o",
                "o",
                "--tag-size",
                "0.08",
                "--tolerance",
                "nan",
            ],
            "--tolerance",
        ),
        (
            [
                "import-bag",
                "b.bag",
                "--image-topic",
                "/i",
                "--urdf",
                "r.urdf",
                "-o",
                "o",
                "--tag-size",
                "0.08",
                "--min-still",
                "inf",
            ],
            "--min-still",
        ),
        (
            [
                "import-bag",
                "b.bag",
                "--image-topic",
                "/i",
                "--urdf",
                "r.urdf",
                "-o",
                "o",
                "--tag-size",
                "0.08",
                "--max-velocity",
                "-1",
            ],
            "--max-velocity",
        ),
        (
            [
                "import-bag",
                "b.bag",
                "--image-topic",
                "/i",
                "--urdf",
                "r.urdf",
                "-o",
                "o",
                "--tag-size",
                "0.08",
                "--tag-id",
                "99999",
            ],
            "--tag-id",
        ),
        (
            ["camera", "x.png", "--board", "charuco:5x4:0.03:0.022", "-o", "c.yaml", "--min-images", "1000000"],
            "--min-images",
        ),
    ],
)
def test_bad_numbers_are_refused_naming_the_flag(args: list[str], flag: str) -> None:
    code, _, err = run("calibrate", *args)
    assert code == 2 and flag in err, err


def test_tag_size_inf_is_a_message_not_an_internal_error(tmp_path: Path) -> None:
    code, _, err = run("calibrate", "simulate", CLEAN_ARM, "-o", tmp_path / "o", "--tag-size", "inf")
    assert code == 2 and "--tag-size must be a finite number" in err
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------- output paths, checked first


def test_out_that_is_a_file_is_a_message(dataset: Path, tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("keep me")
    for args in (
        ["fit", dataset, "--out", blocker],
        ["fit", dataset, "--out", blocker / "sub"],
        ["simulate", CLEAN_ARM, "--flange", "tool0", "-o", blocker],
        [
            "import-bag",
            tmp_path / "b.bag",
            "--image-topic",
            "/i",
            "--urdf",
            CLEAN_ARM,
            "-o",
            blocker,
            "--tag-size",
            "0.08",
        ],
    ):
        code, _, err = run("calibrate", *args)
        assert code == 2 and "file" in err, (args, err)
    assert blocker.read_text() == "keep me"


@pytest.mark.skipif(IS_ROOT, reason="root may write into a read-only directory")
def test_unwritable_out_is_refused_before_the_work(dataset: Path, tmp_path: Path) -> None:
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        for args in (
            ["fit", dataset, "--out", locked / "o"],
            ["fit", dataset, "--out", locked],
            ["simulate", CLEAN_ARM, "--flange", "tool0", "-o", locked / "o"],
            ["camera", _png(tmp_path / "a.png", 8, 8), "--board", "charuco:5x4:0.03:0.022", "-o", locked / "c.yaml"],
            [
                "import-bag",
                tmp_path / "b.bag",
                "--image-topic",
                "/i",
                "--urdf",
                CLEAN_ARM,
                "-o",
                locked / "o",
                "--tag-size",
                "0.08",
            ],
        ):
            t0 = time.monotonic()
            code, _, err = run("calibrate", *args)
            assert code == 2 and "not writable" in err, (args, err)
            assert time.monotonic() - t0 < 5
    finally:
        locked.chmod(0o700)


def test_plot_into_a_missing_directory_fails_before_the_fit(dataset: Path, tmp_path: Path) -> None:
    code, _, err = run("calibrate", "fit", dataset, "--out", tmp_path / "o", "--plot", tmp_path / "no" / "res.png")
    assert code == 2 and "does not exist" in err
    assert not (tmp_path / "o").exists()  # nothing written: the fit never ran


def test_plot_of_an_unknown_format_fails_before_the_fit(dataset: Path, tmp_path: Path) -> None:
    code, _, err = run("calibrate", "fit", dataset, "--out", tmp_path / "o", "--plot", tmp_path / "res.jpg")
    assert code == 2 and "--plot names a file with '.jpg'" in err and "PNG, SVG or PDF" in err
    assert not (tmp_path / "o").exists() and not (tmp_path / "res.jpg").exists()  # the fit never ran


# ---------------------------------------------------------------- files read: internal errors


@pytest.mark.parametrize("name", ["samples.csv", "corners.csv"])
def test_csv_field_over_128_kb_is_named_with_its_line(dataset: Path, name: str) -> None:
    path = dataset / name
    lines = path.read_text().splitlines()
    lines[2] = lines[2] + "," + "9" * 200_000
    path.write_text("\n".join(lines) + "\n")
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and f"{name}:3" in err and "longer than 128 KB" in err, err
    code, _, err = run("calibrate", "fit", dataset, "--out", dataset.parent / "o")
    assert code == 2 and "longer than 128 KB" in err


def test_deeply_nested_yaml_is_a_message(dataset: Path) -> None:
    """camera.yaml nested deeper than Python's recursion limit was an internal error (RecursionError)."""
    (dataset / "camera.yaml").write_text("image_width: 1280\ncamera_matrix: " + "[" * 1200 + "]" * 1200 + "\n")
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and "camera.yaml:2" in err and "nested more than" in err, err
    (dataset / "camera.yaml").write_text("%YAML:1.0\n---\ncamera_matrix: " + "[" * 1200 + "]" * 1200 + "\n")
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and "camera.yaml:3" in err and "nested more than" in err, err


def test_too_many_samples_are_refused(dataset: Path) -> None:
    from armtool.calib.limits import MAX_SAMPLES

    lines = (dataset / "samples.csv").read_text().splitlines()
    extra = [f"x{i},,0,0,0,0,0,0" for i in range(MAX_SAMPLES + 1)]
    (dataset / "samples.csv").write_text("\n".join(lines + extra) + "\n")
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and f"more than {MAX_SAMPLES} samples" in err


def test_dataset_values_are_typed_and_in_range(dataset: Path) -> None:
    manifest = dataset / "dataset.yaml"
    good = manifest.read_text()
    for old, new, expected in [
        ("size_m: 0.08", "size_m: .nan", "target.size_m"),
        ("size_m: 0.08", "size_m: .inf", "target.size_m"),
        ("id: 0", "id: -3", "target.id"),
        ("family: tag36h11", "family: [a]", "target.family"),
        ("{intrinsics: camera.yaml}", "{intrinsics: camera.yaml, images_rectified: maybe}", "images_rectified"),
    ]:
        manifest.write_text(good.replace(old, new))
        code, _, err = run("calibrate", "check", dataset, "--no-detect")
        assert code == 1 and expected in err, (new, err)


# ---------------------------------------------------------------- messages


def test_broken_camera_yaml_gives_the_line(dataset: Path) -> None:
    cam = dataset / "camera.yaml"
    cam.write_text(
        "image_width: 1280\nimage_height: 720\ncamera_matrix: [910, 0, 640, 0, 910, 360, 0, 0, .nan]\n"
        "distortion_coefficients: [0, 0, 0, 0, 0]\n"
    )
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and "camera.yaml:3" in err, err
    cam.write_text(
        "image_width: 1280\nimage_height: -720\ncamera_matrix: [910, 0, 640, 0, 910, 360, 0, 0, 1]\n"
        "distortion_coefficients: [0, 0, 0, 0, 0]\n"
    )
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and "camera.yaml:2" in err, err


def test_image_that_is_a_directory_is_not_reported_missing(dataset: Path, tmp_path: Path) -> None:
    from armtool.calib.inputs.files import unreadable_reason

    (tmp_path / "images").mkdir()
    assert unreadable_reason(tmp_path / "images") == "is a directory, not a file"
    assert unreadable_reason(tmp_path / "nothing") == "does not exist"
    (tmp_path / "flat").write_text("")  # `images` that is a file: the real cause is named
    assert "a part of its path is a file" in (unreadable_reason(tmp_path / "flat" / "0.png") or "")
    (tmp_path / "link.png").symlink_to(tmp_path / "gone.png")
    assert unreadable_reason(tmp_path / "link.png") == "is a broken symbolic link"
    code, _, err = run(
        "calibrate",
        "camera",
        tmp_path / "images" / "a.png",
        "--board",
        "charuco:5x4:0.03:0.022",
        "-o",
        tmp_path / "c.yaml",
    )
    assert code == 2 and "does not exist" in err
    os.mkfifo(tmp_path / "images" / "a.png")  # a FIFO named like an image: reading it would hang
    code, _, err = run(
        "calibrate",
        "camera",
        tmp_path / "images" / "a.png",
        "--board",
        "charuco:5x4:0.03:0.022",
        "-o",
        tmp_path / "c.yaml",
    )
    assert code == 2 and "is not a regular file" in err
    code, _, err = run(
        "calibrate", "camera", tmp_path / "images", "--board", "charuco:5x4:0.03:0.022", "-o", tmp_path / "c.yaml"
    )
    assert code == 2 and "no readable image files in the directory" in err
    # in a dataset: samples.csv as a directory is named as such
    (dataset / "samples.csv").unlink()
    (dataset / "samples.csv").mkdir()
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and "'samples.csv' is a directory" in err


def test_detecting_in_an_image_that_is_a_directory_says_so(dataset: Path, tmp_path: Path) -> None:
    from armtool.calib.inputs.dataset import load_dataset
    from armtool.calib.inputs.observations import observe
    from armtool.calib.model.camera import load_intrinsics

    (dataset / "corners.csv").unlink()
    text = (dataset / "dataset.yaml").read_text().replace("corners: corners.csv\n", "")
    (dataset / "dataset.yaml").write_text(text)
    lines = (dataset / "samples.csv").read_text().splitlines()
    lines[1] = lines[1].replace("0,,", "0,img0.png,", 1)
    (dataset / "samples.csv").write_text("\n".join(lines) + "\n")
    (dataset / "img0.png").mkdir()
    ds = load_dataset(dataset)
    ob = observe(ds, load_intrinsics(ds.intrinsics), workers=1)["0"]
    assert ob.corners_px is None and "is a directory" in ob.reason


def test_base_equal_to_flange_says_what_is_wrong(dataset: Path, tmp_path: Path) -> None:
    manifest = dataset / "dataset.yaml"
    manifest.write_text(manifest.read_text().replace("flange_link: tool0", "flange_link: base_link"))
    code, _, err = run("calibrate", "check", dataset, "--no-detect")
    assert code == 1 and "same link 'base_link'" in err and "no moving joint" not in err
    code, _, err = run("calibrate", "simulate", CLEAN_ARM, "-o", tmp_path / "o", "--base", "tool0", "--flange", "tool0")
    assert code == 2 and "same link 'tool0'" in err


# ---------------------------------------------------------------- resource bounds


def _png(path: Path, width: int, height: int, pixels: bool = True) -> Path:
    """A grey PNG; with pixels=False only its header (a decompression bomb needs no more to lie)."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    body = (
        zlib.compress(b"".join(b"\x00" + b"\x80" * width for _ in range(height)))
        if pixels
        else zlib.compress(b"\x00" * 1000)
    )
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", body) + chunk(b"IEND", b""))
    return path


def test_huge_image_is_refused_before_decoding(tmp_path: Path) -> None:
    from armtool.calib.inputs.files import read_gray

    bomb = _png(tmp_path / "bomb.png", 200_000, 200_000, pixels=False)
    t0 = time.monotonic()
    with pytest.raises(ArmtoolError, match="200000x200000 pixels"):
        read_gray(bomb)
    code, _, err = run("calibrate", "camera", bomb, "--board", "charuco:5x4:0.03:0.022", "-o", tmp_path / "c.yaml")
    assert code == 2 and "pixels" in err
    assert time.monotonic() - t0 < 5
    small = read_gray(_png(tmp_path / "small.png", 16, 8))
    assert small is not None and small.shape == (8, 16)


def test_jpeg_header_size_is_read() -> None:
    import cv2

    from armtool.calib.inputs.files import header_size

    ok, buf = cv2.imencode(".jpg", np.zeros((30, 50), np.uint8))
    assert ok and header_size(buf.tobytes()) == (50, 30)


# ---------------------------------------------------------------- property-based


@settings(HYPO, max_examples=6)
@given(
    holdout=st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([0.0, 0.3, 0.9, -0.1, 1.0])),
    seed=st.integers(min_value=-(2**70), max_value=2**70),
)
def test_fit_numeric_options(
    base_dataset: Path, tmp_path_factory: pytest.TempPathFactory, holdout: float, seed: int
) -> None:
    out = tmp_path_factory.mktemp("fit") / "o"
    before = snapshot(base_dataset)
    t0 = time.monotonic()
    code, stdout, err = run(
        "calibrate",
        "fit",
        base_dataset,
        "--out",
        out,
        "--holdout",
        repr(holdout),
        "--seed",
        str(seed),
        "--format",
        "json",
        "--params",
        "offsets",
    )
    assert code in (0, 1, 2), err
    assert "Traceback" not in err and "internal error" not in err
    if code == 0:
        strict_json(stdout)
    if not 0 <= holdout <= 0.9:  # NaN included
        assert code == 2 and "--holdout" in err, err
    assert snapshot(base_dataset) == before
    assert time.monotonic() - t0 < 30


NUMBER = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-(2**40), 2**40).map(str),
    st.sampled_from(["nan", "inf", "-inf", "0", "-1", "1e308", "1e-308", "", "x"]),
)


@HYPO
@given(flag=st.sampled_from(["--tag-size", "--samples", "--validation", "--bad-samples", "--seed"]), value=NUMBER)
def test_simulate_numeric_options(tmp_path_factory: pytest.TempPathFactory, flag: str, value: str) -> None:
    """Any value ends in a message or (valid values) in the missing-URDF error: never a crash."""
    out = tmp_path_factory.mktemp("sim") / "o"
    code, _, err = run("calibrate", "simulate", out.parent / "missing.urdf", "-o", out, flag, value)
    assert code == 2 and "Traceback" not in err and "internal error" not in err
    assert not out.exists()


@HYPO
@given(flag=st.sampled_from(["--tag-size", "--tolerance", "--max-velocity", "--min-still", "--tag-id"]), value=NUMBER)
def test_import_bag_numeric_options(tmp_path_factory: pytest.TempPathFactory, flag: str, value: str) -> None:
    tmp = tmp_path_factory.mktemp("bag")
    args = ["calibrate", "import-bag", tmp / "missing.bag", "--image-topic", "/i", "--urdf", CLEAN_ARM, "-o", tmp / "o"]
    code, _, err = run(*args, *(["--tag-size", "0.08"] if flag != "--tag-size" else []), flag, value)
    assert code == 2 and "Traceback" not in err and "internal error" not in err
    assert not (tmp / "o").exists()


MUTATIONS = st.sampled_from(["flip", "nan", "inf", "deep", "huge", "truncate", "binary", "negate"])


def _mutate(data: bytes, how: str, where: float, byte: int) -> bytes:
    at = int(where * max(len(data) - 1, 0))
    if how == "flip":
        return data[:at] + bytes([data[at] ^ (byte or 1)]) + data[at + 1 :] if data else data
    if how == "nan":
        return data.replace(b"0.", b"nan", 1) if b"0." in data else data + b"nan\n"
    if how == "inf":
        return data.replace(b"1", b"1e999", 1)
    if how == "deep":
        return data[:at] + b"[" * 1100 + data[at:]
    if how == "huge":
        return data[:at] + b"7" * 140_000 + data[at:]
    if how == "truncate":
        return data[:at]
    if how == "binary":
        return data[:at] + bytes(range(256)) + data[at:]
    return data.replace(b",", b",-", 1)


@settings(HYPO, max_examples=int(os.environ.get("HOSTILE_EXAMPLES", "10")))
@given(
    name=st.sampled_from(["dataset.yaml", "samples.csv", "corners.csv", "camera.yaml"]),
    how=MUTATIONS,
    where=st.floats(0, 1),
    byte=st.integers(0, 255),
    fit=st.booleans(),
)
def test_mutated_dataset_files(
    base_dataset: Path,
    tmp_path_factory: pytest.TempPathFactory,
    name: str,
    how: str,
    where: float,
    byte: int,
    fit: bool,
) -> None:
    tmp = tmp_path_factory.mktemp("mut")
    ds = Path(shutil.copytree(base_dataset, tmp / "ds"))
    target = ds / name
    target.write_bytes(_mutate(target.read_bytes(), how, where, byte))
    before = snapshot(ds)
    t0 = time.monotonic()
    if fit:
        code, stdout, err = run("calibrate", "fit", ds, "--out", tmp / "o", "--format", "json", "--params", "offsets")
    else:
        code, stdout, err = run("calibrate", "check", ds, "--no-detect")
    assert code in (0, 1, 2), err
    assert "Traceback" not in err and "internal error" not in err
    if fit and code == 0:
        strict_json(stdout)
    assert snapshot(ds) == before
    assert time.monotonic() - t0 < 30


def test_broken_truth_is_a_message(dataset: Path) -> None:
    """truth/ is only for scoring a simulated dataset: a broken one is an ArmtoolError (the fit
    then warns and writes its result), never a KeyError or RecursionError."""
    from armtool.calib.choices import Setup
    from armtool.calib.model.calib_model import CalibModel
    from armtool.calib.simulation.truth import load_truth
    from armtool.model.chain import load_chain

    model = CalibModel(load_chain(CLEAN_ARM, "base_link", "tool0"), Setup.EYE_TO_HAND, np.eye(4), np.eye(4))
    (dataset / "truth").mkdir()
    for text in ("joints: " + "[" * 1100 + "]" * 1100, "joints: {}", "- 1"):
        (dataset / "truth" / "truth.yaml").write_text(text + "\n")
        with pytest.raises(ArmtoolError, match="truth files"):
            load_truth(dataset, model)
