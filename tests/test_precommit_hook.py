"""The `armtool-lint` pre-commit hook, run by the real pre-commit: `pre-commit try-repo`.

How this runs offline (the decision, measured: about 4 s per try-repo run):

`try-repo` clones the hook repository, makes a virtualenv and runs `pip install .` in it, which
would fetch armtool's dependencies (typer, lxml, pin, opencv, ...) from an index. Tests must not
need the network, so:

* the hook repository is a snapshot of this checkout's working tree, committed in a temporary
  git repository. Pointed at the checkout itself, try-repo would use the last commit plus changes
  to tracked files only, so a new, not yet committed module (or this hook file) would be
  missing, and a checkout that is not a git repository would not work at all;
* `PIP_NO_INDEX=1` and `PIP_CONFIG_FILE=/dev/null`: pip reads no index or config, so nothing is
  downloaded, and a missing dependency fails the test instead of being fetched;
* armtool's build backend (flit_core, a dev dependency) is taken from this interpreter too:
  `PIP_NO_BUILD_ISOLATION=0` (pip's spelling of "no build isolation") makes pip build armtool in
  the hook virtualenv, where the `sitecustomize.py` below makes flit_core importable;
* armtool's dependencies are found in this interpreter's site-packages: a `sitecustomize.py` on
  `PYTHONPATH` adds them at the end of the hook virtualenv's `sys.path`. pre-commit makes that
  virtualenv from this same interpreter, so compiled packages (lxml) match. pip sees the
  dependencies as installed, and installs only armtool itself in the hook virtualenv; the
  hook runs that installed copy (it comes first on `sys.path`).

What stays real: the manifest and its `files` pattern, the `armtool lint` entry point installed
by pip, the file names pre-commit passes, and the exit code. What is not tested: that the
dependencies install from an index. The other option was a `repo: local` / `language: system`
config plus `pre-commit validate-manifest`; it would not run the manifest's own entry or pattern.
`PRE_COMMIT_HOME`, pip's cache and virtualenv's app data all go to `tmp_path`.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest
import yaml

pytest.importorskip("pre_commit", reason="pre-commit is a dev dependency: pip install -e '.[dev]'")
pytest.importorskip("virtualenv", reason="pre-commit depends on virtualenv")
pytest.importorskip("flit_core", reason="armtool's build backend is a dev dependency: pip install -e '.[dev]'")

CHECKOUT = Path(__file__).resolve().parents[1]
MANIFEST = CHECKOUT / ".pre-commit-hooks.yaml"

pytestmark = pytest.mark.skipif(shutil.which("git") is None, reason="pre-commit needs git")

CLEAN_URDF = """\
<?xml version="1.0"?>
<robot name="two_link_arm">
  <link name="base_link"/>
  <link name="upper_arm">
    <inertial>
      <origin xyz="0 0 0.15" rpy="0 0 0"/>
      <mass value="1.0"/>
      <inertia ixx="0.008" ixy="0" ixz="0" iyy="0.008" iyz="0" izz="0.001"/>
    </inertial>
  </link>
  <link name="forearm">
    <inertial>
      <origin xyz="0 0 0.1" rpy="0 0 0"/>
      <mass value="0.5"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.0005"/>
    </inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base_link"/>
    <child link="upper_arm"/>
    <origin xyz="0 0 0.05" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-3.14" upper="3.14" effort="20" velocity="2.0"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper_arm"/>
    <child link="forearm"/>
    <origin xyz="0 0 0.3" rpy="0 0 1.5708"/>
    <axis xyz="0 1 0"/>
    <limit lower="-2.0" upper="2.0" effort="10" velocity="2.0"/>
  </joint>
