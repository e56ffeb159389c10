"""The pose of a planar target from the corners seen in one image: OpenCV's IPPE.

Every target armtool knows is planar (z = 0 in its frame). IPPE gives the two poses that explain
a plane's image (a tilt one way or the other); when the second reprojects almost as well as the
first (within ×AMBIGUITY_RATIO or AMBIGUITY_MIN_PX; one tag's `apriltag.pnp_pose` asks the same) the
view cannot tell them apart and is flagged `ambiguous`: such a pose must not start a fit.
"""

from __future__ import annotations

import numpy as np

from armtool.calib.model.camera import Array, CameraModel

# IPPE's two solutions are "similar" when the worse one reprojects within this factor of the
# better one, or within this many px (both fit the corners to about their noise).
AMBIGUITY_RATIO = 3.0
AMBIGUITY_MIN_PX = 0.3


def planar_pose(
    points_m: Array, pixels: Array, camera: CameraModel, *, square: bool = False
) -> tuple[Array, float, bool]:
    """(cMt, reprojection RMS px, ambiguous) from the target's points (P,3) and their pixels (P,2),
    rows of NaN pixels (not seen) skipped. Fewer than 4 points seen, or points on one line, give
    an ambiguous identity pose with an infinite RMS. `square`: the points are a tag's 4 corners in
    cv2.aruco's order, for OpenCV's SOLVEPNP_IPPE_SQUARE."""
    import cv2

    obj = np.asarray(points_m, dtype=np.float64).reshape(-1, 3)
    img = np.asarray(pixels, dtype=np.float64).reshape(-1, 2)
    seen = np.all(np.isfinite(img), axis=1)
    obj, img = obj[seen], img[seen]
    if len(obj) < 4 or np.linalg.matrix_rank(obj[:, :2] - obj[:, :2].mean(axis=0), tol=1e-9) < 2:
        return np.eye(4), float("inf"), True
    try:
        n, rvecs, tvecs, _ = cv2.solvePnPGeneric(
            obj, img, camera.K, camera.dist, flags=cv2.SOLVEPNP_IPPE_SQUARE if square else cv2.SOLVEPNP_IPPE
        )
    except cv2.error:
        return np.eye(4), float("inf"), True
    poses = []
    for rvec, tvec in zip(rvecs[:n], tvecs[:n]):
        cMt = np.eye(4)
        cMt[:3, :3] = cv2.Rodrigues(np.asarray(rvec, dtype=np.float64))[0]
        cMt[:3, 3] = np.asarray(tvec, dtype=np.float64).reshape(3)
        proj = camera.project(obj @ cMt[:3, :3].T + cMt[:3, 3])
        rms = float(np.sqrt(np.mean(np.sum((proj - img) ** 2, axis=1)))) if np.all(np.isfinite(proj)) else np.inf
        poses.append((rms, cMt))
    if not poses:
        return np.eye(4), float("inf"), True
    poses.sort(key=lambda p: p[0])
    best_rms, best = poses[0]
    ambiguous = len(poses) > 1 and poses[1][0] < max(AMBIGUITY_RATIO * best_rms, AMBIGUITY_MIN_PX)
    return best, best_rms, ambiguous
