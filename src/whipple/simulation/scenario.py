"""What happens in a simulated run: speed, pushes, catches, sensors (plain, validated data).

A run follows the procedure of the seed paper (Kooijman & Schwab 2009, sections 4.1-4.4): the
bicycle is held upright (launch), released, pushed sideways, left to coast freely, caught, held
upright again, and pushed again. :func:`whipple.simulation.simulator.simulate_run` turns a
:class:`RunScenario` into signals.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from whipple.errors import InputError
from whipple.simulation.coasting import coasting_distance, coasting_speed, stopping_time
from whipple.simulation.run_limits import MAX_RUN_SPEED, MAX_SPEED_NOISE_SHARE, MIN_DURATION, MIN_SAMPLE_RATE

__all__ = ["SIGNALS", "SETTINGS", "PUSH_SIGNS", "MAX_SAMPLES", "MAX_SAMPLES_MEMORY", "ScenarioError", "Push", "Sensor",
           "Sensors", "PERFECT_SENSORS", "MAX_MISALIGNMENT", "MAX_GYRO_SCALE_ERROR", "MAX_STEER_OFFSET",
           "MAX_BIAS_DRIFT", "MAX_BIAS_WALK", "SensorFaults", "NO_FAULTS", "RunScenario"]

#: Signals a simulated run can hold, in the order they are drawn and written.
SIGNALS = ("roll_rate", "yaw_rate", "steer_angle", "steer_rate", "roll_angle", "speed",
           "speedometer")
SETTINGS = ("treadmill", "ground")
#: Directions of automatic pushes (:attr:`RunScenario.push_signs`).
PUSH_SIGNS = ("alternate", "random")
#: Most samples of one simulated run (or of all runs of one ``whipple simulate``): a simulation
#: holds about 400 bytes per sample until its file is written (measured: 470 MB for 10^6).
MAX_SAMPLES = 2_000_000
MAX_SAMPLES_MEMORY = "1 GB of memory"


class ScenarioError(InputError):
    """A run scenario with impossible values (negative speed, zero sample rate, ...)."""


def _check(name: str, value: object, ok: Callable[[float], bool], requirement: str) -> None:
    if (isinstance(value, bool) or not isinstance(value, int | float)
            or not math.isfinite(value) or not ok(value)):
        raise ScenarioError(f"{name} must be a finite number, {requirement}; got {value!r}")


@dataclass(frozen=True)
class Push:
    """A lateral push: half-sine torque pulses on roll and steer.

    Attributes
    ----------
    time : float
        Start of the pulse [s].
    roll_impulse : float or None
        Time integral of the roll torque [N m s] (a lateral force at the saddle times its
        height). None: sized so that the push changes the roll rate by the scenario's
        ``push_roll_rate`` [rad/s] (``roll_impulse = push_roll_rate / B[roll_rate, roll]``).
    steer_impulse : float
        Time integral of the steer torque [N m s].
    duration : float
        Length of the pulse [s].
    """

    time: float
    roll_impulse: float | None = None
    steer_impulse: float = 0.0
    duration: float = 0.1


@dataclass(frozen=True)
class Sensor:
    """A sensor's errors: white noise and a constant bias, in the signal's unit.

    Attributes
    ----------
    noise : float
        Standard deviation of the noise per sample (independent between samples).
    bias : float
        Constant offset added to the true value.
    """

    noise: float = 0.0
    bias: float = 0.0


@dataclass(frozen=True)
class Sensors:
    """Errors of every signal; noise is per sample, whatever the sample rate.

    Defaults are typical of a MEMS rate gyro (0.015 rad/s), a steer potentiometer (0.005 rad,
    noisier than the gyros relative to its signal), a speed from an encoder (0.02 m/s) and a
    magnet pick-up of 1 V amplitude (0.02 V).
    """

    roll_rate: Sensor = Sensor(0.015, 0.004)  # rad/s
    yaw_rate: Sensor = Sensor(0.015, -0.003)  # rad/s
    steer_angle: Sensor = Sensor(0.005, 0.008)  # rad
    steer_rate: Sensor = Sensor(0.05, 0.0)  # rad/s
    roll_angle: Sensor = Sensor(0.003, 0.005)  # rad
    speed: Sensor = Sensor(0.02, 0.0)  # m/s
    speedometer: Sensor = Sensor(0.02, 0.1)  # V

    def scaled(self, noise: float = 1.0, bias: float = 1.0) -> Sensors:
        """Return a copy with every noise level multiplied by `noise` and every bias by `bias`."""
        if not (math.isfinite(noise) and math.isfinite(bias) and noise >= 0 and bias >= 0):
            raise ScenarioError(f"noise and bias scales must be >= 0, got {noise}, {bias}")
        return Sensors(**{name: Sensor(getattr(self, name).noise * noise,
                                       getattr(self, name).bias * bias) for name in SIGNALS})


#: Sensors without noise or bias.
PERFECT_SENSORS = Sensors(**{name: Sensor() for name in SIGNALS})

#: Largest faults a scenario takes: beyond them the sensor is not misaligned or off but
#: mounted another way or broken (IMU tilt [rad], gyro scale error, steer offset [rad],
#: roll-rate bias drift [rad/s^2] and random walk [rad/s/sqrt(s)]).
MAX_MISALIGNMENT = math.radians(20.0)
MAX_GYRO_SCALE_ERROR = 0.5
MAX_STEER_OFFSET = math.radians(10.0)
MAX_BIAS_DRIFT = 0.01
MAX_BIAS_WALK = 0.1


@dataclass(frozen=True)
class SensorFaults:
    """Errors of an instrumented bicycle's sensors beyond noise and a constant bias.

    Applied to the true signals before the sensors' noise and bias
    (:func:`whipple.simulation.sensor_faults.faulty_signals`); the defaults are no fault.

    Attributes
    ----------
    misalignment : float
        The IMU pitched about the lateral axis by this angle [rad], nose up when positive
        (axes of Meijaard et al. 2007: x forward, z down): its roll gyro reads
        ``cos(a) roll_rate - sin(a) yaw_rate`` and its yaw gyro
        ``sin(a) roll_rate + cos(a) yaw_rate``. At most 20 degrees either way.
    gyro_scale : float
        Scale factor of both gyro axes (1.03: they read 3 % high); 0.5 to 1.5.
    bias_drift : float
        The roll-rate bias grows linearly by this much per second [rad/s^2] from t = 0;
        at most 0.01 either way.
    bias_walk : float
        The roll-rate bias is also a random walk of this density [rad/s/sqrt(s)] (standard
        deviation ``bias_walk sqrt(t)`` at time t), drawn from a random stream of its own so
        that the run's other random numbers stay the same; 0 to 0.1.
    steer_offset : float
        Constant error of the steer angle [rad] (a potentiometer zeroed off centre), added to
        the steer sensor's bias; at most 10 degrees either way.
    """

    misalignment: float = 0.0
    gyro_scale: float = 1.0
    bias_drift: float = 0.0
    bias_walk: float = 0.0
    steer_offset: float = 0.0

    def __post_init__(self) -> None:
        _check("misalignment", self.misalignment, lambda x: abs(x) <= MAX_MISALIGNMENT,
               f"within +/-{MAX_MISALIGNMENT:.4g} rad (20 deg)")
        _check("gyro_scale", self.gyro_scale, lambda x: abs(x - 1.0) <= MAX_GYRO_SCALE_ERROR,
               f"within 1 +/- {MAX_GYRO_SCALE_ERROR:g}")
        _check("bias_drift", self.bias_drift, lambda x: abs(x) <= MAX_BIAS_DRIFT,
               f"within +/-{MAX_BIAS_DRIFT:g} rad/s^2")
        _check("bias_walk", self.bias_walk, lambda x: 0 <= x <= MAX_BIAS_WALK,
               f"between 0 and {MAX_BIAS_WALK:g} rad/s/sqrt(s)")
        _check("steer_offset", self.steer_offset, lambda x: abs(x) <= MAX_STEER_OFFSET,
               f"within +/-{MAX_STEER_OFFSET:.4g} rad (10 deg)")

    @property
    def is_none(self) -> bool:
        """True when there is no fault at all."""
        return self == SensorFaults()


#: No sensor fault.
NO_FAULTS = SensorFaults()


@dataclass(frozen=True)
class RunScenario:
    """One simulated run.

    Attributes
    ----------
    speed : float
        True forward speed at t = 0 [m/s].
    sample_rate : float
        [Hz].
    duration : float or None
        Length of the record [s]; None: just long enough for the pushes and their coasting.
    setting : {"treadmill", "ground"}
        Treadmill: constant belt speed. Ground: the bicycle coasts and its speed falls (or,
        down a slope, rises), ``v' = -(deceleration + drag v^2)`` (:mod:`whipple.simulation.coasting`; without drag
        ``speed - deceleration * t``), throughout the run.
    deceleration : float
        Rolling resistance [m/s^2], ground setting only (0.05: a rolling resistance
        coefficient of ~0.004 plus the drag of a riderless bicycle at ~5 m/s), less gravity's
        pull along a downhill road (``g`` times its grade): negative down a slope steeper than
        the rolling resistance, where the bicycle speeds up.
    drag : float
        Air drag coefficient ``rho CdA / (2 m)`` [1/m], ground setting only (0 by default; a
        riderless bicycle of 25 kg with CdA ~ 0.1 m^2: ~0.0024 1/m, 0.06 m/s^2 at 5 m/s).
    pushes : tuple of Push, or None
        Explicit pushes; None: ``n_pushes`` pushes of alternating direction, the first at
        ``release``, spaced by ``push_duration + max_coast + catch_duration + settle``.
    n_pushes : int or None
        Number of automatic pushes; None: 3, or as many as fit in ``duration``.
    push_roll_rate : float
        Roll-rate change of an automatic push [rad/s].
    push_duration : float
        Pulse length of automatic pushes [s].
    release : float
        End of the launch hold [s]; the bicycle is held upright before it.
    max_coast : float
        Longest free coasting before a scheduled catch [s].
    settle : float
        Shortest hold between a scheduled catch and the next push [s].
    catch_duration : float
        Time in which the catch brings the state to within 0.5 % of its value [s]. The catch
        and hold act like a stiff critically damped spring on roll and steer, natural
        frequency ``7.5 / catch_duration`` [rad/s].
    roll_limit, roll_rate_limit : float
        The catch comes as soon as ``|roll|`` [rad] or ``|roll rate|`` [rad/s] exceeds these (keeps
        runs at unstable speeds in the linear range).
    hold_std : float
        Standard deviation of roll and steer [rad] while held (the hand is not perfectly
        still).
    push_signs : {"alternate", "random"}
        Directions of the automatic pushes: alternating (the first to the positive roll
        rate), or each drawn at random (an experimenter who pushes from either side).
    push_spread : float
        Relative spread of the automatic pushes' sizes: each is ``push_roll_rate`` times a
        factor drawn uniformly from ``[1 - push_spread, 1 + push_spread]``; 0 (in [0, 1)):
        all alike.
    coast_spread : float
        Relative spread of the coasts before a scheduled catch: each lasts ``max_coast``
        times a factor drawn uniformly from ``[1 - coast_spread, 1]`` (a hand that catches
        when it chooses); 0 (in [0, 1)): all ``max_coast``.
    sensors : Sensors
        Noise and bias of each signal.
    faults : SensorFaults
        IMU misalignment, gyro scale error, roll-rate bias drift, steer offset (none by
        default). A run without a steer angle leaves ``steer_angle`` out of ``columns``.
    disturbance : tuple of float
        Root-mean-square roll and steer torques [N m] of random disturbances acting throughout
        the run, coasts included: a road's or a belt's roughness, gusts of wind
        (:mod:`whipple.simulation.disturbance`); (0, 0), the default: none.
    disturbance_band : float
        Corner frequency [Hz] of the disturbances (first-order low-pass filtered white noise),
        below half the sample rate.
    columns : tuple of str
        Measured signals to output (``roll_rate`` is required; see ``SIGNALS``). A
        ``speedometer`` column is a raw magnet-ring signal instead of a speed.
    pulses_per_revolution : int
        Zero crossings of the speedometer signal per wheel revolution (twice the magnets).
    seed : int
        Seed of the random generator: equal scenarios give identical runs.
    """

    speed: float = 5.0
    sample_rate: float = 100.0
    duration: float | None = None
    setting: str = "treadmill"
    deceleration: float = 0.05
    drag: float = 0.0
    pushes: tuple[Push, ...] | None = None
    n_pushes: int | None = None
    push_roll_rate: float = 0.5
    push_duration: float = 0.1
    release: float = 1.0
    max_coast: float = 5.0
    settle: float = 1.0
    catch_duration: float = 0.3
    roll_limit: float = 0.25
    roll_rate_limit: float = 1.5
    hold_std: float = 0.001
    push_signs: str = "alternate"
    push_spread: float = 0.0
    coast_spread: float = 0.0
    sensors: Sensors = Sensors()
    faults: SensorFaults = NO_FAULTS
    disturbance: tuple[float, float] = (0.0, 0.0)
    disturbance_band: float = 2.0
    columns: tuple[str, ...] = ("roll_rate", "yaw_rate", "steer_angle", "speed")
    pulses_per_revolution: int = 20
    seed: int = 0

    def __post_init__(self) -> None:
        positive = ("speed", "sample_rate", "push_duration", "max_coast", "catch_duration",
                    "roll_limit", "roll_rate_limit")
        for name in positive:
            _check(name, getattr(self, name), lambda x: x > 0, "positive")
        for name in ("drag", "push_roll_rate", "release", "settle", "hold_std"):
            _check(name, getattr(self, name), lambda x: x >= 0, ">= 0")
        # Negative down a slope steeper than the rolling resistance: the bicycle speeds up.
        _check("deceleration", self.deceleration, lambda x: True, "in m/s^2")
        if self.duration is not None:
            _check("duration", self.duration, lambda x: x > 0, "positive")
        if self.push_signs not in PUSH_SIGNS:
            raise ScenarioError(f"push_signs must be one of {', '.join(PUSH_SIGNS)}, got {self.push_signs!r}")
        for name in ("push_spread", "coast_spread"):
            _check(name, getattr(self, name), lambda x: 0 <= x < 1, "in [0, 1)")
        self._check_disturbance()
        if self.setting not in SETTINGS:
            raise ScenarioError(f"setting must be one of {', '.join(SETTINGS)}, "
                                f"got {self.setting!r}")
        if self.n_pushes is not None and (not isinstance(self.n_pushes, int)
                                          or self.n_pushes < 1):
            raise ScenarioError(f"n_pushes must be a positive integer, got {self.n_pushes!r}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ScenarioError(f"seed must be a non-negative integer, got {self.seed!r}")
        if not isinstance(self.pulses_per_revolution, int) or self.pulses_per_revolution < 2:
            raise ScenarioError("pulses_per_revolution must be an integer >= 2, "
                                f"got {self.pulses_per_revolution!r}")
        unknown = [name for name in self.columns if name not in SIGNALS]
        if unknown or "roll_rate" not in self.columns or len(set(self.columns)) < len(
                self.columns):
            raise ScenarioError(f"columns must be distinct names from {', '.join(SIGNALS)} "
                                f"including roll_rate, got {', '.join(self.columns)}")
        for name in SIGNALS:
            sensor = getattr(self.sensors, name)
            _check(f"{name} noise", sensor.noise, lambda x: x >= 0, ">= 0")
            _check(f"{name} bias", sensor.bias, lambda x: True, "finite")
        if self.setting != "ground" and self.drag != 0:
            raise ScenarioError(f"drag applies to the ground setting only, got {self.drag!r} 1/m on a "
                                f"{self.setting}")
        if not isinstance(self.faults, SensorFaults):
            raise ScenarioError(f"faults must be SensorFaults, got {type(self.faults).__name__}")
        if self.setting == "ground" and not {"speed", "speedometer"} & set(self.columns):
            raise ScenarioError("a ground run needs a speed or speedometer column (its speed "
                                "is not constant)")
        if self.pushes is not None and self.n_pushes is not None:
            raise ScenarioError("give pushes or n_pushes, not both")
        if self.pushes is not None:
            object.__setattr__(self, "pushes", tuple(self.pushes))
            self._check_pushes(self.pushes)
        self._check_size()
        end = self.end_time()
        if self.setting == "ground" and end >= stopping_time(self.speed, self.deceleration, self.drag):
            drag = f" and a drag of {self.drag:g} 1/m" if self.drag else ""
            raise ScenarioError(f"the speed {self.speed:g} m/s decaying by "
                                f"{self.deceleration:g} m/s^2{drag} reaches 0 before the end "
                                f"of the run ({end:.3g} s)")
        self._check_readable(end)

    def _check_disturbance(self) -> None:
        if not isinstance(self.disturbance, tuple | list) or len(self.disturbance) != 2:
            raise ScenarioError(f"disturbance must be two torques (roll, steer) [N m], got {self.disturbance!r}")
        object.__setattr__(self, "disturbance", tuple(self.disturbance))
        for name, value in zip(("roll disturbance", "steer disturbance"), self.disturbance, strict=True):
            _check(name, value, lambda x: x >= 0, ">= 0")
        _check("disturbance_band", self.disturbance_band, lambda x: 0 < x < self.sample_rate / 2,
               "positive and below half the sample rate")

    def _check_readable(self, end: float) -> None:
        """Refuse a run that whipple's reader would refuse (:mod:`whipple.simulation.run_limits`)."""
        if self.sample_rate < MIN_SAMPLE_RATE:
            raise ScenarioError(f"sample rate {self.sample_rate:g} Hz is below {MIN_SAMPLE_RATE:g} Hz, the lowest a "
                                "run is read at: too slow to resolve the weave")
        if end < MIN_DURATION:
            raise ScenarioError(f"the run would last {end:.3g} s; a run is read from {MIN_DURATION:g} s on")
        sensor = self.sensors.speed if "speed" in self.columns else Sensor()
        final = (float(coasting_speed(self.speed, self.deceleration, self.drag, end)) if self.setting == "ground"
                 else self.speed)
        lowest = min(final, self.speed) + sensor.bias
        if not (lowest > 0 and sensor.noise <= MAX_SPEED_NOISE_SHARE * lowest):
            raise ScenarioError(f"the speed sensor's noise ({sensor.noise:.3g} m/s standard deviation, bias "
                                f"{sensor.bias:.3g} m/s) would write negative speeds: it must stay below "
                                f"{MAX_SPEED_NOISE_SHARE:g} of the lowest speed ({lowest:.3g} m/s)")
        highest = max(final, self.speed) + sensor.bias + 10 * sensor.noise
        if highest > MAX_RUN_SPEED:
            raise ScenarioError(f"speeds up to {highest:.9g} m/s would be written (with the sensor's noise and bias); "
                                f"a run is read up to {MAX_RUN_SPEED:g} m/s, faster than any bicycle rides")

    def _check_pushes(self, pushes: tuple[Push, ...]) -> None:
        if not pushes:
            raise ScenarioError("pushes must not be empty (use None for automatic pushes)")
        for push in pushes:
            _check("push time", push.time, lambda x: x >= self.release, f">= release "
                   f"({self.release:g} s)")
            _check("push duration", push.duration, lambda x: x > 0, "positive")
            _check("push steer_impulse", push.steer_impulse, lambda x: True, "finite")
            if push.roll_impulse is not None:
                _check("push roll_impulse", push.roll_impulse, lambda x: True, "finite")
        for first, second in zip(pushes, pushes[1:], strict=False):
            if second.time - self.settle <= first.time + first.duration:
                raise ScenarioError(
                    f"push at {second.time:g} s leaves no coasting after the push at "
                    f"{first.time:g} s (needs a gap > push duration + settle "
                    f"= {first.duration + self.settle:g} s)")

    def _check_size(self) -> None:
        """Refuse, before anything is allocated, a run of more than MAX_SAMPLES samples."""
        if self.duration is not None:
            end = self.duration
        elif self.pushes is not None:
            end = self.pushes[-1].time + self.pushes[-1].duration + self.max_coast + self.catch_duration
        else:
            count = self.n_pushes or 3
            end = self.release + count * self.push_spacing + self.max_coast
        samples = end * self.sample_rate
        if samples > MAX_SAMPLES:
            raise ScenarioError(f"the run would have {samples:.3g} samples ({end:.4g} s at {self.sample_rate:g} Hz); "
                                f"at most {MAX_SAMPLES:g} are simulated (about {MAX_SAMPLES_MEMORY})")

    @property
    def push_spacing(self) -> float:
        """Time between automatic pushes [s]."""
        return self.push_duration + self.max_coast + self.catch_duration + self.settle

    def resolved_pushes(self) -> tuple[Push, ...]:
        """Return the pushes of the run (automatic ones with ``roll_impulse=None``)."""
        if self.pushes is not None:
            return self.pushes
        count = self.n_pushes
        if count is None:
            if self.duration is None:
                count = 3
            else:
                room = self.duration - self.release - self.push_duration - self.max_coast
                count = max(1, int(math.floor(room / self.push_spacing + 1e-9)) + 1)
        # Rounded to 1 ns so that e.g. 1.0 + 6.4 gives 7.4, not 7.3999999999999995.
        return tuple(Push(round(self.release + i * self.push_spacing, 9), None, 0.0,
                          self.push_duration) for i in range(count))

    def end_time(self) -> float:
        """Time of the last sample's bound: ``duration`` or the automatic length [s]."""
        pushes = self.resolved_pushes()
        last = pushes[-1]
        if self.duration is None:
            return last.time + last.duration + self.max_coast + self.catch_duration + 0.5
        if last.time + last.duration >= self.duration:
            raise ScenarioError(f"push at {last.time:g} s does not end before the end of the "
                                f"run ({self.duration:g} s)")
        return self.duration

    def true_speed(self, t: ArrayLike) -> NDArray[np.float64]:
        """Return the true forward speed [m/s] at times ``t`` [s]: constant, or coasting on the ground."""
        if self.setting == "ground":
            return coasting_speed(self.speed, self.deceleration, self.drag, t)
        return np.full(np.shape(t), float(self.speed))

    def distance_rolled(self, t: ArrayLike) -> NDArray[np.float64]:
        """Return the distance rolled since t = 0 [m] at times ``t`` [s] (exact integral of the speed)."""
        if self.setting == "ground":
            return coasting_distance(self.speed, self.deceleration, self.drag, t)
        return self.speed * np.asarray(t, dtype=float)

    def replace(self, **changes: object) -> RunScenario:
        """Return a copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)  # type: ignore[arg-type]

