"""The choices of `armtool traj`'s options, once, without numpy: the CLI declares its options with
them, so `armtool --help` and typer's parser never import numpy."""

from __future__ import annotations

from enum import Enum


class TrajFormat(str, Enum):
    """Trajectory file formats (read: detected from the content; written: `--to` or `-o`'s extension)."""

    CSV = "csv"
    ROS2 = "ros2"
    ROS1 = "ros1"
    MOVEIT = "moveit"
    JSON = "json"


class PathSolver(str, Enum):
    """The IK solvers `traj cartesian` can step a path with: `auto` (the closed form `analytic` when the
    chain has one, else the 1-D `search` where it applies, else `lm`) and every solver of
    `armtool.ik.registry` (tests/traj/test_choices.py keeps the two in step). With `analytic` or
    `search` each point is the solution nearest the previous point."""

    AUTO = "auto"
    LM = "lm"
    DLS = "dls"
    KDL_NR_JL = "kdl-nr-jl"
    KDL_LMA = "kdl-lma"
    TRAC = "trac"
    ANALYTIC = "analytic"
    SEARCH = "search"
