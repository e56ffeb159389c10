"""The model stage: what a measurement should be, given the joints and the parameters.

`params` (the parameter vector and its layout), `calib_model` (the measurement model cMt = L · F(q)^±1 · R
and how each parameter moves it), `se3` (rigid transforms and small corrections), `camera` (the pinhole
camera with lens distortion, and its intrinsics files). It imports no other stage of calib.
"""
