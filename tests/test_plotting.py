"""armtool.plotting: the format by the extension, valid PNG, SVG and PDF files of the figure's size,
the same bytes for the same figure, the style kept to the figures drawn inside it."""

from __future__ import annotations

import re
import struct
from pathlib import Path

import pytest
from matplotlib.figure import Figure

from armtool import plotting
from armtool.errors import ArmtoolError


def _figure(width: float = 4.0, height: float = 3.0) -> Figure:
    with plotting.style():
        fig = plotting.figure(width, height)
        ax = fig.subplots()
        ax.plot([1, 2, 3], [1, 4, 9], label="squares")
        ax.set_title("a title")
        ax.legend()
    return fig


@pytest.mark.parametrize("name, fmt", [("a.png", "png"), ("A.PNG", "png"), ("b.svg", "svg"), ("c.Pdf", "pdf")])
def test_the_extension_names_the_format(name: str, fmt: str) -> None:
    assert plotting.plot_format(Path(name)) == fmt


@pytest.mark.parametrize("name", ["plot.jpg", "plot", "plot.png.txt", "plot.eps"])
def test_another_extension_is_refused_with_the_choices(name: str) -> None:
    with pytest.raises(ArmtoolError) as caught:
        plotting.plot_format(Path(name), "-o")
    error = caught.value
    assert error.what.startswith("-o names a file with") and "PNG, SVG or PDF" in error.what
    assert error.where == name and error.hint is not None and ".svg" in error.hint


def test_png_svg_and_pdf_are_valid_files_of_the_figure_size() -> None:
    fig = _figure(4.0, 3.0)
    png = plotting.render(fig, "png")
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and png[12:16] == b"IHDR"
    width, height = struct.unpack(">II", png[16:24])
    assert (width, height) == (4 * plotting.DPI, 3 * plotting.DPI)
    svg = plotting.render(fig, "svg").decode()
    assert svg.startswith("<?xml") and svg.rstrip().endswith("</svg>")
    assert 'width="288pt" height="216pt"' in svg  # 72 points per inch
    pdf = plotting.render(fig, "pdf")
    assert pdf.startswith(b"%PDF-") and pdf.rstrip().endswith(b"%%EOF")
    assert re.search(rb"/MediaBox \[ ?0 0 288 216 ?\]", pdf)


@pytest.mark.parametrize("fmt", ["png", "svg", "pdf"])
def test_the_same_figure_gives_the_same_bytes(fmt: str) -> None:
    assert plotting.render(_figure(), fmt) == plotting.render(_figure(), fmt)  # no creation date, fixed ids


def test_save_writes_the_format_of_the_extension(tmp_path: Path) -> None:
    fig = _figure()
    plotting.save(fig, tmp_path / "f.svg")
    plotting.save(fig, tmp_path / "f.pdf")
    assert (tmp_path / "f.svg").read_bytes() == plotting.render(_figure(), "svg")
    assert (tmp_path / "f.pdf").read_bytes()[:5] == b"%PDF-"
    with pytest.raises(ArmtoolError, match="PNG, SVG or PDF"):
        plotting.save(fig, tmp_path / "f.gif")
    assert not (tmp_path / "f.gif").exists()


def test_the_style_applies_inside_and_is_restored_after() -> None:
    import matplotlib

    before = matplotlib.rcParams["axes.spines.top"]
    fig = _figure()
    assert not fig.axes[0].spines["top"].get_visible()  # armtool's style: no top spine
    assert matplotlib.rcParams["axes.spines.top"] == before
