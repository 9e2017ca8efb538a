"""Who may use the tablet page: whoever has the token printed at start, from the page's own origin.

The token keeps other people on the network out; the Origin check keeps other web pages, open in
the same browser, from pressing buttons through it (a cross-site WebSocket carries their origin).

A tablet that once opened the page with the token also gets a *pass* (an HttpOnly cookie) derived
from the robot's pairing secret (pairing.py). The secret outlives the run, the token does not: after
a restart with a new token, a paired tablet finds the robot again without retyping an address.
"""
from __future__ import annotations

import base64
import hashlib
import hmac
import secrets
from urllib.parse import urlsplit

PASS_LABEL = b"interbot tablet pass 1"


def new_token() -> str:
    return secrets.token_urlsafe(16)


def _same(given: str | None, expected: str | None) -> bool:
    return (given is not None and expected is not None
            and hmac.compare_digest(given.encode(), expected.encode()))


class Guard:
    def __init__(self, token: str, secret: bytes | None = None) -> None:
        self.token = token
        self.tablet_pass = (None if secret is None else base64.urlsafe_b64encode(
            hmac.new(secret, PASS_LABEL, hashlib.sha256).digest()[:18]).decode())

    def token_ok(self, given: str | None) -> bool:
        return _same(given, self.token)

    def pass_ok(self, given: str | None) -> bool:
        return _same(given, self.tablet_pass)

    def allowed(self, token: str | None, tablet_pass: str | None = None) -> bool:
        """This run's token, or the pass of a tablet paired before (a previous run's)."""
        return self.token_ok(token) or self.pass_ok(tablet_pass)

    @staticmethod
    def origin_ok(origin: str | None, host: str | None) -> bool:
        """The Origin header names the host (host:port) the request was sent to."""
        if not origin or not host:
            return False
        parts = urlsplit(origin)
        return parts.scheme in ("http", "https") and parts.netloc.lower() == host.lower()

    def why_refused(self, token: str | None, origin: str | None, host: str | None,
                    tablet_pass: str | None = None) -> str | None:
        """None when a state-changing request may go ahead, else the reason to refuse it."""
        if not self.allowed(token, tablet_pass):
            return "wrong or missing token (use the URL printed when the robot started)"
        if not self.origin_ok(origin, host):
            return f"origin {origin!r} is not this page ({host})"
        return None
