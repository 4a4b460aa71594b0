"""modalid._information: the information criterion's prefixes and the misfit ratio read
from them, against least squares solved directly."""

import numpy as np

from modalid._information import misfit_ratio, prefix_information


def test_misfit_ratio_is_the_chosen_prefix_sse_over_the_head_sse():
    """Two fixed columns, three candidates of two columns each; the data hold the head and
    the first two candidates plus noise: the criterion picks two, and the ratio equals
    the residual sums of squares of those columns and of the head alone, solved by lstsq."""
    rng = np.random.default_rng(3)
    mat = rng.normal(size=(400, 8))
    y = mat[:, :6] @ rng.normal(size=6) + 0.01 * rng.normal(size=400)
    keep, bic, _ = prefix_information(mat, y, 2, 3, passive=False)
    assert keep.tolist() == [True, True, False]

    def sse(cols):
        x = np.linalg.lstsq(mat[:, :cols], y, rcond=None)[0]
        return float(np.sum((y - mat[:, :cols] @ x) ** 2))

    np.testing.assert_allclose(misfit_ratio(bic, y.size), sse(6) / sse(2), rtol=1e-8)
    assert misfit_ratio(np.array([0.0, 5.0, 9.0]), 100) == 1.0      # none chosen


def test_a_candidate_the_prefix_takes_before_a_strong_one_is_dropped_when_unsupported():
    """Candidates ranked weak, weak, strong (the order persistence gave a comb of noise
    poles before a resonance's own): the data hold the head and the third only. The best
    prefix is all three (the third's gain outweighs two penalties); backward elimination
    keeps the third alone, which the criterion prefers: the kept set's SSE plus its
    penalty against the prefix's, by lstsq."""
    rng = np.random.default_rng(5)
    n = 400
    mat = rng.normal(size=(n, 8))
    y = mat[:, :2] @ rng.normal(size=2) + mat[:, 6:8] @ [3.0, -2.0] + 0.01 * rng.normal(size=n)
    keep, bic, _ = prefix_information(mat, y, 2, 3, passive=False)
    assert int(np.argmin(bic)) == 3 and keep.tolist() == [False, False, True]

    def criterion(cols):
        x = np.linalg.lstsq(mat[:, cols], y, rcond=None)[0]
        sse = float(np.sum((y - mat[:, cols] @ x) ** 2))
        return n * np.log(sse / n) + 4 * (len(cols) - 2) // 2 * np.log(n)

    assert criterion([0, 1, 6, 7]) < criterion(list(range(8)))
