"""How much the default fit (5-fold cross-validation of the parameter sets, nested) costs against
the plain fit (`--folds 0`), measured as a ratio in one run, on real data: the UR5 laser-tracker
grid (1000 poses) and the FR3 camera poses (114), both from ../shared/calib-real.

The two fits are run alternately, `--rounds` times each, in this process (`calibrate`, the fit
alone: the dataset is loaded once, outside the timed region) and as the command a user runs
(`armtool calibrate fit`, whole process: Python start-up, loading, the fit and the files); the
ratio is of the medians. The fit runs on one core (BLAS on one thread, folds one after another),
so the CPU time is the figure that the machine's other jobs disturb least.

It also says whether the default fit makes the same choice as exact fits (the ladder's full fits
on the real model instead of on the hand-eye-only fit's linearisation, and each training fold
fitted by `fit_set` on the real model, started from its full fit, instead of on that fit's
linearised problem): the chosen set, each outer fold's nested choice, the largest difference of
any candidate's held-out score, of any sample's calibrated residual and of the nested held-out
RMS. PASS: the UR5 ratio of CPU times is at most 5 (issue 28) and the choices are the exact fits'.

    python benchmarks/calib_speed.py [--data ../shared/calib-real] [--rounds 3] [--no-exact]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
TARGET = 5.0  # the default fit at most this many times the plain fit's CPU on the 1000 UR5 poses (issue 28)


def load(dataset: Path) -> tuple[Any, Any, list[Any]]:
    """(model, measurements, usable samples) as `calibrate fit` builds them."""
    import numpy as np

    from armtool.calib.fit.calibration import FitOptions
    from armtool.calib.model.calib_model import CalibModel
    from armtool.calib.pipeline import FitRequest, observe_samples, prepare_fit

    job = prepare_fit(FitRequest(dataset, dataset / "unused-out", FitOptions()))
    observed = observe_samples(job, lambda _ds, _camera: {})
    m = observed.measurements
    model = CalibModel(
        job.chain, job.dataset.setup, np.eye(4), np.eye(4), sensor=m.sensor, target=m.target, terms=job.terms
    )
    return model, m, [s for s in observed.samples if m.reason(s.id) is None]


def timed(work: Callable[[], Any]) -> tuple[Any, float, float]:
    wall, cpu = time.perf_counter(), time.process_time()
    out = work()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def exact_choice(model: Any, m: Any, samples: list[Any]) -> Any:
    """The default fit's cross-validation with every fit exact: the ladder's full fits on the real
    model (each from the previous one's solution) instead of on the hand-eye-only fit's
    linearisation, and each training fold fitted by `fit_set` on the real model, started from its
    full fit, instead of on that fit's linearised problem."""
    from functools import partial
    from unittest import mock

    import armtool.calib.fit.calibration as calibration
    from armtool.calib.fit.crossval import CandidateFit

    def exact_ladder(problem: Any, full: Any, options: Any, start: Any) -> Callable[[list[int]], list[Any]]:
        def fit(rows: list[int]) -> list[Any]:
            out = []
            for f in full:
                sub = problem.subset(rows).with_model(f.problem.model).with_sigma(f.problem.sigma)
                fitted = calibration.fit_set(sub, f.x, f.free, options, identify_at=start.x_hat, ident=f.ident)
                out.append(
                    CandidateFit(
                        fitted.problem.model, fitted.x, fitted.problem.sigma, fitted.limit, fitted.subspace.dimension
                    )
                )
            return out

        return fit

    with (
        mock.patch.object(calibration, "_full_ladder", partial(calibration._full_ladder, exact=True)),
        mock.patch.object(calibration, "fold_ladder", exact_ladder),
    ):
        return calibration.calibrate(model, m, samples, calibration.FitOptions())


def case(name: str, dataset: Path, out: Path, rounds: int, exact: bool) -> tuple[float, bool | None]:
    """Prints the row (and the exact fits' comparison); returns the CPU ratio and whether the
    exact fits made the same choices (None: not compared)."""
    import subprocess

    from armtool.calib.fit.calibration import FitOptions, calibrate

    model, m, samples = load(dataset)
    plain_cpu, default_cpu, plain_wall, default_wall = [], [], [], []
    result = None
    for _ in range(rounds):  # interleaved, so that a change of the machine's load hits both
        _r, wall, cpu = timed(lambda: calibrate(model, m, samples, FitOptions(folds=0)))
        plain_wall.append(wall)
        plain_cpu.append(cpu)
        result, wall, cpu = timed(lambda: calibrate(model, m, samples, FitOptions()))
        default_wall.append(wall)
        default_cpu.append(cpu)
    command_plain: list[float] = []
    command_default: list[float] = []
    for _ in range(rounds):
        for times, extra in ((command_plain, ["--folds", "0"]), (command_default, [])):
            start = time.perf_counter()
            run = subprocess.run(
                [
                    sys.executable,
                    "-m",
                    "armtool",
                    "calibrate",
                    "fit",
                    str(dataset),
                    "-o",
                    str(out),
                    "--format",
                    "json",
                    *extra,
                ],
                capture_output=True,
                text=True,
                cwd=ROOT,
            )
            times.append(time.perf_counter() - start)
            if run.returncode != 0:
                sys.exit(run.stderr)
    median = statistics.median
    assert result is not None and result.crossval is not None and result.crossval.nested is not None
    cv = result.crossval
    print(
        f"| {name} | {len(samples)} | {median(plain_cpu):.2f} / {median(plain_wall):.2f} | "
        f"{median(default_cpu):.2f} / {median(default_wall):.2f} | **{median(default_cpu) / median(plain_cpu):.1f}×** / "
        f"{median(default_wall) / median(plain_wall):.1f}× | {median(command_plain):.1f} / {median(command_default):.1f} "
        f"({median(command_default) / median(command_plain):.1f}×) | {cv.chosen.name} |"
    )
    if exact:
        exact_result, wall, _cpu = timed(lambda: exact_choice(model, m, samples))
        reference = exact_result.crossval
        assert reference is not None and reference.nested is not None
        difference = max(abs(a.loss - b.loss) / max(abs(b.loss), 1e-12) for a, b in zip(cv.scores, reference.scores))
        same = cv.chosen == reference.chosen and cv.nested.chosen == reference.nested.chosen
        blocks = [b.name for b in result.blocks]
        fit_change = {
            b: max(abs(r.after[b] - e.after[b]) for r, e in zip(result.residuals, exact_result.residuals) if r.after)
            for b in blocks
        }
        held_change = {b: abs(cv.nested.rms[b] - reference.nested.rms[b]) for b in blocks}
        compared: bool | None = same
        print(
            f"|   exact fits ({wall:.1f} s wall) | | | | | | {reference.chosen.name}: "
            f"{'the same choice' if same else 'A DIFFERENT CHOICE'}, nested choices "
            f"{'the same' if cv.nested.chosen == reference.nested.chosen else 'differ'}; scores within {difference:.1e} "
            f"(relative); each sample's calibrated residual within {_figures(result, fit_change)}, the nested held-out "
            f"RMS within {_figures(result, held_change)} |"
        )
    else:
        compared = None
    return median(default_cpu) / median(plain_cpu), compared


def _figures(result: Any, values: dict[str, float]) -> str:
    """'1.2e-05 mm, 0.0001 deg': figures already in each block's unit."""
    return ", ".join(f"{v:.2g} {result.block(b).unit}" for b, v in values.items())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=ROOT / ".." / "shared" / "calib-real")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--no-exact", dest="exact", action="store_false", help="skip the exact fold fits")
    args = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from calib_real import UR5_CSV, ur5_rows, write_manifest, write_ur5_dataset

    load_before = os.getloadavg()
    print(
        "| data | poses | plain fit CPU / wall s | default fit CPU / wall s | default / plain, CPU / wall | "
        "command plain / default wall s | chosen |"
    )
    print("|---|---|---|---|---|---|---|")
    verdict: tuple[float, bool | None] | None = None
    with tempfile.TemporaryDirectory() as tmp:
        ur5 = args.data / "ur5_tracker"
        if (ur5 / UR5_CSV).is_file():
            dataset = write_ur5_dataset(Path(tmp) / "ur5", ur5_rows(ur5))
            verdict = case("UR5 tracker", dataset, Path(tmp) / "ur5-out", args.rounds, args.exact)
        fr3 = args.data / "franka_fr3"
        if (fr3 / "camera_in_board.csv").is_file():
            dataset = write_manifest(Path(tmp) / "fr3", fr3.resolve())
            case("FR3 camera poses", dataset, Path(tmp) / "fr3-out", args.rounds, args.exact)
    load_after = os.getloadavg()
    print(
        f"one core per fit; load average {load_before[0]:.1f} before, {load_after[0]:.1f} after "
        f"({os.cpu_count()} cores, shared with other jobs)"
    )
    if verdict is not None:
        ratio, same = verdict
        ok = ratio <= TARGET and same is not False
        print(
            f"{'PASS' if ok else 'FAIL'}: UR5 tracker default / plain {ratio:.1f}× CPU (target ≤ {TARGET:g}×)"
            + {True: ", the same choices as exact fits", False: ", NOT the exact fits' choices", None: ""}[same]
        )


if __name__ == "__main__":
    main()
