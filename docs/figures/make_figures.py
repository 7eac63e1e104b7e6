"""Write the figures of docs/stability.md into docs/figures/ and print the numbers they show.

Run from anywhere:  python docs/figures/make_figures.py

Figures:

- stability_<bicycle>.png for the built-in bicycles benchmark, kooijman2008 and sbw2024:
  eigenvalues against speed (whipple.stability.plots.plot_eigenvalues) with the crossings
  found by whipple.stability.critical.critical_speeds, as `whipple stability --plot` draws them.
- conditions_benchmark.png: the two scalar stability conditions of the benchmark bicycle over
  speed (the Hopf condition prod_(i<j) (lambda_i + lambda_j) and det A), each taken to the
  root of its degree so that both are in 1/s and keep their sign.
- uncertainty_kooijman2008.png: critical speeds of docs/examples/kooijman2008-uncertain.toml
  for Monte Carlo samples of its [uncertainty] table, against the normal distribution with the
  first-order standard deviation that `whipple check` reports.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from whipple.atomic import atomic_path  # noqa: E402
from whipple.model.assembly import build_linear_model, linear_model  # noqa: E402
from whipple.model.parameters import PARAMETER_UNITS, load_bicycle  # noqa: E402
from whipple.stability.characteristic import hopf_condition, real_condition  # noqa: E402
from whipple.stability.critical import critical_speeds, critical_speeds_batch  # noqa: E402
from whipple.stability.eigen import eigen_analysis  # noqa: E402
from whipple.stability.plots import plot_eigenvalues  # noqa: E402
from whipple.stability.report import analyse_bicycle  # noqa: E402

HERE = Path(__file__).resolve().parent
EXAMPLE = HERE.parent / "examples" / "kooijman2008-uncertain.toml"
SPEEDS = np.linspace(0.0, 10.0, 1001)  # m/s, as `whipple stability` (default --points)
DPI = 150
#: Monte Carlo samples and seed for the uncertainty figure.
SAMPLES, SEED = 4000, 20240607
#: Grid step [m/s] for the Monte Carlo critical speeds (roots are still solved exactly).
SAMPLE_STEP = 0.05


def save(figure: Figure, name: str) -> None:
    """Write `figure` to HERE/name atomically."""
    with atomic_path(HERE / name) as temporary:
        figure.savefig(temporary, dpi=DPI)
    print(f"wrote {HERE / name}")


def stability_figure(name: str) -> None:
    """Eigenvalues against speed of a built-in bicycle, with its critical speeds."""
    bicycle = load_bicycle(name)
    model = linear_model(bicycle)
    critical = critical_speeds(model, 0.0, 10.0)
    figure = plot_eigenvalues(eigen_analysis(model, SPEEDS), critical, title=name)
    save(figure, f"stability_{name}.png")
    for crossing in critical.crossings:
        print(f"  {name}: {crossing.kind} crossing at {crossing.speed!r} m/s, mode "
              f"{crossing.mode}, {crossing.direction}, eigenvalue {crossing.eigenvalue:.6g}")
    print(f"  {name}: stable speed ranges {critical.stable_speed_ranges}")


def signed_root(values: np.ndarray, degree: int) -> np.ndarray:
    """sign(x) |x|^(1/degree): a condition of degree `degree` in the eigenvalues, in 1/s."""
    return np.sign(values) * np.abs(values) ** (1.0 / degree)


def conditions_figure() -> None:
    """The Hopf and real conditions of the benchmark bicycle over speed, with their roots."""
    model = linear_model(load_bicycle("benchmark"))
    speeds = np.linspace(0.0, 10.0, 2001)
    eigenvalues = np.linalg.eigvals(model.state_matrix(speeds))
    n = eigenvalues.shape[-1]
    hopf = signed_root(hopf_condition(eigenvalues), n * (n - 1) // 2)
    real = signed_root(real_condition(eigenvalues), n)
    critical = critical_speeds(model, 0.0, 10.0)

    figure = Figure(figsize=(11.0, 4.2))
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    axes.plot(speeds, hopf, color="tab:blue", lw=1.8,
              label=r"Hopf: sign$(H)\,|H|^{1/6}$, $H=\prod_{i<j}(\lambda_i+\lambda_j)$")
    axes.plot(speeds, real, color="tab:red", lw=1.8,
              label=r"real: sign$(d)\,|d|^{1/4}$, $d=\det A=\prod_i\lambda_i$")
    axes.axhline(0.0, color="black", lw=0.6)
    for crossing in critical.crossings:
        colour = "tab:blue" if crossing.kind == "hopf" else "tab:red"
        axes.axvline(crossing.speed, color=colour, lw=0.9, ls="-.")
        axes.annotate(f"{crossing.mode} {crossing.speed:.3f} m/s", xy=(crossing.speed, 1.0),
                      xycoords=("data", "axes fraction"), xytext=(3, -12),
                      textcoords="offset points", fontsize=8, rotation=90, va="top")
    axes.plot([0.0], [0.0], "o", mfc="none", color="tab:blue",
              label="Hopf zero at v = 0: real pair of opposite sign (rejected)")
    axes.set_xlim(speeds[0], speeds[-1])
    axes.set_xlabel("forward speed v [m/s]")
    axes.set_ylabel("condition, root-scaled [1/s]")
    axes.set_title("benchmark: stability conditions over speed")
    axes.grid(alpha=0.3)
    axes.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    figure.tight_layout()
    save(figure, "conditions_benchmark.png")


def uncertainty_figure() -> None:
    """Monte Carlo critical speeds of the example file against the first-order result."""
    bicycle = load_bicycle(EXAMPLE)
    report = analyse_bicycle(bicycle)
    nominal = {"weave": report.critical.weave_speed, "capsize": report.critical.capsize_speed}

    rng = np.random.default_rng(SEED)
    parameters = {key: np.full(SAMPLES, value) for key, value in bicycle.parameters.items()}
    for key, std in bicycle.uncertainty.items():
        parameters[key] = bicycle.parameters[key] + std * rng.standard_normal(SAMPLES)
    model = build_linear_model(parameters, bicycle.extensions, bicycle.controller)
    results = critical_speeds_batch(model, 0.0, 10.0, step=SAMPLE_STEP)
    sampled = {
        "weave": np.array([r.weave_speed for r in results], dtype=float),
        "capsize": np.array([r.capsize_speed for r in results], dtype=float),
    }

    figure = Figure(figsize=(9.0, 3.8))
    FigureCanvasAgg(figure)
    uncertain = ", ".join(f"{k} ± {v:g} {PARAMETER_UNITS[k]}" for k, v in bicycle.uncertainty.items())
    print(f"  Monte Carlo: {SAMPLES} samples of {uncertain} (seed {SEED})")
    for index, kind in enumerate(("weave", "capsize")):
        speeds = sampled[kind]
        missing = int(np.sum(~np.isfinite(speeds)))
        speeds = speeds[np.isfinite(speeds)]
        centre, std = nominal[kind], report.speed_std[kind]
        assert centre is not None and std is not None
        mc_std = float(np.std(speeds, ddof=1))
        # Standard error of a sample standard deviation (normal samples): std / sqrt(2 (N-1)).
        relative_error = 1.0 / np.sqrt(2.0 * (speeds.size - 1))
        print(f"  {kind}: speed {centre!r} m/s, first-order std {std:.6g} m/s; Monte Carlo "
              f"mean {np.mean(speeds):.6g} m/s, std {mc_std:.6g} m/s "
              f"(ratio {mc_std / std:.4f}, sampling error of the std ±{relative_error:.1%}); "
              f"{missing} samples without a {kind} speed")
        axes = figure.add_subplot(1, 2, index + 1)
        axes.hist(speeds, bins=50, density=True, color="0.75", label=f"Monte Carlo, N = {speeds.size}")
        grid = np.linspace(centre - 4 * std, centre + 4 * std, 400)
        axes.plot(grid, np.exp(-0.5 * ((grid - centre) / std) ** 2) / (std * np.sqrt(2 * np.pi)),
                  color="tab:blue" if kind == "weave" else "tab:red", lw=1.8,
                  label=f"first order: {centre:.4f} ± {std:.2g} m/s")
        axes.set_xlabel(f"{kind} speed [m/s]")
        axes.set_ylabel("probability density [s/m]")
        axes.legend(fontsize=8, loc="upper left")
        axes.grid(alpha=0.3)
    figure.suptitle(f"{bicycle.name}: {uncertain}", fontsize=10)
    figure.tight_layout()
    save(figure, "uncertainty_kooijman2008.png")


def main() -> None:
    for name in ("benchmark", "kooijman2008", "sbw2024"):
        stability_figure(name)
    conditions_figure()
    uncertainty_figure()


if __name__ == "__main__":
    main()
