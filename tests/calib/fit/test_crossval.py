"""The parameter set is chosen on poses the fit never saw, and the reported held-out residual
never comes from poses that took part in the choice."""

from __future__ import annotations

import numpy as np

from armtool.calib.fit.calibration import FitOptions, calibrate
from armtool.calib.fit.crossval import HAND_EYE, CandidateFit, cross_validate, fold_rows, ladder, pose_groups
from armtool.calib.fit.verdict import judge
from armtool.calib.model.params import Family
from armtool.model.chain import Chain
from tests.calib.synthetic import make_measured, make_problem


def test_the_ladder_follows_the_requested_families() -> None:
    names = [c.name for c in ladder((Family.ORIGINS, Family.OFFSETS))]
    assert names == ["hand-eye only", "zero offsets", "offsets + origin rotations", "origins + offsets"]
    assert [c.name for c in ladder((Family.OFFSETS,))] == ["hand-eye only", "zero offsets"]
    assert [c.name for c in ladder((Family.ORIGINS, Family.OFFSETS, Family.GAINS))][-1] == "origins + offsets + gains"
    assert [c.name for c in ladder((Family.ORIGINS,))] == ["hand-eye only", "origin rotations", "origins"]


def test_repeats_of_a_pose_stay_in_one_fold() -> None:
    Q = np.random.default_rng(0).uniform(-2, 2, size=(20, 6))
    Q[7] = Q[3] + 1e-5  # the arm stood still for two images
    Q[12] = Q[3]
    groups = pose_groups(Q)
    assert [3, 7, 12] in groups and len(groups) == 18
    folds = fold_rows(groups, 5, seed=1)
    assert sorted(r for f in folds for r in f) == list(range(20))
    assert any({3, 7, 12} <= set(f) for f in folds)


def test_pose_groups_are_remembered_by_their_readings_and_handed_out_as_copies() -> None:
    Q = np.random.default_rng(5).uniform(-2, 2, size=(15, 6))
    Q[9] = Q[2]
    first = pose_groups(Q)
    first[0].append(99)  # a caller's change stays its own
    first.pop()
    again = pose_groups(Q.copy())
    assert [2, 9] in again and len(again) == 14 and all(99 not in g for g in again)
    Q[9] = Q[2] + 0.5  # other readings: grouped again, not looked up
    assert len(pose_groups(Q)) == 15


def test_without_repeats_the_folds_are_the_plain_random_partition() -> None:
    Q = np.random.default_rng(0).uniform(-2, 2, size=(23, 6))
    order = np.random.default_rng(4).permutation(23)
    assert fold_rows(pose_groups(Q), 5, seed=4) == [sorted(int(i) for i in order[k::5]) for k in range(5)]


def test_a_correct_urdf_keeps_its_kinematics(clean_chain: Chain) -> None:
    # The robot is exactly its URDF and the tag corners are noisy: every kinematic correction
    # fitted to 20 poses only fits their noise, and held-out poses say so.
    p = make_problem(clean_chain, n=20, noise_px=0.3, seed=2, errors=False)
    result = calibrate(p.model, p.measurements, p.samples, FitOptions(nested=False))
    assert result.candidate == HAND_EYE and result.crossval is not None
    assert result.crossval.chosen == HAND_EYE
    verdict = judge(result.crossval, result.candidate.name, True, 20, 8.0, result.motion_deg)
    assert not verdict.improves and verdict.checked
    assert "no kinematic calibration beats the nominal robot on held-out poses" in verdict.summary
    assert "poses" in verdict.advice


def test_real_errors_choose_the_full_set_on_every_fold(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "pose", n=50, noise_mm=0.1, noise_deg=0.02, seed=1)
    result = calibrate(m.model, m.measurements, m.samples)
    cv = result.crossval
    assert cv is not None and cv.nested is not None
    assert result.candidate.name == "origins + offsets" == cv.chosen.name
    assert cv.nested.chosen == ["origins + offsets"] * 5
    assert cv.nested.rms["position"] < 0.3 < 1.0 < cv.nested.hand_eye_rms["position"]
    scores = [s.loss for s in cv.scores]
    assert scores[-1] == min(scores)
    assert all(len(r.cross_validated) == 2 for r in result.residuals)  # each sample's held-out residual


def test_no_fold_is_fitted_on_the_samples_it_scores(clean_chain: Chain) -> None:
    m = make_measured(clean_chain, "point", n=30, seed=3)
    problem = m.measurements.problem(m.model, m.samples)
    candidates = ladder((Family.OFFSETS,))
    fitted_on: list[list[int]] = []

    def spy(rows: list[int]) -> list[CandidateFit]:
        fitted_on.append(rows)
        return [CandidateFit(problem.model, np.zeros(problem.model.size), np.ones(1), np.full(1, np.inf), 0, "spy")] * 2

    cv = cross_validate(problem, candidates, spy, 4, 0, lambda _p: 3.0, nested=True, repeats=lambda _n: 1)
    outer = fold_rows(pose_groups(problem.Q), 4, 0)
    everything = set(range(problem.samples))
    assert [set(r) for r in fitted_on[:4]] == [everything - set(t) for t in outer]
    # Each outer training set chooses by a 3-fold over the other outer folds: the training set
    # without folds i and j serves both outer folds, and is fitted once (6 pairs, not 12).
    pairs = [set(r) for r in fitted_on[4:]]
    assert len(pairs) == 6 and len({tuple(r) for r in fitted_on}) == len(fitted_on)
    assert sorted(sorted(everything - p) for p in pairs) == sorted(
        sorted(set(outer[i]) | set(outer[j])) for i in range(4) for j in range(i + 1, 4)
    )
    assert cv.nested is not None and len(cv.nested.chosen) == 4


def test_few_poses_are_chosen_on_a_repeated_k_fold(clean_chain: Chain) -> None:
    # 18 poses: one 5-fold partition's choice rests on folds of 3 or 4 poses, so ten partitions
    # are pooled and each pose's held-out loss is its mean over the ten.
    from armtool.calib.fit.crossval import repeats_for

    assert repeats_for(18) == 10 and repeats_for(40) == 5 and repeats_for(200) == 1
    m = make_measured(clean_chain, "point", n=18, seed=3)
    problem = m.measurements.problem(m.model, m.samples)
    candidates = ladder((Family.OFFSETS,))
    fitted_on: list[tuple[int, ...]] = []

    def spy(rows: list[int]) -> list[CandidateFit]:
        fitted_on.append(tuple(rows))
        return [CandidateFit(problem.model, np.zeros(problem.model.size), np.ones(1), np.full(1, np.inf), 0)] * 2

    cv = cross_validate(problem, candidates, spy, 5, 0, lambda _p: 3.0, nested=False)
    assert cv.repeats == 10
    partitions = [fold_rows(pose_groups(problem.Q), 5, 0, r) for r in range(10)]
    assert len({tuple(map(tuple, p)) for p in partitions}) == 10  # ten different partitions
    expected = {tuple(sorted(set(range(18)) - set(t))) for p in partitions for t in p}
    assert set(fitted_on) == expected
    assert all(len(s.losses) == 18 for s in cv.scores)  # one pooled loss per pose, not per repeat
