"""`armtool calibrate fit` end to end, without the terminal: the command only parses its options,
shows progress and prints.

The order is the promise made to the user: every input and output is checked before any work
(`prepare_fit`), the slow detection and fit run next (`observe_samples`, `run_fit`), every output
is computed and checked before the first is written (`fit_files`), then each file is written
atomically (`write_files`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from armtool.calib.fit.calibration import CalibrationResult, FitOptions, calibrate
from armtool.calib.fit.convention_check import ConventionCheck, checked_conventions
from armtool.calib.fit.holdout import VALIDATION_PREFIX, check_same_setup, validation_samples
from armtool.calib.fit.measurements import CornerMeasurements, Measurements
from armtool.calib.fit.verdict import Verdict
from armtool.calib.inputs.dataset import Dataset, Sample, require_ok
from armtool.calib.inputs.load import Inputs, input_files, load_inputs
from armtool.calib.inputs.observations import Detect
from armtool.calib.model.calib_model import CalibModel
from armtool.calib.model.camera import CameraModel
from armtool.calib.model.joint_term import JointTerm
from armtool.calib.outputs.ur_kinematics import UrTarget, ur_target
from armtool.errors import ArmtoolError
from armtool.model.chain import Chain


@dataclass(frozen=True)
class FitRequest:
    """What the user asked `calibrate fit` for (the options, parsed)."""

    dataset: Path
    out: Path
    options: FitOptions  # --params, --holdout, --seed, --folds, --select, --nested
    validation: Path | None = None
    plot: Path | None = None
    xacro_args: dict[str, str] = field(default_factory=dict)
    package_paths: list[Path] = field(default_factory=list)
    ur_kinematics: Path | None = None
    ur_kinematics_in: Path | None = None
    keep_conventions: bool = False  # do not refuse a dataset whose measurements fit far better read another way


@dataclass(frozen=True)
class FitJob:
    """A request whose inputs are loaded and whose outputs are known to be writable."""

    request: FitRequest
    dataset: Dataset
    chain: Chain
    camera: CameraModel | None  # None for measured poses or points
    validation: Inputs | None
    ur: UrTarget | None
    conventions: ConventionCheck | None = None  # measured poses or points: how the declared reading fits
    terms: tuple[JointTerm, ...] = ()  # the joint terms --params asks for or the k-fold tries (compliance, harmonics)
    untried: tuple[str, ...] = ()  # why a joint term the default k-fold tries could not be (no inertials)


@dataclass(frozen=True)
class Observed:
    samples: list[Sample]  # the dataset's, then the validation dataset's (ids `validation:<id>`)
    measurements: Measurements
    validation_ids: set[str]  # kept out of the fit, with a random --holdout share of the others


@dataclass(frozen=True)
class FitFiles:
    files: dict[Path, str | bytes]  # path -> content, written by `write_files`
    document: dict[str, Any]  # calibration.yaml as data
    truth_warning: str | None  # why a simulated dataset could not be scored against its truth
    verdict: Verdict
    skipped: list[str]  # outputs not written because the calibration does not beat the nominal robot


def prepare_fit(request: FitRequest) -> FitJob:
    """Load and check everything the fit reads and writes, before the slow work starts."""
    plot = request.plot
    if plot is not None and not plot.parent.is_dir():  # at once; the full check follows the dataset's
        raise ArmtoolError("--plot's directory does not exist", str(plot), "create it, or write the plot elsewhere")
    ds, chain, camera = load_inputs(request.dataset, request.xacro_args, request.package_paths)
    require_ok(ds)
    assert chain is not None and (camera is not None or ds.measurement is not None)  # require_ok refused the rest
    validation = None
    if request.validation is not None:
        validation = load_inputs(request.validation, request.xacro_args, request.package_paths)
        vds, vchain, vcamera = validation
        require_ok(vds)
        check_same_setup(ds, chain, camera, vds, vchain, vcamera, request.validation)
    if request.options.hand_eye_only and request.ur_kinematics is not None:
        raise ArmtoolError(
            "--ur-kinematics with --params none: the robot is held nominal, so there is no calibrated arm to write",
            hint="drop --ur-kinematics, or fit kinematic parameters (the default --params origins,offsets)",
        )
    ur = ur_target(ds, chain, request.ur_kinematics, request.ur_kinematics_in)
    inputs = input_files(ds, validation.dataset if validation else None) + ([ur.source] if ur else [])
    _check_outputs(request, inputs)
    if plot is not None:
        from armtool.plotting import plot_format

        plot_format(plot)  # a format it can write, before the work
    conventions = None
    if ds.measurement is not None:
        conventions = checked_conventions(ds, chain, refuse=not request.keep_conventions)
    from armtool.calib.model.terms.registry import build_terms
    from armtool.model.load import urdf_text

    def text() -> str:
        return urdf_text(ds.urdf, ds.xacro_args, ds.package_paths)

    tried, untried = _tried_terms(request.options, chain, text)
    terms = build_terms(request.options.families, chain, text) + tried
    return FitJob(request, ds, chain, camera, validation, ur, conventions, terms, untried)


def _tried_terms(
    options: FitOptions, chain: Chain, urdf_xml: Callable[[], str]
) -> tuple[tuple[JointTerm, ...], tuple[str, ...]]:
    """The joint terms the default k-fold ladder tries beyond the requested families
    (`FitOptions.tried`): each one the robot allows (compliance needs the URDF's inertials); one
    it does not is not a candidate, and the fit says so (the second part: why, per term)."""
    from armtool.calib.model.terms.registry import build_terms

    if options.families_explicit or not options.select or options.folds < 2:
        return (), ()
    out: list[JointTerm] = []
    untried: list[str] = []
    for family in options.tried:
        if family in options.families:
            continue
        try:
            out += build_terms([family], chain, urdf_xml)
        except ArmtoolError as exc:
            untried.append(f"the k-fold did not try {family.value}: {exc.what}")
    return tuple(out), tuple(untried)


def _check_outputs(request: FitRequest, inputs: list[Path]) -> None:
    """Every file fit writes, checked against the run's inputs before the work starts."""
    from armtool.fileio import check_output_paths

    out = request.out
    outputs: dict[str, Path | None] = {"--plot": request.plot, "--ur-kinematics": request.ur_kinematics}
    if out.is_dir():  # else created by the fit: nothing in it can be an input
        outputs = {
            "--out (calibrated.urdf)": out / "calibrated.urdf",
            "--out (calibration.yaml)": out / "calibration.yaml",
            "--out (calibrated_with_terms.urdf)": out / "calibrated_with_terms.urdf",
            **outputs,
        }
    check_output_paths(outputs, inputs)


def observe_samples(job: FitJob, detect: Detect) -> Observed:
    """The measurements of the dataset's samples (tag corners, or measured poses or points) and
    of the validation dataset's (prepare_fit checked it is of the same setup), renamed
    `validation:<id>`."""
    ds, camera = job.dataset, job.camera
    samples = list(ds.samples)
    measurements = _measurements(ds, camera, detect)
    validation_ids: set[str] = set()
    if job.validation is not None:
        vds, _vchain, vcamera = job.validation
        renamed = validation_samples(vds.samples)
        samples += renamed
        validation_ids = {s.id for s in renamed}
        # its own conventions; prepare_fit refused a missing or different camera
        others = _measurements(vds, vcamera or camera, detect)
        measurements = measurements.merged(others, VALIDATION_PREFIX)
    return Observed(samples, measurements, validation_ids)


def _measurements(ds: Dataset, camera: CameraModel | None, detect: Detect) -> Measurements:
    """A dataset's measured poses or points, or the target corners detected in its images."""
    if ds.measurement is not None:
        from armtool.calib.fit.measurements import dataset_measurements

        return dataset_measurements(ds.measurement, ds.measured_rows)
    assert camera is not None  # prepare_fit refused an image dataset without intrinsics
    from armtool.calib.targets.spec import Target

    return CornerMeasurements(camera, detect(ds, camera), Target.of(ds).points_m)


def run_fit(job: FitJob, observed: Observed, progress: Callable[[str], None] | None = None) -> CalibrationResult:
    ds = job.dataset
    measurements = observed.measurements
    model = CalibModel(
        job.chain,
        ds.setup,
        np.eye(4),
        np.eye(4),
        sensor=measurements.sensor,
        target=measurements.target,
        terms=job.terms,
    )
    result = calibrate(
        model,
        measurements,
        observed.samples,
        job.request.options,
        ds.hints,
        validation_ids=observed.validation_ids,
        progress=progress,
    )
    result.warnings.extend(job.untried)
    return result


def fit_files(job: FitJob, result: CalibrationResult) -> FitFiles:
    """calibrated.urdf (checked to reproduce the fitted kinematics), calibration.yaml, and the
    plot and UR kinematics file when asked for; nothing is written yet."""
    import yaml

    from armtool.calib.apply import TERMS_URDF
    from armtool.calib.fit.verdict import hand_eye_verdict, judge
    from armtool.calib.outputs.report import calibration_document
    from armtool.calib.outputs.urdf import (
        check_reproduces,
        corrected_text,
        joint_corrections,
        relocate_meshes,
    )
    from armtool.calib.simulation.truth import has_truth, truth_scores
    from armtool.model.load import urdf_text

    request, ds = job.request, job.dataset
    # what was fitted: calibrated.urdf's set, or the joint terms on the nominal geometry when only
    # terms were asked for (--params compliance), which calibrated_with_terms.urdf carries
    terms = result.joint_terms
    judged = terms.candidate if terms is not None and result.candidate.is_nominal else result.candidate
    verdict = judge(
        result.crossval,
        judged.name,
        judged.is_nominal,
        result.fit_samples,
        result.coordinates_per_sample,
        result.motion_deg,
        result.blocks,
    )
    text = urdf_text(ds.urdf, ds.xacro_args, ds.package_paths)
    corrected = corrected_text(text, joint_corrections(result.model, result.x), ds.urdf.name)
    new_urdf = relocate_meshes(corrected, ds.urdf.parent, request.out)
    check_reproduces(new_urdf, result.model, result.x, ds.urdf.name)
    document = calibration_document(result, str(request.dataset), ds.urdf.name, verdict, job.conventions)
    if document.get("joint_terms"):  # what `calibrate apply` reloads the terms from (the fit's URDF, its args)
        document["joint_terms"]["dataset"] = str(request.dataset.resolve())
        document["joint_terms"]["xacro_args"] = dict(request.xacro_args)
    warning = None
    if has_truth(request.dataset):
        try:
            document["against_truth"] = truth_scores(request.dataset, result)
        except ArmtoolError as exc:  # only a score: never lose the fit for it
            warning = f"not scored against the truth: {exc}"
    files: dict[Path, str | bytes] = {}
    skipped: list[str] = []
    if request.options.hand_eye_only:  # asked for: the URDF is the nominal one, nothing to judge or write
        verdict = hand_eye_verdict()
    elif verdict.improves:
        files[request.out / "calibrated.urdf"] = new_urdf
        if result.joint_terms is not None:  # the chosen set's own geometry, for use with its terms
            terms_x = result.joint_terms.urdf_x(result.model)
            with_terms = corrected_text(text, joint_corrections(result.model, terms_x), ds.urdf.name)
            with_terms = relocate_meshes(with_terms, ds.urdf.parent, request.out)
            check_reproduces(with_terms, result.model, terms_x, ds.urdf.name)
            files[request.out / TERMS_URDF] = with_terms
    else:
        skipped.append(str(request.out / "calibrated.urdf"))
    files[request.out / "calibration.yaml"] = yaml.safe_dump(document, sort_keys=False, allow_unicode=True)
    if request.plot is not None:
        from armtool.calib.outputs.plot import calibration_figure
        from armtool.plotting import plot_format, render

        files[request.plot] = render(calibration_figure(result, str(request.dataset)), plot_format(request.plot))
    if request.ur_kinematics is not None and job.ur is not None:
        if verdict.improves:
            from armtool.calib.outputs.ur_kinematics import ur_kinematics_yaml

            files[request.ur_kinematics] = ur_kinematics_yaml(new_urdf, job.ur.joints, job.ur.hash, "calibrated.urdf")
        else:
            skipped.append(str(request.ur_kinematics))
    return FitFiles(files, document, warning, verdict, skipped)


def write_files(files: dict[Path, str | bytes], out: Path) -> None:
    """Create `out` and write each file atomically."""
    from armtool.fileio import write_atomic

    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ArmtoolError(
            f"cannot create --out: {exc.strerror or exc}", str(out), "check the path and its permissions"
        ) from None
    for path, data in files.items():
        write_atomic(path, data)
