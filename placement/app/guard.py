"""Who may use the workbench: this machine's pages holding the session's token, and no tunnel out.

The workbench serves on loopback, but a loopback port is reachable from every web page the user's browser
shows: any page could open its websocket and drive it (change fields, start maps), and a DNS-rebinding name
could read it. So every HTTP request and websocket handshake is checked (:class:`Gate`):

- ``Host`` must name this server: a loopback name (127.0.0.1, localhost, [::1]) or the address it was told
  to serve on, with its port, or an origin given with ``--allow-origin``;
- ``Origin``, when the browser sends one (it does for every websocket and every cross-site request), must be
  this server's own (``http://<one of those hosts>:<port>``) or one given with ``--allow-origin``;
- the session's token (a random 32-character string made at start, printed in the address as Jupyter does):
  the page is served only to ``/?token=...``, which sets a cookie (HttpOnly, SameSite=Strict, this port's
  name) that the page's own websocket and later loads carry;
- every answer carries ``X-Frame-Options: DENY``, a ``Content-Security-Policy`` (no framing, connections
  only back to this server, no plugins; no ``script-src``: viser's page runs the scripts its server sends with
  ``new Function``, as :mod:`placement.app.shown` does to read the fields), ``X-Content-Type-Options: nosniff``,
  ``Referrer-Policy: no-referrer`` (the token never leaves in a Referer) and ``Cache-Control: no-store``.

A refused request is answered 403 with one line saying why, and logged in one line.

viser (the page's library) offers no hook for these checks, so the gate is put in by the one narrow means it
leaves: while :func:`guarded_server` builds the viser server, viser's call to ``websockets``' ``serve`` is
given the gate's ``process_request``/``process_response`` around viser's own (see :func:`_serving_through`);
the server refuses to start if the gate did not get in (a viser that serves otherwise fails closed). The
share tunnel (viser's *Share* button, and a ``ShareUrlRequest`` any websocket client may send) is refused
by overriding :meth:`viser.ViserServer.request_share_url` in :class:`GuardedServer`, and its button is hidden.
Malformed websocket frames, which viser lets escape as a traceback, are logged in one line
(:class:`OneLineErrors`).
"""

from __future__ import annotations

import contextlib
import hmac
import http
import http.cookies
import logging
import secrets
import threading
from collections.abc import Callable, Iterator
from typing import Any
from urllib.parse import parse_qs, urlsplit

import viser  # optional dependency: the [app] extra, checked by placement.app
import websockets.asyncio.server  # viser's own dependency
from websockets.http11 import Request, Response

from placement.exceptions import SettingsError

LOG = logging.getLogger("placement.app")
LOOPBACK_NAMES = ("127.0.0.1", "localhost", "[::1]")
SECURITY_HEADERS = {
    "X-Frame-Options": "DENY",
    "Content-Security-Policy": "frame-ancestors 'none'; connect-src 'self' blob: data:; object-src 'none'; "
                               "base-uri 'none'; form-action 'none'",
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
}
_SERVING = threading.Lock()  # one guarded server built at a time (the hook below is in place while it starts)


def allowed_origin(text: str) -> str:
    """An ``--allow-origin`` value as the browser sends it: ``scheme://host[:port]``, lower case, no path.

    Raises:
        SettingsError: Not such an origin.
    """
    parts = urlsplit(text.strip())
    if parts.scheme not in ("http", "https") or not parts.hostname or parts.path not in ("", "/") or parts.query:
        raise SettingsError(f"--allow-origin: expected an origin such as http://myhost:8080, got {text!r}")
    return f"{parts.scheme}://{parts.netloc.lower()}"


def _bracketed(host: str) -> str:
    return f"[{host}]" if ":" in host and not host.startswith("[") else host


