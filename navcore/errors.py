"""navcore's one base exception: every error class of navcore derives from ``NavcoreError``
(each keeps its other base too, so ``except ValueError`` still catches a ``MapError``)."""

from __future__ import annotations


class NavcoreError(Exception):
    """Base of navcore's errors (``ParameterError``, ``MapError``, ``RouteError``, ``ReadError``)."""
