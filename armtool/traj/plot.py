"""A PNG of a trajectory: per joint its position, velocity and acceleration over time (or over the
point index for an untimed path), with the limits as red lines; optionally the tool path.

Drawn with OpenCV, which armtool already depends on, as `ik-bench --plot` is (no matplotlib).
Velocities and accelerations are the file's own if it has them, else finite differences.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from armtool.errors import ArmtoolError
from armtool.model.chain import Chain
from armtool.traj.limits import JointLimits
from armtool.traj.trajectory import Array, Trajectory

_BLUE, _RED, _GREY, _BLACK = (180, 119, 31), (40, 39, 214), (200, 200, 200), (0, 0, 0)


def _series(traj: Trajectory) -> tuple[Array, Array, Array | None, Array | None, str]:
    q = traj.positions
    if traj.times is None:
        return np.arange(traj.n_points, dtype=np.float64), q, None, None, "point"
    t = traj.times
    v = traj.velocities if traj.velocities is not None else np.gradient(q, t, axis=0)
    a = traj.accelerations if traj.accelerations is not None else np.gradient(v, t, axis=0)
    return t, q, v, a, "time (s)"


def _panel(
    img: np.ndarray, box: tuple[int, int, int, int], x: Array, y: Array, limits: tuple[float, float] | None, title: str
) -> None:
    import cv2

    x0, y0, x1, y1 = box
    cv2.rectangle(img, (x0, y0), (x1, y1), _BLACK, 1)
    lo, hi = float(np.min(y)), float(np.max(y))
    if limits is not None and all(math.isfinite(v) for v in limits):
        lo, hi = min(lo, limits[0]), max(hi, limits[1])
    pad = (hi - lo) * 0.05 or 1.0
    lo, hi = lo - pad, hi + pad
    xl, xh = float(x[0]), float(x[-1]) if x[-1] > x[0] else float(x[0]) + 1.0

    def px(xv: Array, yv: Array) -> np.ndarray:
        return np.stack(
            [x0 + (xv - xl) / (xh - xl) * (x1 - x0), y1 - (yv - lo) / (hi - lo) * (y1 - y0)], axis=1
        ).astype(np.int32)

    if lo < 0 < hi:
        cv2.line(
            img, tuple(px(np.array([xl]), np.array([0.0]))[0]), tuple(px(np.array([xh]), np.array([0.0]))[0]), _GREY, 1
        )
    if limits is not None:
        for v in limits:
            if math.isfinite(v):
                a, b = px(np.array([xl, xh]), np.array([v, v]))
                cv2.line(img, tuple(a), tuple(b), _RED, 1, cv2.LINE_AA)
    cv2.polylines(img, [px(x, y)], False, _BLUE, 1, cv2.LINE_AA)
    font = cv2.FONT_HERSHEY_SIMPLEX
    cv2.putText(img, title, (x0 + 4, y0 + 14), font, 0.4, _BLACK, 1, cv2.LINE_AA)
    cv2.putText(img, f"{hi:.3g}", (x0 - 52, y0 + 10), font, 0.35, _BLACK, 1, cv2.LINE_AA)
    cv2.putText(img, f"{lo:.3g}", (x0 - 52, y1), font, 0.35, _BLACK, 1, cv2.LINE_AA)


def write_plot(path: Path, traj: Trajectory, limits: JointLimits, chain: Chain | None = None) -> None:

    if path.suffix.lower() != ".png":
        raise ArmtoolError("the plot is a PNG", str(path), "name the output *.png")
    x, q, v, a, xlabel = _series(traj)
    n = len(traj.joint_names)
    cols = 1 if v is None else 3
    extra = 1 if chain is not None else 0
    ph, pw, left, top = 120, 340, 70, 30
    H = top + (n + extra) * (ph + 30) + 30
    W = left + cols * (pw + 70)
    img = np.full((H, W, 3), 255, np.uint8)
    for j, name in enumerate(traj.joint_names):
        k = limits.names.index(name) if name in limits.names else None
        unit = "m" if (k is not None and limits.prismatic[k]) else "rad"
        y0 = top + j * (ph + 30)
        pos_lim = (float(limits.lower[k]), float(limits.upper[k])) if k is not None else None
        _panel(img, (left, y0, left + pw, y0 + ph), x, q[:, j], pos_lim, f"{name} position ({unit})")
        if v is not None and a is not None:
            vl = float(limits.velocity[k]) if k is not None else math.nan
            al = float(limits.acceleration[k]) if k is not None else math.nan
            _panel(
                img, (left + pw + 70, y0, left + 2 * pw + 70, y0 + ph), x, v[:, j], (-vl, vl), f"velocity ({unit}/s)"
            )
            _panel(
                img,
                (left + 2 * (pw + 70), y0, left + 3 * pw + 140, y0 + ph),
                x,
                a[:, j],
                (-al, al),
                f"acceleration ({unit}/s2)",
            )
    if chain is not None:
        names = [nm for nm in chain.joint_names if nm not in traj.joint_names]
        if names:
            raise ArmtoolError(
                f"the trajectory lacks joint(s) {', '.join(names)} of the chain {chain.base} -> {chain.tip}",
                traj.source,
            )
        qc = traj.reorder(chain.joint_names).positions
        P = np.array([chain.fk(qi)[:3, 3] for qi in qc])
        y0 = top + n * (ph + 30)
        for c, (i, k, label) in enumerate(
            ((0, 1, "tool path x-y (m)"), (0, 2, "tool path x-z (m)"), (1, 2, "tool path y-z (m)"))
        ):
            x0 = left + c * (pw + 70)
            side = min(pw, ph)
            _xy(img, (x0, y0, x0 + side, y0 + side), P[:, i], P[:, k], label)
    _save(img, f"{traj.source}: {traj.n_points} points, x = {xlabel}; red = limits", left, path)


def _xy(img: np.ndarray, box: tuple[int, int, int, int], a: Array, b: Array, title: str) -> None:
    """An equal-aspect plot of a curve (tool path projection)."""
    import cv2

    x0, y0, x1, y1 = box
    cv2.rectangle(img, (x0, y0), (x1, y1), _BLACK, 1)
    ca, cb = (a.max() + a.min()) / 2, (b.max() + b.min()) / 2
    span = max(np.ptp(a), np.ptp(b), 1e-6) * 1.1
    pts = np.stack([x0 + ((a - ca) / span + 0.5) * (x1 - x0), y1 - ((b - cb) / span + 0.5) * (y1 - y0)], axis=1).astype(
        np.int32
    )
    cv2.polylines(img, [pts], False, _BLUE, 1, cv2.LINE_AA)
    cv2.putText(img, title, (x0 + 4, y0 + 14), cv2.FONT_HERSHEY_SIMPLEX, 0.4, _BLACK, 1, cv2.LINE_AA)
    cv2.putText(
        img, f"span {span * 1000:.0f} mm", (x0 + 4, y1 - 6), cv2.FONT_HERSHEY_SIMPLEX, 0.35, _BLACK, 1, cv2.LINE_AA
    )


def write_cartesian_plot(
    path: Path, chain: Chain, q: Array, dev_m: Array, dev_rad: Array, precision_m: float, precision_rad: float
) -> None:
    """The tool path of a Cartesian joint path (three projections) and, per step, how far the tool at
    the joint midpoint lies from the ideal path (the precision check's measure), with the bound."""

    if path.suffix.lower() != ".png":
        raise ArmtoolError("the plot is a PNG", str(path), "name the output *.png")
    P = np.array([chain.fk(qi)[:3, 3] for qi in q])
    W, H = 1100, 560
    img = np.full((H, W, 3), 255, np.uint8)
    for c, (i, k, label) in enumerate(
        ((0, 1, "tool path x-y (m)"), (0, 2, "tool path x-z (m)"), (1, 2, "tool path y-z (m)"))
    ):
        x0 = 70 + c * 340
        _xy(img, (x0, 30, x0 + 280, 310), P[:, i], P[:, k], label)
    steps = np.arange(len(dev_m), dtype=np.float64) if len(dev_m) > 1 else np.array([0.0, 1.0])
    m = dev_m * 1000 if len(dev_m) > 1 else np.zeros(2)
    r = dev_rad if len(dev_rad) > 1 else np.zeros(2)
    _panel(img, (70, 350, 520, 520), steps, m, (0.0, precision_m * 1000), "midpoint deviation (mm) per step")
    _panel(img, (600, 350, 1050, 520), steps, r, (0.0, precision_rad), "midpoint deviation (rad) per step")
    _save(img, f"{chain.base} -> {chain.tip}: {len(q)} points; red = --precision bounds", 70, path)


def _save(img: np.ndarray, title: str, left: int, path: Path) -> None:
    """Title the image and write it as a PNG (atomically)."""
    import cv2

    from armtool.fileio import write_atomic

    cv2.putText(img, title, (left, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.45, _BLACK, 1, cv2.LINE_AA)
    ok, buf = cv2.imencode(".png", img)
    if not ok:
        raise ArmtoolError("could not encode the PNG", str(path))
    write_atomic(path, buf.tobytes())