class Gate:
    """The checks of every request (see the module's text).

    Args:
        host: The address served on.
        origins: Further origins allowed (``--allow-origin``), as :func:`allowed_origin` writes them.
    """

    def __init__(self, host: str, origins: tuple[str, ...] = ()) -> None:
        self.token = secrets.token_urlsafe(24)
        self.names = tuple(dict.fromkeys((*LOOPBACK_NAMES, _bracketed(host.lower()))))
        self.origins = origins
        self.port = 0  # known once the server listens
        self.installed = False  # whether the server's requests pass through this gate
        self.refused: list[str] = []  # why each refused request was refused (for the tests and the log)

    @property
    def cookie(self) -> str:
        """The session cookie's name (one per port: browsers share cookies between a host's ports)."""
        return f"placement-workbench-{self.port}"

    def hosts(self) -> set[str]:
        """Every ``Host`` header accepted."""
        hosts = {f"{name}:{self.port}" for name in self.names}
        hosts |= {urlsplit(origin).netloc for origin in self.origins}
        return hosts

    def why_refused(self, request: Request) -> str | None:
        """Why the request is refused, or None."""
        host = request.headers.get("Host", "").lower()
        if host not in self.hosts():
            return f"Host {host!r} is not this server's"
        origin = request.headers.get("Origin")
        if origin is not None and origin.lower() not in {f"http://{h}" for h in self.hosts()} | set(self.origins):
            return f"Origin {origin!r} is not this server's page"
        if not self._has_token(request):
            return "no session token (open the address the command printed, with its ?token=...)"
        return None

    def _has_token(self, request: Request) -> bool:
        given = parse_qs(urlsplit(request.path).query).get("token", [])
        jar = http.cookies.SimpleCookie()
        with contextlib.suppress(http.cookies.CookieError):
            jar.load(request.headers.get("Cookie", ""))
        if self.cookie in jar:
            given.append(jar[self.cookie].value)
        return any(hmac.compare_digest(value.encode(), self.token.encode()) for value in given)

    def process_request(self, inner: Callable | None) -> Callable:
        """viser's ``process_request`` behind the checks."""
        def checked(connection: Any, request: Request) -> Response | None:
            why = self.why_refused(request)
            if why is not None:
                self.refused.append(why)
                LOG.warning("workbench: refused %s %s: %s", "websocket" if _upgrade(request) else "request",
                            request.path.split("?")[0], why)
                return connection.respond(http.HTTPStatus.FORBIDDEN, f"refused: {why}\n")
            return inner(connection, request) if inner is not None else None

        self.installed = True
        return checked

    def process_response(self, inner: Callable | None) -> Callable:
        """Whatever answers (viser's or the checks'), with the security headers and, for a request bearing the
        token in its address, the session cookie."""
        def headed(connection: Any, request: Request, response: Response) -> Response | None:
            if inner is not None:
                response = inner(connection, request, response) or response
            for name, value in SECURITY_HEADERS.items():
                response.headers[name] = value
            if response.status_code == http.HTTPStatus.OK and "token=" in request.path:
                response.headers["Set-Cookie"] = (f"{self.cookie}={self.token}; Path=/; HttpOnly; "
                                                  "SameSite=Strict")
            return response

        return headed


def _upgrade(request: Request) -> bool:
    return request.headers.get("Upgrade", "").lower() == "websocket"


class GuardedServer(viser.ViserServer):
    """viser's server without its share tunnel: a ``ShareUrlRequest`` (its Share button's, or any client's) is
    refused and logged."""

    share_refusals = 0

    def request_share_url(self, verbose: bool = True) -> str | None:
        """Refuse: the workbench is never published through viser's public tunnel."""
        type(self).share_refusals += 1
        LOG.warning("workbench: refused a request for a public share address (the workbench stays on this machine)")
        return None


class OneLineErrors(logging.Filter):
    """websockets' "connection handler failed" (a frame viser could not decode) in one line, without the
    traceback."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.exc_info and record.exc_info[1] is not None:
            error = record.exc_info[1]
            text = " ".join(str(error).split())[:200]
            record.msg, record.args = f"workbench: {record.getMessage()}: {type(error).__name__}: {text}", ()
            record.exc_info, record.exc_text = None, None
        return True


@contextlib.contextmanager
def _serving_through(gate: Gate) -> Iterator[None]:
    """While viser starts its server: its ``websockets`` ``serve`` call gets the gate's checks around viser's own
    request handler (the only hook viser leaves; undone at once)."""
    original = websockets.asyncio.server.serve

    class GatedServe(original):  # type: ignore[misc, valid-type]
        def __init__(self, *args: Any, process_request: Callable | None = None,
                     process_response: Callable | None = None, **kwargs: Any) -> None:
            super().__init__(*args, process_request=gate.process_request(process_request),
                             process_response=gate.process_response(process_response), **kwargs)

    websockets.asyncio.server.serve = GatedServe  # type: ignore[misc]
    try:
        yield
    finally:
        websockets.asyncio.server.serve = original  # type: ignore[misc]


def guarded_server(host: str, port: int, origins: tuple[str, ...] = ()) -> tuple[GuardedServer, Gate]:
    """A viser server whose every request passes through a :class:`Gate`, without share tunnel or Share button.

    Raises:
        RuntimeError: The gate could not be put in (a viser that serves otherwise): nothing is served.
    """
    gate = Gate(host, origins)
    with _SERVING, _serving_through(gate):
        server = GuardedServer(host=host, port=port, verbose=False)
    if not gate.installed:
        server.stop()
        raise RuntimeError("the workbench could not check its requests with this viser version: not served")
    gate.port = server.get_port()
    server.gui.configure_theme(control_width="large", show_logo=False, show_share_button=False)
    for name in ("websockets.server", "websockets.asyncio.server"):
        logger = logging.getLogger(name)
        if not any(isinstance(f, OneLineErrors) for f in logger.filters):
            logger.addFilter(OneLineErrors())
    return server, gate
