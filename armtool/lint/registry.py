"""Every lint rule, in code order. A new rule is one module plus one line here."""

from __future__ import annotations

from armtool.lint.rule import Rule
from armtool.lint.rules.u001_invalid_xml import InvalidXml
from armtool.lint.rules.u002_not_a_robot import NotARobot
from armtool.lint.rules.u003_entity_declaration import EntityDeclaration
from armtool.lint.rules.u101_unknown_link import UnknownLink
from armtool.lint.rules.u102_duplicate_name import DuplicateName
from armtool.lint.rules.u103_multiple_roots import MultipleRoots
from armtool.lint.rules.u104_multiple_parents import MultipleParents
from armtool.lint.rules.u105_unknown_joint_type import UnknownJointType
from armtool.lint.rules.u106_mimic_unknown_joint import MimicUnknownJoint
from armtool.lint.rules.u107_missing_name import MissingRequired
from armtool.lint.rules.u201_missing_limit import MissingLimit
from armtool.lint.rules.u202_limit_missing_attribute import LimitMissingAttribute
from armtool.lint.rules.u203_non_positive_velocity import NonPositiveVelocity
from armtool.lint.rules.u204_non_positive_effort import NonPositiveEffort
from armtool.lint.rules.u205_lower_above_upper import LowerAboveUpper
from armtool.lint.rules.u206_continuous_with_limits import ContinuousWithLimits
from armtool.lint.rules.u301_rpy_out_of_range import RpyOutOfRange
from armtool.lint.rules.u302_zero_axis import ZeroAxis
from armtool.lint.rules.u303_non_unit_axis import NonUnitAxis
from armtool.lint.rules.u304_non_finite_number import NonFiniteNumber
from armtool.lint.rules.u305_malformed_number import MalformedNumber
from armtool.lint.rules.u401_missing_inertial import MissingInertial
from armtool.lint.rules.u402_root_inertia import RootInertia
from armtool.lint.rules.u403_non_positive_mass import NonPositiveMass
from armtool.lint.rules.u404_inertia_not_positive_definite import InertiaNotPositiveDefinite
from armtool.lint.rules.u405_inertia_triangle_inequality import InertiaTriangleInequality
from armtool.lint.rules.u406_incomplete_inertial import IncompleteInertial
from armtool.lint.rules.u501_unresolved_mesh import UnresolvedMesh
from armtool.lint.rules.u502_unknown_package import UnknownPackage
from armtool.lint.rules.u503_transmission_unknown_joint import TransmissionUnknownJoint
from armtool.lint.rules.u504_non_positive_reduction import NonPositiveReduction
from armtool.lint.rules.x001_xacro_error import XacroError
from armtool.lint.rules.s001_invalid_srdf import InvalidSrdf
from armtool.lint.rules.s002_urdf_not_found import UrdfNotFound
from armtool.lint.rules.k001_invalid_yaml import InvalidYaml
from armtool.lint.rules.k002_srdf_not_found import SrdfNotFound

RULES: tuple[type[Rule], ...] = (
    InvalidXml,
    NotARobot,
    EntityDeclaration,
    UnknownLink,
    DuplicateName,
    MultipleRoots,
    MultipleParents,
    UnknownJointType,
    MimicUnknownJoint,
    MissingRequired,
    MissingLimit,
    LimitMissingAttribute,
    NonPositiveVelocity,
    NonPositiveEffort,
    LowerAboveUpper,
    ContinuousWithLimits,
    RpyOutOfRange,
    ZeroAxis,
    NonUnitAxis,
    NonFiniteNumber,
    MalformedNumber,
    MissingInertial,
    RootInertia,
    NonPositiveMass,
    InertiaNotPositiveDefinite,
    InertiaTriangleInequality,
    IncompleteInertial,
    UnresolvedMesh,
    UnknownPackage,
    TransmissionUnknownJoint,
    NonPositiveReduction,
    XacroError,
    InvalidSrdf,
    UrdfNotFound,
    InvalidYaml,
    SrdfNotFound,
)

BY_CODE: dict[str, type[Rule]] = {r.code: r for r in RULES}
BY_NAME: dict[str, type[Rule]] = {r.name: r for r in RULES}


def find_rule(code_or_name: str) -> type[Rule] | None:
    return BY_CODE.get(code_or_name.upper()) or BY_NAME.get(code_or_name.lower())
