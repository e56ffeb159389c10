"""OpenCV's seven closed-form hand-eye methods by name: the five AX = XB ones and the two AX = ZB ones.

Each gives both frames of G_i · X · C_i = Z (`armtool.calib.handeye.views`). The AX = XB methods
(`armtool.calib.fit.handeye`) solve the motion pairs for X; Z is then the mean of G_i X C_i over the
images (chordal mean of the rotations). The robot-world methods (`armtool.calib.fit.robot_world`)
solve A_i X = Z B_i with A_i = G_i and B_i = C_i⁻¹, both frames at once.
"""

from __future__ import annotations

from armtool.calib.fit.handeye import AxXbMethod, average_pose, motion_pairs, solve_ax_xb
from armtool.calib.fit.robot_world import AxZbMethod, solve_ax_zb
from armtool.calib.model import se3
from armtool.calib.model.se3 import Array

Method = AxXbMethod | AxZbMethod
METHODS: tuple[Method, ...] = (*AxXbMethod, *AxZbMethod)


def closed_form(method: Method, G: Array, C: Array) -> tuple[Array, Array]:
    """(X, Z) of G_i X C_i = Z from the flange-side poses G (N, 4, 4) and the board poses C (N, 4, 4)."""
    if isinstance(method, AxZbMethod):
        return solve_ax_zb(G, se3.inv(C), method)
    A, B = motion_pairs(G, C)
    X = solve_ax_xb(A, B, method)
    return X, average_pose(list(G @ X @ C))
