"""The closed-form cubic roots shared by the critical-speed labels and Ferrari's resolvent."""

import numpy as np
import pytest

from whipple.stability.cubic import cubic_roots, real_cubic_root


def _coefficients(roots: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """b, c, d of the monic cubics with the given roots (rows of three)."""
    poly = np.array([np.real(np.poly(row)) for row in roots])
    return poly[:, 1], poly[:, 2], poly[:, 3]


def test_roots_match_numpy_on_random_cubics():
    rng = np.random.default_rng(7)
    b, c, d = rng.normal(scale=5.0, size=(3, 2000))
    ours = np.sort_complex(cubic_roots(b, c, d))
    reference = np.sort_complex(np.array([np.roots([1.0, *row]) for row in zip(b, c, d, strict=True)]))
    scale = 1.0 + np.abs(reference)
    assert np.max(np.abs(ours - reference) / scale) < 1e-9


def test_largest_real_root_first():
    rng = np.random.default_rng(8)
    three_real = np.sort(rng.uniform(-10, 10, size=(500, 3)), axis=1)
    b, c, d = _coefficients(three_real)
    assert np.allclose(real_cubic_root(b, c, d), three_real[:, 2], rtol=1e-10, atol=1e-9)
    one_real = np.column_stack([rng.uniform(-10, 10, 500), rng.uniform(-5, 5, 500) + 1j * rng.uniform(0.5, 5, 500)])
    one_real = np.column_stack([one_real[:, 0], one_real[:, 1], np.conj(one_real[:, 1])])
    b, c, d = _coefficients(one_real)
    assert np.allclose(real_cubic_root(b, c, d), one_real[:, 0].real, rtol=1e-10, atol=1e-9)


@pytest.mark.parametrize("roots", [(2.0, 2.0, 2.0), (-1.0, 3.0, 3.0), (0.0, 0.0, -4.0)])
def test_multiple_roots_stay_finite(roots):
    b, c, d = _coefficients(np.array([roots]))
    found = cubic_roots(b, c, d)[0]
    assert np.all(np.isfinite(found))
    # A double or triple root is only determined to about the cube root of rounding.
    assert np.allclose(np.sort_complex(found), np.sort_complex(np.array(roots, dtype=complex)), atol=1e-4)
