"""A-priori bounds on the rounding error of float64 computations whose order of operations
is not ours to fix: numpy's reductions, BLAS products and SIMD elementary functions pick
their kernels by CPU (numpy's dispatch, OpenBLAS's core type, glibc's ifuncs), so the
same expression gives different last bits on different machines. A test that compares
such a number with a recorded one, or two of them computed differently, allows the
bound below instead of asserting bits.

The bounds are Higham's (Accuracy and Stability of Numerical Algorithms, 2nd ed.,
Sec. 3.1 and 4.2): with u = 2^-53 and gamma_k = k u / (1 - k u), a sum of n terms in any
order and any blocking differs from the exact one by at most gamma_(n-1) sum |x_i|, a dot
product of n terms by gamma_n sum |x_i y_i|. They hold for every order of summation at
once, so they bound a numpy/BLAS result on any CPU, and twice them the distance between
two such results.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

UNIT_ROUNDOFF = 2.0**-53
# Largest error, in units in the last place of the result, allowed for a float64 tanh.
# numpy validates its float64 tanh (its own SIMD kernels, else the C library's) to 2 ulp
# (numpy/_core/tests/data/umath-validation-set-tanh.csv); against a 50-digit reference
# on 9000 points in [-20, 20] we measured 1.11 ulp for numpy's AVX2 kernel and 1.94 ulp
# for glibc 2.36's tanh with and without its FMA/AVX2 paths. 4 leaves room for others.
TANH_ULPS = 4


def gamma(k: int) -> float:
    """gamma_k = k u / (1 - k u): the relative error bound of k successive roundings."""
    if k * UNIT_ROUNDOFF >= 1.0:
        raise ValueError(f"gamma_{k}: k u >= 1, no bound")
    return k * UNIT_ROUNDOFF / (1.0 - k * UNIT_ROUNDOFF)


def mean_square_bound(residual: np.ndarray) -> float:
    """Bound on |computed - exact| of mean((a - b)**2) in float64, in any summation order,
    given the computed residual a - b: the subtraction and the square round once each
    (u), the n - 1 additions of nonnegative terms give at most gamma_(n-1) of the sum,
    the division by n once more, so gamma_(n+3) of the mean."""
    r = np.asarray(residual, dtype=float)
    return gamma(r.size + 3) * float(np.mean(r * r))


def dense_forward_bound(
    weights: Sequence[np.ndarray],
    biases: Sequence[np.ndarray],
    z: np.ndarray,
    z_error: np.ndarray,
    activation: Callable[[np.ndarray], np.ndarray] = np.tanh,
    activation_ulps: int = TANH_ULPS,
) -> tuple[np.ndarray, np.ndarray]:
    """A multilayer perceptron z -> W_k z + b_k with `activation` between the layers (none
    after the last), evaluated here in numpy, and a componentwise bound on how far ANY
    float64 evaluation of it (any summation order, FMA or not, any activation within
    `activation_ulps` ulp) lies from the exact result.

    z: the inputs as columns ([features, points]); z_error: a bound on their error. The
    activation must be 1-Lipschitz and bounded by 1 in magnitude (tanh, the logistic
    sigmoid): an input error E then passes through unamplified, and its own rounding adds
    at most activation_ulps ulp <= 2 activation_ulps u of the result.

    Layer k with input bound E: |fl(W z^ + b) - (W z + b)| <= |W| E +
    gamma_(m+1) (|W| |z^| + |b|), m the inner dimension (m products and m additions with
    the bias, Higham Sec. 3.5). The bound is computed in float64 from the computed
    values; its own rounding is a relative 1e-13 of itself, far inside its slack.
    Returns (output rows as computed here, bound), both [outputs, points]."""
    z = np.asarray(z, dtype=float)
    bound = np.asarray(z_error, dtype=float)
    for k, (w, b) in enumerate(zip(weights, biases)):
        w = np.asarray(w, dtype=float)
        b = np.asarray(b, dtype=float).reshape(-1, 1)
        inner = w.shape[1]
        magnitude = np.abs(w) @ np.abs(z) + np.abs(b)
        bound = np.abs(w) @ bound + gamma(inner + 1) * magnitude
        z = w @ z + b
        if k < len(weights) - 1:
            z = activation(z)
            bound = bound + 2 * activation_ulps * UNIT_ROUNDOFF * np.abs(z)
    return z, bound
