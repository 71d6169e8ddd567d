"""The explorer: a local web application over the library (``kapitza serve``).

Needs the ``web`` extra (``pip install 'kapitza[web]'``: FastAPI and uvicorn); ``import kapitza``
never imports it. :func:`create_app` builds the ASGI application, :func:`serve` runs it.
"""
from __future__ import annotations

__all__ = ["create_app", "serve", "bind"]


def __getattr__(name):
    if name == "create_app":
        from .app import create_app

        return create_app
    if name in ("serve", "bind"):
        from . import server

        return getattr(server, name)
    raise AttributeError(name)
