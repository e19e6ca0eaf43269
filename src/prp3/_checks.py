"""Former home of the validation helpers; they live in :mod:`prp3.validation` now."""

from __future__ import annotations

from .validation import check_real, first_non_finite, require_finite

__all__ = ["first_non_finite", "real_array", "require_finite"]

real_array = check_real
