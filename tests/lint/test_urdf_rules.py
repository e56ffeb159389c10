"""Each URDF rule on a minimal bad and good robot: (code, line), severity and message."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from armtool.lint.finding import Finding, Severity
from tests.lint.helpers import LINK, codes, lint_text, revolute, robot

BASE = '<link name="base"/>'


def two_links(joint: str, child_link: str = LINK.format(name="l1")) -> str:
    return robot(f"{BASE}\n{child_link}\n{joint}")


def only(findings, code):  # type: ignore[no-untyped-def]
    return [f for f in findings if f.code == code]


def test_sound_robot_has_no_findings(tmp_path: Path) -> None:
    assert lint_text(tmp_path, two_links(revolute("j1", "base", "l1"))) == []


def test_u101_unknown_link_suggests_closest(tmp_path: Path) -> None:
    found = lint_text(tmp_path, two_links(revolute("j1", "base", "lnk1"), LINK.format(name="link1")))
    (f,) = only(found, "U101")
    assert f.line == 4 and "'lnk1' does not exist" in f.message and "did you mean 'link1'" in f.message
    assert f.severity is Severity.ERROR


def test_u102_duplicate_link(tmp_path: Path) -> None:
    text = robot(f"{BASE}\n{LINK.format(name='l1')}\n{LINK.format(name='l1')}\n{revolute('j1', 'base', 'l1')}")
    assert ("U102", 4) in codes(lint_text(tmp_path, text))


def test_u103_second_root(tmp_path: Path) -> None:
    text = robot(f"{BASE}\n{LINK.format(name='l1')}\n{LINK.format(name='camera')}\n{revolute('j1', 'base', 'l1')}")
    (f,) = only(lint_text(tmp_path, text), "U103")
    assert f.line == 4 and "'camera'" in f.message


def test_u104_two_parents(tmp_path: Path) -> None:
    text = robot(
        f"{BASE}\n{LINK.format(name='l1')}\n{LINK.format(name='l2')}\n"
        f"{revolute('j1', 'base', 'l1')}\n{revolute('j2', 'base', 'l2')}\n{revolute('j3', 'l1', 'l2')}"
    )
    assert codes(only(lint_text(tmp_path, text), "U104")) == [("U104", 7)]


def test_u105_unknown_joint_type(tmp_path: Path) -> None:
    joint = '<joint name="j1" type="revolve"><parent link="base"/><child link="l1"/></joint>'
    (f,) = only(lint_text(tmp_path, two_links(joint)), "U105")
    assert "did you mean 'revolute'" in f.message


def test_u106_mimic_unknown_joint(tmp_path: Path) -> None:
    joint = revolute("j1", "base", "l1", extra='<mimic joint="j0"/>')
    assert codes(only(lint_text(tmp_path, two_links(joint)), "U106")) == [("U106", 4)]


def test_u107_joint_without_child(tmp_path: Path) -> None:
    joint = '<joint name="j1" type="fixed"><parent link="base"/></joint>'
    assert ("U107", 4) in codes(lint_text(tmp_path, two_links(joint)))


def test_u107_robot_without_name(tmp_path: Path) -> None:
    text = two_links(revolute("j1", "base", "l1")).replace('<robot name="arm">', "<robot>")
    assert codes(lint_text(tmp_path, text)) == [("U107", 1)]


def test_u201_revolute_without_limit(tmp_path: Path) -> None:
    joint = '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/></joint>'
    assert codes(lint_text(tmp_path, two_links(joint))) == [("U201", 4)]


def test_u202_limit_without_effort_and_velocity(tmp_path: Path) -> None:
    (f,) = lint_text(tmp_path, two_links(revolute("j1", "base", "l1", limit='lower="-1" upper="1"')))
    assert f.code == "U202" and "effort and velocity" in f.message


@pytest.mark.parametrize(
    ("limit", "code"),
    [
        ('lower="-1" upper="1" effort="10" velocity="0"', "U203"),
        ('lower="-1" upper="1" effort="0" velocity="1"', "U204"),
        ('lower="1" upper="-1" effort="10" velocity="1"', "U205"),
    ],
)
def test_limit_values(tmp_path: Path, limit: str, code: str) -> None:
    assert codes(lint_text(tmp_path, two_links(revolute("j1", "base", "l1", limit=limit)))) == [(code, 4)]


def _caster_base(actuation: str, arm_effort: str = "10") -> str:
    """A base with two driven arm joints and a passive caster (effort 0), and `actuation` elements."""
    caster = (
        '<joint name="caster" type="continuous"><parent link="base"/><child link="l2"/><axis xyz="0 0 1"/>'
        '<limit effort="0" velocity="3"/></joint>'
    )
    arm = revolute("j1", "base", "l1", limit=f'lower="-1" upper="1" effort="{arm_effort}" velocity="1"')
    arm += revolute("j2", "l1", "l3")
    body = "\n".join(LINK.format(name=n) for n in ("base", "l1", "l2", "l3"))
    return robot(f"{body}\n{arm}\n{caster}\n{actuation}")


def _u204(findings: list[Finding]) -> list[str]:
    return [f.message for f in findings if f.code == "U204"]


ROS2_CONTROL = '<ros2_control name="hw" type="system"><joint name="j1"/><joint name="j2"/></ros2_control>'
TRANSMISSION = (
    '<transmission name="t1"><joint name="j1"/></transmission><transmission name="t2"><joint name="j2"/></transmission>'
)


@pytest.mark.parametrize("actuation", [ROS2_CONTROL, TRANSMISSION, ""])
def test_u204_effort_0_on_a_passive_joint_is_true(tmp_path: Path, actuation: str) -> None:
    """effort 0 on a joint nothing drives (not named by the transmissions / ros2_control that name
    the others; continuous, where the model names no actuation): the caster of trossen's mobile_ai."""
    assert _u204(lint_text(tmp_path, _caster_base(actuation))) == []
    # the driven (or ranged) joint with effort 0 is still reported
    assert _u204(lint_text(tmp_path, _caster_base(actuation, arm_effort="0"))) == ["joint 'j1': effort limit is 0"]


