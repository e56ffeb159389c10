"""The inputs stage: a calibration dataset read as its files state it, every problem at its file and line.

`dataset` (the manifest, samples.csv, corners.csv), `conventions` (how a file states a pose or a point),
`measured` (the `observations:` section and its CSV), `observations` (target corners per sample, detected
or read), `files` (readable files, size-bounded images), `load` (a dataset with its chain and camera),
`bag_import` (ROS bags into datasets). It imports the model and detection stages only.
"""
