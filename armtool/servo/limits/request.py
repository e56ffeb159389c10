"""What `armtool limits` was asked to do, checked before the bus is opened: the options that
go together, the joints (from --arm or --ids), the URDF to edit and the outputs to write.

Why before the bus: nothing moves, and no recording is made, for a run that must fail."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from armtool.errors import ArmtoolError
from armtool.servo.limits.arm_file import Joint, load_arm, parse_ids
from armtool.servo.limits.auto import AutoParams
from armtool.servo.limits.choices import Mode
from armtool.servo.limits.urdf import check_urdf_names
from armtool.servo.registry import Protocol


@dataclass(frozen=True)
class Request:
    """The options of `armtool limits`, in the order the command declares them."""

    port: str | None
    mode: Mode | None
    protocol: Protocol | None
    baud: int | None
    ids: str | None
    model: str | None
    arm: Path | None
    output: Path | None
    margin: float
    duration: float | None
    rate: float
    min_dwell: float
    torque_limit: float  # percent
    speed: float
    stall_window: float
    stall_load: float  # percent
    back_off: float
    max_seek: float | None
    first_dir: str
    urdf: Path | None
    in_place: bool
    urdf_out: Path | None
    allow_widen: bool
    write_eeprom: bool
    yes: bool
    dry_run: bool
    timeout_ms: float
    lerobot_calibration: Path | None
    lerobot_full_turn: str | None
    from_lerobot: Path | None
    # A xacro --urdf: expanded with these, its expansion is what --urdf-out writes.
    xacro_args: tuple[tuple[str, str], ...] = ()
    package_paths: tuple[Path, ...] = ()

    @property
    def urdf_is_xacro(self) -> bool:
        return self.urdf is not None and self.urdf.name.lower().endswith(".xacro")

    def auto_params(self) -> AutoParams:
        return AutoParams(
            torque_limit=self.torque_limit / 100,
            speed_deg_s=self.speed,
            stall_window_s=self.stall_window,
            stall_load=self.stall_load / 100,
            back_off_deg=self.back_off,
            max_seek_s=self.max_seek,
            first_dir=-1 if self.first_dir == "-" else 1,
        )


def check_request(r: Request, interactive: bool) -> None:
    """Options that contradict each other, or need a terminal that is not there."""
    if r.from_lerobot is not None or r.lerobot_calibration is not None or r.lerobot_full_turn is not None:
        _check_lerobot_options(r)
    elif r.port is None or r.mode is None:
        raise ArmtoolError(
            f"{'--port' if r.port is None else '--mode'} is required",
            hint="e.g. --port /dev/ttyUSB0 --mode manual (or --from-lerobot FILE --arm arm.yaml to convert a LeRobot file)",
        )
    if (r.ids is None) == (r.arm is None):
        raise ArmtoolError(
            "give exactly one of --ids or --arm", hint="e.g. --ids 1,2,3 --model AX-12A, or --arm arm.yaml"
        )
    if r.first_dir not in ("-", "+"):
        raise ArmtoolError(f"--first-dir must be - or +, got '{r.first_dir}'")
    if r.urdf is not None and r.in_place == (r.urdf_out is not None):
        raise ArmtoolError("with --urdf pass either --in-place or --urdf-out FILE")
    if r.urdf is None and (r.in_place or r.urdf_out is not None):
        raise ArmtoolError("--in-place and --urdf-out need --urdf")
    if r.in_place and r.urdf_is_xacro:
        raise ArmtoolError(
            "--in-place cannot edit a xacro: its limits are written by macros and expressions",
            str(r.urdf),
            "pass --urdf-out FILE to write the expanded URDF (--xacro-arg, --package-path) with the recorded limits",
        )
    if r.dry_run and not r.write_eeprom:
        raise ArmtoolError("--dry-run applies to --write-eeprom")
    if r.port is not None and r.mode is Mode.MANUAL and r.duration is None and not interactive:
        raise ArmtoolError("manual mode ends on Enter, but stdin is not a terminal", hint="pass --duration SECONDS")
    if r.mode is Mode.AUTO and not r.yes and not interactive:
        raise ArmtoolError(
            "auto mode moves the arm and needs a confirmation, but stdin is not a terminal",
            hint="pass --yes once the workspace is clear",
        )
    if r.write_eeprom and not r.dry_run and not r.yes and not interactive:
        raise ArmtoolError(
            "--write-eeprom needs a confirmation, but stdin is not a terminal",
            hint="pass --yes, or --dry-run to see the writes",
        )


def _check_lerobot_options(r: Request) -> None:
    out, source = r.lerobot_calibration, r.from_lerobot
    if r.lerobot_full_turn is not None and out is None:
        raise ArmtoolError("--lerobot-full-turn applies to --lerobot-calibration")
    if r.arm is None:
        raise ArmtoolError(
            "--lerobot-calibration and --from-lerobot need --arm (its joint names are LeRobot's motor names)",
            hint="joints: [{name: shoulder_pan, id: 1, model: STS3215}, ...]",
        )
    if out is not None and source is not None:
        raise ArmtoolError("give one of --lerobot-calibration (write a file) and --from-lerobot (read one)")
    if out is not None and (r.port is None or r.mode is None):
        raise ArmtoolError("--lerobot-calibration writes a recording: it needs --port and --mode")
    if r.port is None and r.mode is not None:
        raise ArmtoolError(
            "--mode records the arm: it needs --port", hint="without --port, --from-lerobot converts the file"
        )
    if r.port is not None and r.mode is None:
        raise ArmtoolError(
            "--mode is required with --port", hint="--from-lerobot with --port records the arm to compare it"
        )
    if r.port is None and r.write_eeprom:
        raise ArmtoolError("--write-eeprom needs --port")


@dataclass(frozen=True)
class Arm:
    """The joints to record and the bus they are on."""

    joints: list[Joint]
    protocol: str
    baud: int


def resolve_arm(r: Request) -> Arm:
    """Joints from --arm (with its bus settings as defaults) or --ids; every model on the protocol."""
    from armtool.servo.models import by_name

    if r.arm is not None:
        arm_file = load_arm(r.arm)
        joints = arm_file.joints
        proto = r.protocol.value if r.protocol else (arm_file.protocol or Protocol.DXL1.value)
        baud = r.baud if r.baud is not None else (arm_file.baud or 1_000_000)
    else:
        expected = by_name(r.model) if r.model else None
        joints = [Joint(f"id{i}", i, expected) for i in parse_ids(r.ids or "")]
        proto = r.protocol.value if r.protocol else Protocol.DXL1.value
        baud = r.baud if r.baud is not None else 1_000_000
    for j in joints:
        if j.model is not None and j.model.protocol != proto:
            raise ArmtoolError(
                f"joint '{j.name}': {j.model.name} speaks {j.model.protocol}, not {proto}",
                hint=f"pass --protocol {j.model.protocol}",
            )
    return Arm(joints, proto, baud)


def read_urdf(r: Request, joints: list[Joint]) -> str | None:
    """The URDF's text when --urdf is given, its joint names checked against the arm's."""
    if r.urdf is None:
        return None
    from armtool.fileio import read_text

    if r.urdf_is_xacro:
        from armtool.model.load import urdf_text

        text = urdf_text(r.urdf, dict(r.xacro_args), r.package_paths)
    else:
        # Decoded from the bytes as they are: line endings and a byte-order mark stay (Path.read_text
        # turned CRLF into LF, so the patched URDF and the --in-place backup were not the user's file).
        text = read_text(r.urdf, "--urdf", keep_bom=True)
    check_urdf_names(text, [j.name for j in joints], str(r.urdf))
    return text


def check_outputs(r: Request) -> None:
    """Every output writable, and none an input, before the bus is opened (nothing moves for a
    write that must fail)."""
    from armtool.fileio import backup_path, check_output_path, check_output_paths

    check_output_paths(
        {"-o": r.output, "--urdf-out": r.urdf_out, "--lerobot-calibration": r.lerobot_calibration},
        inputs=[r.arm, r.urdf, r.from_lerobot],
    )
    if r.in_place and r.urdf is not None:
        check_output_path(r.urdf, "--in-place")
        check_output_path(backup_path(r.urdf), "--in-place (backup)")


def full_turn_names(text: str | None, joints: list[Joint]) -> set[str]:
    """The joints named by --lerobot-full-turn, each one of the arm's."""
    if text is None:
        return set()
    names = {n.strip() for n in text.split(",") if n.strip()}
    unknown = sorted(names - {j.name for j in joints})
    if unknown or not names:
        raise ArmtoolError(
            f"--lerobot-full-turn: {', '.join(unknown) or 'no joint'} not in the arm file",
            hint="joints: " + ", ".join(j.name for j in joints),
        )
    return names


def check_motion_options(joint: Joint, margin_deg: float, back_off_deg: float) -> None:
    """The options that bound motion against the servo's range, once its model is known."""
    model = joint.model
    assert model is not None  # known once the servo answered (or the arm file named it)
    if 2 * margin_deg >= model.range_deg:
        raise ArmtoolError(
            f"--margin {margin_deg:g}° leaves nothing of the {model.name}'s {model.range_deg:g}° range "
            f"(joint '{joint.name}')",
            hint="a margin of a few degrees is usual (default 2)",
        )
    if back_off_deg >= model.range_deg / 2:
        raise ArmtoolError(
            f"--back-off {back_off_deg:g}° is half the {model.name}'s {model.range_deg:g}° range or more "
            f"(joint '{joint.name}')",
            hint="a back-off of a few degrees is usual (default 3)",
        )
