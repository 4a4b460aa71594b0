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
