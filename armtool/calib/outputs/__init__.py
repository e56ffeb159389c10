"""The outputs stage: what a calibration writes for people, drivers and robot descriptions.

`report` (calibration.yaml and its JSON summary), `plot` (the `--plot` figure), `urdf` (the corrections folded
into the URDF's joint origins, checked to reproduce the fitted model), `ur_kinematics` (Universal
Robots' `default_kinematics.yaml`). It imports the fit stage and the ones below it.
"""
