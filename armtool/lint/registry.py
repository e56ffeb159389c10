"""Every lint rule, in code order. A new rule is one module plus one line here.

Rule modules are imported on use, per file kind: `armtool lint robot.urdf` loads only the URDF
rules, which keeps pre-commit start-up short. The table repeats each rule's code and name so that
configuration can be checked without importing anything (a test keeps them in step).
"""

from __future__ import annotations

import importlib
from typing import Any

from armtool.lint.rule import Rule, Target

# (code, name, "module:Class" in armtool.lint.rules)
RULE_TABLE: tuple[tuple[str, str, str], ...] = (
    ("U001", "invalid-xml", "u001_invalid_xml:InvalidXml"),
    ("U002", "not-a-robot", "u002_not_a_robot:NotARobot"),
    ("U003", "entity-declaration", "u003_entity_declaration:EntityDeclaration"),
    ("U101", "unknown-link", "u101_unknown_link:UnknownLink"),
    ("U102", "duplicate-name", "u102_duplicate_name:DuplicateName"),
    ("U103", "multiple-roots", "u103_multiple_roots:MultipleRoots"),
    ("U104", "multiple-parents", "u104_multiple_parents:MultipleParents"),
    ("U105", "unknown-joint-type", "u105_unknown_joint_type:UnknownJointType"),
    ("U106", "mimic-unknown-joint", "u106_mimic_unknown_joint:MimicUnknownJoint"),
    ("U107", "missing-required", "u107_missing_name:MissingRequired"),
    ("U201", "missing-limit", "u201_missing_limit:MissingLimit"),
    ("U202", "limit-missing-attribute", "u202_limit_missing_attribute:LimitMissingAttribute"),
    ("U203", "non-positive-velocity", "u203_non_positive_velocity:NonPositiveVelocity"),
    ("U204", "non-positive-effort", "u204_non_positive_effort:NonPositiveEffort"),
    ("U205", "lower-above-upper", "u205_lower_above_upper:LowerAboveUpper"),
    ("U206", "continuous-with-limits", "u206_continuous_with_limits:ContinuousWithLimits"),
    ("U301", "rpy-out-of-range", "u301_rpy_out_of_range:RpyOutOfRange"),
    ("U302", "zero-axis", "u302_zero_axis:ZeroAxis"),
    ("U303", "non-unit-axis", "u303_non_unit_axis:NonUnitAxis"),
    ("U304", "non-finite-number", "u304_non_finite_number:NonFiniteNumber"),
    ("U305", "malformed-number", "u305_malformed_number:MalformedNumber"),
    ("U401", "missing-inertial", "u401_missing_inertial:MissingInertial"),
    ("U402", "root-inertia", "u402_root_inertia:RootInertia"),
    ("U403", "non-positive-mass", "u403_non_positive_mass:NonPositiveMass"),
    ("U404", "inertia-not-positive-definite", "u404_inertia_not_positive_definite:InertiaNotPositiveDefinite"),
    ("U405", "inertia-triangle-inequality", "u405_inertia_triangle_inequality:InertiaTriangleInequality"),
    ("U406", "incomplete-inertial", "u406_incomplete_inertial:IncompleteInertial"),
    ("U501", "unresolved-mesh", "u501_unresolved_mesh:UnresolvedMesh"),
    ("U502", "unknown-package", "u502_unknown_package:UnknownPackage"),
    ("U503", "transmission-unknown-joint", "u503_transmission_unknown_joint:TransmissionUnknownJoint"),
    ("U504", "non-positive-reduction", "u504_non_positive_reduction:NonPositiveReduction"),
    ("U505", "ros2-control-unknown-joint", "u505_ros2_control_unknown_joint:Ros2ControlUnknownJoint"),
    ("X001", "xacro-error", "x001_xacro_error:XacroError"),
    ("X002", "urdf-is-xacro", "x002_urdf_is_xacro:UrdfIsXacro"),
    ("X003", "include-fragment", "x003_include_fragment:IncludeFragment"),
    ("M101", "setup-assistant-missing-file", "m101_setup_assistant_missing_file:SetupAssistantMissingFile"),
    ("M102", "moveit-config-file-not-found", "m102_moveit_config_file_not_found:MoveItConfigFileNotFound"),
    ("S001", "invalid-srdf", "s001_invalid_srdf:InvalidSrdf"),
    ("S002", "urdf-not-found", "s002_urdf_not_found:UrdfNotFound"),
    ("S003", "srdf-for-other-variant", "s003_srdf_for_other_variant:SrdfForOtherVariant"),
    ("K001", "invalid-yaml", "k001_invalid_yaml:InvalidYaml"),
    ("K002", "srdf-not-found", "k002_srdf_not_found:SrdfNotFound"),
    ("S101", "srdf-unknown-joint", "s101_srdf_unknown_joint:SrdfUnknownJoint"),
    ("S102", "srdf-unknown-link", "s102_srdf_unknown_link:SrdfUnknownLink"),
    ("S103", "unknown-group", "s103_unknown_group:UnknownGroup"),
    ("S104", "chain-tip-not-below-base", "s104_chain_tip_not_below_base:ChainTipNotBelowBase"),
    ("S105", "end-effector-parent-link", "s105_end_effector_parent_link:EndEffectorParentLink"),
    ("S106", "group-state-out-of-limits", "s106_group_state_out_of_limits:GroupStateOutOfLimits"),
    ("S107", "group-state-missing-joint", "s107_group_state_missing_joint:GroupStateMissingJoint"),
    ("S108", "disable-collisions-unknown-link", "s108_disable_collisions_unknown_link:DisableCollisionsUnknownLink"),
    ("S109", "gripper-joint-in-arm-group", "s109_gripper_joint_in_arm_group:GripperJointInArmGroup"),
    ("S110", "robot-name-mismatch", "s110_robot_name_mismatch:RobotNameMismatch"),
    ("S111", "virtual-joint-not-root", "s111_virtual_joint_not_root:VirtualJointNotRoot"),
    ("S112", "passive-joint-in-group", "s112_passive_joint_in_group:PassiveJointInGroup"),
    ("S113", "virtual-joint-incomplete", "s113_virtual_joint_incomplete:VirtualJointIncomplete"),
    ("K101", "kinematics-unknown-group", "k101_kinematics_unknown_group:KinematicsUnknownGroup"),
    ("K102", "unknown-solver-plugin", "k102_unknown_solver_plugin:UnknownSolverPlugin"),
    ("K103", "non-positive-timeout", "k103_non_positive_timeout:NonPositiveTimeout"),
    ("K104", "timeout-below-1ms", "k104_timeout_below_1ms:TimeoutBelow1ms"),
    ("K105", "non-positive-search-resolution", "k105_non_positive_search_resolution:NonPositiveSearchResolution"),
    ("K106", "group-settings-not-a-mapping", "k106_group_settings_not_a_mapping:GroupSettingsNotAMapping"),
    ("L001", "invalid-joint-limits-yaml", "l001_invalid_joint_limits_yaml:InvalidJointLimitsYaml"),
    ("L002", "joint-limits-robot-not-found", "l002_joint_limits_robot_not_found:JointLimitsRobotNotFound"),
    ("L101", "joint-limits-unknown-joint", "l101_joint_limits_unknown_joint:JointLimitsUnknownJoint"),
    ("L102", "integer-limit", "l102_integer_limit:IntegerLimit"),
    ("L103", "limit-wrong-type", "l103_limit_wrong_type:LimitWrongType"),
    ("L104", "missing-acceleration-limit", "l104_missing_acceleration_limit:MissingAccelerationLimit"),
    ("L105", "non-positive-limit", "l105_non_positive_limit:NonPositiveLimit"),
    ("L106", "limit-above-urdf", "l106_limit_above_urdf:LimitAboveUrdf"),
    ("L107", "scaling-factor-out-of-range", "l107_scaling_factor_out_of_range:ScalingFactorOutOfRange"),
    ("L108", "limit-without-flag", "l108_limit_without_flag:LimitWithoutFlag"),
    ("P001", "invalid-pilz-yaml", "p001_invalid_pilz_yaml:InvalidPilzYaml"),
    ("P101", "missing-cartesian-limit", "p101_missing_cartesian_limit:MissingCartesianLimit"),
    ("P102", "invalid-cartesian-limit", "p102_invalid_cartesian_limit:InvalidCartesianLimit"),
    ("P103", "integer-cartesian-limit", "p103_integer_cartesian_limit:IntegerCartesianLimit"),
    ("C001", "invalid-controllers-yaml", "c001_invalid_controllers_yaml:InvalidControllersYaml"),
    ("C101", "controller-unknown-joint", "c101_controller_unknown_joint:ControllerUnknownJoint"),
    ("C102", "group-without-controller", "c102_group_without_controller:GroupWithoutController"),
    ("C103", "controller-not-defined", "c103_controller_not_defined:ControllerNotDefined"),
    ("C104", "unknown-controller-type", "c104_unknown_controller_type:UnknownControllerType"),
)

