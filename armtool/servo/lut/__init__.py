"""Compensation tables (`armtool servo-lut`): `table` (the fitted inverse map and its fit),
`csv_format` (the measurement CSV), `measure` (driving a servo through the points and checking
a table), `export` (C header, CSV, JSON) and `apply` (converting a trajectory through a table).
Empty on purpose: each module imports numpy, and the command line must start without it."""
