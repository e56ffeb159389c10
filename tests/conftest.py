"""Suite-wide settings. In CI (CI=true) hypothesis draws the same examples on every run
(derandomize): a CI run checks the code, it does not hunt for new inputs; hunting is what a local
run does, with fresh random examples each time."""

from __future__ import annotations

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
    settings.load_profile("ci")
