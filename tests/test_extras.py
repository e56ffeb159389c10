"""Optional dependencies: a light base install, extras per command, and a clear exit without them.

The base install is what `armtool lint` (the pre-commit hook) needs. Each heavy command runs here
in a fresh interpreter whose import system refuses the optional modules, as in a venv with only
`pip install armtool`: it must exit 2 with the exact install command, without a traceback, and
write nothing.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from armtool import extras

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
FIXTURES = ROOT / "fixtures"
URDF = FIXTURES / "robots" / "clean_arm" / "urdf" / "clean_arm.urdf"
LUT_MEAS = FIXTURES / "servo" / "lut" / "ax12a_meas.csv"

# Distributions the base install must never pull in (sizes from issue 12: pin's cmeel prefix
# 380 MB, OpenCV 150 MB, SciPy 140 MB, yourdfpy -> trimesh/embree).
HEAVY_DISTRIBUTIONS = {
    "pin",
    "numpy",
    "scipy",
    "opencv-python",
    "opencv-python-headless",
    "yourdfpy",
    "trimesh",
    "numba",
    "threadpoolctl",
    "llvmlite",
    "dynamixel-sdk",
    "pyserial",
    "matplotlib",
    "pandas",
    "torch",
}
BASE_ALLOWED = {"typer", "rich", "lxml", "xacro", "pyyaml", "tomli"}
OPTIONAL_MODULES = sorted(extras.DISTRIBUTIONS)

# Runs `armtool ARGS` with the optional modules unimportable (as if not installed), then exits.
_PRELUDE = """\
import json, sys
blocked = set(json.loads(sys.argv[1]))

class NotInstalled:
    def find_spec(self, name, path=None, target=None):
        if any(name == b or name.startswith(b + ".") for b in blocked):
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None

sys.meta_path.insert(0, NotInstalled())
if json.loads(sys.argv[2]):  # bypass require(): the CLI's ModuleNotFoundError net must catch it
    import armtool.extras
    armtool.extras.require = lambda extra: None
