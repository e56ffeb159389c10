"""Compensation tables (`armtool servo-lut`): `table` (the fitted inverse map and its fit),
`csv_format` (the measurement CSV), `measure` (driving a servo through the points and checking
a table), `session` (setting a servo up for `measure` and `check`, and the two runs), `export`
(C header, CSV, JSON), `apply` (converting a trajectory through a table) and `choices` (the
options' enums, numpy-free).
Empty on purpose: most modules import numpy, and the command line must start without it."""
