"""The fit and selection stage: which parameters the data determines, their values, and whether
they beat the nominal robot on poses the fit never saw.

`measurements` (a dataset's measurements by sample id → their residual problem), `problems` (what
a fit minimises, per measurement kind), `noise` (each block's σ), `handeye` (the closed-form start
of the measurement frames), `identify` (identifiability), `crossval` (the ladder of parameter sets
and k-fold cross-validation), `holdout` (what is kept out), `calibration` (the fit as named steps),
`zero_offsets` (which offsets are physical), `verdict` (whether the calibration beats the nominal
robot), `convention_check` (every other reading of a measurement file), `intrinsics` (the camera's
own calibration, `calibrate camera`). It imports the model, detection and inputs stages.
"""
