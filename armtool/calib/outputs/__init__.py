"""The outputs stage: what a calibration writes for people, drivers and robot descriptions.

`report` (calibration.yaml, its JSON summary, the residual plot), `urdf` (the corrections folded
into the URDF's joint origins, checked to reproduce the fitted model), `ur_kinematics` (Universal
Robots' `default_kinematics.yaml`). It imports the fit stage and the ones below it.
"""