def test_u204_effort_0_on_a_driven_continuous_joint_is_reported(tmp_path: Path) -> None:
    driven = ROS2_CONTROL.replace('"j1"', '"caster"')
    assert _u204(lint_text(tmp_path, _caster_base(driven))) == ["joint 'caster': effort limit is 0"]


def test_u206_continuous_with_limits_but_not_zero_placeholders(tmp_path: Path) -> None:
    joint = '<joint name="j1" type="continuous"><parent link="base"/><child link="l1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
    assert codes(lint_text(tmp_path, two_links(joint))) == [("U206", 4)]
    placeholder = joint.replace('lower="-3" upper="3"', 'lower="0" upper="0"')
    assert lint_text(tmp_path, two_links(placeholder)) == []


def test_u301_degrees_are_flagged_and_pi_is_not(tmp_path: Path) -> None:
    joint = revolute("j1", "base", "l1", extra='<origin xyz="0 0 0.1" rpy="0 0 90"/>')
    (f,) = lint_text(tmp_path, two_links(joint))
    assert f.code == "U301" and "looks like degrees" in f.message and "1.570796327" in (f.hint or "")
    assert f.edit is not None
    for pi in ("3.1416", "3.14159265359", "-3.1416"):
        ok = revolute("j1", "base", "l1", extra=f'<origin xyz="0 0 0.1" rpy="{pi} 0 0"/>')
        assert lint_text(tmp_path, two_links(ok)) == [], pi


def test_u301_radians_beyond_pi_are_info_and_degrees_a_warning(tmp_path: Path) -> None:
    # 3π/2 written as 4.71238898038 (talos wrist_left_tool_joint) is the same rotation as -π/2, in
    # radians: no parser or planner minds; only values that look like degrees are warnings.
    radians = revolute("j1", "base", "l1", extra='<origin xyz="0 0 0.1" rpy="0 0 4.71238898038"/>')
    (f,) = lint_text(tmp_path, two_links(radians))
    assert (f.code, f.severity) == ("U301", Severity.INFO) and f.edit is not None
    degrees = radians.replace("4.71238898038", "270")
    (g,) = lint_text(tmp_path, two_links(degrees))
    assert (g.code, g.severity) == ("U301", Severity.WARNING)
    mixed = radians.replace('rpy="0 0 4.71238898038"', 'rpy="0 90 4.71"')  # 90 is plainly degrees
    (h,) = lint_text(tmp_path, two_links(mixed))
    assert (h.code, h.severity) == ("U301", Severity.WARNING) and "degrees" in h.message


