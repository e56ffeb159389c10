"""How armtool draws its figures (`calibrate fit --plot`, `ik-bench --plot`, `traj plot`, `traj
cartesian --plot`): matplotlib on its Agg canvas, one style, the format chosen by the file's
extension, the file written atomically.

The figures are `matplotlib.figure.Figure` objects attached to an Agg canvas: pyplot is never
imported, so no display backend is chosen and no global figure state is kept (a figure is freed
with its last reference). matplotlib is imported inside the functions: the command modules call
`plot_format` while checking their options, before any work, and `armtool --help` must not pay
for matplotlib.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

from armtool.errors import ArmtoolError

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from matplotlib.typing import RcKeyType

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
DPI = 110  # a 14-inch-wide figure is about 1500 px: readable on a screen and in a report

# The shared colours: the nominal robot (hand-eye only) grey, calibrated blue, held out orange,
# outliers and limits red (matplotlib's tab10, which colour-blind readers tell apart best of its maps).
NOMINAL = "#7f7f7f"
CALIBRATED = "#1f77b4"
HELD_OUT = "#ff7f0e"
CROSS_VALIDATED = "#2ca02c"
OUTLIER = "#d62728"
LIMIT = "#d62728"

_STYLE: dict[RcKeyType, Any] = {  # matplotlib's default colour cycle (tab10) is kept
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "axes.axisbelow": True,  # grid lines under the data, never across a marker
    "grid.color": "#dddddd",
    "grid.linewidth": 0.6,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "svg.fonttype": "path",  # text as outlines: the SVG looks the same without the fonts installed
    "svg.hashsalt": "armtool",  # the same figure gives the same SVG bytes
    "pdf.fonttype": 42,
}


def plot_format(path: Path, option: str = "--plot") -> str:
    """The format the extension of `path` names ('png', 'svg', 'pdf'); anything else is refused,
    so that a typo is caught before the work and not after it."""
    fmt = FORMATS.get(path.suffix.lower())
    if fmt is None:
        named = f"'{path.suffix}'" if path.suffix else "no extension"
        raise ArmtoolError(
            f"{option} names a file with {named}: plots are written as PNG, SVG or PDF",
            str(path),
            "end the name with .png, .svg or .pdf",
        )
    return fmt


@contextmanager
def style() -> Iterator[None]:
    """armtool's style for the figures built (and rendered) inside it."""
    import matplotlib

    with matplotlib.rc_context(_STYLE):
        yield


def figure(width_in: float, height_in: float) -> Figure:
    """A new figure on an Agg canvas with constrained layout (labels never overlap)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def render(fig: Figure, fmt: str) -> bytes:
    """The figure's file content in `fmt` ('png', 'svg' or 'pdf'), without a creation date, so the
    same figure gives the same bytes."""
    import io

    metadata: dict[str, str | None] = {}
    if fmt in ("svg", "pdf"):
        metadata = {"Date": None} if fmt == "svg" else {"CreationDate": None}
    buffer = io.BytesIO()
    with style():
        fig.savefig(buffer, format=fmt, dpi=DPI, metadata=metadata, facecolor="white")
    return buffer.getvalue()


def save(fig: Figure, path: Path, option: str = "--plot") -> None:
    """Write the figure to `path` atomically, in the format its extension names."""
    from armtool.fileio import write_atomic

    write_atomic(path, render(fig, plot_format(path, option)))
