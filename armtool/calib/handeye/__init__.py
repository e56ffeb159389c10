"""Hand-eye calibration from flange poses and images, without joint readings: `armtool calibrate handeye`.

Many controllers (KUKA, ABB, Fanuc, UR's TCP) report the flange pose, not the joints. From images
of a board and those poses, this stage finds the camera in the flange (eye-in-hand) or in the base
(eye-to-hand) and the board in the base (or flange): `dataset` (the files and their conventions),
`views` (the board in each image), `turns` (which turn of a board that looks alike turned each
image shows), `closed_forms` (OpenCV's seven closed forms by name), `refine` (the joint
reprojection fit), `crossval` (held-out reprojection and the board's spread, per method),
`conventions` (every other reading of the pose file), `run` (the command end to end), `simulate`
(datasets with known truth). It is the last stage: it imports the others, none imports it.
"""
