"""What is held out of a fit: a random share, a validation dataset, or both."""

from __future__ import annotations

import numpy as np
import pytest

from armtool.calib.fit.holdout import VALIDATION_PREFIX, holdout_ids, split_holdout, validation_samples
from armtool.calib.fit.measurements import CornerMeasurements
from armtool.calib.inputs.dataset import Sample
from armtool.calib.inputs.observations import Observation
from armtool.calib.model.camera import CameraModel
from armtool.errors import ArmtoolError

CORNERS = np.zeros((4, 2))


def _samples(ids: list[str]) -> list[Sample]:
    return [Sample(i, k + 2, np.zeros(2), None) for k, i in enumerate(ids)]


def _seen(ids: list[str], missing: tuple[str, ...] = ()) -> dict[str, Observation]:
    return {i: Observation(i, None if i in missing else CORNERS, "no tag" if i in missing else "") for i in ids}


def _corners(camera: CameraModel, ids: list[str], missing: tuple[str, ...] = ()) -> CornerMeasurements:
    return CornerMeasurements(camera, _seen(ids, missing), np.zeros((4, 3)))


def test_split_is_reproducible_and_refuses_to_hold_out_everything() -> None:
    ids = [str(i) for i in range(20)]
    assert split_holdout(ids, 0.25, 7) == split_holdout(ids, 0.25, 7)
    assert len(split_holdout(ids, 0.25, 7)) == 5 and split_holdout(ids, 0.0, 7) == set()
    with pytest.raises(ArmtoolError, match="leaves nothing to fit"):
        split_holdout(ids, 1.0, 0)


def test_validation_samples_are_renamed_so_ids_cannot_collide(camera: CameraModel) -> None:
    assert [s.id for s in validation_samples(_samples(["0"]))] == ["validation:0"]
    merged = _corners(camera, ["0", "1"]).merged(_corners(camera, ["0"], ("0",)), VALIDATION_PREFIX)
    assert isinstance(merged, CornerMeasurements)
    seen = merged.observations
    assert sorted(seen) == ["0", "1", "validation:0"] and seen["validation:0"].sample_id == "validation:0"
    assert seen["validation:0"].corners_px is None and seen["validation:0"].reason == "no tag"
    assert merged.reason("validation:0") == "no tag" and merged.reason("0") is None
    assert seen["0"].corners_px is not None


def test_holdout_takes_the_validation_set_plus_a_share_of_the_detected_others(camera: CameraModel) -> None:
    ids = [str(i) for i in range(10)] + ["validation:a"]
    measurements = _corners(camera, ids, missing=("3",))
    usable = [i for i in ids if measurements.reason(i) is None]  # as the fit takes them
    assert holdout_ids(usable, 0.0, 0) == set()
    assert holdout_ids(usable, 0.0, 0, {"validation:a"}) == {"validation:a"}
    held = holdout_ids(usable, 0.5, 1, {"validation:a"})
    assert "validation:a" in held and "3" not in held
    assert len(held) == 1 + round(0.5 * 9)  # the share is of the 9 detected dataset samples
    assert held == {"2", "4", "7", "9", "validation:a"}  # the split of the samples' order, as before
