"""Tag detection accuracy and time on rendered images with known truth (the README's table).

research/calibration.md §2's set-up: 1280×720, fx = fy = 910, an 80 mm tag36h11 at 0.3–1.0 m,
tilt 0–60°, "typical" image quality (blur σ 0.8–1.2 px, noise 3/255, black 0.08–0.20, white
0.60–0.90); once without and once with lens distortion. Corner error against the projection of
the true corners; pose error of `pnp_pose` against the true pose; CPU time of `detect_tag` on one
OpenCV thread.

    python benchmarks/apriltag_bench.py [--images 90] [--seed 0]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np


def run(images: int, seed: int, distortion: bool) -> str:
    import cv2

    from armtool.calib.simulation.render import random_view_pose, render_tag, tag_in_view
    from armtool.calib.simulation.simulate import default_camera
    from armtool.calib.targets.apriltag import detect_tag, pnp_pose, tag_object_points

    cv2.setNumThreads(1)
    camera = default_camera(distortion)
    rng = np.random.default_rng(seed)
    size = 0.08
    truth_px = []
    errors, vectors, trans_mm, rot_deg, cpu_ms = [], [], [], [], []
    found = 0
    while len(truth_px) < images:
        cMt = random_view_pose(camera, rng, distance_m=(0.3, 1.0), max_tilt_deg=60.0)
        if not tag_in_view(camera, cMt, size):
            continue
        img = render_tag(
            camera,
            cMt,
            size,
            "tag36h11",
            0,
            blur_sigma_px=rng.uniform(0.8, 1.2),
            noise_sigma=3 / 255,
            black=rng.uniform(0.08, 0.20),
            white=rng.uniform(0.60, 0.90),
            rng=rng,
        )
        if img is None:
            continue
        true = camera.project(tag_object_points(size) @ cMt[:3, :3].T + cMt[:3, 3])
        truth_px.append(true)
        t0 = time.process_time()
        det = detect_tag(img, "tag36h11", 0, camera)
        cpu_ms.append((time.process_time() - t0) * 1e3)
        if not det.ok:
            continue
        found += 1
        diff = det.corners_px - true
        errors.extend(np.linalg.norm(diff, axis=1))
        vectors.append(diff.mean(axis=0))
        est, _, _ = pnp_pose(det.corners_px, size, camera)
        trans_mm.append(float(np.linalg.norm(est[:3, 3] - cMt[:3, 3])) * 1e3)
        R = est[:3, :3].T @ cMt[:3, :3]
        rot_deg.append(math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2)))))

    def pct(values: list[float], *qs: float) -> str:
        return " / ".join(f"{np.percentile(values, q):.3f}" for q in qs)

    mean = np.mean(vectors, axis=0)
    lens = "§2 distortion" if distortion else "none"
    return (
        f"| {lens} | {found}/{images} | {pct(errors, 50, 90, 99)} | ({mean[0]:+.3f}, {mean[1]:+.3f}) | "
        f"{pct(trans_mm, 50, 90)} | {pct(rot_deg, 50, 90)} | {np.percentile(cpu_ms, 10):.0f}–{np.percentile(cpu_ms, 90):.0f} |"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--images", type=int, default=90)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    print(f"{args.images} rendered images per row, 80 mm tag36h11 at 0.3-1.0 m, typical quality\n")
    print(
        "| lens | detected | corner error median / p90 / p99 px | mean error vector px | translation median / p90 mm | rotation median / p90 ° | CPU ms / image (p10–p90) |"
    )
    print("|---|---|---|---|---|---|---|")
    for distortion in (False, True):
        print(run(args.images, args.seed, distortion))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
