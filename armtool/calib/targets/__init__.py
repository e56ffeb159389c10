"""What the camera sees in a calibration: one AprilTag or a board (chessboard, ChArUco, AprilTag grid).

`spec` is the dataset's target (its points in the target frame), `chessboard` OpenCV's chessboard
detector with the board's orientation decided, `detect` a target's corners in one image, `pose` a
planar target's pose from its corners.
"""
