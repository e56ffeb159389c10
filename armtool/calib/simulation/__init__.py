"""The simulation stage: datasets with known truth, to rehearse a pose set and to test every other stage.

`simulate` (a true robot with injected errors, its joint readings and images: `calibrate simulate`),
`render` (camera images of a tag or a board, exact where corner accuracy matters), `truth` (a
calibration scored against the truth `simulate` kept apart). It may import every other stage.
"""
