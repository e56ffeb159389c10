"""calibration.yaml's JSON summary (what `calibrate fit --format json` prints)."""

from __future__ import annotations

from armtool.calib.outputs.report import SUMMARY_KEYS, json_summary


def test_summary_keeps_the_summary_keys_and_the_truth_only_when_scored() -> None:
    document = {key: key.upper() for key in (*SUMMARY_KEYS, "joints", "samples", "dataset")}
    summary = json_summary(document)
    assert summary == {**{key: key.upper() for key in SUMMARY_KEYS}, "schema_version": 1}
    assert json_summary({**document, "against_truth": {"improvement": 30.0}})["against_truth"] == {"improvement": 30.0}