CODES: dict[str, str] = {code: name for code, name, _ in RULE_TABLE}
NAMES: dict[str, str] = {name: code for code, name, _ in RULE_TABLE}
_TARGET_OF_LETTER = {
    "U": Target.URDF,
    "X": Target.URDF,
    "S": Target.SRDF,
    "K": Target.KINEMATICS,
    "L": Target.JOINT_LIMITS,
    "P": Target.PILZ,
    "C": Target.CONTROLLERS,
    "M": Target.SETUP_ASSISTANT,
}
_loaded: dict[str, type[Rule]] = {}


def rule_class(code: str) -> type[Rule]:
    """The rule with this code (imports its module)."""
    rule = _loaded.get(code)
    if rule is None:
        target = next(t for c, _, t in RULE_TABLE if c == code)
        module, _, cls = target.partition(":")
        rule = getattr(importlib.import_module(f"armtool.lint.rules.{module}"), cls)
        _loaded[code] = rule
    return rule


def rules_for(target: Target) -> list[type[Rule]]:
    return [rule_class(code) for code, _, _ in RULE_TABLE if _TARGET_OF_LETTER[code[0]] is target]


# Reported by the engine while it loads a file (bad XML, no <robot>, xacro failed, no URDF beside
# an SRDF, ...); their check() finds nothing, so a lint run need not import them to run them.
LOADER_CODES = frozenset(
    {
        "U001",
        "U002",
        "U003",
        "X001",
        "X002",
        "X003",
        "M101",
        "M102",
        "S001",
        "S002",
        "S003",
        "K001",
        "K002",
        "L001",
        "P001",
        "C001",
    }
)


def checks_for(target: Target) -> list[type[Rule]]:
    """The rules whose check() looks at a loaded file of this kind, in code order."""
    return [
        rule_class(code)
        for code, _, _ in RULE_TABLE
        if _TARGET_OF_LETTER[code[0]] is target and code not in LOADER_CODES
    ]


def all_rules() -> tuple[type[Rule], ...]:
    return tuple(rule_class(code) for code, _, _ in RULE_TABLE)


def find_rule(code_or_name: str) -> type[Rule] | None:
    code = code_or_name.upper() if code_or_name.upper() in CODES else NAMES.get(code_or_name.lower())
    return rule_class(code) if code else None


def __getattr__(name: str) -> Any:
    # RULES, BY_CODE, BY_NAME: the full registry for listings, docs and SARIF (imports every rule).
    if name == "RULES":
        return all_rules()
    if name == "BY_CODE":
        return {r.code: r for r in all_rules()}
    if name == "BY_NAME":
        return {r.name: r for r in all_rules()}
    raise AttributeError(name)
