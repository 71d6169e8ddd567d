"""The explorer command: serve."""
from __future__ import annotations

import sys

from ._common import CLIError


def register(sub):
    p = sub.add_parser(
        "serve",
        help="the explorer: the chart and the moving pendulum in a web browser",
        description="Start the explorer, a local web application: the exact stability chart (zoom and pan\n"
        "with the mouse, edges recomputed for every view), and for any point clicked its report and the\n"
        "pendulum moving on its vibrating pivot, linear and nonlinear side by side. Prints its address;\n"
        "binds to this machine only (127.0.0.1) unless --host says otherwise. Needs the 'web' extra.",
        epilog="examples:\n  kapitza serve                 # a free port on 127.0.0.1\n"
        "  kapitza serve --port 8000 --open\n"
        "  kapitza serve --workers 1     # one process",
    )
    p.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1: this machine only)")
    p.add_argument("--port", type=int, default=0, help="port (default 0: a free one)")
    p.add_argument("--open", action="store_true", help="open the page in the web browser")
    p.add_argument("--workers", type=int, default=None,
                   help="server processes sharing the port (default: one per CPU, at most 4), so a class's "
                        "requests are answered side by side")
    p.set_defaults(func=cmd_serve)


def cmd_serve(args):
    try:
        import fastapi  # noqa: F401
        import orjson  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError:
        raise CLIError("the explorer needs the 'web' extra: pip install 'kapitza[web]' "
                       "(or pip install -e '.[web]' in a checkout)") from None
    from ..web.server import address, bind, is_loopback, serve

    if not (0 <= args.port <= 65535):
        raise CLIError(f"--port must be between 0 and 65535; got {args.port}")
    if args.workers is None:
        from .._validate import cpus

        args.workers = min(4, cpus())
    if not (1 <= args.workers <= 64):
        raise CLIError(f"--workers must be between 1 and 64; got {args.workers}")
    try:
        sock = bind(args.host, args.port)
    except OSError as exc:
        raise CLIError(f"cannot listen on {args.host}:{args.port} ({exc.strerror or exc})") from None
    url = address(sock)
    if not is_loopback(args.host):
        print(f"kapitza serve: warning: listening on {args.host}, reachable from other machines", file=sys.stderr)
    print(f"kapitza explorer at {url}  (Ctrl-C stops it)", flush=True)
    if args.open:
        import webbrowser

        webbrowser.open(url)
    try:
        serve(sock, workers=args.workers, host=args.host)
    finally:
        sock.close()
    return 0
