"""How fast is `armtool lint`? Ratios against peers, all measured in the same run (offline).

(a) start-up: `armtool lint panda.urdf` as a whole process, against `python -c "import typer, rich,
    lxml.etree"` (the floor for a Typer + lxml CLI) on the same interpreter. Target: <= 1.25x.
    Both `python -m armtool` and the `armtool` console script are measured. A bare `armtool lint
    PATH...` (pre-commit's call) never builds Typer's parser; one with an option does, and is shown
    for information.
(b) throughput: every example-robot-data URDF in one `armtool lint` call, against Debian's
    `check_urdf` (liburdfdom-tools) run once per file, as a shell loop or a pre-commit hook would.
    Target: faster (ratio < 1). Nothing is cached between runs.
(c) what `armtool lint` imports: none of Pinocchio, OpenCV, SciPy, NumPy, yourdfpy should be loaded.
(d) with --instructions: (a) again as instructions executed, counted by valgrind's callgrind, which
    other jobs on the machine do not disturb (wall-clock ratios on a loaded machine scatter more
    than the 1.25x target is wide).

Runs are interleaved (A, B, A, B, ...) after a warm-up, so drift hits both sides alike; medians
are reported, for (b) both wall clock and CPU time (user + system of the child processes: on a
machine shared with other jobs, what the two sides cost rather than how long they waited). Child
processes run without PYTHONDONTWRITEBYTECODE, which would otherwise make every run compile
armtool from source; the table says whether armtool is a regular or an editable install (an
editable one measures the source tree, not what `pip install .` gives a pre-commit hook). The
table goes to stdout (markdown), progress to stderr.

    python benchmarks/lint_bench.py [--repeat 30] [--check-urdf /usr/bin/check_urdf] [--instructions]
"""

from __future__ import annotations

import argparse
import atexit
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

STARTUP_TARGET = 1.25
THROUGHPUT_TARGET = 1.0  # one armtool call must beat check_urdf run once per file
HEAVY = ("pinocchio", "cv2", "scipy", "numpy", "yourdfpy")
PANDA = "panda_description/urdf/panda.urdf"
# Variables that change what a child Python does at start-up, so would distort the timings.
DISTORTING_ENV = ("PYTHONDONTWRITEBYTECODE", "PYTHONPROFILEIMPORTTIME", "PYTHONDEVMODE", "PYTHONTRACEMALLOC")
APT_HINT = "apt-get install -y liburdfdom-tools"

# Runs the CLI in-process, then prints the top-level names in sys.modules as the last stdout line.
_PROBE = """\
import json, sys
sys.argv = ["armtool", *sys.argv[1:]]
from armtool.cli import main
try:
    main()
except SystemExit:
    pass
sys.stdout.flush()
print()
print(json.dumps(sorted({name.partition(".")[0] for name in sys.modules})))
"""


@dataclass(frozen=True)
class Timing:
    label: str
    samples_s: tuple[float, ...]
    cpu_samples_s: tuple[float, ...] = ()

    @property
    def median_ms(self) -> float:
        return statistics.median(self.samples_s) * 1e3

    @property
    def cpu_median_ms(self) -> float:
        return statistics.median(self.cpu_samples_s) * 1e3


def log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def child_env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in DISTORTING_ENV}
    env["NO_COLOR"] = "1"
    return env


def find_robots_dir(given: Path | None) -> Path:
    if given is not None:
        if not (given / PANDA).is_file():
            sys.exit(f"error: {given / PANDA} not found\n  hint: --robots is example-robot-data's robots/ directory")
        return given
    prefix = Path(sys.prefix)
    pyver = f"python{sys.version_info[0]}.{sys.version_info[1]}"
    likely = [
        prefix / "lib" / pyver / "site-packages" / "cmeel.prefix" / "share" / "example-robot-data" / "robots",
        prefix / "share" / "example-robot-data" / "robots",
    ]
    for robots in likely:
        if (robots / PANDA).is_file():
            return robots
    for panda in prefix.glob(f"**/example-robot-data/robots/{PANDA}"):
        return panda.parents[2]
    sys.exit(
        f"error: example-robot-data not found under {prefix}\n"
        "  hint: pip install example-robot-data (a dev dependency), or pass --robots DIR"
    )