def test_u301_wraps_to_same_rotation(tmp_path: Path) -> None:
    from armtool.lint.rules.u301_rpy_out_of_range import wrap

    assert wrap(4.0) == pytest.approx(4.0 - 2 * 3.141592653589793)
    assert wrap(-3.141592653589793) == pytest.approx(3.141592653589793)


@pytest.mark.parametrize(("axis", "code"), [("0 0 0", "U302"), ("0 0 2", "U303")])
def test_axis(tmp_path: Path, axis: str, code: str) -> None:
    joint = revolute("j1", "base", "l1").replace('<axis xyz="0 0 1"/>', f'<axis xyz="{axis}"/>')
    assert codes(lint_text(tmp_path, two_links(joint))) == [(code, 4)]


def test_u304_nan_and_u305_wrong_count(tmp_path: Path) -> None:
    joint = revolute("j1", "base", "l1", extra='<origin xyz="0 nan 0.1" rpy="0 0"/>')
    assert sorted(codes(lint_text(tmp_path, two_links(joint)))) == [("U304", 4), ("U305", 4)]


def test_u401_missing_inertial_on_moving_body(tmp_path: Path) -> None:
    body = '<link name="l1"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>'
    (f,) = lint_text(tmp_path, two_links(revolute("j1", "base", "l1"), body))
    assert (f.code, f.severity) == ("U401", Severity.WARNING)


def test_u401_quiet_for_fixed_frames_and_info_for_virtual_links(tmp_path: Path) -> None:
    fixed = '<joint name="j1" type="fixed"><parent link="base"/><child link="l1"/></joint>'
    assert lint_text(tmp_path, two_links(fixed, '<link name="l1"/>')) == []
    virtual = robot(
        f"{BASE}\n<link name='v'/>\n{LINK.format(name='l2')}\n{revolute('j1', 'base', 'v')}\n{revolute('j2', 'v', 'l2')}"
    )
    (f,) = lint_text(tmp_path, virtual)
    assert (f.code, f.severity) == ("U401", Severity.INFO)


def test_u401_mass_on_welded_child_counts(tmp_path: Path) -> None:
    text = robot(
        f"{BASE}\n<link name='l1'><visual><geometry><box size='1 1 1'/></geometry></visual></link>\n{LINK.format(name='shell')}\n"
        f"{revolute('j1', 'base', 'l1')}\n"
        "<joint name='weld' type='fixed'><parent link='l1'/><child link='shell'/></joint>"
    )
    assert lint_text(tmp_path, text) == []


def test_u402_root_inertia_is_info(tmp_path: Path) -> None:
    text = robot(f"{LINK.format(name='base')}\n{LINK.format(name='l1')}\n{revolute('j1', 'base', 'l1')}")
    (f,) = lint_text(tmp_path, text)
    assert (f.code, f.severity) == ("U402", Severity.INFO)


@pytest.mark.parametrize(
    ("inertial", "code", "severity"),
    [
        ('<mass value="-1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>', "U403", Severity.ERROR),
        ('<mass value="0"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>', "U403", Severity.WARNING),
        (
            '<mass value="1"/><inertia ixx="-0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>',
            "U404",
            Severity.ERROR,
        ),
        (
            '<mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.05"/>',
            "U405",
            Severity.ERROR,
        ),
        ('<mass value="1"/>', "U406", Severity.ERROR),
    ],
)
def test_inertial_values(tmp_path: Path, inertial: str, code: str, severity: Severity) -> None:
    link = f'<link name="l1"><inertial>{inertial}</inertial></link>'
    (f,) = lint_text(tmp_path, two_links(revolute("j1", "base", "l1"), link))
    assert (f.code, f.line, f.severity) == (code, 3, severity)


def test_inertia_products_are_used(tmp_path: Path) -> None:
    # Diagonal 1,1,1 with ixy=2 has principal moments -1, 1, 3: not positive definite.
    link = '<link name="l1"><inertial><mass value="1"/><inertia ixx="1" ixy="2" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>'
    assert [f.code for f in lint_text(tmp_path, two_links(revolute("j1", "base", "l1"), link))] == ["U404"]


