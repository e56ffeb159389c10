"""Output formats by name. A new format is one module plus one line here (imported on use)."""

from __future__ import annotations

import importlib
from enum import Enum

from armtool.output.base import Formatter


class OutputFormat(str, Enum):
    TEXT = "text"
    JSON = "json"
    SARIF = "sarif"
    GITHUB = "github"


FORMATS: dict[OutputFormat, str] = {
    OutputFormat.TEXT: "armtool.output.text:TextFormatter",
    OutputFormat.JSON: "armtool.output.json_format:JsonFormatter",
    OutputFormat.SARIF: "armtool.output.sarif:SarifFormatter",
    OutputFormat.GITHUB: "armtool.output.github:GithubFormatter",
}


def formatter(fmt: OutputFormat) -> Formatter:
    module, _, cls = FORMATS[fmt].partition(":")
    return getattr(importlib.import_module(module), cls)()  # type: ignore[no-any-return]
