"""A PNG for ik-bench: solve-time CDF per solver (log time axis) and success rate bars.

Drawn with OpenCV, which armtool already depends on, rather than adding matplotlib.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from armtool.errors import ArmtoolError
from armtool.ik.bench import SolverReport

_COLORS = [
    (180, 119, 31),
    (14, 127, 255),
    (44, 160, 44),
    (40, 39, 214),
    (189, 103, 148),
    (75, 86, 140),
    (194, 119, 227),
    (127, 127, 127),
]


def write_plot(path: Path, reports: list[SolverReport]) -> None:
    import cv2

    W, H = 1100, 520
    img = np.full((H, W, 3), 255, np.uint8)
    font = cv2.FONT_HERSHEY_SIMPLEX
    # Left: CDF of wall time (µs, log scale).
    x0, y0, x1, y1 = 70, 40, 700, 460
    cv2.rectangle(img, (x0, y0), (x1, y1), (0, 0, 0), 1)
    singles = [r for r in reports if r.mode == "single" and r.wall_times_us]
    all_times = np.concatenate([np.asarray(r.wall_times_us) for r in singles]) if singles else np.array([1.0, 10.0])
    lo = math.floor(math.log10(max(all_times.min(), 0.1)))
    hi = math.ceil(math.log10(max(all_times.max(), 1.0)))
    hi = max(hi, lo + 1)

    def xpos(us: float) -> int:
        return int(x0 + (math.log10(max(us, 10**lo)) - lo) / (hi - lo) * (x1 - x0))

    for decade in range(lo, hi + 1):
        x = xpos(10**decade)
        cv2.line(img, (x, y0), (x, y1), (220, 220, 220), 1)
        cv2.putText(img, f"1e{decade}", (x - 14, y1 + 18), font, 0.4, (0, 0, 0), 1, cv2.LINE_AA)
    for frac in (0.0, 0.25, 0.5, 0.75, 1.0):
        y = int(y1 - frac * (y1 - y0))
        cv2.putText(img, f"{frac:.2f}", (x0 - 40, y + 4), font, 0.4, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.putText(
        img,
        "solve time (us, log) - fraction of targets solved within",
        (x0, y1 + 40),
        font,
        0.45,
        (0, 0, 0),
        1,
        cv2.LINE_AA,
    )
    for k, r in enumerate(singles):
        color = _COLORS[k % len(_COLORS)]
        times = np.sort(np.asarray(r.wall_times_us)[np.asarray(r.solved, dtype=bool)])
        if times.size == 0:
            continue
        ys = np.arange(1, times.size + 1) / len(r.wall_times_us)  # failures never count as solved
        pts = np.array([[xpos(t), int(y1 - f * (y1 - y0))] for t, f in zip(times, ys)], np.int32)
        cv2.polylines(img, [pts], False, color, 2, cv2.LINE_AA)
        cv2.putText(img, r.solver, (x0 + 10, y0 + 20 + 18 * k), font, 0.5, color, 1, cv2.LINE_AA)
    # Right: success bars.
    bx0, by1 = 760, 460
    bar_w = max(8, min(40, int(300 / max(len(reports), 1)) - 6))
    for k, r in enumerate(reports):
        color = _COLORS[k % len(_COLORS)]
        h = int(r.success_rate * 400)
        x = bx0 + k * (bar_w + 6)
        cv2.rectangle(img, (x, by1 - h), (x + bar_w, by1), color, -1)
        cv2.putText(img, f"{100 * r.success_rate:.0f}", (x, by1 - h - 4), font, 0.35, (0, 0, 0), 1, cv2.LINE_AA)
        label = r.solver[:10] + ("*" if r.mode == "batch" else "")
        cv2.putText(img, label, (x, by1 + 14 + 12 * (k % 2)), font, 0.33, (0, 0, 0), 1, cv2.LINE_AA)
    cv2.putText(img, "success % (* batch)", (bx0, 30), font, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    ok, data = cv2.imencode(".png", img)
    if not ok:
        raise ArmtoolError("could not encode the plot", str(path))
    from armtool.fileio import write_atomic

    write_atomic(path, data.tobytes())
