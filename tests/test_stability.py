"""Eigenvalues over speed: whipple.stability.eigen (and the figure of whipple.stability.plots).

Benchmark numbers are published facts: Meijaard, Papadopoulos, Ruina & Schwab (2007),
"Linearized dynamics equations for the balance and steer of a bicycle: a benchmark and
review", Proc. R. Soc. A 463, 1955-1982 — matrices M, C1, K0 (without g), K2 of Appendix A
and the eigenvalues of Table 2, as reproduced in src/whipple/data/reference/meijaard2007-benchmark.toml.
"""

from __future__ import annotations

import io

import numpy as np
import pytest

from whipple.errors import InputError
from whipple.model.linear import LinearModel, second_order_model
from whipple.stability.critical import critical_speeds
from whipple.stability.eigen import eigen_analysis, eigenvalue_table, weave_eigenvalue

G = 9.81
M = [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]]
C1 = [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]]
K0 = [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]
K2 = [[0.0, 76.59734589573222], [0.0, 2.65431523794604]]

# Table 2: eigenvalues [1/s] at v = 0, 1, ..., 10 m/s, as (re, im) pairs; at v >= 1 the
# columns are capsize, weave (two), castering.
TABLE_2 = [
    [(3.13164324790656, 0), (-3.13164324790656, 0), (5.53094371765393, 0),
     (-5.53094371765393, 0)],
    [(-3.13423125066578, 0), (3.52696170990070, 0.8077402751993),
     (3.52696170990070, -0.8077402751993), (-7.11008014637442, 0)],
    [(-3.07158645641514, 0), (2.68234517512745, 1.68066296590675),
     (2.68234517512745, -1.68066296590675), (-8.67387984831735, 0)],
    [(-2.63366137253667, 0), (1.70675605663975, 2.31582447384325),
     (1.70675605663975, -2.31582447384325), (-10.35101467245920, 0)],
    [(-1.42944427361326, 0), (0.41325331521125, 3.07910818603206),
     (0.41325331521125, -3.07910818603206), (-12.15861426576450, 0)],
    [(-0.32286642900409, 0), (-0.77534188219585, 4.46486771378823),
     (-0.77534188219585, -4.46486771378823), (-14.07838969279820, 0)],
    [(-0.00406690076970, 0), (-1.52644486584142, 5.87673060598709),
     (-1.52644486584142, -5.87673060598709), (-16.08537123098030, 0)],
    [(0.10268170574766, 0), (-2.13875644258362, 7.19525913329805),
     (-2.13875644258362, -7.19525913329805), (-18.15788466125262, 0)],
    [(0.14327879765713, 0), (-2.69348683581097, 8.46037971396931),
     (-2.69348683581097, -8.46037971396931), (-20.27940894394569, 0)],
    [(0.15790184030917, 0), (-3.21675402252485, 9.69377351531791),
     (-3.21675402252485, -9.69377351531791), (-22.43788559040858, 0)],
    [(0.16105338653172, 0), (-3.72016840437287, 10.90681139476287),
     (-3.72016840437287, -10.90681139476287), (-24.62459635017404, 0)],
]


def benchmark() -> LinearModel:
    return second_order_model(M, C1, np.array(K0) * G, K2, description="benchmark")


def table_2() -> np.ndarray:
    return np.array([[complex(re, im) for re, im in row] for row in TABLE_2])


def test_table_2_eigenvalues_from_published_matrices() -> None:
    # From the 14-15 digit published matrices the largest difference is 8.6e-13 (v = 7 m/s).
    result = eigen_analysis(benchmark(), np.arange(11.0))
    reference = table_2()
    for ours, published in zip(result.eigenvalues, reference, strict=True):
        distance = np.abs(ours[:, None] - published[None, :])
        assert np.max(np.min(distance, axis=0)) < 1e-12
        assert np.max(np.min(distance, axis=1)) < 1e-12
    # Labels agree with the table's columns from 1 m/s on.
    np.testing.assert_allclose(result.mode("capsize")[1:], reference[1:, 0], atol=1e-12)
    np.testing.assert_allclose(result.mode("weave")[1:], reference[1:, 1], atol=1e-12)
    np.testing.assert_allclose(result.mode("castering")[1:], reference[1:, 3], atol=1e-12)
    # At standstill the two unstable real modes are the ones that will merge into weave.
    assert result.mode("weave_real_upper")[0] == pytest.approx(5.53094371765393, abs=1e-12)
    assert result.mode("weave_real_lower")[0] == pytest.approx(3.13164324790656, abs=1e-12)


