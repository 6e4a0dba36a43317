"""The studio's server: a Bokeh server (Tornado) on the loopback interface, behind a token.

Safe by default, as Jupyter is: it binds 127.0.0.1 (another interface only when asked, with a
printed warning); a random token in the URL it prints is the key — the first request that
carries it gets a signed cookie, every other request (the page, its websocket, its static files
excepted: BokehJS from the installed package) without the cookie or the token is refused (403);
Bokeh's session ids are signed with a per-run secret and its websocket accepts only this origin.
Nothing runs but the part script named on the command line.
"""

from __future__ import annotations

import hmac
import os
import secrets
import socket
import sys
from collections.abc import Callable
from pathlib import Path

from transplanter.core.errors import SpecError, check_int

__all__ = ["COOKIE", "LOOPBACK", "free_port", "serve"]

LOOPBACK = "127.0.0.1"
#: the cookie that carries the token after the first request
COOKIE = "transplanter-studio"


def free_port(host: str = LOOPBACK) -> int:
    """A port nothing listens on at ``host`` now (the OS's choice)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def _user(handler, token: str) -> str | None:
    """ "designer" if the request carries the token (then it gets the cookie) or the cookie; else None."""
    from tornado.websocket import WebSocketHandler

    given = handler.get_argument("token", default=None)
    if given is not None and hmac.compare_digest(given, token):
        if not isinstance(handler, WebSocketHandler):  # a websocket sets no cookie
            handler.set_secure_cookie(COOKIE, token, expires_days=None, httponly=True, samesite="Strict")
        return "designer"
    held = handler.get_secure_cookie(COOKIE)
    if held is not None and hmac.compare_digest(held.decode("ascii", "replace"), token):
        return "designer"
    return None


def _files(token: str):
    """A handler of the build's output folder, read-only, for the holder of the token: a regular
    file inside the folder only (a link, or a path that leads out of it, is refused)."""
    from tornado.web import HTTPError, StaticFileHandler

    class Files(StaticFileHandler):
        def prepare(self) -> None:
            if _user(self, token) is None:
                raise HTTPError(403, "open the URL transplanter design printed: it carries the token")

        def validate_absolute_path(self, root: str, absolute_path: str):
            inside = os.path.realpath(root) + os.sep
            if os.path.islink(absolute_path) or not os.path.realpath(absolute_path).startswith(inside):
                raise HTTPError(403)
            found = super().validate_absolute_path(root, absolute_path)
            if found is not None and not os.path.isfile(found):
                raise HTTPError(403)
            return found

    return Files


def _auth(token: str):
    from bokeh.server.auth_provider import AuthProvider
    from tornado.web import HTTPError, RequestHandler

    class Refused(RequestHandler):
        def get(self) -> None:
            raise HTTPError(403, "open the URL transplanter design printed: it carries the token")

    class TokenAuth(AuthProvider):
        @property
        def get_user(self):
            return lambda handler: _user(handler, token)

        @property
        def login_url(self) -> str:
            return "/refused"

        @property
        def login_handler(self):
            return Refused

    return TokenAuth()


def serve(
    apps: dict[str, Callable],
    *,
    host: str = LOOPBACK,
    port: int = 0,
    open_browser: bool = True,
    files: Path | None = None,
) -> None:
    """Serve each ``apps[path](doc)`` at its path until interrupted; prints the URL of ``/`` with its token.
    ``files``: a folder served read-only under ``/files/`` (the build's output: its reports)."""
    from bokeh.application import Application
    from bokeh.application.handlers.function import FunctionHandler
    from bokeh.server.server import Server

    if not isinstance(host, str) or not host:
        raise SpecError.out_of_range("--host", host, "an interface address, e.g. 127.0.0.1")
    port = check_int("--port", port, 0, 65535) or free_port(host)
    if host != LOOPBACK:
        print(
            f"warning: the studio listens on {host}, not on {LOOPBACK}: anyone who can reach that interface "
            "and has the token can drive it and run this part script",
            file=sys.stderr,
        )
    token = secrets.token_urlsafe(24)
    shown_host = "127.0.0.1" if host in (LOOPBACK, "0.0.0.0") else host
    server = Server(
        {path: Application(FunctionHandler(make)) for path, make in apps.items()},
        address=host,
        port=port,
        allow_websocket_origin=[f"{shown_host}:{port}", f"localhost:{port}"],
        auth_provider=_auth(token),
        cookie_secret=secrets.token_urlsafe(32),
        secret_key=secrets.token_urlsafe(32).encode(),
        sign_sessions=True,
        generate_session_ids=True,
        num_procs=1,
        extra_patterns=[(r"/files/(.*)", _files(token), {"path": str(files)})] if files is not None else [],
    )
    server.start()
    url = f"http://{shown_host}:{port}/?token={token}"
    print(f"transplanter design: {url}", flush=True)
    print("(Ctrl-C stops it)", file=sys.stderr, flush=True)
    if open_browser:
        import webbrowser

        server.io_loop.add_callback(webbrowser.open, url)
    try:
        server.io_loop.start()
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()
