"""Who may use the tablet page: whoever has the token printed at start, from the page's own origin.

The token keeps other people on the network out; the Origin check keeps other web pages, open in
the same browser, from pressing buttons through it (a cross-site WebSocket carries their origin).
"""
from __future__ import annotations

import hmac
import secrets
from urllib.parse import urlsplit


def new_token() -> str:
    return secrets.token_urlsafe(16)


class Guard:
    def __init__(self, token: str) -> None:
        self.token = token

    def token_ok(self, given: str | None) -> bool:
        return given is not None and hmac.compare_digest(given.encode(), self.token.encode())

    @staticmethod
    def origin_ok(origin: str | None, host: str | None) -> bool:
        """The Origin header names the host (host:port) the request was sent to."""
        if not origin or not host:
            return False
        parts = urlsplit(origin)
        return parts.scheme in ("http", "https") and parts.netloc.lower() == host.lower()

    def why_refused(self, token: str | None, origin: str | None, host: str | None) -> str | None:
        """None when a state-changing request may go ahead, else the reason to refuse it."""
        if not self.token_ok(token):
            return "wrong or missing token (use the URL printed when the robot started)"
        if not self.origin_ok(origin, host):
            return f"origin {origin!r} is not this page ({host})"
        return None
