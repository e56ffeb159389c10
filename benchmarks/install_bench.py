"""How long does the base install take, and how big is it? (issue 12: the pre-commit hook's cost)

pre-commit builds a hook's environment as `python -mvirtualenv ENV` and then `python -mpip install .`
inside the hook's repository. This script does the same with armtool's base install (no extras),
non-editable:

1. `python -m virtualenv` (as pre-commit; `python -m venv` when virtualenv is not installed, or with
   `--venv-tool venv`) in a temporary directory (timed);
2. `pip install .` in SRC, a copy of pyproject.toml, README.md and armtool/ (timed; pip builds
   armtool's wheel with its build backend, as pre-commit's pip does). The dependencies and the
   build backend come from a local wheel cache: before the timed runs, `pip download` fetches
   them once (with the ambient pip configuration) into a temporary directory, and the timed
   install reads only that (`PIP_NO_INDEX=1`, `PIP_FIND_LINKS`), so network latency is not
   measured. `--online` times the install against the ambient configuration (indexes) instead.
   Wall time and the CPU time of the child processes are both printed: on a loaded machine the
   wall time mostly measures the load;
3. the size: what the install added to the venv (`du` of the venv after minus before: armtool and
   its dependencies, with the .pyc files pip compiles), and the whole venv, which also holds the
   pip and setuptools that every virtualenv is seeded with, whatever is installed into it;
4. `armtool lint` from the venv: the clean arm (URDF + MoveIt config) must exit 0, the broken
   arm must exit 1 with findings; and no heavy distribution may be installed.

Targets: venv + install <= 15 s (wall), the install <= 40 MB, lint works. Prints a markdown table and
PASS/FAIL; exit status 0 only if every target is met.

    python benchmarks/install_bench.py [--repeat 3] [--venv-tool virtualenv|venv] [--online]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
TIME_TARGET_S = 15.0
SIZE_TARGET_MB = 40.0
HEAVY = {
    "pin",
    "numpy",
    "scipy",
    "opencv-python-headless",
    "opencv-python",
    "yourdfpy",
    "trimesh",
    "dynamixel-sdk",
    "pyserial",
    "numba",
    "threadpoolctl",
    "llvmlite",
}


def _du_bytes(path: Path) -> int:
    """Bytes on disk (st_blocks, as `du`), every file counted once."""
    total, seen = 0, set()
    for dirpath, dirnames, filenames in os.walk(path):
        for name in dirnames + filenames:
            st = os.lstat(os.path.join(dirpath, name))
            if (st.st_dev, st.st_ino) not in seen:
                seen.add((st.st_dev, st.st_ino))
                total += st.st_blocks * 512
    return total + os.lstat(path).st_blocks * 512


def _cpu_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _run(cmd: list[str | Path], **kw: object) -> tuple[float, float, subprocess.CompletedProcess[str]]:
    """Wall seconds, CPU seconds of the child processes, and the result."""
    cpu, start = _cpu_children(), time.perf_counter()
    result = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)  # type: ignore[call-overload]
    return time.perf_counter() - start, _cpu_children() - cpu, result


def _source_copy(dest: Path) -> Path:
    """What `pip install .` needs, outside the checkout (an in-tree build would leave build/ there)."""
    src = dest / "armtool-src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    shutil.copytree(ROOT / "armtool", src / "armtool", ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return src


def fill_wheel_cache(src: Path, wheels: Path) -> None:
    """Download the base dependencies and the build backend (not armtool itself) into `wheels`."""
    with open(src / "pyproject.toml", "rb") as f:
        build_requires = tomllib.load(f)["build-system"]["requires"]
    for what in ([str(src)], build_requires):
        _, _, got = _run([sys.executable, "-m", "pip", "download", "--quiet", "--dest", wheels, *what])
        if got.returncode != 0:
            sys.exit(f"pip download {' '.join(what)} failed:\n{got.stderr}")
    for own in wheels.glob("armtool-*.whl"):
        own.unlink()  # armtool is built from source in every timed run, as pre-commit does


def measure_once(venv_tool: str, tmp: Path, wheels: Path | None) -> dict[str, object]:
    src = _source_copy(tmp)
    venv = tmp / "venv"
    venv_s, venv_cpu, made = _run([sys.executable, "-m", venv_tool, venv], cwd="/")
    if made.returncode != 0:
        sys.exit(f"python -m {venv_tool} failed:\n{made.stderr}")
    vpy = venv / ("Scripts" if os.name == "nt" else "bin") / "python"
    empty = _du_bytes(venv)
    offline = {"PIP_NO_INDEX": "1", "PIP_FIND_LINKS": str(wheels)} if wheels is not None else {}
    install_s, install_cpu, inst = _run(
        [vpy, "-m", "pip", "install", "--quiet", "."], cwd=src, env={**os.environ, **offline}
    )
    if inst.returncode != 0:
        sys.exit(f"pip install failed:\n{inst.stderr}")
    _, _, listed = _run([vpy, "-m", "pip", "list", "--format", "json"])
    dists = sorted(d["name"].lower() for d in json.loads(listed.stdout))
    armtool = vpy.parent / "armtool"
    robots = ROOT / "fixtures" / "robots"
    env = {**os.environ, "NO_COLOR": "1"}
    _, _, clean = _run([armtool, "lint", robots / "clean_arm" / "urdf", robots / "clean_arm" / "config"], env=env)
    _, _, broken = _run([armtool, "lint", "--format", "json", robots / "broken_arm"], env=env)
    findings = len(json.loads(broken.stdout)["findings"]) if broken.returncode == 1 else 0
    return {
        "venv_s": venv_s,
        "venv_cpu_s": venv_cpu,
        "install_s": install_s,
        "install_cpu_s": install_cpu,
        "venv_mb": _du_bytes(venv) / 1e6,
        "added_mb": (_du_bytes(venv) - empty) / 1e6,
        "distributions": dists,
        "lint_clean_exit": clean.returncode,
        "lint_clean_stderr": clean.stderr,
        "lint_broken_exit": broken.returncode,
        "lint_broken_findings": findings,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1, help="fresh venvs to time (medians reported)")
    parser.add_argument(
        "--venv-tool",
        choices=("virtualenv", "venv"),
        default=None,
        help="how to make the venv [default: virtualenv, as pre-commit, if installed]",
    )
    parser.add_argument(
        "--online", action="store_true", help="install from the configured indexes, not a local wheel cache"
    )
    args = parser.parse_args()
    venv_tool = args.venv_tool or ("virtualenv" if importlib.util.find_spec("virtualenv") else "venv")

    with tempfile.TemporaryDirectory(prefix="armtool-install-bench-") as cache:
        wheels = None
        if not args.online:
            wheels = Path(cache)
            fill_wheel_cache(_source_copy(wheels), wheels)
            shutil.rmtree(wheels / "armtool-src")
        runs = _measure(args.repeat, venv_tool, wheels)
    return _report(runs, venv_tool, "a local wheel cache" if wheels else "the configured indexes")


def _measure(repeat: int, venv_tool: str, wheels: Path | None) -> list[dict[str, object]]:
    runs = []
    for i in range(repeat):
        with tempfile.TemporaryDirectory(prefix="armtool-install-bench-") as tmp:
            run = measure_once(venv_tool, Path(tmp), wheels)
        runs.append(run)
        print(
            f"run {i + 1}: {venv_tool} {run['venv_s']:.1f} s (CPU {run['venv_cpu_s']:.1f} s) + pip install "
            f"{run['install_s']:.1f} s (CPU {run['install_cpu_s']:.1f} s), added {run['added_mb']:.1f} MB, "
            f"load average {os.getloadavg()[0]:.1f}",
            file=sys.stderr,
        )
    return runs


def _report(runs: list[dict[str, object]], venv_tool: str, source: str) -> int:
    def med(key: str) -> float:
        return statistics.median(float(r[key]) for r in runs)  # type: ignore[arg-type]

    for run in runs:
        run["total_s"] = float(run["venv_s"]) + float(run["install_s"])  # type: ignore[arg-type]
        run["total_cpu_s"] = float(run["venv_cpu_s"]) + float(run["install_cpu_s"])  # type: ignore[arg-type]
    last = runs[-1]
    total_s = med("total_s")
    heavy = sorted(HEAVY.intersection(last["distributions"]))  # type: ignore[arg-type]
    lint_ok = last["lint_clean_exit"] == 0 and last["lint_broken_exit"] == 1 and last["lint_broken_findings"] > 0  # type: ignore[operator]
    cpu_s = med("total_cpu_s")
    checks = [
        (
            f"{venv_tool} + `pip install .` (wall)",
            f"{total_s:.1f} s (runs: {', '.join(format(r['total_s'], '.1f') for r in runs)} s; CPU {cpu_s:.1f} s)",
            f"<= {TIME_TARGET_S:g} s",
            total_s <= TIME_TARGET_S,
        ),
        (
            "size of the install (du, venv after - before)",
            f"{med('added_mb'):.1f} MB (whole venv with its pip and setuptools: {med('venv_mb'):.1f} MB)",
            f"<= {SIZE_TARGET_MB:g} MB",
            med("added_mb") <= SIZE_TARGET_MB,
        ),
        (
            "`armtool lint` in that venv",
            f"clean arm exit {last['lint_clean_exit']}, broken arm exit "
            f"{last['lint_broken_exit']} with {last['lint_broken_findings']} findings",
            "0; 1 with findings",
            lint_ok,
        ),
        ("heavy distributions installed", ", ".join(heavy) or "none", "none", not heavy),
    ]
    print(
        f"Base install (`pip install .`, no extras) into a fresh {venv_tool} from {source}, median of {len(runs)} run(s), "
        f"Python {'.'.join(map(str, sys.version_info[:3]))}, load average {os.getloadavg()[0]:.1f} on "
        f"{os.cpu_count()} CPUs; installed: {', '.join(last['distributions'])}"
    )  # type: ignore[arg-type]
    print()
    print("| measurement | result | target | |")
    print("|---|---|---|---|")
    for label, value, target, ok in checks:
        print(f"| {label} | {value} | {target} | {'PASS' if ok else 'FAIL'} |")
    if last["lint_clean_exit"] != 0:
        print(last["lint_clean_stderr"], file=sys.stderr)
    passed = all(ok for *_, ok in checks)
    print()
    print("PASS" if passed else "FAIL")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
