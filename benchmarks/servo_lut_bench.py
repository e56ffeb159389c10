"""How much does a `servo-lut` table help? Before/after errors on the simulator's non-linear AX-12A.

The simulator (armtool.servo.sim) models an AX-12A whose potentiometer is non-linear near both
ends (about 3° at 30° in from each end, research/servo.md 3.1); the servo regulates its own
reading, so only the external encoder (the sim's second pty, `A <id>` -> `<deg>`, Gaussian
noise --noise) sees the true angle. The benchmark runs the real code path on the real pty:

1. `measure`: --points commands between the stops' safe range, approached from below, --reads
   encoder readings each;
2. `fit` with pchip, linear and a cubic polynomial, the same held-out points for all three;
3. `check`: the same --n random angles (not knots), each commanded through the table and through
   the nominal datasheet map (300/1023 ° per tick), measured by the encoder.

Errors are measured minus wanted angle, in degrees. Prints a markdown table on stdout (or JSON
with --format json); progress on stderr.

    python benchmarks/servo_lut_bench.py [--points 41] [--n 25] [--noise 0.05] [--seed 0]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from typing import Any

from armtool.servo.bus import open_bus
from armtool.servo.guard import TorqueGuard
from armtool.servo.lut.csv_format import parse_measurements, render_measurements
from armtool.servo.lut.measure import Driver, Motion, check, check_angles, measure, plan_commands, speed_register
from armtool.servo.lut.table import Method, fit_table
from armtool.servo.reference import open_reference
from armtool.servo.sim import SimBus

STOPS = (92, 914)  # true-angle stops of the simulated joint, in nominal ticks
SAFE = (100, 906)  # the range `armtool limits` would give with a small margin


def run(points: int, n: int, noise: float, seed: int, reads: int, speed: float) -> dict[str, Any]:
    config = {
        "protocol": "dxl1",
        "baud": 1000000,
        "return_delay": 0,
        "seed": seed,
        "encoder": {"noise_deg": noise},
        "joints": [{"id": 1, "model": "AX-12A", "stops": list(STOPS), "start": 512}],
    }
    out: dict[str, Any] = {
        "schema_version": 1,
        "config": {
            "points": points,
            "n": n,
            "noise_deg": noise,
            "seed": seed,
            "reads": reads,
            "speed_deg_s": speed,
            "range_ticks": SAFE,
        },
    }
    with SimBus.start(config) as sim:
        bus = open_bus(sim.port_path, "dxl1", 1000000, echo_check_id=1)
        ref = open_reference(f"encoder:{sim.encoder_port_path}")
        try:
            bus.identify([1])
            model = bus.model(1)
            motion = Motion(backoff_ticks=10, dwell_s=0.02)
            with TorqueGuard(bus) as guard:
                guard.set_ram(1, "moving_speed", speed_register(model, speed))
                guard.torque_on(1)
                driver = Driver(bus, guard, 1, motion)
                t0 = time.monotonic()
                commands = plan_commands(*SAFE, "up", motion.backoff_ticks, points=points)
                samples = measure(driver, ref, commands, "up", *SAFE, reads=reads)
                out["measure_s"] = round(time.monotonic() - t0, 2)
                sys.stderr.write(
                    f"measured {len(samples)} readings at {len(commands)} points in {out['measure_s']} s\n"
                )
                meas = parse_measurements(
                    render_measurements({"servo_id": "1", "servo_model": model.name, "reference": ref.spec}, samples),
                    "sim",
                )
                rows = []
                for method in Method:
                    table = fit_table(meas, method, degree=3, holdout=0.2, seed=seed)
                    report = table.report
                    assert report is not None
                    angles = check_angles(table, n, seed, *SAFE)
                    t1 = time.monotonic()
                    result = check(driver, ref, table, angles, *SAFE, reads=reads)
                    sys.stderr.write(f"checked {method.value} at {n} angles in {time.monotonic() - t1:.1f} s\n")
                    rows.append(
                        {
                            "method": method.value if method is not Method.POLY else "poly (cubic)",
                            "fit_holdout": report.holdout,
                            "fit_holdout_nominal": {
                                "rms_deg": report.holdout_nominal.rms_deg,
                                "max_deg": report.holdout_nominal.max_deg,
                            },
                            "fit_holdout_lut": {
                                "rms_deg": report.holdout_lut.rms_deg,
                                "max_deg": report.holdout_lut.max_deg,
                            },
                            "check_nominal": result.nominal,
                            "check_lut": result.lut,
                        }
                    )
                out["nonlinearity"] = {
                    "nominal_max_deg": report.nominal_max_deg,
                    "best_line_max_deg": report.nonlinearity_deg,
                }
                out["methods"] = rows
            out["torque_enable_after"] = sim.peek(1, "torque_enable")
        finally:
            ref.close()
            bus.close()
    return out


def render_markdown(doc: dict[str, Any]) -> str:
    c = doc["config"]
    lines = [
        f"Simulated AX-12A (potentiometer off by up to {doc['nonlinearity']['nominal_max_deg']:.2f}° from the "
        f"datasheet map), encoder noise σ = {c['noise_deg']}°, {c['points']} points x {c['reads']} readings "
        f"({doc['measure_s']} s), seed {c['seed']}. RMS / max error in degrees.",
        "",
        "| table | fit held-out: nominal | fit held-out: table | live check: nominal | live check: table | check ratio (max) |",
        "|---|---|---|---|---|---|",
    ]
    for r in doc["methods"]:

        def cell(s: dict[str, float]) -> str:
            return f"{s['rms_deg']:.3f} / {s['max_deg']:.3f}"

        ratio = (
            r["check_nominal"]["max_deg"] / r["check_lut"]["max_deg"] if r["check_lut"]["max_deg"] > 0 else float("inf")
        )
        lines.append(
            f"| {r['method']} | {cell(r['fit_holdout_nominal'])} | {cell(r['fit_holdout_lut'])} | "
            f"{cell(r['check_nominal'])} | {cell(r['check_lut'])} | {ratio:.1f}x |"
        )
    lines.append("")
    lines.append(
        f"Fit held-out: {doc['methods'][0]['fit_holdout']} measured points left out of the fit. Live check: "
        f"{c['n']} random angles (not knots), commanded and measured by the encoder; a servo takes whole "
        "ticks, so the table's floor is about half a tick (0.15°)."
    )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", type=int, default=41)
    parser.add_argument("--n", type=int, default=25)
    parser.add_argument("--noise", type=float, default=0.05, help="encoder noise, 1-sigma degrees")
    parser.add_argument("--reads", type=int, default=3)
    parser.add_argument("--speed", type=float, default=300.0, help="degrees per second")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--format", choices=("markdown", "json"), default="markdown")
    args = parser.parse_args()
    doc = run(args.points, args.n, args.noise, args.seed, args.reads, args.speed)
    print(json.dumps(doc, indent=2) if args.format == "json" else render_markdown(doc))


if __name__ == "__main__":
    main()
