"""Start ``kapitza serve`` as a real process on a free loopback port, for the web tests."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def running_server(*args, timeout=30.0, prelude=None):
    """Yield ``(base_url, seconds_to_first_response, process)`` of ``kapitza serve --port 0``
    (after the Python code ``prelude`` where given, e.g. a user's drive registered)."""
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    t0 = time.perf_counter()
    start = ["-m", "kapitza"] if prelude is None else [
        "-c", f"{prelude}\nimport sys\nfrom kapitza.cli import main\nsys.exit(main(sys.argv[1:]))"]
    proc = subprocess.Popen([sys.executable, *start, "serve", "--port", "0", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        line = proc.stdout.readline()
        m = re.search(r"(http://\S+/)", line)
        if not m:
            proc.kill()
            raise RuntimeError(f"kapitza serve printed {line!r}; stderr: {proc.stderr.read()}")
        base = m.group(1)
        first = None
        while time.perf_counter() - t0 < timeout:
            try:
                with urllib.request.urlopen(base + "openapi.json", timeout=5) as r:
                    r.read()
                first = time.perf_counter() - t0
                break
            except OSError:
                time.sleep(0.02)
        if first is None:
            raise RuntimeError("kapitza serve did not answer")
        yield base, first, proc
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        proc.stderr_text = proc.stderr.read()
        for stream in (proc.stdout, proc.stderr):
            stream.close()


#: Debian's chromium, which the browser tests drive through Playwright (None where it is missing)
CHROMIUM = shutil.which("chromium") or ("/usr/bin/chromium" if Path("/usr/bin/chromium").exists() else None)
#: where the browser tests write their screenshots
SCREENS = Path(__file__).resolve().parents[1] / "out" / "web-screens"
#: Chromium's switches for a headless run that reaches nothing but the test server
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]