def find_check_urdf(given: str | None) -> str | None:
    """Debian's compiled check_urdf; skips script wrappers of the same name (e.g. cmeel's in a venv)."""
    if given is not None:
        return given if shutil.which(given) else None
    for directory in os.environ.get("PATH", "").split(os.pathsep) + ["/usr/bin"]:
        candidate = Path(directory) / "check_urdf"
        if candidate.is_file() and os.access(candidate, os.X_OK):
            with candidate.open("rb") as fh:
                if fh.read(4) == b"\x7fELF":
                    return str(candidate)
    return None


# Every command runs in an empty directory, as in a robot repository without [tool.armtool]
# (run from this checkout, armtool would find and parse this project's pyproject.toml).
_NEUTRAL: list[str] = []


def neutral_cwd() -> str:
    """An empty directory made on first use and removed when the script ends."""
    if not _NEUTRAL:
        _NEUTRAL.append(tempfile.mkdtemp(prefix="armtool-bench-"))
        atexit.register(shutil.rmtree, _NEUTRAL[0], True)
    return _NEUTRAL[0]


def run_once(cmd: Sequence[str], env: dict[str, str]) -> float:
    start = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, check=False, cwd=neutral_cwd())
    return time.perf_counter() - start


def _children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_loop(cmds: Sequence[Sequence[str]], env: dict[str, str]) -> tuple[float, float]:
    """Wall clock and CPU time (user + system of the finished children) of running `cmds` in turn."""
    cpu, start = _children_cpu_s(), time.perf_counter()
    for cmd in cmds:
        subprocess.run(
            cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, check=False, cwd=neutral_cwd()
        )
    return time.perf_counter() - start, _children_cpu_s() - cpu


def interleaved(
    jobs: Mapping[str, Sequence[Sequence[str]]], repeat: int, warmup: int, env: dict[str, str]
) -> dict[str, Timing]:
    """Each job is a list of commands run one after another; jobs take turns, order rotating."""
    names = list(jobs)
    for _ in range(warmup):
        for name in names:
            run_loop(jobs[name], env)
    samples: dict[str, list[float]] = {name: [] for name in names}
    cpu: dict[str, list[float]] = {name: [] for name in names}
    for i in range(repeat):
        shift = i % len(names)
        for name in names[shift:] + names[:shift]:
            wall, used = run_loop(jobs[name], env)
            samples[name].append(wall)
            cpu[name].append(used)
    return {name: Timing(name, tuple(samples[name]), tuple(cpu[name])) for name in names}


def install_kind(python: str) -> str:
    """'regular' or 'editable' (PEP 610's direct_url.json), as the interpreter that runs armtool sees it."""
    probe = (
        "import json, importlib.metadata as m\n"
        "d = m.distribution('armtool').read_text('direct_url.json')\n"
        "print('editable' if d and json.loads(d).get('dir_info', {}).get('editable') else 'regular')"
    )
    result = subprocess.run([python, "-c", probe], capture_output=True, text=True, check=False)
    return result.stdout.strip() or "unknown"


def instructions(cmd: Sequence[str], env: dict[str, str], valgrind: str) -> int:
    """Instructions `cmd` executes (valgrind --tool=callgrind, forked children included)."""
    result = subprocess.run(
        [valgrind, "--tool=callgrind", "--callgrind-out-file=/dev/null", "--trace-children=no", *cmd],
        capture_output=True,
        text=True,
        env=env,
        check=False,
        cwd=neutral_cwd(),
    )
    counts = [int(line.rsplit(None, 1)[-1]) for line in result.stderr.splitlines() if "Collected :" in line]
    if not counts:
        sys.exit(f"error: callgrind counted nothing for {' '.join(cmd)}\n{result.stderr[-2000:]}")
    return sum(counts)


