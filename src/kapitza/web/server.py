"""Running the explorer: bind a socket (a free port by default), then serve the app on it.

Connections are bounded in time as well as in number: a request's head (its line and headers)
must arrive within :data:`HEAD_SECONDS` of the connection or of the previous answer, an idle
keep-alive connection is closed after :data:`KEEP_ALIVE_SECONDS`, and at most
:data:`MAX_WAITING` connections per process may wait for their head at once (a new one closes
the one waiting longest). Half-sent requests (slowloris) therefore cannot hold the server.
"""
from __future__ import annotations

import collections
import ipaddress
import os
import socket

__all__ = ["bind", "serve", "is_loopback", "HEAD_SECONDS", "KEEP_ALIVE_SECONDS", "MAX_WAITING", "HOSTS_ENV"]

#: Seconds a connection may take to send a request's line and headers.
HEAD_SECONDS = 10.0
#: Seconds an idle keep-alive connection is kept.
KEEP_ALIVE_SECONDS = 5
#: Connections of one process that may be waiting for a request's head at once.
MAX_WAITING = 64
#: Requests one process handles at once (more get 503).
MAX_CONCURRENT = 256
#: Names the explorer answers to besides the loopback ones (comma-separated; :func:`serve` adds the
#: ``--host`` name here for its worker processes). A request naming any other host gets 421.
HOSTS_ENV = "KAPITZA_ALLOWED_HOSTS"


def is_loopback(host: str) -> bool:
    """Whether ``host`` is reachable only from this machine."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def bind(host: str = "127.0.0.1", port: int = 0) -> socket.socket:
    """A listening socket on ``host:port`` (``port=0``: a free port chosen by the system).

    Parameters
    ----------
    host : str
    port : int

    Returns
    -------
    socket.socket

    Raises
    ------
    OSError
        If the address is taken or cannot be bound.

    Examples
    --------
    >>> from kapitza.web.server import bind
    >>> sock = bind()
    >>> host, port = sock.getsockname()[:2]
    >>> host, port > 0
    ('127.0.0.1', True)
    >>> sock.close()
    """
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    # IPPROTO_TCP, not 0: accepted connections inherit it, and asyncio sets TCP_NODELAY only on
    # sockets that say they are TCP. Without it a small answer (a point's report) waits ~40 ms
    # for the client's delayed ACK before its body leaves (Nagle's algorithm).
    sock = socket.socket(family, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.bind((host, port))
    sock.listen(128)
    return sock


def address(sock: socket.socket) -> str:
    """``http://host:port/`` of a bound socket."""
    host, port = sock.getsockname()[:2]
    return f"http://[{host}]:{port}/" if ":" in host else f"http://{host}:{port}/"


def host_names(host: str) -> list[str]:
    """The names a request's ``Host`` may give for a server bound to ``host``: ``host`` itself, and
    for a wildcard address (``0.0.0.0``, ``::``) this machine's name and addresses."""
    names = [host]
    try:
        wildcard = ipaddress.ip_address(host).is_unspecified
    except ValueError:
        wildcard = False
    if wildcard:
        names += [socket.gethostname(), socket.getfqdn()]
        try:
            names += socket.gethostbyname_ex(socket.gethostname())[2]
        except OSError:
            pass
    return names


#: uvicorn's log levels
LOG_LEVELS = ("critical", "error", "warning", "info", "debug", "trace")