def test_u405_a_singular_tensor_hidden_by_rounding_is_caught(tmp_path: Path) -> None:
    """All six entries 0.01 (Sawyer's right_hand with gazebo:=true): moments 0, 0, 0.03, whose
    closed form gives the zero as about -1e-17; that is rounding (U404: singular), not a negative
    moment, and the tensor breaks the triangle inequality."""
    link = '<link name="l1"><inertial><mass value="0.01"/><inertia ixx="0.01" ixy="0.01" ixz="0.01" iyy="0.01" iyz="0.01" izz="0.01"/></inertial></link>'
    found = [f for f in lint_text(tmp_path, two_links(revolute("j1", "base", "l1"), link)) if f.code != "U402"]
    assert [(f.code, f.severity) for f in found] == [("U404", Severity.INFO), ("U405", Severity.ERROR)]
    assert "principal moments 0, 0, 0.03 break the triangle inequality" in found[1].message


def test_u405_a_negligible_dummy_tensor_is_info(tmp_path: Path) -> None:
    """Every entry 1e-6 beside a real link (anymal's and Sawyer's dummy frame links): the letter is
    broken, the dynamics are not changed: info."""
    dummy = '<link name="l1"><inertial><mass value="1e-6"/><inertia ixx="1e-6" ixy="1e-6" ixz="1e-6" iyy="1e-6" iyz="1e-6" izz="1e-6"/></inertial></link>'
    text = robot(f"{LINK.format(name='base')}\n{dummy}\n{revolute('j1', 'base', 'l1')}")
    found = [f for f in lint_text(tmp_path, text) if f.code == "U405"]
    assert [(f.severity, f.message.endswith("(a dummy?)")) for f in found] == [(Severity.INFO, True)]


def test_float_noise_inertia_is_quiet(tmp_path: Path) -> None:
    link = '<link name="l1"><inertial><mass value="1"/><inertia ixx="1e-20" ixy="-2e-20" ixz="0" iyy="1e-20" iyz="0" izz="0"/></inertial></link>'
    assert lint_text(tmp_path, two_links(revolute("j1", "base", "l1"), link)) == []


def test_meshes_resolve_relative_package_and_missing(tmp_path: Path) -> None:
    pkg = tmp_path / "my_robot"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "urdf").mkdir()
    (pkg / "package.xml").write_text("<package><name>my_robot</name></package>")
    (pkg / "meshes" / "a.stl").write_text("solid a\nendsolid a\n")
    link = (
        '<link name="l1"><visual><geometry><mesh filename="package://my_robot/meshes/a.stl"/></geometry></visual>'
        '<collision><geometry><mesh filename="package://my_robot/meshes/b.stl"/></geometry></collision>'
        '<visual><geometry><mesh filename="package://other_pkg/x.stl"/></geometry></visual>'
        '<visual><geometry><mesh filename="../meshes/a.stl"/></geometry></visual></link>'
    )
    link = link.replace(
        '<link name="l1">',
        '<link name="l1"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>',
    )
    found = lint_text(pkg / "urdf", two_links(revolute("j1", "base", "l1"), link))
    assert sorted(f.code for f in found) == ["U501", "U502"]
    assert "b.stl" in only(found, "U501")[0].message and "other_pkg" in only(found, "U502")[0].message


def _mesh_link(uri: str) -> str:
    return (
        '<link name="l1"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>'
        f'</inertial><visual><geometry><mesh filename="{uri}"/></geometry></visual></link>'
    )


def _package(tmp_path: Path) -> Path:
    pkg = tmp_path / "pkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "package.xml").write_text("<package><name>pkg</name></package>")
    return pkg


@pytest.mark.parametrize(
    ("where", "severity", "says"),
    [
        # file:///usr/<vendor SDK>/... (romeo_laas_small.urdf): whether it exists depends on the machine
        ("sdk/meshes/torso.mesh", Severity.WARNING, "outside the package"),
        ("pkg/meshes/torso.stl", Severity.ERROR, "not found"),
    ],
)
@pytest.mark.parametrize("scheme", ["file://", ""])
def test_missing_absolute_mesh_is_a_warning_outside_the_package_only(
    tmp_path: Path, where: str, severity: Severity, says: str, scheme: str
) -> None:
    pkg = _package(tmp_path)
    uri = f"{scheme}{tmp_path / where}"
    (f,) = lint_text(pkg / "urdf", two_links(revolute("j1", "base", "l1"), _mesh_link(uri)))
    assert (f.code, f.severity) == ("U501", severity) and says in f.message


