"""What a lint run checked, per package: which URDF, SRDF and MoveIt files, and which file could
not be paired with the counterpart its checks need (issue 27: no silent pass). The text report
shows it as a short "checked:" block, the JSON report as `checked`.

A file that needs a counterpart and was linted without one (an SRDF without its URDF, a
kinematics.yaml without its SRDF, a joint_limits.yaml without a robot) also has a finding that
says so (S002, K002, L002) with the option that fixes it; this summary lists them beside what was
paired, so the reader sees at once what "All checks passed" covered.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

_NEEDS = {"srdf": "URDF", "kinematics": "SRDF", "joint_limits": "URDF"}  # what a file kind is checked against


class PackageChecked(NamedTuple):
    package: str  # the package's directory, as findings show paths
    urdfs: tuple[str, ...]
    srdfs: tuple[str, ...]
    moveit: tuple[str, ...]  # MoveIt YAML files and .setup_assistant
    unpaired: tuple[tuple[str, str], ...]  # (file, what it lacked: "URDF" or "SRDF")

    def as_dict(self) -> dict[str, object]:
        return {
            "package": self.package,
            "urdf": list(self.urdfs),
            "srdf": list(self.srdfs),
            "moveit_files": list(self.moveit),
            "not_paired": [{"file": f, "missing": what} for f, what in self.unpaired],
        }


def by_package(files: list[Path], counterparts: dict[str, tuple[str | None, str | None, str]]) -> list[PackageChecked]:
    """Per ROS package (the nearest package.xml, else the file's directory), in first-seen order;
    only packages with an SRDF or a MoveIt file among the files (a lone URDF needs no summary)."""
    from armtool.lint.locate import display_path
    from armtool.model.packages import package_root

    groups: dict[str, dict[str, dict[str, None]]] = {}
    unpaired: dict[str, list[tuple[str, str]]] = {}
    interesting: set[str] = set()
    for path in files:
        if str(path) == "-":
            continue
        root = package_root(path.resolve().parent, 6) or path.resolve().parent
        key = display_path(root)
        record = counterparts.get(str(path.resolve()))
        if record is None:
            continue  # not loaded as a robot file (a macro library, another tool's YAML, a loader error)
        urdf, srdf, kind = record
        if kind != "urdf":
            interesting.add(key)
        group = groups.setdefault(key, {"urdf": {}, "srdf": {}, "moveit": {}})
        unpaired.setdefault(key, [])
        if kind not in ("urdf", "srdf"):
            group["moveit"][display_path(path)] = None
        if urdf is not None:
            group["urdf"][urdf] = None
        if srdf is not None:
            group["srdf"][srdf] = None
        need = _NEEDS.get(kind)
        if need is not None and (urdf if need == "URDF" else srdf) is None:
            unpaired[key].append((display_path(path), need))
    return [
        PackageChecked(key, tuple(g["urdf"]), tuple(g["srdf"]), tuple(g["moveit"]), tuple(dict.fromkeys(unpaired[key])))
        for key, g in groups.items()
        if key in interesting
    ]


def lines(checked: list[PackageChecked]) -> list[str]:
    """The text report's "checked:" block (empty when nothing needs saying)."""
    if not checked:
        return []
    out = ["checked:"]
    for pkg in checked:
        prefix = pkg.package.rstrip("/") + "/"

        def short(path: str, prefix: str = prefix) -> str:
            return path[len(prefix) :] if path.startswith(prefix) else path

        parts = [
            "URDF " + (", ".join(short(p) for p in pkg.urdfs) or "none"),
            "SRDF " + (", ".join(short(p) for p in pkg.srdfs) or "none"),
        ]
        if pkg.moveit:
            parts.append(", ".join(short(p) for p in pkg.moveit))
        out.append(f"  {pkg.package}: " + "; ".join(parts))
        for file, what in pkg.unpaired:
            out.append(f"    not paired with a{'n' if what == 'SRDF' else ''} {what}: {short(file)}")
    return out
