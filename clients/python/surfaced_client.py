"""Compatibility shim: the client is the ``surfaced`` package now (``pip install ./clients/python``, then
``import surfaced``). This module stays importable for one more release and will then be removed.

It re-exports ``surfaced``; its :class:`Client` keeps the old return values of :meth:`Client.curves` and
:meth:`Client.implicit_query` (the parsed JSON document, where ``surfaced.Client`` returns a ``Result``). Options are
checked against the API now: a misspelt option is a TypeError instead of a 400 from the server.
"""
from __future__ import annotations

import warnings
from typing import Any, Dict

import surfaced
from surfaced import (  # noqa: F401  (re-exported)
    API_VERSION, MESH_MEDIA_TYPES, IncompatibleServerError, Result, SurfacedError, is_compatible,
)

__all__ = ["Client", "Result", "SurfacedError", "IncompatibleServerError", "MESH_MEDIA_TYPES", "API_VERSION",
           "is_compatible"]

warnings.warn("surfaced_client is deprecated: import surfaced", DeprecationWarning, stacklevel=2)


class Client(surfaced.Client):
    """``surfaced.Client`` with the old module's return values for curves and implicit_query."""

    def curves(self, *args: Any, **kwargs: Any) -> Dict[str, Any]:  # type: ignore[override]
        """POST /curves; returns the parsed JSON answer (``surfaced.Client.curves(...).json``)."""
        return super().curves(*args, **kwargs).json

    def implicit_query(self, *args: Any, **kwargs: Any) -> Dict[str, Any]:  # type: ignore[override]
        """POST /implicit/query; returns the parsed JSON answer (``surfaced.Client.implicit_query(...).json``)."""
        return super().implicit_query(*args, **kwargs).json
