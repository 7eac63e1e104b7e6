"""The choices a diagnosis makes, in one object: :class:`DiagnosisOptions`.

Every choice of :func:`whipple.diagnose` (and ``whipple diagnose``) is a field here, with the
reason for its default; the report records the options it ran with
(:attr:`whipple.diagnosis.report.DiagnosisReport.options`). Change a choice by passing other
options, e.g. ``DiagnosisOptions(comparison="eigenvalues", verdict=VerdictRules(margin=3.0))``;
nothing in the package changes behaviour through module constants.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from whipple.diagnosis.causes import Cause
from whipple.diagnosis.fitting import COMPARISONS
from whipple.diagnosis.instrument import InstrumentErrors
from whipple.diagnosis.model_terms import term_causes
from whipple.diagnosis.registry import CauseDeclaration, candidate_causes
from whipple.errors import InputError
from whipple.measurement.measure import MeasurementOptions
from whipple.model.fleet import Model

__all__ = ["OCCAM_CHARGES", "FIXED_POINT_STARTS", "GAIN_BY_CAUSE", "VerdictRules", "PairRules",
           "DiagnosisOptions"]

#: How the evidence charges a cause's fitted values (:attr:`DiagnosisOptions.occam`).
OCCAM_CHARGES = ("bic", "laplace", "prior")
#: Where the fitting bias' fixed point starts (:attr:`DiagnosisOptions.fixed_point_start`).
FIXED_POINT_STARTS = ("measured", "model")
#: What ``gain_by_cause`` may ask for (:attr:`DiagnosisOptions.gain_by_cause`).
GAIN_BY_CAUSE = ("singles", "pairs")


@dataclass(frozen=True)
class VerdictRules:
    """When the evidence names a cause, says ``ambiguous`` or ``none``.

    Evidence is a natural-log Bayes factor against the base model (see
    :mod:`whipple.diagnosis.evidence`); the defaults are the usual odds of Kass and Raftery's scale.

    Attributes
    ----------
    named_threshold : float
        Evidence a cause needs over the base model to be anything but ``none`` (default 3:
        odds of about 20:1, "strong").
    margin : float
        Evidence by which the best must beat the runner-up to be named (default 2: about 7:1).
    close_evidence : float
        A runner-up within this much evidence whose predictions are within ``separation`` of the
        best's makes the verdict ambiguous (default 5): a prior or one more fitted value is then
        all that ranks them.
    separation : float
        Half the summed squared whitened difference of two fits' predictions below which the data
        could not single out one of them even if it were true (default 2: odds below e^2).
    high_dispersion : float
        Median dispersion of the leading model above which the verdict is never a confident name
        (default 5: the typical window more than 2.2 standard deviations off; in simulated trials
        with realistic noise the true cause left up to about 3).
    speed_dependence : float
        Evidence for values that differ between the low and the high speeds above which a
        leading cause is not named: its form does not follow how the error changes with speed
        (default 2, the margin's odds).
    null_distance : float
        A leading cause of one value that lies no more than this many of its standard
        deviations from the value at which it changes nothing (:attr:`Cause.null
        <whipple.diagnosis.causes.Cause>`; the spread of the value refitted with the windows of
        each speed left out in turn, :func:`~whipple.diagnosis.consistency.jackknife_std`,
        included) is no cause: the verdict is ``none`` whatever its evidence (default 2).
        Causes of several values are not held to it: each value's own spread says little where
        values trade off (a load's mass and position; tried with the mass alone, 10 of 18
        treadmill trials led by a true load lost their verdict). The evidence counts
        the windows as independent; an error the windows of one speed share, or one window's
        defect, can give a cause evidence that its values, refitted without that speed, do not
        bear out (a ground trial sampled at 500 Hz: a speed scale of 1.0012 +/- 0.011 led with
        evidence 13.5, carried by one window whose measured speed was 0.08 % off).
    one_speed_lead : float
        Evidence by which a cause named must still lead every rival once the share of its lead
        that the windows of any one speed give is taken away (default 2, the margin's odds;
        0: not checked). The evidence sums over windows; a lead that one speed's windows carry
        (one window's defect, a catch, an effect that only there parts two models) is not the
        data's as a whole: the verdict is then ``ambiguous`` with that rival. Each speed's
        share is its part of the two fits' chi-square difference, at the values fitted to
        every window. (A twice-size steer spring: a front payload led the steer spring's own
        form, the K0 steer-steer term at its true value, by 38.5, of which the one window at
        3 m/s gave 40.2.)
    """

    named_threshold: float = 3.0
    margin: float = 2.0
    close_evidence: float = 5.0
    separation: float = 2.0
    high_dispersion: float = 5.0
    speed_dependence: float = 2.0
    null_distance: float = 2.0
    one_speed_lead: float = 2.0

    def __post_init__(self) -> None:
        for name in ("named_threshold", "margin", "close_evidence", "separation", "high_dispersion",
                     "speed_dependence", "null_distance", "one_speed_lead"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and 0.0 <= value < 1e6):
                raise InputError(f"verdict rule {name} must be a number from 0 to 1e6, got {value!r}")


@dataclass(frozen=True)
class PairRules:
    """When and which pairs of causes are fitted jointly.

    Attributes
    ----------
    dispersion : float
        Median dispersion of the best single cause above which pairs are tried (default 2: the
        typical window 1.4 standard deviations off; 0 tries them always).
    flexible_values : int
        A leading single cause with at least this many fitted values (a payload's mass and
        position) could stand in for two effects together: pairs are then tried even when it
        fits (default 3; in 150 two-effect trials such a payload was the wrong name in 20 of 21
        wrong verdicts until pairs were tried).
    leading : int
        How many leading single causes are tried in pairs (default 3: 3 pairs).
    screened : int
        How many more pairs, the best by a screen of all pairs linearised at the base model
        (default 3: the true pair is often not among the leading singles).
    screened_away : int
        How many more again, the best by a screen linearised away from the base model (default 3:
        a payload's position does nothing at zero mass, so only this screen can move it).
    """

    dispersion: float = 2.0
    flexible_values: int = 3
    leading: int = 3
    screened: int = 3
    screened_away: int = 3

    def __post_init__(self) -> None:
        if not (isinstance(self.dispersion, int | float) and 0.0 <= self.dispersion < 1e6):
            raise InputError(f"pair rule dispersion must be a number from 0 to 1e6, got {self.dispersion!r}")
        for name in ("flexible_values", "leading", "screened", "screened_away"):
            value = getattr(self, name)
            if not (isinstance(value, int) and 0 <= value <= 100):
                raise InputError(f"pair rule {name} must be a whole number from 0 to 100, got {value!r}")


@dataclass(frozen=True)
class DiagnosisOptions:
    """Every choice of a diagnosis, each with the reason for its default.

    Attributes
    ----------
    measurement : MeasurementOptions
        How the runs become weave eigenvalues: the one measurement ``whipple fit`` shares
        (:class:`~whipple.measurement.measure.MeasurementOptions`).
    comparison : {"samples", "fitting-function", "eigenvalues"}
        How each model is compared with the windows. ``"samples"`` (default): its own free
        response, every mode of it, fitted to each window's samples, so that no fitting function
        stands between model and data (it named more hidden effects right than the others,
        docs/diagnosis.md); ``"fitting-function"``: its weave eigenvalue plus the bias the
        seed paper's fitting function shows on the model's own response; ``"eigenvalues"``:
        its weave eigenvalue directly (fastest).
    parameters : bool
        Consider one wrong benchmark parameter as a cause (default True: the inertias and the
        trail are often estimated rather than measured).
    model_terms : bool
        Let model terms (an entry added to C1, D, K0 or K2) compete (default True: when the truth
        is none of the physical candidates, a term of its form turns a confident wrong name into
        "the error has the form of ...").
    rigid_loads : bool
        Include the payloads' rigid-load form, a load with its own radii of gyration (default
        True: it named rack loads right more often).
    causes : tuple of CauseDeclaration
        More candidate causes, declared as :mod:`whipple.diagnosis.registry` describes (default
        none: the package's own registry is always used).
    verdict : VerdictRules
        When a cause is named (:class:`VerdictRules`).
    pairs : PairRules
        When and which pairs of causes are fitted (:class:`PairRules`).
    occam : {"bic", "prior", "laplace"}
        How the evidence charges fitted values. ``"bic"`` (default): ln(n)/2 per fitted value.
        ``"prior"``: the Laplace approximation of the marginal likelihood under each value's
        prior, a measured parameter's uncertainty or a cause's documented physical range
        (:mod:`whipple.diagnosis.priors`), so that a value pressed against a bound pays what it
        should; the calibration candidate (every measured parameter within its prior) competes
        only in this mode. Not the default: on the benchmark bicycle the calibration took the
        name from a hidden tyre compliance in 4 of 6 trials (measured when the tyre model still
        paid for its fast modes' amplitudes in every window). ``"laplace"``: the share of a cause's
        bounds its fit leaves open.
    samples_screen : float
        Evidence (times the dispersion) by which a cause may trail the best and still be
        refitted to the samples (default 50: further behind it is evaluated at its fit to the
        eigenvalues; a comparison with the samples costs several times one with eigenvalues).
    bias_screen : float
        The same for the fitting-function comparison (default 100: twice the most the bias moved
        a cause against the leader on 40 runs with a rack load).
    fixed_point_start : {"measured", "model"}
        Where the fitting bias' fixed point starts: the window's measured eigenvalue (default) or
        the model's.
    held_out_gain : bool
        Measure the extended model's gain on whole speeds it never saw (default True; the
        hidden-effect trials turn it off: only the verdict is scored there).
    gain_by_cause : {None, "singles", "pairs"}
        Also every candidate's held-out gain, refitted on every fold without a choice, and the
        gain of choosing by prediction (default None: many times the cost of a diagnosis).
    prediction_shortlist : int
        Where no candidate explains the data (the typical window's dispersion above
        ``verdict.high_dispersion``) and the windows span three speeds or more, the model offered
        is chosen among this many best-supported physically consistent candidates by how well
        each, refitted without it, predicts every speed left out in turn (default 6; 0: always
        the best-supported consistent candidate). The evidence assumes one candidate is the
        truth; on real bicycles none is, and what a corrected model must do is carry over to
        speeds it never saw (:mod:`whipple.diagnosis.offer`).
    prediction_standard_errors : float
        The one-standard-error rule of that choice: the simplest candidate (fewest fitted values,
        the base model none) whose mean squared error on the left-out speeds exceeds the best
        predictor's by at most this many standard errors of the excess (the speed groups the
        units) is offered (default 1.0; 0: the best predictor, the smallest RMS).
    amplitude_check : bool
        Compare the nonlinear model's weave at each window's measured amplitude with the linear
        one (default True: it says where the linear model is out of its range).
    speed_range : tuple of float
        Speeds [m/s] over which the critical speeds of the base and extended models are searched
        (default 0 to 10).
    instrument : InstrumentErrors or None
        The roll gyro's scale error and the IMU's misalignment, fitted with every model compared
        with the samples (the base model included) as values shared by all windows
        (:mod:`whipple.diagnosis.instrument`); None: the signals are taken as read.
    """

    measurement: MeasurementOptions = field(default_factory=MeasurementOptions)
    comparison: str = "samples"
    parameters: bool = True
    model_terms: bool = True
    rigid_loads: bool = True
    causes: tuple[CauseDeclaration, ...] = ()
    verdict: VerdictRules = field(default_factory=VerdictRules)
    pairs: PairRules = field(default_factory=PairRules)
    occam: str = "bic"
    samples_screen: float = 50.0
    bias_screen: float = 100.0
    fixed_point_start: str = "measured"
    held_out_gain: bool = True
    gain_by_cause: str | None = None
    prediction_shortlist: int = 6
    prediction_standard_errors: float = 1.0
    instrument: InstrumentErrors | None = field(default_factory=InstrumentErrors)
    amplitude_check: bool = True
    speed_range: tuple[float, float] = (0.0, 10.0)

    def __post_init__(self) -> None:
        _choice("comparison", self.comparison, COMPARISONS)
        _choice("occam", self.occam, OCCAM_CHARGES)
        _choice("fixed_point_start", self.fixed_point_start, FIXED_POINT_STARTS)
        if self.gain_by_cause is not None:
            _choice("gain_by_cause", self.gain_by_cause, GAIN_BY_CAUSE)
        for name in ("samples_screen", "bias_screen"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and 0.0 <= value < 1e9):
                raise InputError(f"{name} must be a number from 0 to 1e9, got {value!r}")
        if not (isinstance(self.prediction_shortlist, int) and 0 <= self.prediction_shortlist <= 1000):
            raise InputError("prediction_shortlist must be a whole number from 0 to 1000, "
                             f"got {self.prediction_shortlist!r}")
        value = self.prediction_standard_errors
        if isinstance(value, bool) or not (isinstance(value, int | float) and 0.0 <= value <= 100.0):
            raise InputError(f"prediction_standard_errors must be a number from 0 to 100, got {value!r}")
        low, high = self.speed_range
        if not 0.0 <= low < high < 1e6:
            raise InputError(f"speed_range must hold 0 <= low < high, got {self.speed_range}")
        if not all(isinstance(cause, CauseDeclaration) for cause in self.causes):
            raise InputError("causes must be CauseDeclaration objects (whipple.diagnosis.registry)")
        object.__setattr__(self, "causes", tuple(self.causes))

    def candidates(self, bicycle: Model) -> list[Cause]:
        """Return the candidate causes these options consider for a bicycle.

        Parameters
        ----------
        bicycle : Bicycle
            The base bicycle (the causes' bounds follow it; controller causes need a controller).

        Returns
        -------
        list of Cause
            Every form of every declared cause (the package's and :attr:`causes`), without the
            parameter causes unless :attr:`parameters`, then the model terms no declared cause
            is, if :attr:`model_terms`.
        """
        priors = self.occam == "prior"
        causes = candidate_causes(bicycle, self.parameters, rigid_loads=self.rigid_loads, priors=priors,
                                  extra=self.causes)
        return causes + (term_causes(bicycle, self.causes, priors) if self.model_terms else [])

    def to_dict(self) -> dict[str, Any]:
        """Return the options as JSON-ready data (the report's record of what it ran with)."""
        return {"measurement": self.measurement.to_dict(), "comparison": self.comparison,
                "parameters": self.parameters, "model_terms": self.model_terms, "rigid_loads": self.rigid_loads,
                "causes": [cause.name for cause in self.causes], "verdict": vars(self.verdict).copy(),
                "pairs": vars(self.pairs).copy(), "occam": self.occam,
                "samples_screen": self.samples_screen, "bias_screen": self.bias_screen,
                "fixed_point_start": self.fixed_point_start, "held_out_gain": self.held_out_gain,
                "gain_by_cause": self.gain_by_cause, "prediction_shortlist": self.prediction_shortlist,
                "prediction_standard_errors": self.prediction_standard_errors,
                "amplitude_check": self.amplitude_check,
                "speed_range": list(self.speed_range)}


def _choice(name: str, value: object, allowed: Sequence[str]) -> None:
    if value not in allowed:
        raise InputError(f"{name} must be one of {', '.join(allowed)}, got {value!r}")
