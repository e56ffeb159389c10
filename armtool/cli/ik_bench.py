"""`armtool ik-bench URDF`: compare IK solvers on your robot with TRAC-IK's protocol."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from armtool.cli import options as opt
from armtool.cli.options import MoveItConfig, PackagePaths, RobotConfig, XacroArgs
from armtool.errors import ArmtoolError
from armtool.extras import require
from armtool.ik import MAX_SAMPLES, MAX_TIMEOUT_S
from armtool.ik.modes import BenchFormat, SeedMode

if TYPE_CHECKING:
    from armtool.cli.options import RobotOptions


def ik_bench(
    urdf: Path | None = typer.Argument(
        None, help="URDF or xacro of the robot (with --moveit-config: the package's, unless given)."
    ),
    base: str | None = typer.Option(None, "--base", help="Base link of the chain (default: the root link)."),
    tip: str | None = typer.Option(
        None,
        "--tip",
        help="Tip link (default: the arm's end before any gripper joint, at a tool frame such as tool0 or *_tcp if there is one).",
    ),
    group: str | None = typer.Option(
        None,
        "--group",
        help="MoveIt group whose chain to use, built as MoveIt builds it (needs --srdf or --moveit-config).",
    ),
    srdf: Path | None = typer.Option(
        None, "--srdf", help="SRDF (or .srdf.xacro, expanded with --xacro-arg/--package-path) that defines --group."
    ),
    kinematics_yaml: Path | None = typer.Option(
        None,
        "--kinematics-yaml",
        help="MoveIt kinematics.yaml: the group's kinematics_solver_timeout and position_only_ik.",
    ),
    solvers: str | None = typer.Option(None, "--solvers", help="Comma-separated built-in solvers (default: all)."),
    peers: str | None = typer.Option(
        None, "--peers", help="Comma-separated peer solvers, or 'all' (needs armtool[peers])."
    ),
    batch: bool = typer.Option(
        True, "--batch/--no-batch", help="Also time one batch call (all targets at once) per solver that has one."
    ),
    samples: int = typer.Option(
        1000,
        "--samples",
        callback=opt.int_range(1, MAX_SAMPLES),
        help=f"Number of random targets (1..{MAX_SAMPLES:,}).",
    ),
    seed: int = typer.Option(
        0, "--seed", callback=opt.seed(), help="Random seed for targets (and restarts); any integer."
    ),
    seed_mode: SeedMode = typer.Option(
        SeedMode.MID, "--seed-mode", help="Start each solve from mid-range, random, or near the answer."
    ),
    timeout: float | None = typer.Option(
        None,
        "--timeout",
        callback=opt.seconds(MAX_TIMEOUT_S),
        help=f"Seconds per solve, > 0 and ≤ {MAX_TIMEOUT_S:g} [default: 0.005, or the group's in --kinematics-yaml].",
    ),
    tolerance: float = typer.Option(
        1e-5,
        "--tolerance",
        callback=opt.positive_float(1.0, unit="(m and rad)"),
        help="Pose tolerance (m and rad), > 0 and ≤ 1.",
    ),
    output_format: BenchFormat = typer.Option(BenchFormat.TABLE, "--format", help="table, json or csv on stdout."),
    plot: Path | None = typer.Option(
        None,
        "--plot",
        help="Write a figure (PNG, SVG or PDF, by the extension): solve-time CDF and success per solver.",
    ),
    lock: list[str] | None = typer.Option(
        None, "--lock", help="Hold a joint at a value: JOINT=VALUE (rad or m), repeatable or a comma list."
    ),
    xacro_arg: XacroArgs = None,
    package_path: PackagePaths = None,
    robot_config: RobotConfig = None,
    moveit_config: MoveItConfig = None,
) -> None:
    require("ik")  # exit 2 with the install command when the extra is missing
    from rich.markup import escape

    from armtool.cli.options import RobotOptions
    from armtool.console import say, stderr, write_stdout
    from armtool.fileio import check_output_paths
    from armtool.ik.bench import (
        BenchConfig,
        NotApplicable,
        SolverReport,
        make_targets,
        native_stderr_note,
        run_bench,
        run_header,
    )
    from armtool.ik.group import GroupSettings, counterpart_solver, group_chain, group_settings
    from armtool.ik.lineup import build_lineup, names_option
    from armtool.ik.locks import describe, parse_locks
    from armtool.ik.locks import lock as lock_chain
    from armtool.ik.peers import check_peer_name, native_stdout_to_stderr, peer_names
    from armtool.ik.registry import solver_class, solver_names
    from armtool.model.chain import chain_from_xml, default_base_tip
    from armtool.model.load import load_robot_xml, load_srdf_xml
    from armtool.output.ik_bench import render_csv, render_json, render_table
    from armtool.plotting import plot_format

    robot = RobotOptions(xacro_arg, package_path, robot_config)
    package_args: dict[str, str] = {}
    if moveit_config is not None:
        urdf, srdf, kinematics_yaml, package_args, group = _from_moveit_config(
            moveit_config, robot, urdf, srdf, kinematics_yaml, group, base, tip
        )
    if urdf is None:
        raise ArmtoolError("no robot given", hint="pass the URDF (or xacro), or --moveit-config DIR")
    names = names_option("--solvers", solvers, solver_names())
    wanted = names_option("--peers", peers, peer_names(), everything="all", what="peer") if peers is not None else []
    for name in names:
        solver_class(name)  # an unknown name fails now, before any file is read
    for name in wanted:
        check_peer_name(name)
    locks = parse_locks(lock)
    check_output_paths({"--plot": plot}, inputs=[urdf, srdf, kinematics_yaml])  # before the work, not after it
    if plot is not None:
        plot_format(plot)
    if group is not None:
        if srdf is None:
            raise ArmtoolError(
                "--group needs --srdf", hint="pass the MoveIt SRDF that defines the group, or --moveit-config DIR"
            )
        if base or tip:
            raise ArmtoolError("give either --group or --base/--tip, not both")
    xacro_args = robot.xacro_args(urdf, package_args)
    root = load_robot_xml(urdf, xacro_args, robot.package_paths)
    settings = GroupSettings()
    how = ""
    if group is not None and srdf is not None:
        srdf_args = robot.xacro_args(srdf, package_args)
        found = group_chain(load_srdf_xml(srdf, srdf_args, robot.package_paths), group, root, source=str(srdf))
        base, tip = found.base, found.tip
        how = f"group '{group}' of {srdf.name}"
        if kinematics_yaml is not None:
            settings = group_settings(kinematics_yaml, group)
    elif base is None and tip is None:
        base, tip = default_base_tip(root, source=urdf.name)
        how = "default chain (pass --base/--tip for another)"
    moveit_solver = counterpart_solver(settings.solver_plugin)
    if solvers is None and moveit_solver in names:
        names = [moveit_solver, *(n for n in names if n != moveit_solver)]  # MoveIt's own first
    if settings.solver_plugin:
        stand_in = f"armtool's {moveit_solver} stands for it" if moveit_solver else "no built-in solver works like it"
        how += f"; MoveIt's solver {settings.solver_plugin} ({stand_in})"
    chain = lock_chain(chain_from_xml(root, base, tip, source=urdf.name), locks)
    if chain.locks:
        how += ("; " if how else "") + f"locked {describe(chain)}"
    if timeout is None:
        timeout = settings.timeout_s or 0.005
    config = BenchConfig(
        samples=samples,
        rng_seed=seed,
        seed_mode=seed_mode,
        timeout=timeout,
        tolerance=tolerance,
        position_only=settings.position_only,
    )
    # Native peers print on fd 1 themselves (TRAC-IK: a WARNING per solve of a 1-joint chain): while
    # solvers are built and run, fd 1 is stderr, so stdout carries the JSON/CSV/table only.
    with native_stdout_to_stderr():
        lineup = build_lineup(
            names,
            wanted,
            chain,
            root,
            timeout=timeout,
            tolerance=tolerance,
            seed=seed,
            position_only=config.position_only,
        )
        targets = make_targets(lineup.chain, config)
        for name, why in lineup.not_installed:
            say(why, label=f"peer {name} skipped:", style="yellow")
        for row in lineup.not_applicable:
            say(row.reason, label=f"{row.solver} not applicable:", style="yellow")
        stderr().print(escape(run_header(chain, config, how)))
        from rich.progress import TaskID

        from armtool.console import progress_bar

        entries = lineup.entries(batch)
        with progress_bar(label_width=16) as bar:
            tasks: dict[str, TaskID] = {e.label: bar.add_task(e.label, total=samples) for e in entries}

            def advance(label: str, k: int) -> None:
                bar.advance(tasks[label], k)

            # The solvers take turns on blocks of targets, so a change of the CPU's speed during
            # the run (turbo, thermal limits, other programs) lands on all of them alike.
            reports: list[SolverReport | NotApplicable] = list(
                run_bench(lineup.chain, entries, targets, config, progress=advance)
            )
    reports += lineup.not_applicable
    if output_format is BenchFormat.JSON:
        write_stdout(render_json(chain, config, reports))
    elif output_format is BenchFormat.CSV:
        write_stdout(render_csv(reports))
    else:
        render_table(chain, config, reports)
    # What a peer's native code wrote on fd 2 during its solves (a Rust panic's message) was held
    # back so as not to break into the progress bar; said here once per solver, after its row.
    for solver in {id(e.solver): e.solver for e in entries}.values():
        note = native_stderr_note(solver)
        if note:
            say(note, label="note:")
    if plot is not None:
        from armtool.ik.plot import write_plot

        title = f"{urdf.name}: {chain.base} → {chain.tip}, {samples} targets, timeout {timeout * 1e3:g} ms"
        write_plot(plot, [r for r in reports if isinstance(r, SolverReport)], title)
        stderr().print(f"wrote {escape(str(plot))}")


def _from_moveit_config(
    directory: Path,
    robot: RobotOptions,
    urdf: Path | None,
    srdf: Path | None,
    kinematics_yaml: Path | None,
    group: str | None,
    base: str | None,
    tip: str | None,
) -> tuple[Path | None, Path | None, Path | None, dict[str, str], str | None]:
    """URDF, SRDF, kinematics.yaml, the URDF's xacro arguments and the group, from a MoveIt
    config package; what the command line gives wins."""
    from armtool.ik.group import planning_group

    pkg, urdf = robot.moveit_package(directory, urdf, "the URDF argument")
    srdf = srdf or pkg.srdf
    kinematics_yaml = kinematics_yaml or pkg.kinematics
    if group is None and base is None and tip is None:
        group = planning_group(kinematics_yaml, directory)
    return urdf, srdf, kinematics_yaml, pkg.urdf_xacro_args, group
