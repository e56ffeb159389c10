"""Kinematic calibration: the core of `armtool calibrate`, one package per stage.

`model` (what a measurement should be) < `targets` (tags and boards, found in images) < `inputs`
(the dataset as its files state it) < `fit` (what the data determines, and whether it beats the
nominal robot) < `outputs` (what a calibration writes) < `simulation` (datasets with known truth);
each imports only the stages before it. `check` and `pipeline` run `calibrate check` and `calibrate
fit` end to end; `choices` and `limits` are shared, numpy-free, with the command line.
"""
