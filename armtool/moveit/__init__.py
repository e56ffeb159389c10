"""A MoveIt config package read the way MoveIt's launch files read it.

`params`: one reader for MoveIt's YAML files (ROS 1 flat files and ROS 2 parameter files, keys
with launch substitutions); `package`: which files a package's launch would load
(MoveItConfigsBuilder's rules); `joint_limits` and `controllers`: those files' contents, with
line numbers for findings. No numpy here: `armtool lint` imports it.
"""