def test_eigenpairs_match_numpy_in_any_speed_order() -> None:
    model = benchmark()
    speeds = np.array([7.3, 0.2, 5.0, 0.2, 2.5, 9.99, -1.0])
    result = eigen_analysis(model, speeds)
    assert result.eigenvalues.shape == (7, 4) and result.eigenvectors.shape == (7, 4, 4)
    np.testing.assert_array_equal(result.speeds, speeds)
    for s, speed in enumerate(speeds):
        A = model.state_matrix(speed)
        expected = np.sort_complex(np.linalg.eigvals(A))
        np.testing.assert_allclose(np.sort_complex(result.eigenvalues[s]), expected, atol=1e-12)
        vectors = result.eigenvectors[s]
        np.testing.assert_allclose(A @ vectors, vectors * result.eigenvalues[s], atol=1e-10)
    np.testing.assert_array_equal(result.eigenvalues[1], result.eigenvalues[3])


def test_without_eigenvectors_the_eigenvalues_and_labels_are_the_same() -> None:
    """Tables and plots skip the eigenvectors; the labels must not depend on that."""
    rng = np.random.default_rng(5)
    scale = np.exp(0.2 * rng.standard_normal((12, 1, 1)))
    models = [benchmark(), second_order_model(np.array(M) * scale, C1, np.array(K0) * G, K2)]
    for model in models:
        for speeds in (np.linspace(0.0, 10.0, 501), np.array([7.3, -2.0, 0.0, 15.0])):
            full, quick = eigen_analysis(model, speeds), eigen_analysis(model, speeds, vectors=False)
            assert quick.eigenvectors is None
            np.testing.assert_array_equal(quick.labels, full.labels)
            np.testing.assert_allclose(quick.eigenvalues, full.eigenvalues, rtol=0, atol=1e-12)


def test_batch_equals_one_model_at_a_time() -> None:
    scale = np.array([0.9, 1.0, 1.15])[:, None, None]
    batch = second_order_model(np.array(M) * scale, C1, np.array(K0) * G, K2)
    speeds = np.linspace(0.0, 10.0, 37)
    together = eigen_analysis(batch, speeds)
    assert together.eigenvalues.shape == (3, 37, 4) and together.labels.shape == (3, 37, 4)
    for index in range(3):
        alone = eigen_analysis(batch.select(index), speeds)
        np.testing.assert_allclose(together.eigenvalues[index], alone.eigenvalues, atol=1e-13)
        np.testing.assert_array_equal(together.labels[index], alone.labels)


def test_weave_eigenvalue_is_nan_until_the_weave_forms() -> None:
    double_root = 0.68428307889246  # Meijaard et al. 2007, Table 2(a)
    speeds = np.array([0.0, 0.5, double_root - 1e-4, double_root + 1e-4, 1.0, 5.0])
    weave = weave_eigenvalue(benchmark(), speeds)
    assert np.all(np.isnan(weave[:3]))
    assert np.all(weave[3:].imag > 0)
    assert weave[-1] == pytest.approx(table_2()[5, 1], abs=1e-12)
    batch = second_order_model(np.stack([M, M]), C1, np.array(K0) * G, K2)
    assert weave_eigenvalue(batch, [5.0]).shape == (2, 1)


def test_eigenvalue_table_rows() -> None:
    result = eigen_analysis(benchmark(), [1.0, 5.0])
    header, rows = eigenvalue_table(result)
    assert header[:4] == ["speed_m_per_s", "eig1_real_per_s", "eig1_imag_per_s", "eig1_mode"]
    assert len(header) == 13 and len(rows) == 2 and all(len(row) == 13 for row in rows)
    assert rows[1][0] == 5.0
    assert rows[1][1] + 1j * rows[1][2] == result.eigenvalues[1, 0]
    assert rows[1][3] == result.labels[1, 0]
    with pytest.raises(ValueError):
        eigenvalue_table(eigen_analysis(second_order_model(np.stack([M, M]), C1, K0, K2), [1.0]))


def test_bad_input_raises_input_error() -> None:
    with pytest.raises(InputError):
        eigen_analysis(benchmark(), [1.0, np.nan])
    with pytest.raises(InputError):
        eigen_analysis(benchmark(), [])
    broken = second_order_model(M, C1, [[np.nan, 0.0], [0.0, 1.0]], K2)
    with pytest.raises(InputError):
        eigen_analysis(broken, [1.0])


def test_figure_is_returned_not_shown() -> None:
    import matplotlib.pyplot as plt

    from whipple.stability.plots import plot_eigenvalues

    model = benchmark()
    result = eigen_analysis(model, np.linspace(0.0, 10.0, 201))
    figure = plot_eigenvalues(result, critical_speeds(model), title="benchmark",
                              measured=[(5.5, 5.6, -1.32 + 5.96j)])
    axes = figure.axes[0]
    assert axes.get_xlabel().startswith("forward speed")
    texts = [text.get_text() for text in axes.get_legend().get_texts()]
    for name in ("weave", "capsize", "castering", "imaginary part", "stable"):
        assert any(name in text for text in texts)
    assert any(line.get_linestyle() == "--" for line in axes.get_lines())
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    assert buffer.getvalue()[:4] == b"\x89PNG"
    assert plt.get_fignums() == []
