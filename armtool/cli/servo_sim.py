"""`armtool servo-sim CONFIG.yaml`: a simulated servo bus on a pseudo-terminal, until Ctrl-C."""

from __future__ import annotations

from pathlib import Path

import typer

from armtool.cli import options as opt
from armtool.errors import ArmtoolError


def servo_sim(
    config: Path = typer.Argument(
        ..., help="Simulator YAML (protocol, joints with stops, faults); see fixtures/servo/."
    ),
    duration: float | None = typer.Option(
        None, "--duration", callback=opt.seconds(), help="Stop after this many seconds (default: until Ctrl-C)."
    ),
    port_file: Path | None = typer.Option(
        None,
        "--port-file",
        help="Also write the bus port path to this new file (for scripts); "
        "removed at exit. An existing file is refused unless it is a stale port file.",
    ),
    person: bool = typer.Option(
        False, "--person", help="Start the scripted person: torque-off joints are moved to both stops."
    ),
) -> None:
    """Prints the bus port path (line 1) and the encoder port path (line 2) on stdout."""
    import signal
    import sys

    from armtool.console import stderr, write_stdout
    from armtool.fileio import PortFile
    from armtool.servo.sim import PersonSpec, SimBus, load_sim_config

    if sys.platform == "win32":
        raise ArmtoolError("servo-sim needs pseudo-terminals (Linux or macOS)")
    cfg = load_sim_config(config)
    if person and cfg.person is None:
        cfg.person = PersonSpec()
    # the port file goes through armtool.fileio: never over a user's file or a device, removed
    # at exit only if it is still the file written here
    marker = PortFile(port_file) if port_file is not None else None
    if marker is not None:
        marker.claim()
    sim = SimBus.start(cfg)
    signal.signal(signal.SIGTERM, lambda *_: sim.stop())
    try:
        if marker is not None:
            marker.write(sim.port_path)
        write_stdout(sim.port_path)
        write_stdout(sim.encoder_port_path)
        ids = ", ".join(f"{s.id} {s.model.name}" for s in cfg.servos)
        stderr().print(
            f"servo-sim: {cfg.protocol} at {cfg.baud} baud on {sim.port_path} (IDs {ids}); "
            f"encoder on {sim.encoder_port_path}; "
            + (f"stopping after {duration:g} s" if duration else "Ctrl-C to stop")
        )
        sim.wait(duration)
    except KeyboardInterrupt:
        pass
    finally:
        sim.stop()
        if marker is not None:
            marker.remove()
