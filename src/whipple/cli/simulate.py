"""Simulate measured runs of a bicycle and write them as run files.

Each run follows the seed paper's procedure: the bicycle is held upright, released, pushed
sideways, coasts freely, is caught and held, and is pushed again. The true motion is the
bicycle's linear model (with its extensions and controller), or with --nonlinear the nonlinear
Whipple model (with its controller and steer damping; the rear wheel driven along the speed
profile); the signals carry sensor noise and bias, and on request sensor faults (an IMU
misalignment, a gyro scale error, a drifting roll-rate bias, a steer offset, no steer angle).
On the ground the bicycle coasts and its speed falls by rolling resistance and air drag (or
rises down a slope: a negative --deceleration). Each file lists its true free-coasting
windows in the ``# true_windows:`` line. One file is written per speed: into DIR as
``<bicycle>_<setting>_<speed>ms.csv``, or to FILE (ending in .csv) for a single speed.
"""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path
from typing import Any

from whipple.atomic import check_writable, is_standard_output, refuse_input_overwrite
from whipple.cli.arguments import add_rider_argument, bicycle_inputs, integer, number, speed_list
from whipple.cli.progress import Progress
from whipple.errors import InputError
from whipple.model.assembly import linear_model
from whipple.model.parameters import load_bicycle
from whipple.number_text import parse_number
from whipple.simulation.nonlinear_run import simulate_nonlinear_run
from whipple.simulation.scenario import (
    MAX_BIAS_DRIFT,
    MAX_BIAS_WALK,
    MAX_GYRO_SCALE_ERROR,
    MAX_MISALIGNMENT,
    MAX_SAMPLES,
    MAX_SAMPLES_MEMORY,
    MAX_STEER_OFFSET,
    RunScenario,
    SensorFaults,
    Sensors,
)
from whipple.simulation.simulator import simulate_run, write_run_csv

