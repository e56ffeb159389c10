"""Hand-eye benchmark: the refinement against OpenCV's seven closed forms, on images none of them saw.

Datasets without images (`armtool.calib.handeye.simulate.corner_observations`): 25 views of a 10x7
chessboard at 0.5-1.0 m from a 640x480 camera, corners with Gaussian noise, each flange pose off
by the controller's error (1σ per axis). Every method is scored as `calibrate handeye` scores it:
5-fold over images, the RMS of every held-out corner (without the refinement's outlier images).
Per regime: the mean held-out RMS of the refinement, of the best closed form of each dataset (the
lowest of the seven, chosen after the fact: a bar no single method reaches), and of plain least
squares on the pixels (the refinement without the flange noise in its weights); the mean ratio to
the best closed form, and in how many datasets the refinement is ahead of it.

    python benchmarks/handeye_bench.py [--datasets 8]
"""

from __future__ import annotations

import argparse

import numpy as np

# (name, corner noise px, flange position mm, flange rotation °, rows whose pose is 2 cm off)
REGIMES = [
    ("corners dominate", 0.1, 0.02, 0.002, 0),
    ("typical", 0.1, 0.3, 0.03, 0),
    ("robot dominates", 0.15, 1.0, 0.1, 0),
    ("typical, a bad pose row", 0.1, 0.3, 0.03, 1),
]


def plain_least_squares(obs, start, camera):  # type: ignore[no-untyped-def]
    """X, Z by unweighted least squares on the pixels from `start`, soft-L1 with a 1 px knee."""
    from scipy.optimize import least_squares

    from armtool.calib.handeye.refine import Reprojection

    problem = Reprojection(obs, *start, camera, False)
    x = least_squares(problem.residuals, problem.x0, jac=problem.jacobian, loss="soft_l1", f_scale=1.0).x
    X, Z, _cam = problem.unpack(x)
    return X, Z


def run(regime: tuple[str, float, float, float, int], datasets: int) -> dict[str, object]:
    from armtool.calib.choices import Intrinsics
    from armtool.calib.handeye.refine import reprojection_residuals
    from armtool.calib.handeye.scores import folds_of, score_methods, start
    from armtool.calib.handeye.simulate import SMALL_CAMERA, corner_observations
    from armtool.calib.handeye.views import Observations
    from armtool.calib.model import se3

    _name, pixel, mm, deg, bad = regime
    refined, closed, plain = [], [], []
    for seed in range(datasets):
        obs, _X, _Z = corner_observations(n=25, seed=500 + seed, flange_mm=mm, flange_deg=deg, pixel_px=pixel)
        if bad:
            G = obs.G.copy()
            G[3] = G[3] @ se3.delta(np.array([0.02, 0.0, -0.01, 0.02, -0.02, 0.0]))
            obs = Observations(obs.setup, G, obs.C, obs.start, obs.pnp_rms_px, obs.image, obs.points, obs.pixels)
        scores = score_methods(obs, SMALL_CAMERA, intrinsics=Intrinsics.FIXED)
        inliers = ~np.isin(obs.image, scores.refined.outliers)
        refined.append(scores.chosen.heldout_inlier_rms_px)
        closed.append(min(r.heldout_inlier_rms_px for r in scores.rows if not r.method.startswith("refined")))
        held = np.full((len(obs.pixels), 2), np.nan)
        for test in folds_of(obs.count, 5, 0):
            train = obs.subset(np.setdiff1d(np.arange(obs.count), test))
            X, Z = plain_least_squares(train, start(train, SMALL_CAMERA), SMALL_CAMERA)
            held[np.isin(obs.image, test)] = reprojection_residuals(obs.subset(test), X, Z, SMALL_CAMERA)
        plain.append(float(np.sqrt(np.mean(np.sum(held[inliers] ** 2, axis=1)))))
    r, c, p = np.array(refined), np.array(closed), np.array(plain)
    return {
        "refined": r.mean(),
        "closed": c.mean(),
        "plain": p.mean(),
        "ratio": float(np.mean(r / c)),
        "plain_ratio": float(np.mean(p / c)),
        "ahead": int(np.sum(r < c)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--datasets", type=int, default=8)
    args = parser.parse_args()
    import scipy.optimize  # noqa: F401  (loaded before BLAS is limited to one thread)

    from armtool.calib.fit.calibration import one_blas_thread

    print(
        "| regime | corners px | flange mm, ° | refined px | best closed form px | plain LS px "
        "| refined / best closed | plain / best closed | refined ahead |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    with one_blas_thread():
        for regime in REGIMES:
            out = run(regime, args.datasets)
            name, pixel, mm, deg, _bad = regime
            print(
                f"| {name} | {pixel:g} | {mm:g}, {deg:g} | {out['refined']:.4f} | {out['closed']:.4f} | {out['plain']:.4f} "
                f"| {out['ratio']:.3f} | {out['plain_ratio']:.3f} | {out['ahead']} of {args.datasets} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