sys.argv = ["armtool", *sys.argv[3:]]
from armtool.cli import main
main()
"""


def _run(
    *args: str, blocked: list[str] = OPTIONAL_MODULES, bypass_require: bool = False, timeout: float = 60
) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", _PRELUDE, json.dumps(blocked), json.dumps(bypass_require), *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        stdin=subprocess.DEVNULL,
        env={**os.environ, "NO_COLOR": "1", "COLUMNS": "200"},
    )


def _name(requirement: str) -> str:
    """`opencv-python-headless>=4.9` -> `opencv-python-headless`; `armtool[ik,calib]` -> `armtool`."""
    match = re.match(r"[A-Za-z0-9._-]+", requirement.strip())
    assert match, requirement
    return match.group(0).lower().replace("_", "-")


def _project() -> dict[str, object]:
    with open(ROOT / "pyproject.toml", "rb") as f:
        project: dict[str, object] = tomllib.load(f)["project"]
    return project


# ---- pyproject.toml ---------------------------------------------------------------------------


def test_base_dependencies_have_no_heavy_package() -> None:
    base = {_name(r) for r in _project()["dependencies"]}  # type: ignore[attr-defined]
    assert base & HEAVY_DISTRIBUTIONS == set()
    assert base <= BASE_ALLOWED, f"new base dependency {sorted(base - BASE_ALLOWED)}: does `armtool lint` need it?"


def test_yourdfpy_is_not_declared_anywhere() -> None:
    optional: dict[str, list[str]] = _project()["optional-dependencies"]  # type: ignore[assignment]
    declared = [*_project()["dependencies"], *(r for reqs in optional.values() for r in reqs)]  # type: ignore[misc]
    assert "yourdfpy" not in {_name(r) for r in declared}


@pytest.mark.parametrize("extra", sorted(extras.MODULES))
def test_each_extra_provides_the_modules_its_commands_require(extra: extras.Extra) -> None:
    optional: dict[str, list[str]] = _project()["optional-dependencies"]  # type: ignore[assignment]
    declared = {_name(r) for r in optional[extra]}
    assert {extras.DISTRIBUTIONS[m] for m in extras.MODULES[extra]} <= declared


def test_all_extra_is_every_command_extra() -> None:
    optional: dict[str, list[str]] = _project()["optional-dependencies"]  # type: ignore[assignment]
    assert optional["all"] == [f"armtool[{','.join(sorted(extras.MODULES, key=list(optional).index))}]"]


# ---- require() and the CLI's net ----------------------------------------------------------------


def test_require_passes_when_installed_and_names_the_install_command_when_not(monkeypatch: pytest.MonkeyPatch) -> None:
    extras.require("servo")  # the test environment has every extra
    real = extras.importlib.util.find_spec
    monkeypatch.setattr(extras.importlib.util, "find_spec", lambda name: None if name == "cv2" else real(name))
    with pytest.raises(extras.ArmtoolError) as err:
        extras.require("calib")
    assert err.value.hint == "install them: pip install 'armtool[calib]'"
    assert err.value.what.endswith("not installed: opencv-python-headless")


@pytest.mark.parametrize(
    ("module", "current", "extra"),
    [
        ("cv2", None, "calib"),  # one home
        ("numpy", None, "all"),  # in every extra, no command running
        ("numpy", "servo", "servo"),  # the running command's extra
        ("cv2", "servo", "calib"),  # a camera reference in servo-lut: not the servo extra's module
        ("pinocchio.utils", None, "ik"),
    ],
)
def test_missing_extra_error_names_the_extra(
    module: str, current: str | None, extra: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(extras, "_current", current)
    error = extras.missing_extra_error(ModuleNotFoundError(f"No module named {module!r}", name=module))
    assert error is not None and error.hint == f"install them: pip install 'armtool[{extra}]'"


def test_missing_extra_error_ignores_other_modules() -> None:
    assert extras.missing_extra_error(ModuleNotFoundError("No module named 'foo'", name="foo")) is None


# ---- every command in a base-only environment -----------------------------------------------------


def _assert_needs(result: subprocess.CompletedProcess[str], extra: str) -> None:
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    assert result.stdout == ""
    # The printed hint, character for character: rich must not have eaten `[calib]` as markup.
    assert f"  hint: install them: pip install 'armtool[{extra}]'\n" in result.stderr, result.stderr


def _commands(tmp: Path) -> list[tuple[list[str], str]]:
    port = "/dev/ttyUSB-none"  # never opened: the extra check comes first
    return [
        (["ik-bench", str(URDF), "--samples", "5"], "ik"),
        (["calibrate", "check", str(tmp / "dataset")], "calib"),
        (["calibrate", "fit", str(tmp / "dataset"), "--out", str(tmp / "out")], "calib"),
        (["calibrate", "simulate", str(URDF), "--out", str(tmp / "out"), "--samples", "5"], "calib"),
        (["calibrate", "handeye", str(tmp / "dataset")], "calib"),
        (["calibrate", "handeye-simulate", "--out", str(tmp / "out"), "--images", "3"], "calib"),
        (["limits", "--port", port, "--mode", "auto", "--ids", "1", "--yes", "-o", str(tmp / "out")], "servo"),
        (["servo-lut", "fit", str(LUT_MEAS), "-o", str(tmp / "out")], "servo"),
        (["servo-lut", "export", str(tmp / "lut.json"), "--format", "c", "-o", str(tmp / "out")], "servo"),
        (["servo-lut", "apply", str(tmp / "lut.json"), "--angles", "90"], "servo"),
        (
            [
                "servo-lut",
                "measure",
                "--port",
                port,
                "--id",
                "1",
                "--reference",
                "manual",
                "--yes",
                "-o",
                str(tmp / "out"),
            ],
            "servo",
        ),
        (
            [
                "servo-lut",
                "check",
                str(tmp / "lut.json"),
                "--port",
                port,
                "--id",
                "1",
                "--reference",
                "manual",
                "--yes",
            ],
            "servo",
        ),
        (
            ["calibrate", "camera", str(tmp / "a.png"), "--board", "charuco:10x7:0.03:0.022", "-o", str(tmp / "out")],
            "calib",
        ),
        (
            [
                "calibrate",
                "import-bag",
                str(tmp / "bag"),
                "--image-topic",
                "/image",
                "--urdf",
                str(URDF),
                "--tag-size",
                "0.05",
                "-o",
                str(tmp / "out"),
            ],
            "calib",
        ),
        (["traj", "time", str(tmp / "path.csv"), "--urdf", str(URDF), "-o", str(tmp / "out")], "traj"),
        (["traj", "check", str(tmp / "path.csv"), "--urdf", str(URDF)], "traj"),
        (
            [
                "traj",
                "cartesian",
                str(URDF),
                "--base",
                "base_link",
                "--tip",
                "tool0",
                "--line",
                "0,0,0.1",
                "-o",
                str(tmp / "out"),
            ],
            "traj",
        ),
    ]


@pytest.mark.parametrize("index", range(17), ids=lambda i: " ".join(_commands(Path("T"))[i][0][:2]))
def test_command_without_its_extra_exits_2_with_the_install_command(index: int, tmp_path: Path) -> None:
    args, extra = _commands(tmp_path)[index]
    _assert_needs(_run(*args), extra)
    assert not (tmp_path / "out").exists()


def test_a_partly_installed_extra_names_what_is_missing(tmp_path: Path) -> None:
    result = _run("calibrate", "simulate", str(URDF), "--out", str(tmp_path / "out"), blocked=["cv2"])
    _assert_needs(result, "calib")
    assert "not installed: opencv-python-headless\n" in result.stderr


def test_an_import_that_skips_require_still_gets_the_hint() -> None:
    # ik-bench's solvers import pinocchio at module level: without require() the import itself fails.
    _assert_needs(_run("ik-bench", str(URDF), "--samples", "5", blocked=["pinocchio"], bypass_require=True), "ik")
    # numpy is in every extra: with no command's extra known, the hint is the one that surely has it.
    _assert_needs(_run("ik-bench", str(URDF), "--samples", "5", bypass_require=True), "all")


def test_internal_module_errors_are_not_mistaken_for_extras() -> None:
    result = _run("ik-bench", str(URDF), "--samples", "5", blocked=["armtool.ik"])
    assert result.returncode == 2 and "internal error" in result.stderr and "pip install" not in result.stderr


@pytest.mark.parametrize(
    "args",
    [
        ["--help"],
        ["calibrate", "fit", "--help"],
        ["servo-lut", "--help"],
        ["rules", "U301"],
        [
            "lint",
            "--format",
            "json",
            str(FIXTURES / "robots" / "clean_arm" / "urdf"),
            str(FIXTURES / "robots" / "clean_arm" / "config"),
        ],
    ],
    ids=lambda args: " ".join(args[:2]),
)
def test_base_commands_and_help_work_without_extras(args: list[str]) -> None:
    result = _run(*args)
    assert result.returncode == 0, result.stderr
    assert result.stdout and "Traceback" not in result.stderr


def test_lint_finds_defects_without_extras() -> None:
    result = _run("lint", "--format", "json", str(FIXTURES / "robots" / "broken_arm"))
    assert result.returncode == 1, result.stderr
    assert json.loads(result.stdout)["findings"]


def test_servo_sim_needs_no_extra(tmp_path: Path) -> None:
    """The simulator is pure Python: it runs in the base install."""
    result = _run("servo-sim", str(FIXTURES / "servo" / "ax12_arm.yaml"), "--duration", "0.2")
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("/dev/")
