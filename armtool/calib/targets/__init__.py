"""The detection stage: what the camera sees in a calibration, one AprilTag or a board (chessboard,
ChArUco, AprilTag grid), and finding its corners in an image.

`apriltag` the tag detector (edge-fitted corners), `boards` the board specs and their corners,
`chessboard` OpenCV's chessboard detector with the board's orientation decided, `spec` the
dataset's target (its points in the target frame), `detect` a target's corners in one image,
`pose` a planar target's pose from its corners. It imports only the model stage (the camera).
"""
