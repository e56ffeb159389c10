"""Shared paths and small builders for the traj tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from armtool.traj.limits import JointLimits, load_limits
from armtool.traj.trajectory import Trajectory

ROOT = Path(__file__).resolve().parents[2]
CLEAN_URDF = ROOT / "fixtures" / "robots" / "clean_arm" / "urdf" / "clean_arm.urdf"
CLEAN_LIMITS = ROOT / "fixtures" / "traj" / "clean_arm_joint_limits.yaml"
JOINTS = ("joint1", "joint2", "joint3", "joint4", "joint5", "joint6")
START = "0,-0.6,1.2,0,0.9,0"


def clean_limits() -> JointLimits:
    return load_limits(CLEAN_URDF, CLEAN_LIMITS)


def random_path(seed: int, points: int = 5, spread: float = 0.5) -> Trajectory:
    lim = clean_limits().subset(JOINTS)
    rng = np.random.default_rng(seed)
    q = rng.uniform(lim.lower * spread, lim.upper * spread, size=(points, len(JOINTS)))
    return Trajectory(JOINTS, q, source="random.csv")