def test_missing_mesh_inside_the_package_through_a_symlink_is_still_an_error(tmp_path: Path) -> None:
    # colcon --symlink-install: the path names the package through a link; it is still inside it.
    pkg = _package(tmp_path)
    (tmp_path / "link").symlink_to(tmp_path)
    uri = f"file://{tmp_path / 'link' / 'pkg' / 'meshes' / 'missing.stl'}"
    (f,) = lint_text(pkg / "urdf", two_links(revolute("j1", "base", "l1"), _mesh_link(uri)))
    assert (f.code, f.severity) == ("U501", Severity.ERROR) and "not found" in f.message


def test_three_slash_package_mesh_suggests_the_two_slash_uri_that_exists(tmp_path: Path) -> None:
    pkg = _package(tmp_path)
    (pkg / "meshes" / "a.stl").write_text("solid a\nendsolid a\n")
    found = lint_text(pkg / "urdf", two_links(revolute("j1", "base", "l1"), _mesh_link("package:///pkg/meshes/a.stl")))
    (f,) = found
    assert (f.code, f.severity) == ("U501", Severity.ERROR) and "names no package" in f.message
    assert f.hint == 'write filename="package://pkg/meshes/a.stl" (two slashes; that file exists)'
    (g,) = lint_text(pkg / "urdf", two_links(revolute("j1", "base", "l1"), _mesh_link("package:///pkg/meshes/b.stl")))
    assert g.hint is not None and "package://PACKAGE/path" in g.hint


@pytest.mark.parametrize(
    ("uri", "suggested"),
    [
        # a renamed folder: meshes/visual/ is now meshes/visuals/
        ("package://pkg/meshes/visual/forearm.stl", "package://pkg/meshes/visuals/forearm.stl"),
        # a misspelt and a differently cased name, relative to the URDF
        ("../meshes/visuals/forarm.stl", "../meshes/visuals/forearm.stl"),
        ("../meshes/visuals/Forearm.STL", "../meshes/visuals/forearm.stl"),
        # an absolute path inside the package keeps its form
        ("{pkg}/meshes/visuals/Link_1.stl", "{pkg}/meshes/visuals/link1.stl"),
        ("file://{pkg}/meshes/visual/link1.stl", "file://{pkg}/meshes/visuals/link1.stl"),
    ],
)
def test_missing_mesh_suggests_the_existing_file_with_the_closest_path(
    tmp_path: Path, uri: str, suggested: str
) -> None:
    pkg = _package(tmp_path)
    (pkg / "meshes" / "visuals").mkdir()
    for name in ("forearm.stl", "link1.stl", "link2.stl", "hand.stl"):
        (pkg / "meshes" / "visuals" / name).write_text("solid\nendsolid\n")
    real = str(pkg.resolve())
    (f,) = lint_text(pkg / "urdf", two_links(revolute("j1", "base", "l1"), _mesh_link(uri.format(pkg=real))))
    expected = suggested.format(pkg=real)
    assert (f.code, f.severity) == ("U501", Severity.ERROR)
    assert f"did you mean '{expected}'?" in f.message
    assert f.hint == f'write filename="{expected}" (that file exists; file names are case-sensitive)'


@pytest.mark.parametrize(
    "uri",
    [
        "package://pkg/meshes/visuals/base.stl",  # only forearm, link1, link2, hand: none is base
        "package://pkg/meshes/visuals/link3.stl",  # link3 is not a misspelling of link1 or link2
        "package://pkg/meshes/visual/Base.stl",  # a renamed folder, but no file of that name in it
    ],
)
def test_missing_mesh_suggests_nothing_unrelated(tmp_path: Path, uri: str) -> None:
    pkg = _package(tmp_path)
    (pkg / "meshes" / "visuals").mkdir()
    for name in ("forearm.stl", "link1.stl", "link2.stl", "hand.stl"):
        (pkg / "meshes" / "visuals" / name).write_text("solid\nendsolid\n")
    (f,) = lint_text(pkg / "urdf", two_links(revolute("j1", "base", "l1"), _mesh_link(uri)))
    assert (
        f.code == "U501" and "did you mean" not in f.message and f.hint == "fix the path; file names are case-sensitive"
    )


