"""The bounds calibrate accepts, from the command line and from dataset files.

Kept apart from the modules that use them so the CLI can name them in `--help` without
importing numpy or OpenCV.
"""

from __future__ import annotations

TAG_SIZE_M = (0.001, 2.0)  # edge of the tag's black square: a 1 mm print to a 2 m banner
MAX_SAMPLES = 10_000  # rows of samples.csv / corners.csv (real datasets hold 30-300 poses)
MAX_SIMULATED = 10_000  # `simulate --samples/--validation/--bad-samples`
MAX_TAG_ID = 4_095  # above every AprilTag family's size (tag36h11: 587 codes)
MAX_IMAGE_PIXELS = 100_000_000  # 100 MP: above any calibration camera, far below a decompression bomb
MAX_IMAGES = 10_000  # `calibrate camera` inputs
MAX_CSV_FIELD = 128 * 1024  # Python's csv module default; a longer field is reported, not raised
MAX_FILE_BYTES = 64 * 1024 * 1024  # dataset.yaml, camera.yaml, samples.csv, corners.csv
