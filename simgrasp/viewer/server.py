"""``simgrasp view PATH --port P``: the page of PATH served on localhost only (127.0.0.1)."""

from __future__ import annotations

import contextlib
import http.server
from collections.abc import Callable


def serve(page: Callable[[], str], port: int) -> None:
    """Serve ``page()`` (called on each request to ``/``) at ``http://127.0.0.1:PORT/`` until
    interrupted."""

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:  # noqa: N802 (http.server's name)
            if self.path not in ("/", "/index.html"):
                self.send_error(404)
                return
            body = page().encode()
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

    with http.server.ThreadingHTTPServer(("127.0.0.1", port), Handler) as server:
        print(f"serving http://127.0.0.1:{server.server_address[1]}/ (Ctrl-C stops)")
        with contextlib.suppress(KeyboardInterrupt):
            server.serve_forever()