def test_package_path_option(tmp_path: Path) -> None:
    (tmp_path / "pkgs" / "meshes_pkg").mkdir(parents=True)
    (tmp_path / "pkgs" / "meshes_pkg" / "package.xml").write_text("<package><name>meshes_pkg</name></package>")
    (tmp_path / "pkgs" / "meshes_pkg" / "m.stl").write_text("solid\nendsolid\n")
    (tmp_path / "robot").mkdir()
    link = '<link name="l1"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial><visual><geometry><mesh filename="package://meshes_pkg/m.stl"/></geometry></visual></link>'
    text = two_links(revolute("j1", "base", "l1"), link)
    assert [f.code for f in lint_text(tmp_path / "robot", text)] == ["U502"]
    assert lint_text(tmp_path / "robot", text, package_paths=[tmp_path / "pkgs"]) == []


def test_transmissions(tmp_path: Path) -> None:
    trans = (
        '<transmission name="t1"><type>transmission_interface/SimpleTransmission</type>'
        '<joint name="j9"><hardwareInterface>PositionJointInterface</hardwareInterface></joint>'
        '<actuator name="m1"><mechanicalReduction>0</mechanicalReduction></actuator></transmission>'
    )
    text = robot(f"{BASE}\n{LINK.format(name='l1')}\n{revolute('j1', 'base', 'l1')}\n{trans}")
    assert sorted(codes(lint_text(tmp_path, text))) == [("U503", 5), ("U504", 5)]


def test_columns_point_at_the_attribute(tmp_path: Path) -> None:
    joint = revolute("j1", "base", "l1", limit='lower="-1" upper="1" effort="10" velocity="0"')
    (f,) = lint_text(tmp_path, two_links(joint))
    line = two_links(joint).splitlines()[f.line - 1]
    assert line[f.column - 1 :].startswith('velocity="0"')


@given(
    st.floats(min_value=-1e4, max_value=1e4, allow_nan=False),
    st.sampled_from(["{:.0f}", "{:.3f}", "{:.12f}", "{:g}", "{!r}", "{:e}", "{:.4E}"]),
)
def test_u301_text_precheck_never_misses_a_large_angle(value: float, style: str) -> None:
    import math

    from armtool.lint.rules.u301_rpy_out_of_range import TOLERANCE_RAD, _out_of_range

    text = style.format(value)
    assert _out_of_range(f"0 {text} 0") == (abs(float(text)) > math.pi + TOLERANCE_RAD)


def test_u505_ros2_control_joint_not_in_the_urdf(tmp_path: Path) -> None:
    text = robot(
        "\n".join(
            [
                LINK.format(name="base"),
                LINK.format(name="l1"),
                revolute("joint1", "base", "l1"),
                '<ros2_control name="arm" type="system"><hardware><plugin>mock_components/GenericSystem</plugin></hardware>',
                '<joint name="joint_1"><command_interface name="position"/></joint>',
                '<joint name="joint1"><command_interface name="position"/></joint>',
                '<gpio name="flange_io"><command_interface name="digital_out"/></gpio></ros2_control>',
            ]
        )
    )
    found = [f for f in lint_text(tmp_path, text) if f.code == "U505"]
    assert [(f.line, f.message) for f in found] == [
        (6, "ros2_control 'arm': joint 'joint_1' is not in the URDF (did you mean 'joint1'?)")
    ]


def test_x002_a_xacro_named_urdf_is_expanded(tmp_path: Path) -> None:
    """Parsed as URDF it gave a U101 (link 'l1' exists only inside the macro definition) and the
    macro's own `${parent}` joint as a second tree."""
    text = (
        '<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:macro name="segment" params="name parent">\n'
        + LINK.format(name="${name}")
        + "\n"
        + revolute("${name}_joint", "${parent}", "${name}")
        + "\n</xacro:macro>\n"
        + '<link name="base"/>\n<xacro:segment name="l1" parent="base"/>\n'
        + LINK.format(name="tool")
        + "\n"
        + revolute("tool_joint", "l1", "tool")
        + "\n</robot>\n"
    )
    found = lint_text(tmp_path, text, "arm.urdf")
    assert [(f.code, f.severity) for f in found] == [("X002", Severity.INFO)]
    assert "arm.urdf is a xacro" in found[0].message and "arm.urdf.xacro" in (found[0].hint or "")


def test_x002_not_for_stdin() -> None:
    """A document on stdin cannot be expanded (xacro needs its file): it is read as it is."""
    from armtool.lint.engine import STDIN, LintOptions, lint_paths

    found = lint_paths([STDIN], LintOptions(stdin=b'<robot name="a"><link name="${x}"/></robot>\n')).findings
    assert [f.code for f in found] == []