def serve(sock: socket.socket, log_level: str = "warning", workers: int = 1, host: str | None = None) -> None:
    """Serve the explorer on ``sock`` until interrupted, in ``workers`` processes sharing it.

    ``host``: the name (or address) given to ``kapitza serve --host``; requests naming it are
    answered besides those naming the loopback (the ``Host`` check of :mod:`kapitza.web.app`).

    Parameters
    ----------
    sock : socket.socket
        From :func:`bind`.
    log_level : {"critical", "error", "warning", "info", "debug", "trace"}
    workers : int
        Processes, 1 to 64.
    host : str, optional

    Returns
    -------
    None

    Raises
    ------
    KapitzaValueError
        If ``sock`` is not a socket, ``log_level`` not one of its choices or ``workers`` not a whole
        number from 1 to 64; nothing is served then.

    Examples
    --------
    Blocks until interrupted (``kapitza serve`` does this):

    >>> from kapitza.web.server import bind, serve
    >>> serve(bind(port=8000))  # doctest: +SKIP
    """
    from .. import _validate as _v

    if not isinstance(sock, socket.socket):
        raise _v.KapitzaValueError(f"sock must be a bound socket.socket (bind); got {type(sock).__name__}")
    if log_level not in LOG_LEVELS:
        raise _v.KapitzaValueError(f"log_level must be one of {', '.join(map(repr, LOG_LEVELS))}; got {log_level!r}")
    workers = _v.bounded_count("workers", workers, 64, minimum=1, what="processes of one explorer")
    import uvicorn

    if host:
        extra = [h for h in os.environ.get(HOSTS_ENV, "").split(",") if h.strip()]
        os.environ[HOSTS_ENV] = ",".join(extra + host_names(host))  # read by each worker's create_app
    config = uvicorn.Config("kapitza.web.app:create_app", factory=True, log_level=log_level,
                            limit_concurrency=MAX_CONCURRENT, timeout_keep_alive=KEEP_ALIVE_SECONDS,
                            h11_max_incomplete_event_size=16384, workers=workers,
                            http="kapitza.web.server:BoundedH11Protocol")
    if workers == 1:
        uvicorn.Server(config).run(sockets=[sock])
        return
    import inspect

    from uvicorn.supervisors import Multiprocess

    server = uvicorn.Server(config)
    if "target" in inspect.signature(Multiprocess).parameters:  # uvicorn < 0.36 names the target
        Multiprocess(config, target=server.run, sockets=[sock]).run()  # type: ignore[call-arg]
    else:
        Multiprocess(config, sockets=[sock]).run()


def _protocol():
    """uvicorn's h11 protocol with a deadline on each request's head (imported with uvicorn)."""
    import h11
    from uvicorn.protocols.http.h11_impl import H11Protocol

    class BoundedH11Protocol(H11Protocol):
        """H11Protocol whose connections must send each request's head within :data:`HEAD_SECONDS`;
        of the connections waiting for a head, at most :data:`MAX_WAITING` are kept (per process)."""

        #: connections waiting for a request's head, oldest first
        waiting: collections.OrderedDict = collections.OrderedDict()

        def connection_made(self, transport):
            super().connection_made(transport)
            self._head_deadline = None
            self._await_head()

        def data_received(self, data):
            super().data_received(data)
            self._await_head()

        def on_response_complete(self):
            super().on_response_complete()
            self._await_head()

        def connection_lost(self, exc):
            self._head_received()
            super().connection_lost(exc)

        def _await_head(self):
            """Arm the deadline while a request's head is incomplete (h11 still IDLE on their
            side, bytes of it received or not), disarm it once the head is in."""
            if self.transport.is_closing():
                self._head_received()
            elif self.conn.their_state is h11.IDLE:
                if self._head_deadline is None:
                    self._head_deadline = self.loop.call_later(HEAD_SECONDS, self._head_timeout)
                    waiting = type(self).waiting
                    waiting[self] = None
                    while len(waiting) > MAX_WAITING:
                        oldest = next(iter(waiting))
                        oldest._head_timeout()
            else:
                self._head_received()

        def _head_received(self):
            if getattr(self, "_head_deadline", None) is not None:
                self._head_deadline.cancel()
                self._head_deadline = None
            type(self).waiting.pop(self, None)

        def _head_timeout(self):
            self._head_received()
            if not self.transport.is_closing():
                self.transport.close()  # nothing was asked: nothing to answer

    return BoundedH11Protocol


def __getattr__(name):
    if name == "BoundedH11Protocol":
        cls = _protocol()
        globals()[name] = cls
        return cls
    raise AttributeError(name)
