"""Write the figures of docs/measured-runs.md into docs/figures/ and print the numbers they show.

Run from anywhere:  python docs/figures/make_run_figures.py

Figures (the bundled treadmill runs of the steer-by-wire bicycle, model ``sbw2024``):

- runs_signals.png: seed Figure 4, the signals of the 16.2 km/h run over 30 s with the free
  coasting windows found automatically (whipple.measurement.plots.plot_run).
- runs_fit.png: seed Figure 5, the fit of the first window of that run, with the speed and its
  regression (plot_weave_fit).
- runs_eigenvalues.png: seed Figure 6, every usable window of the five runs, found
  automatically and measured as ``whipple fit --bundled --bicycle sbw2024`` and ``whipple
  diagnose`` measure them (:func:`whipple.measurement.measure.measure_runs`), as a bar over its
  speed range on the eigenvalues of the sbw2024 model (plot_measured_eigenvalues).
- runs_windows.png: roll rate of each run over 40 s, automatic windows shaded, the windows
  picked by hand drawn as bars above the trace.
- runs_simulated.png: a simulated run of the benchmark bicycle on the ground (500 Hz, raw
  speedometer signal) with its true coasting windows and the automatic ones.
- runs_calibration.png: fitted eigenvalue errors divided by the reported standard deviation
  over many noise draws, for white and for autocorrelated noise, with the white-noise and the
  automatic (Newey-West when needed) covariance.

It also prints how the automatic windows and the fit do on simulated benchmark runs at
unstable and stable speeds (the numbers of the "Known limitations" section).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from whipple.atomic import atomic_path  # noqa: E402
from whipple.measurement.bundled import bundled_reference_windows, bundled_runs  # noqa: E402
from whipple.measurement.measure import measure_runs  # noqa: E402
from whipple.measurement.plots import plot_measured_eigenvalues, plot_run, plot_weave_fit  # noqa: E402
from whipple.measurement.reference_windows import compare_windows, read_windows  # noqa: E402
from whipple.measurement.runs import (
    read_run,  # noqa: E402
    run_from_simulation,
)
from whipple.measurement.speedometer import speed_regression  # noqa: E402
from whipple.measurement.weavefit import NoOscillationError, fit_weave, fit_window  # noqa: E402
from whipple.measurement.windows import find_windows  # noqa: E402
from whipple.model.assembly import linear_model  # noqa: E402
from whipple.model.parameters import load_bicycle  # noqa: E402
from whipple.simulation.scenario import RunScenario  # noqa: E402
from whipple.simulation.simulator import simulate_run  # noqa: E402
from whipple.stability.critical import critical_speeds  # noqa: E402
from whipple.stability.eigen import eigen_analysis, weave_eigenvalue  # noqa: E402

HERE = Path(__file__).resolve().parent
DPI = 120
#: The run of the Figure 4 and 5 analogues (4.7 m/s, inside the stable speed range), and the
#: 30 s of it shown.
SIGNALS_RUN, SIGNALS_SPAN = 3, (14.0, 44.0)
#: Noise draws and seed of the calibration figure.
DRAWS, SEED = 400, 20090826


def save(figure: Figure, name: str) -> None:
    """Write `figure` to HERE/name atomically."""
    with atomic_path(HERE / name) as temporary:
        figure.savefig(temporary, dpi=DPI)
    print(f"wrote {HERE / name}")


def bundled_figures() -> None:
    """Figures 4, 5, 6 analogues and the window comparison on the bundled runs."""
    bicycle = load_bicycle("sbw2024")
    model = linear_model(bicycle)
    runs = [read_run(entry) for entry in bundled_runs()]
    reference = read_windows(bundled_reference_windows(), runs)
    searches = [find_windows(run) for run in runs]

    run, search = runs[SIGNALS_RUN], searches[SIGNALS_RUN]
    save(plot_run(run, search.windows, rejected=search.rejected, span=SIGNALS_SPAN),
         "runs_signals.png")
    window = search.windows[0]
    fit = fit_window(run, window)
    speed = speed_regression(run.time, run.speed(), window.start, window.stop)
    save(plot_weave_fit(fit, run, speed, title=f"{run.name}, window 1"), "runs_fit.png")
    print(f"runs_fit: {window.start:.2f}-{window.stop:.2f} s, lambda = {fit.eigenvalue:.3f} "
          f"+/- ({fit.eigenvalue_std[0]:.3f}, {fit.eigenvalue_std[1]:.3f}), R^2 "
          f"{fit.r_squared:.3f}, speed {speed.start_speed:.3f} -> {speed.stop_speed:.3f} m/s")

    speeds, fits = run_table(runs, reference, bicycle)
    runs_on = [read_run(entry) for entry in bundled_runs("model-matching-on")]
    run_table(runs_on, read_windows(bundled_reference_windows(), runs_on), load_bicycle("sbw2024-mm"))

    result = eigen_analysis(model, np.linspace(0.0, 10.0, 1001))
    critical = critical_speeds(model, 0.0, 10.0)
    save(plot_measured_eigenvalues(speeds, fits, result, critical,
                                   title="bundled treadmill runs and the sbw2024 model"),
         "runs_eigenvalues.png")
    print(f"runs_eigenvalues: {len(fits)} windows; model weave speed {critical.weave_speed:.3f} "
          f"m/s, capsize speed {critical.capsize_speed:.3f} m/s")
    windows_figure(runs, searches, reference)


def run_table(runs, reference, bicycle) -> tuple[list, list]:
    """Print each run's windows against the reference ones; return the usable windows' speeds and fits.

    Measured as `whipple fit --bundled --bicycle ...` measures (roll rate and steer angle
    jointly, the quality checks): the one measurement of fit and diagnose.
    """
    model = linear_model(bicycle)
    measured = measure_runs(runs, bicycle=bicycle)
    on_reference = measure_runs(runs, windows=reference, bicycle=bicycle)
    print(f"\nrun ({measured.describe()}): reference windows matched / reference, windows found "
          "automatically: listed, fitted, usable; median of the usable automatic windows, of the fitted "
          "reference windows, and model weave [1/s] (how the automatic windows match the reference "
          "ones: `whipple fit --bundled`)")
    speeds, fits = [], []
    for run_measured, run_reference in zip(measured, on_reference, strict=True):
        run = run_measured.run
        mine = [w for w in reference if w.run == run.name]
        comparison = compare_windows(run_measured.search.windows, mine)
        usable = [m for m in run_measured if m.usable]
        fits += [m.fit for m in usable]
        speeds += [m.speed for m in usable]
        measured_values = np.array([m.fit.eigenvalue for m in usable])
        # The hand-picked windows are the authors' choice: every one fitted counts, usable or not.
        reference_values = np.array([m.fit.eigenvalue for m in run_reference.fitted])
        mean_speed = np.mean([m.speed.mean for m in usable])
        predicted = complex(weave_eigenvalue(model, [mean_speed])[0])
        print(f"  {run.name}: {comparison.matched}/{len(mine)}, {len(run_measured)} listed, "
              f"{len(run_measured.fitted)} fitted, {len(usable)} usable; "
              f"v {mean_speed:.2f} m/s; median automatic "
              f"{np.median(measured_values.real):+.2f}{np.median(measured_values.imag):+.2f}i, median on the "
              f"reference windows {np.median(reference_values.real):+.2f}"
              f"{np.median(reference_values.imag):+.2f}i, model {predicted.real:+.2f}"
              f"{predicted.imag:+.2f}i")
    return speeds, fits


def windows_figure(runs, searches, reference) -> None:
    """Roll rate of each bundled run over 40 s: automatic windows and hand-picked ones."""
    figure = Figure(figsize=(10, 9), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(len(runs), 1)
    for axis, run, search in zip(axes, runs, searches, strict=True):
        mine = [w for w in reference if w.run == run.name]
        begin = min(w.start for w in mine) - 2.0
        shown = (run.time >= begin) & (run.time <= begin + 40.0)
        axis.plot(run.time[shown], run.signals["roll_rate"][shown], color="k", linewidth=0.6)
        for window in search.windows:
            axis.axvspan(window.start, window.stop, color="tab:green", alpha=0.3, linewidth=0)
        top = float(np.max(np.abs(run.signals["roll_rate"][shown])))
        for window in mine:
            axis.plot([window.start, window.stop], [1.1 * top] * 2, color="tab:orange",
                      linewidth=4, solid_capstyle="butt")
        axis.set_xlim(begin, begin + 40.0)
        axis.set_ylim(-1.2 * top, 1.25 * top)
        speed = float(np.median(run.speed()))
        axis.set_ylabel(f"roll rate [rad/s]\n{speed:.2f} m/s", fontsize=8)
    axes[0].set_title("green: windows found automatically; orange bars: windows picked by hand "
                      "(reference_windows.csv)", fontsize=9)
    axes[-1].set_xlabel("time [s]")
    save(figure, "runs_windows.png")


def simulated_figure() -> None:
    """A simulated ground run with a speedometer: true and automatic windows."""
    bicycle = load_bicycle("benchmark")
    scenario = RunScenario(speed=5.0, setting="ground", sample_rate=500.0, seed=0,
                           columns=("roll_rate", "yaw_rate", "steer_angle", "speedometer"))
    simulated = simulate_run(bicycle, scenario)
    run = run_from_simulation(simulated)
    search = find_windows(run)
    figure = plot_run(run, search.windows, rejected=search.rejected)
    axis = figure.axes[1]
    top = axis.get_ylim()[1]
    for start, stop in simulated.segments:
        axis.plot([start, stop], [0.9 * top] * 2, color="tab:orange", linewidth=4,
                  solid_capstyle="butt")
    axis.set_title("orange bars: true free-coasting windows of the simulation", fontsize=8)
    save(figure, "runs_simulated.png")
    model = linear_model(bicycle)
    staircase = run.speed()
    print("\nsimulated ground run (benchmark, 5 m/s, 0.05 m/s^2, 500 Hz, speedometer):")
    print("  true windows: " + ", ".join(f"{a:.2f}-{b:.2f}" for a, b in simulated.segments))
    for window in search.windows:
        speed = speed_regression(run.time, staircase, window.start, window.stop)
        centre = 0.5 * (window.start + window.stop)
        truth = float(np.interp(centre, simulated.time, simulated.speed))
        fit = fit_window(run, window)
        predicted = complex(weave_eigenvalue(model, [speed.mean])[0])
        print(f"  automatic {window.start:.2f}-{window.stop:.2f} s ({window.reason}): speed "
              f"{speed.mean:.4f} m/s (true {truth:.4f}, error {100 * (speed.mean / truth - 1):+.3f}"
              f" %), lambda {fit.eigenvalue:.3f}, model {predicted:.3f}")


def calibration_figure() -> None:
    """z-scores of the fitted eigenvalue for white and AR(1) noise, white and auto covariance."""
    rng = np.random.default_rng(SEED)
    d, w, fs, duration, sigma = -1.32, 5.96, 100.0, 1.6, 0.02  # the seed's run 1202
    t = np.arange(0.0, duration, 1.0 / fs)
    clean = 0.05 + np.exp(d * t) * (0.5 * np.cos(w * t) - 0.2 * np.sin(w * t))

    def ar1(rho: float) -> np.ndarray:
        shocks = sigma * np.sqrt(1 - rho**2) * rng.standard_normal(t.size)
        noise = np.empty(t.size)
        noise[0] = sigma * rng.standard_normal()
        for k in range(1, t.size):
            noise[k] = rho * noise[k - 1] + shocks[k]
        return noise

    figure = Figure(figsize=(10, 6.5), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(2, 2, sharex=True)
    bins = np.linspace(-6, 6, 49)
    grid = np.linspace(-6, 6, 241)
    normal = np.exp(-0.5 * grid**2) / np.sqrt(2 * np.pi)
    print(f"\ncalibration: lambda = {d} + {w}i, {t.size} samples at {fs:g} Hz, sigma {sigma}, "
          f"{DRAWS} draws; share of |error| < 2 std (d, w):")
    for row, (label, rho) in enumerate((("white noise", 0.0), ("AR(1) noise, ρ = 0.8", 0.8))):
        values = [clean + (ar1(rho) if rho else sigma * rng.standard_normal(t.size))
                  for _ in range(DRAWS)]
        for column, noise in enumerate(("white", "auto")):
            fits = [fit_weave(t, y, noise=noise) for y in values]
            error = np.array([(f.damping - d, f.frequency - w) for f in fits])
            std = np.array([f.eigenvalue_std for f in fits])
            z = error / std
            coverage = (np.abs(z) < 2).mean(axis=0)
            axis = axes[row, column]
            # Beyond +/- 6 the values are piled into the outer bins.
            shown = np.clip(z, bins[0] + 1e-9, bins[-1] - 1e-9)
            axis.hist(shown[:, 0], bins=bins, density=True, alpha=0.5, label="real part d")
            axis.hist(shown[:, 1], bins=bins, density=True, alpha=0.5, label="imaginary part w")
            axis.plot(grid, normal, color="k", linewidth=1, label="N(0, 1)")
            covariance = "white-noise covariance" if noise == "white" else "automatic covariance"
            axis.set_title(f"{label}, {covariance}\nwithin 2σ: {100 * coverage[0]:.1f} % (d), "
                           f"{100 * coverage[1]:.1f} % (w)", fontsize=9)
            print(f"  {label}, noise={noise}: {coverage[0]:.3f}, {coverage[1]:.3f}; spread of z "
                  f"{z[:, 0].std():.2f}, {z[:, 1].std():.2f}")
    axes[0, 0].legend(fontsize=8)
    for axis in axes[1]:
        axis.set_xlabel("(fitted - true) / reported standard deviation")
    save(figure, "runs_calibration.png")


def simulated_bias() -> None:
    """Automatic windows on simulated benchmark runs: found, and the fit's error.

    Prints, per speed, how many of the true coasting windows an automatic window matches and,
    for the constant (seed) and quadratic baselines, the median error of the fitted eigenvalue
    relative to the model's |lambda| and in units of the reported standard deviation.
    """
    from whipple.measurement.reference_windows import compare_windows
    from whipple.measurement.windows import Window

    bicycle = load_bicycle("benchmark")
    model = linear_model(bicycle)
    print("\nsimulated benchmark treadmill runs, 100 Hz, 3 pushes, seeds 0-4 (weave speed "
          f"{critical_speeds(model).weave_speed:.2f} m/s):")
    for speed in (3.0, 4.0, 4.5, 5.0, 6.0):
        truth = complex(weave_eigenvalue(model, [speed])[0])
        found = total = 0
        errors: dict[str, list[tuple[float, float, float]]] = {"constant": [], "quadratic": []}
        on_true: list[complex] = []
        for seed in range(5):
            simulated = simulate_run(bicycle, RunScenario(speed=speed, seed=seed))
            run = run_from_simulation(simulated)
            search = find_windows(run)
            true = [Window(run.name, a, b, -1, -1) for a, b in simulated.segments]
            comparison = compare_windows(search.windows, true)
            found, total = found + comparison.matched, total + len(true)
            for window in true:
                try:
                    on_true.append(fit_window(run, window).eigenvalue)
                except NoOscillationError:
                    pass
            for window in search.windows:
                for baseline, rows in errors.items():
                    try:
                        fit = fit_window(run, window, baseline=baseline)
                    except NoOscillationError:
                        continue
                    error = fit.eigenvalue - truth
                    rows.append((abs(error) / abs(truth), abs(error.real) / fit.eigenvalue_std[0],
                                 abs(error.imag) / fit.eigenvalue_std[1]))
        text = f"  {speed:.1f} m/s, model {truth.real:+.2f}{truth.imag:+.2f}i: {found} of {total} true windows found"
        if on_true:
            values = np.array(on_true)
            text += (f"; fitted on the true windows: median {np.median(values.real):+.2f}"
                     f"{np.median(values.imag):+.2f}i")
        print(text)
        for baseline, rows in errors.items():
            if rows:
                table = np.array(rows)
                print(f"    automatic windows, {baseline} baseline ({len(rows)} fits): median "
                      f"|error|/|lambda| {100 * np.median(table[:, 0]):.1f} % (max "
                      f"{100 * table[:, 0].max():.1f} %), median |error|/std d "
                      f"{np.median(table[:, 1]):.1f}, w {np.median(table[:, 2]):.1f}")


if __name__ == "__main__":
    bundled_figures()
    simulated_figure()
    simulated_bias()
    calibration_figure()