#: Fault options of either sign: flag, metavar, help, largest magnitude and its unit.
_SIGNED_FAULTS = (
    ("--misalignment", "DEG", "IMU pitched nose up by DEG degrees: the roll gyro mixes in the yaw rate",
     math.degrees(MAX_MISALIGNMENT), "degrees"),
    ("--gyro-scale", "PERCENT", "scale error of both gyro axes, percent (3: they read 3%% high)",
     100 * MAX_GYRO_SCALE_ERROR, "percent"),
    ("--bias-drift", "RATE", "roll-rate bias growing linearly, rad/s per s", MAX_BIAS_DRIFT, "rad/s per s"),
    ("--steer-offset", "DEG", "constant steer angle error, degrees", math.degrees(MAX_STEER_OFFSET), "degrees"),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the options of this command to `parser`."""
    add_rider_argument(parser)
    parser.add_argument("--bicycle", required=True, metavar="PARAMS",
                        help="bicycle file (.toml or BicycleParameters *.txt) or built-in name")
    speeds = parser.add_mutually_exclusive_group(required=True)
    speeds.add_argument("--speed", type=number, metavar="V", help="true forward speed, m/s")
    speeds.add_argument("--speeds", type=speed_list, metavar="V1,V2,...",
                        help="several speeds, m/s: one run file each")
    parser.add_argument("--sample-rate", type=number, default=100.0, metavar="HZ",
                        help="sample rate, Hz (default 100)")
    parser.add_argument("--setting", choices=("treadmill", "ground"), default="treadmill",
                        help="constant belt speed, or a speed changing while coasting "
                             "(default treadmill)")
    parser.add_argument("--deceleration", type=number, default=None, metavar="A",
                        help="rolling resistance on the ground, m/s^2 (default 0.05); negative down a "
                             "slope that speeds the bicycle up")
    parser.add_argument("--drag", type=number, default=None, metavar="K",
                        help="air drag on the ground: the speed falls by (A + K v^2) m/s^2, K in 1/m "
                             "(default 0)")
    parser.add_argument("--pushes", type=integer, default=None, metavar="N",
                        help="number of pushes (default 3, or as many as fit in --duration)")
    parser.add_argument("--duration", type=number, default=None, metavar="S",
                        help="length of each run, s (default: long enough for the pushes)")
    parser.add_argument("--speedometer", action="store_true",
                        help="write a raw magnet-ring speedometer signal instead of speed")
    parser.add_argument("--noise", type=number, default=1.0, metavar="SCALE",
                        help="multiply every sensor's noise by SCALE (0: noise-free; default 1)")
    parser.add_argument("--bias", type=number, default=1.0, metavar="SCALE",
                        help="multiply every sensor's bias by SCALE (default 1)")
    faults = parser.add_argument_group("sensor faults (default: none)")
    faults.add_argument("--no-steer-angle", action="store_true",
                        help="write no steer angle column (a roll-rate gyro without a steer sensor)")
    for flag, metavar, text, limit, _ in _SIGNED_FAULTS:
        faults.add_argument(flag, type=number, default=0.0, metavar=metavar, help=f"{text} (|{metavar}| <= {limit:g})")
    faults.add_argument("--bias-walk", type=number, default=0.0, metavar="DENSITY",
                        help="roll-rate bias as a random walk, rad/s per sqrt(s) "
                             f"(0 <= DENSITY <= {MAX_BIAS_WALK:g})")
    parser.add_argument("--disturbance", type=_torque_pair, default=(0.0, 0.0), metavar="ROLL,STEER",
                        help="random roll and steer torques throughout the run (a road's roughness, wind), "
                             "root-mean-square N m, e.g. 2,0.1 (default: none)")
    parser.add_argument("--disturbance-band", type=number, default=2.0, metavar="HZ",
                        help="corner frequency of the random torques' low-pass filter, Hz (default 2)")
    parser.add_argument("--seed", type=integer, default=0, metavar="N",
                        help="random seed of the first run; the k-th speed uses N + k "
                             "(default 0)")
    parser.add_argument("--nonlinear", action="store_true",
                        help="integrate the nonlinear model (constraint drift and energy balance reported)")
    parser.add_argument("--output", required=True, metavar="DIR-or-FILE",
                        help="folder for the run files, or a .csv file for a single speed ('-': standard output)")


def _torque_pair(text: str) -> tuple[float, float]:
    """``ROLL,STEER`` in N m."""
    try:
        roll, steer = (parse_number(item) for item in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected two torques like 2,0.1 (N m), got {text!r}") from None
    return roll, steer


def _file_name(bicycle: str, setting: str, speed: float) -> str:
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", bicycle) or "bicycle"
    return f"{stem}_{setting}_{speed:.2f}ms.csv"


def run(args: argparse.Namespace) -> int:
    """Run the command; return the exit status."""
    speeds = args.speeds if args.speeds is not None else [args.speed]
    bad = [v for v in speeds if not (math.isfinite(v) and v > 0)]
    if bad:
        raise InputError(f"speeds must be positive m/s, got {bad[0]:g}")
    output = Path(args.output)
    refuse_input_overwrite(output, bicycle_inputs(args))
    to_stdout = is_standard_output(args.output)
    single_file = output.suffix.lower() == ".csv" or to_stdout
    if single_file and len(speeds) > 1:
        raise InputError(f"{len(speeds)} speeds need an output folder, not a .csv file or standard output",
                         args.output)
    if not single_file and output.exists() and not output.is_dir():
        raise InputError("output exists and is not a folder", args.output)
    check_writable(output, is_folder=not single_file)

    ground = _ground_options(args)
    faults = _sensor_faults(args)
    bicycle = load_bicycle(args.bicycle, rider=args.rider)
    model = linear_model(bicycle)
    columns = ["roll_rate", "yaw_rate", *([] if args.no_steer_angle else ["steer_angle"]),
               "speedometer" if args.speedometer else "speed"]
    sensors = Sensors().scaled(noise=args.noise, bias=args.bias)
    name = bicycle.name or Path(args.bicycle).stem
    scenarios = [
        RunScenario(speed=speed, sample_rate=args.sample_rate, duration=args.duration,
                    setting=args.setting, **ground, n_pushes=args.pushes, sensors=sensors,
                    faults=faults, columns=tuple(columns), seed=args.seed + k, disturbance=args.disturbance,
                    disturbance_band=args.disturbance_band)
        for k, speed in enumerate(speeds)
    ]  # all validated before anything is written
    total = sum(s.end_time() * s.sample_rate for s in scenarios)
    if total > MAX_SAMPLES:
        raise InputError(f"{len(scenarios)} runs would have {total:.3g} samples in all; at most "
                         f"{MAX_SAMPLES:g} are simulated at once ({MAX_SAMPLES_MEMORY}): fewer speeds per call")
    targets = [output if single_file else output / _file_name(name, args.setting, s.speed)
               for s in scenarios]
    for target in targets:
        refuse_input_overwrite(target, bicycle_inputs(args))
    # Simulate everything first: a bad speed (e.g. aliasing) must not leave half the files.
    runs = []
    with Progress(len(scenarios), "run", "simulating") as progress:
        for scenario, target in zip(scenarios, targets, strict=True):
            run_name = _file_name(name, args.setting, scenario.speed)[:-4] if to_stdout else target.stem
            runs.append(simulate_nonlinear_run(bicycle, scenario, name=run_name) if args.nonlinear
                        else simulate_run(bicycle, scenario, model=model, name=run_name))
            progress.update()
    for scenario, target, simulated in zip(scenarios, targets, runs, strict=True):
        write_run_csv(simulated, target)
        windows = ", ".join(f"{a:.2f}-{b:.2f}" for a, b in simulated.segments) or "none"
        print(f"{target}: {scenario.speed:g} m/s, {simulated.time.size} samples at "
              f"{scenario.sample_rate:g} Hz, coasting windows (s): {windows}")
        if simulated.checks is not None:
            c = simulated.checks
            print(f"  nonlinear: constraint drift {c.holonomic_drift:.2g} m, {c.velocity_drift:.2g} m/s; energy "
                  f"balance error {c.energy_error:.2g} J ({c.energy_error_relative:.2g} of the kinetic energy)")
    return 0


def _ground_options(args: argparse.Namespace) -> dict[str, Any]:
    """--deceleration and --drag as RunScenario fields; refused on a treadmill."""
    given = {name: value for name, value in (("deceleration", args.deceleration), ("drag", args.drag))
             if value is not None}
    if given and args.setting != "ground":
        raise InputError(f"--{next(iter(given))} applies to --setting ground only (a treadmill's speed is constant)")
    return given


def _sensor_faults(args: argparse.Namespace) -> SensorFaults:
    """Return the fault options as SensorFaults, checked in the units the user gave them."""
    for flag, _, _, limit, unit in _SIGNED_FAULTS:
        value = getattr(args, flag[2:].replace("-", "_"))
        if not (math.isfinite(value) and abs(value) <= limit):
            raise InputError(f"{flag} must be within +/-{limit:g} {unit}, got {value:g}")
    if not (math.isfinite(args.bias_walk) and 0 <= args.bias_walk <= MAX_BIAS_WALK):
        raise InputError(f"--bias-walk must be between 0 and {MAX_BIAS_WALK:g} rad/s per sqrt(s), "
                         f"got {args.bias_walk:g}")
    return SensorFaults(misalignment=math.radians(args.misalignment), gyro_scale=1.0 + args.gyro_scale / 100,
                        bias_drift=args.bias_drift, bias_walk=args.bias_walk,
                        steer_offset=math.radians(args.steer_offset))
