"""`armtool ik-bench URDF`: compare IK solvers on your robot with TRAC-IK's protocol."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import List, Optional

import typer

from armtool.errors import ArmtoolError
from armtool.extras import require


class BenchFormat(str, Enum):
    TABLE = "table"
    JSON = "json"
    CSV = "csv"


class SeedModeOption(str, Enum):
    MID = "mid"
    RANDOM = "random"
    NEAR = "near"


def ik_bench(
    urdf: Path = typer.Argument(..., help="URDF or xacro of the robot."),
    base: Optional[str] = typer.Option(None, "--base", help="Base link of the chain (default: the root)."),
    tip: Optional[str] = typer.Option(None, "--tip", help="Tip link (default: end of the longest chain)."),
    group: Optional[str] = typer.Option(None, "--group", help="MoveIt group whose chain to use (needs --srdf)."),
    srdf: Optional[Path] = typer.Option(None, "--srdf", help="SRDF that defines --group."),
    kinematics_yaml: Optional[Path] = typer.Option(None, "--kinematics-yaml", help="MoveIt kinematics.yaml: the group's timeout."),
    solvers: Optional[str] = typer.Option(None, "--solvers", help="Comma-separated built-in solvers (default: all)."),
    peers: Optional[str] = typer.Option(None, "--peers", help="Comma-separated peer solvers, or 'all' (needs armtool[peers])."),
    batch: bool = typer.Option(True, "--batch/--no-batch", help="Also time one vectorized solve_batch call per solver that has one."),
    samples: int = typer.Option(1000, "--samples", min=1, help="Number of random targets."),
    seed: int = typer.Option(0, "--seed", help="Random seed for targets (and restarts)."),
    seed_mode: SeedModeOption = typer.Option(SeedModeOption.MID, "--seed-mode", help="Start each solve from mid-range, random, or near the answer."),
    timeout: Optional[float] = typer.Option(None, "--timeout", help="Seconds per solve [default: 0.005, or the group's in --kinematics-yaml]."),
    tolerance: float = typer.Option(1e-5, "--tolerance", help="Pose tolerance (m and rad)."),
    output_format: BenchFormat = typer.Option(BenchFormat.TABLE, "--format", help="table, json or csv on stdout."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write a PNG: solve-time CDF and success per solver."),
    xacro_arg: List[str] = typer.Option([], "--xacro-arg", help="xacro argument NAME:=VALUE (repeatable)."),
    package_path: List[Path] = typer.Option([], "--package-path", help="Directory holding ROS packages (repeatable)."),
) -> None:
    require("ik")  # exit 2 with the install command when the extra is missing
    from armtool.cli.lint import _parse_xacro_args
    from armtool.console import stderr, write_stdout
    from armtool.ik.bench import BenchConfig, SeedMode, make_targets, run_solver
    from armtool.ik.chain import chain_from_xml
    from armtool.ik.group import group_chain, group_timeout
    from armtool.ik.peers import make_peer, peer_names
    from armtool.ik.registry import make_solver, solver_names
    from armtool.ik.solver import Solver
    from armtool.ik.report import render_csv, render_json, render_table
    from armtool.model.load import load_robot_xml

    if timeout is not None and not timeout > 0:
        raise ArmtoolError(f"--timeout must be > 0 seconds, got {timeout}", hint="e.g. --timeout 0.005 (5 ms)")
    if group is not None:
        if srdf is None:
            raise ArmtoolError("--group needs --srdf", hint="pass the MoveIt SRDF that defines the group")
        if base or tip:
            raise ArmtoolError("give either --group or --base/--tip, not both")
    root = load_robot_xml(urdf, _parse_xacro_args(xacro_arg), package_path)
    if group is not None and srdf is not None:
        links = {j.get("name", ""): (j.find("parent").get("link", ""), j.find("child").get("link", ""))
                 for j in root.findall("joint") if j.find("parent") is not None and j.find("child") is not None}
        base, tip = group_chain(srdf, group, links)
    chain = chain_from_xml(root, base, tip, source=urdf.name)
    if timeout is None:
        timeout = 0.005
        if kinematics_yaml is not None and group is not None:
            timeout = group_timeout(kinematics_yaml, group) or timeout
    names = [s.strip() for s in solvers.split(",") if s.strip()] if solvers else solver_names()
    built, skipped = [], []
    for name in names:
        try:
            built.append(make_solver(name, chain, timeout=timeout, tolerance=tolerance, seed=seed))
        except ArmtoolError as exc:
            if solvers:  # asked for by name: say why it cannot run
                raise
            skipped.append((name, exc.what))  # e.g. no closed form for this robot
    peer_list = []
    if peers:
        wanted = peer_names() if peers.strip() == "all" else [p.strip() for p in peers.split(",")]
        for name in wanted:
            peer = make_peer(name, chain, root, timeout=timeout, tolerance=tolerance)
            if isinstance(peer, str):
                stderr().print(f"[yellow]peer {name} skipped:[/yellow] {peer}")
            else:
                peer_list.append(peer)
    config = BenchConfig(samples=samples, rng_seed=seed, seed_mode=SeedMode(seed_mode.value), timeout=timeout, tolerance=tolerance)
    targets = make_targets(chain, config)
    for name, why in skipped:
        stderr().print(f"[yellow]{name} skipped:[/yellow] {why}")
    stderr().print(
        f"{chain.name}: {chain.base} → {chain.tip}, {chain.n} joints; {samples} targets, seed {seed_mode.value}, "
        f"timeout {timeout * 1e3:g} ms, tolerance {tolerance:g}"
    )
    from rich.progress import TaskID

    from armtool.console import progress_bar

    reports = []
    runs = [(s, False) for s in [*built, *peer_list]]
    if batch:
        runs += [(s, True) for s in built if type(s).solve_batch is not Solver.solve_batch]
    with progress_bar(label_width=16) as bar:
        for solver, as_batch in runs:
            label = solver.name + (" (batch)" if as_batch else "")
            task = bar.add_task(label, total=samples)

            def advance(k: int, t: TaskID = task) -> None:
                bar.advance(t, k)

            reports.append(run_solver(chain, solver, targets, config, batch=as_batch, progress=advance))
    if output_format is BenchFormat.JSON:
        write_stdout(render_json(chain, config, reports))
    elif output_format is BenchFormat.CSV:
        write_stdout(render_csv(reports))
    else:
        render_table(chain, config, reports)
    if plot is not None:
        from armtool.ik.plot import write_plot

        write_plot(plot, reports)
        stderr().print(f"wrote {plot}")
