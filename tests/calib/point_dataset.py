"""A tracker dataset as a user writes one: one CSV of joints (rad) and measured points (mm)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

import yaml


def write_point_dataset(
    directory: Path,
    urdf: Path,
    joints: Sequence[str],
    rows: Iterable[tuple[str, Sequence[float], Sequence[float]]],  # id, joint readings (rad), point (mm)
    base_link: str = "base_link",
    flange_link: str = "tool0",
) -> Path:
    directory.mkdir(parents=True)
    lines = ["id," + ",".join(joints) + ",x,y,z"]
    lines += [sid + "," + ",".join(repr(float(v)) for v in [*q, *p]) for sid, q, p in rows]
    (directory / "data.csv").write_text("\n".join(lines) + "\n")
    doc = {
        "format": "armtool-calib-dataset/1",
        "setup": "eye_to_hand",
        "robot": {
            "urdf": str(urdf),
            "base_link": base_link,
            "flange_link": flange_link,
            "joints": list(joints),
            "joint_units": "rad",
        },
        "samples": "data.csv",
        "observations": {
            "kind": "point",
            "file": "data.csv",
            "position_units": "mm",
            "position_columns": ["x", "y", "z"],
        },
    }
    (directory / "dataset.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return directory
