"""Tests of armtool.calib, one package per stage as calib has; the end-to-end and real-data
tests and the shared builders (synthetic.py, render_board.py, ...) are at this level."""