def imported_by_lint(python: str, urdf: Path, env: dict[str, str]) -> list[str]:
    result = subprocess.run(
        [python, "-c", _PROBE, "lint", str(urdf)], capture_output=True, text=True, env=env, check=False
    )
    lines = result.stdout.strip().splitlines()
    if not lines:
        sys.exit(f"error: the import probe printed nothing\n{result.stderr}")
    modules: list[str] = json.loads(lines[-1])
    return modules


def ms(value: float) -> str:
    return f"{value:.1f} ms"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--repeat", type=int, default=30, help="measured runs per command for (a) (default: 30)")
    parser.add_argument("--repeat-all", type=int, default=7, help="measured runs per side for (b) (default: 7)")
    parser.add_argument("--warmup", type=int, default=2, help="unmeasured runs per command first (default: 2)")
    parser.add_argument(
        "--robots",
        type=Path,
        default=None,
        help="example-robot-data's robots/ directory (default: found under sys.prefix)",
    )
    parser.add_argument(
        "--check-urdf", default=None, help="check_urdf binary (default: the first compiled one on PATH)"
    )
    parser.add_argument("--strict", action="store_true", help="exit 1 when a target is missed")
    parser.add_argument(
        "--instructions",
        action="store_true",
        help="also count the instructions of (a) with valgrind's callgrind (deterministic; ~1 min)",
    )
    args = parser.parse_args(argv)
    if args.repeat < 1 or args.repeat_all < 1 or args.warmup < 0:
        parser.error("--repeat and --repeat-all must be >= 1, --warmup >= 0")

    env = child_env()
    python = sys.executable
    robots = find_robots_dir(args.robots)
    panda = robots / PANDA
    urdfs = sorted(robots.rglob("*.urdf"))
    script = Path(python).with_name("armtool")
    check_urdf = find_check_urdf(args.check_urdf)

    rows: list[tuple[str, str, str, str, str, str]] = []
    failed = False

    # (a) start-up, whole process
    startup_jobs: dict[str, Sequence[Sequence[str]]] = {
        "baseline": [[python, "-c", "import typer, rich, lxml.etree"]],
        "python -m armtool": [[python, "-m", "armtool", "lint", str(panda)]],
    }
    if script.is_file():
        startup_jobs["armtool (console script)"] = [[str(script), "lint", str(panda)]]
    # Any option builds Typer's parser (a bare `armtool lint PATH...`, pre-commit's call, does not).
    startup_jobs["with an option"] = [[python, "-m", "armtool", "lint", "--format", "text", str(panda)]]
    log(f"(a) start-up: {len(startup_jobs)} commands x {args.repeat} runs, interleaved ...")
    startup = interleaved(startup_jobs, args.repeat, args.warmup, env)
    base = startup["baseline"]
    for name, timing in startup.items():
        if name == "baseline":
            continue
        ratio = timing.median_ms / base.median_ms
        if name == "with an option":
            rows.append(
                (
                    "(a) `python -m armtool lint --format text panda.urdf` (any option: Typer parses it) vs the same",
                    ms(timing.median_ms),
                    ms(base.median_ms),
                    f"{ratio:.2f}x",
                    "-",
                    "(information: the target is the bare call pre-commit makes)",
                )
            )
            continue
        ok = ratio <= STARTUP_TARGET
        failed |= not ok
        shown = "armtool lint panda.urdf" if name.startswith("armtool") else "python -m armtool lint panda.urdf"
        rows.append(
            (
                f'(a) `{shown}` vs `python -c "import typer, rich, lxml.etree"`',
                ms(timing.median_ms),
                ms(base.median_ms),
                f"{ratio:.2f}x",
                f"<= {STARTUP_TARGET}x",
                "PASS" if ok else "FAIL",
            )
        )
    if not script.is_file():
        rows.append(("(a) `armtool` console script", "-", "-", "-", "-", f"skipped: no {script}"))

    # (b) all URDFs: one armtool call vs check_urdf per file
    label_b = f"(b) {len(urdfs)} URDFs: one `armtool lint` vs `check_urdf` per file"
    if check_urdf is None:
        log(f"(b) check_urdf not found; install it with: {APT_HINT}")
        rows.append((label_b, "-", "-", "-", "-", f"skipped: `{APT_HINT}`"))
    else:
        jobs = {
            "armtool": [[python, "-m", "armtool", "lint", *map(str, urdfs)]],
            "check_urdf": [[check_urdf, str(u)] for u in urdfs],
        }
        log(f"(b) {len(urdfs)} URDFs: 2 sides x {args.repeat_all} runs, interleaved ...")
        both = interleaved(jobs, args.repeat_all, 1, env)
        ratio = both["armtool"].median_ms / both["check_urdf"].median_ms
        ok = ratio < THROUGHPUT_TARGET
        failed |= not ok
        verdict = f"armtool {1 / ratio:.2f}x faster" if ratio < 1 else f"armtool {ratio:.2f}x slower"
        rows.append(
            (
                label_b + ", wall clock",
                ms(both["armtool"].median_ms),
                ms(both["check_urdf"].median_ms),
                f"{ratio:.2f}x",
                f"< {THROUGHPUT_TARGET:.2f}x",
                f"{'PASS' if ok else 'FAIL'} ({verdict})",
            )
        )
        cpu_ratio = both["armtool"].cpu_median_ms / both["check_urdf"].cpu_median_ms
        rows.append(
            (
                label_b + ", CPU time (all processes)",
                ms(both["armtool"].cpu_median_ms),
                ms(both["check_urdf"].cpu_median_ms),
                f"{cpu_ratio:.2f}x",
                "-",
                "(information: work done, whatever else runs)",
            )
        )

    # (d) instructions, deterministic
    if args.instructions:
        valgrind = shutil.which("valgrind")
        if valgrind is None:
            rows.append(("(d) instructions (callgrind)", "-", "-", "-", "-", "skipped: `apt-get install -y valgrind`"))
        else:
            log("(d) counting instructions with callgrind ...")
            floor = instructions([python, "-c", "import typer, rich, lxml.etree"], env, valgrind)
            ours = instructions([python, "-m", "armtool", "lint", str(panda)], env, valgrind)
            ratio_i = ours / floor
            ok_i = ratio_i <= STARTUP_TARGET
            failed |= not ok_i
            rows.append(
                (
                    "(d) instructions: `python -m armtool lint panda.urdf` vs the import floor",
                    f"{ours / 1e6:.1f} M",
                    f"{floor / 1e6:.1f} M",
                    f"{ratio_i:.3f}x",
                    f"<= {STARTUP_TARGET}x",
                    "PASS" if ok_i else "FAIL",
                )
            )

    # (c) imports
    modules = set(imported_by_lint(python, panda, env))
    heavy = sorted(modules.intersection(HEAVY))
    failed |= bool(heavy)
    rows.append(
        (
            "(c) heavy modules imported by `armtool lint panda.urdf` (" + ", ".join(HEAVY) + ")",
            ", ".join(heavy) or "none",
            "-",
            "-",
            "none",
            "FAIL" if heavy else "PASS",
        )
    )

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(
        f"armtool lint benchmark: Python {platform.python_version()} on {platform.machine()}, "
        f"{os.cpu_count()} CPUs (load average {load:.1f} at the end), armtool: {install_kind(python)} install; "
        f"medians of {args.repeat} interleaved runs for (a), {args.repeat_all} for (b)."
    )
    print()
    print("| measurement | armtool | peer | ratio | target | result |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    print()
    spread = ", ".join(
        f"{t.label} {ms(min(t.samples_s) * 1e3)}..{ms(max(t.samples_s) * 1e3)}" for t in startup.values()
    )
    print(f"(a) min..max: {spread}.")
    if check_urdf is not None:
        spread_b = ", ".join(
            f"{t.label} {ms(min(t.samples_s) * 1e3)}..{ms(max(t.samples_s) * 1e3)}" for t in both.values()
        )
        print(
            f"(b) min..max: {spread_b}. check_urdf: {check_urdf}; armtool's exit code 1 (findings) is expected there."
        )
        print("(b) no cache: every run reads, parses and checks every file; with >= 16 files armtool forks one")
        print("    worker per extra CPU (the parent lints too).")
    return 1 if failed and args.strict else 0


if __name__ == "__main__":
    sys.exit(main())