</robot>
"""

# rpy in degrees (U301) and a misspelled child link (U101).
BROKEN_URDF = CLEAN_URDF.replace('rpy="0 0 1.5708"', 'rpy="0 0 90"').replace(
    '<child link="forearm"/>', '<child link="forarm"/>'
)


def _env(tmp_path: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("GIT_", "PIP_", "PRE_COMMIT", "VIRTUALENV_"))}
    env.pop("SKIP", None)  # pre-commit's "skip these hook ids"
    deps = tmp_path / "deps"
    deps.mkdir()
    site_dirs = list(dict.fromkeys(sysconfig.get_paths()[key] for key in ("purelib", "platlib")))
    (deps / "sitecustomize.py").write_text(f"import sys\nsys.path.extend({site_dirs!r})\n")
    env.update(
        PRE_COMMIT_HOME=str(tmp_path / "pre-commit-home"),
        PIP_CONFIG_FILE=os.devnull,
        PIP_NO_INDEX="1",
        PIP_NO_BUILD_ISOLATION="0",  # build with this interpreter's flit_core: nothing to download
        PIP_CACHE_DIR=str(tmp_path / "pip-cache"),
        PIP_DISABLE_PIP_VERSION_CHECK="1",
        VIRTUALENV_OVERRIDE_APP_DATA=str(tmp_path / "virtualenv-app-data"),
        PYTHONPATH=os.pathsep.join([str(deps), *filter(None, [os.environ.get("PYTHONPATH")])]),
        GIT_CONFIG_NOSYSTEM="1",
        GIT_CONFIG_GLOBAL=os.devnull,  # no user hooksPath, templates or signing
        NO_COLOR="1",
    )
    return env


def _git(cwd: Path, env: dict[str, str], *args: str) -> None:
    subprocess.run(["git", *args], cwd=cwd, env=env, check=True, capture_output=True, timeout=60)


def _git_repo(path: Path, env: dict[str, str]) -> None:
    path.mkdir(parents=True, exist_ok=True)
    _git(path, env, "init", "-q")
    _git(path, env, "config", "user.email", "test@example.invalid")
    _git(path, env, "config", "user.name", "armtool tests")
    _git(path, env, "config", "commit.gpgsign", "false")


def _hook_repo(tmp_path: Path, env: dict[str, str]) -> Path:
    """This checkout's working tree, as far as `pip install .` and pre-commit need it, committed."""
    repo = tmp_path / "hook-repo"
    _git_repo(repo, env)
    for name in (".pre-commit-hooks.yaml", "pyproject.toml", "README.md"):
        shutil.copy2(CHECKOUT / name, repo / name)
    shutil.copytree(CHECKOUT / "armtool", repo / "armtool", ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    _git(repo, env, "add", "-A")
    _git(repo, env, "commit", "-q", "-m", "snapshot of the working tree")
    return repo


def _try_repo(tmp_path: Path, files: dict[str, str]) -> subprocess.CompletedProcess[str]:
    env = _env(tmp_path)
    hook_repo = _hook_repo(tmp_path, env)
    work = tmp_path / "robot-repo"
    _git_repo(work, env)
    for name, text in files.items():
        (work / name).parent.mkdir(parents=True, exist_ok=True)
        (work / name).write_text(text)
    _git(work, env, "add", "-A")
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "pre_commit",
            "try-repo",
            str(hook_repo),
            "armtool-lint",
            "--all-files",
            "--color",
            "never",
        ],
        cwd=work,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_hook_fails_on_a_broken_urdf(tmp_path: Path) -> None:
    result = _try_repo(tmp_path, {"urdf/broken.urdf": BROKEN_URDF, "urdf/clean.urdf": CLEAN_URDF})
    out = result.stdout + result.stderr
    assert result.returncode == 1, out
    assert re.search(r"^armtool lint\.+Failed$", out, re.MULTILINE), out
    assert "urdf/broken.urdf" in out
    assert "U101" in out and "'forarm'" in out
    assert "U301" in out and 'rpy="0 0 90"' in out
    assert "urdf/clean.urdf" not in out  # no findings there, so not listed


def test_hook_passes_on_a_clean_urdf_and_skips_other_files(tmp_path: Path) -> None:
    # README.md would fail (U001, not XML) if the hook's `files` pattern let it through.
    files = {"urdf/clean.urdf": CLEAN_URDF, "README.md": "# robot\n", "config/joint_limits.yaml": "joint_limits: {}\n"}
    result = _try_repo(tmp_path, files)
    out = result.stdout + result.stderr
    assert result.returncode == 0, out
    assert re.search(r"^armtool lint\.+Passed$", out, re.MULTILINE), out


@pytest.mark.parametrize(
    ("path", "selected"),
    [
        ("arm.urdf", True),
        ("urdf/arm.urdf.xacro", True),
        ("urdf/arm.xacro", True),
        ("config/arm.srdf", True),
        ("config/arm.srdf.xacro", True),
        ("config/kinematics.yaml", True),
        ("kinematics.yml", True),
        ("config/left_arm_kinematics.yaml", True),
        ("meshes/ARM.URDF", True),
        ("config/joint_limits.yaml", True),
        ("config/hard_joint_limits.yaml", True),
        ("config/pilz_cartesian_limits.yaml", True),
        ("config/ros2_controllers.yaml", True),
        ("config/moveit_controllers.yml", True),
        ("config/joint_limits.yaml.bak", False),
        ("config/ompl_planning.yaml", False),
        ("config/kinematics.yaml.bak", False),
        ("urdf/arm.urdf.bak", False),
        ("README.md", False),
    ],
)
def test_manifest_files_pattern(path: str, selected: bool) -> None:
    (hook,) = yaml.safe_load(MANIFEST.read_text())
    assert (hook["id"], hook["entry"], hook["language"]) == ("armtool-lint", "armtool lint", "python")
    assert bool(re.search(hook["files"], path)) is selected
