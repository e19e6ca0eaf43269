"""Random misuse of every public function: the project's error or a result, nothing else.

:mod:`test_public_api` spoils each argument of each public callable in every
listed way; here hypothesis draws the bad values (issue 33: "a hypothesis test
per public module that feeds it wrong types, NaN, ±inf, huge, empty and wrongly
shaped values"): any of ``None``, booleans, text, complex numbers, integers far
beyond float64, floats with NaN and infinity, arrays of any small shape and
dtype, lists, mappings, and the good value scaled by a huge or tiny factor.  The
call must return or raise a :class:`~prp3.errors.Prp3Error` with a one-line
message; a ``TypeError``, ``ValueError``, numpy warning (an error under the
suite's ``filterwarnings``) or any other exception fails.
"""

from __future__ import annotations

from typing import Any

import hypothesis.extra.numpy as hnp
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from prp3.errors import Prp3Error
from test_public_api import CASES, SLOW

FLOATS = st.floats(allow_nan=True, allow_infinity=True, width=64)
SHAPES = hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)
JUNK = st.one_of(
    st.none(),
    st.booleans(),
    st.text(max_size=4),
    st.complex_numbers(allow_nan=True, allow_infinity=True),
    st.sampled_from([-(10**400), 10**400, 2**63, -1, 0, 10**20]),
    FLOATS,
    hnp.arrays(np.float64, SHAPES, elements=FLOATS),
    hnp.arrays(st.sampled_from([np.bool_, np.int64, np.complex128, np.str_]), SHAPES),
    st.lists(FLOATS, max_size=4),
    st.dictionaries(st.text(max_size=3), FLOATS, max_size=2),
)
FACTORS = st.sampled_from([1e300, -1e300, 1e-300, 1e200, np.nan, np.inf, -1.0, 0.0])

NAMES = sorted(n for n in CASES if n not in SLOW)


def _scaled(good: Any, factor: float) -> Any:
    """The good value times ``factor``, where it is a number or an array of numbers."""
    if isinstance(good, bool) or not isinstance(good, (int, float, np.ndarray)):
        return None
    array = np.asarray(good)
    if array.dtype.kind not in "iuf":
        return None
    with np.errstate(all="ignore"):
        return array * factor if isinstance(good, np.ndarray) else float(good) * factor


@pytest.mark.parametrize("name", NAMES)
@settings(suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_misuse_is_refused_or_computed(name: str, data: st.DataObject) -> None:
    case = CASES[name]
    arguments = case.good()
    argument = data.draw(st.sampled_from(sorted(case.kinds)), label="argument")
    scaled = _scaled(arguments[argument], data.draw(FACTORS, label="factor"))
    choices = JUNK if scaled is None else st.one_of(JUNK, st.just(scaled))
    arguments[argument] = data.draw(choices, label="value")
    try:
        case.call(**arguments)
    except Prp3Error as error:
        assert "\n" not in str(error), str(error)
