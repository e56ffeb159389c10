"""Joint terms (`calib/model/joint_term.py`): corrections of a joint's angle that depend on the
pose, one kind per module, registered in `registry.py` with the `--params` family that frees it:
`compliance` (deflection under gravity), `harmonics` (errors periodic in the joint angle)."""
