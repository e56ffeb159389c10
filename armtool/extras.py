"""Optional dependency groups (pip extras): which one a command needs, and a clear error without it.

The base install (`pip install armtool`) is what `armtool lint` needs, so the pre-commit hook
installs in seconds; the numeric and hardware libraries come with extras. A command calls
`require(extra)` first, so a missing extra ends with the install command (exit 2), not with an
ImportError from deep inside numpy-using code. `missing_extra_error` is the net under it: the CLI
maps any ModuleNotFoundError of a known optional module to the same message.
"""

from __future__ import annotations

import importlib.util
from typing import Literal

from armtool.errors import ArmtoolError

Extra = Literal["ik", "calib", "servo", "traj"]

# Top-level module -> the distribution that provides it (as named in pyproject.toml's extras).
DISTRIBUTIONS: dict[str, str] = {
    "numpy": "numpy",
    "scipy": "scipy",
    "pinocchio": "pin",
    "cv2": "opencv-python-headless",
    "numba": "numba",
    "threadpoolctl": "threadpoolctl",
    "serial": "pyserial",
    "dynamixel_sdk": "dynamixel-sdk",
    "rosbags": "rosbags",
    "matplotlib": "matplotlib",
}

# Extra -> the modules its commands import (tests/test_extras.py keeps this and pyproject.toml in step).
MODULES: dict[Extra, tuple[str, ...]] = {
    "ik": ("numpy", "scipy", "pinocchio", "numba", "matplotlib"),  # numba: lm; matplotlib: --plot
    "calib": (
        "numpy",
        "scipy",
        "pinocchio",
        "cv2",
        "rosbags",
        "threadpoolctl",
        "matplotlib",
    ),  # pinocchio: fit's URDF check, simulate's IK; rosbags: import-bag; threadpoolctl: fit's small matrices;
    # matplotlib: fit --plot
    "servo": ("numpy", "scipy", "serial", "dynamixel_sdk"),  # servo-sim needs none of them
    "traj": ("numpy", "scipy", "pinocchio", "numba", "matplotlib"),  # lm for IK, matplotlib for the plots
}

# Where a module comes from when the running command's extra does not have it.
_HOME: dict[str, Extra] = {
    "pinocchio": "ik",
    "numba": "ik",
    "threadpoolctl": "calib",
    "cv2": "calib",
    "serial": "servo",
    "dynamixel_sdk": "servo",
    "rosbags": "calib",
    "matplotlib": "calib",
}

_current: Extra | None = None  # the extra of the running command, for missing_extra_error


def install_command(extra: str) -> str:
    """The shell command that installs an extra (quoted: `[` is a glob character in zsh)."""
    return f"pip install 'armtool[{extra}]'"


def _missing(modules: tuple[str, ...]) -> list[str]:
    out = []
    for module in modules:
        try:
            found = importlib.util.find_spec(module) is not None
        except (ImportError, ValueError):  # a broken or shadowed package counts as missing
            found = False
        if not found:
            out.append(module)
    return out


def _error(extra: str, modules: list[str]) -> ArmtoolError:
    names = ", ".join(DISTRIBUTIONS.get(m, m) for m in modules)
    what = f"this command needs the optional dependencies in armtool[{extra}]; not installed: {names}"
    return ArmtoolError(what, hint=f"install them: {install_command(extra)}")


def require(extra: Extra) -> None:
    """Raise ArmtoolError naming `pip install 'armtool[<extra>]'` unless every module of the extra
    can be imported. Looks the modules up without importing them (about 0.5 ms)."""
    global _current
    _current = extra
    missing = _missing(MODULES[extra])
    if missing:
        raise _error(extra, missing)


def missing_extra_error(exc: ModuleNotFoundError) -> ArmtoolError | None:
    """The install hint for an optional module that failed to import, or None for any other module.

    Names the running command's extra when it has the module, else the module's home extra (cv2:
    calib, for a camera reference in servo-lut), else `all`."""
    module = (exc.name or "").partition(".")[0]
    if module not in DISTRIBUTIONS:
        return None
    if _current is not None and module in MODULES[_current]:
        extra: str = _current
    else:
        extra = _HOME.get(module, "all")
    return _error(extra, [module])
