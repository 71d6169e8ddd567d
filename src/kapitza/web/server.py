"""Running the explorer: bind a socket (a free port by default), then serve the app on it."""
from __future__ import annotations

import ipaddress
import socket

__all__ = ["bind", "serve", "is_loopback"]


def is_loopback(host: str) -> bool:
    """Whether ``host`` is reachable only from this machine."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def bind(host: str = "127.0.0.1", port: int = 0) -> socket.socket:
    """A listening socket on ``host:port`` (``port=0``: a free port chosen by the system)."""
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


def serve(sock: socket.socket, log_level: str = "warning", workers: int = 1) -> None:
    """Serve the explorer on ``sock`` until interrupted, in ``workers`` processes sharing it."""
    import uvicorn

    config = uvicorn.Config("kapitza.web.app:create_app", factory=True, log_level=log_level, limit_concurrency=256,
                            timeout_keep_alive=5, h11_max_incomplete_event_size=16384, workers=workers)
    if workers == 1:
        uvicorn.Server(config).run(sockets=[sock])
        return
    import inspect

    from uvicorn.supervisors import Multiprocess

    server = uvicorn.Server(config)
    if "target" in inspect.signature(Multiprocess).parameters:  # uvicorn < 0.36 names the target
        Multiprocess(config, target=server.run, sockets=[sock]).run()
    else:
        Multiprocess(config, sockets=[sock]).run()
