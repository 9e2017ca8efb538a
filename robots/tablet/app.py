"""The tablet's web app (Starlette): the page, its static files, pictures, and one WebSocket per
open page that pushes every new screen and carries the presses back. `/hello` tells a page that
lost the robot whether it is back and would let it in (200), is back with another key (403), or
is still gone (no answer at all).

Runs on the server's event loop; the robot's thread only touches `ScreenContent`, whose change
listener wakes the loop through `call_soon_threadsafe` (nothing here can block the tick).
"""
from __future__ import annotations

import asyncio
import json
import logging
from pathlib import Path

from starlette.applications import Starlette
from starlette.responses import FileResponse, HTMLResponse, PlainTextResponse, Response
from starlette.routing import Mount, Route, WebSocketRoute
from starlette.staticfiles import StaticFiles
from starlette.websockets import WebSocket, WebSocketDisconnect

from robots.tablet.guard import Guard
from robots.tablet.screen import ScreenContent

log = logging.getLogger("interbot.tablet")

STATIC = Path(__file__).parent / "static"
HEADERS = {
    "Cache-Control": "no-store",
    "Referrer-Policy": "no-referrer",      # the token is in the URL: never pass it on
    "Content-Security-Policy": "default-src 'self'; img-src 'self'; connect-src 'self'; "
                               "style-src 'self'; script-src 'self'; frame-ancestors 'none'",
    "X-Content-Type-Options": "nosniff",
}
REFUSED_CODE = 4403        # WebSocket close code: wrong token or origin
PASS_MAX_AGE = 365 * 24 * 3600    # s a paired tablet keeps its pass (the cookie)


def pass_cookie(url) -> str:
    """The pass's cookie name; cookies ignore the port, so two robots on one host keep theirs."""
    return f"interbot_pass_{url.port or 80}"


class Hub:
    """The open pages: each waits on its own event, set whenever the screen changes."""

    def __init__(self, content: ScreenContent) -> None:
        self.content = content
        self.loop: asyncio.AbstractEventLoop | None = None
        self.waiting: set[asyncio.Event] = set()
        content.listeners.append(self.changed)

    def changed(self) -> None:
        """Called from the robot's thread: wake every page's sender on the server's loop."""
        loop = self.loop
        if loop is not None and not loop.is_closed():
            try:
                loop.call_soon_threadsafe(self._wake)
            except RuntimeError:      # the loop closed in between: nobody is listening
                pass

    def _wake(self) -> None:
        for event in self.waiting:
            event.set()

    @property
    def connected(self) -> int:
        return len(self.waiting)


def build_app(content: ScreenContent, guard: Guard) -> Starlette:
    hub = Hub(content)

    def allowed(request) -> bool:
        return guard.allowed(request.query_params.get("token"),
                             request.cookies.get(pass_cookie(request.url)))

    async def page(request) -> Response:
        if not allowed(request):
            return PlainTextResponse("403: wrong or missing token; open the URL printed when "
                                     "the robot started\n", status_code=403, headers=HEADERS)
        response = HTMLResponse((STATIC / "index.html").read_text(encoding="utf-8"),
                                headers=HEADERS)
        if guard.tablet_pass is not None:      # pair this tablet: it finds the next run too
            response.set_cookie(pass_cookie(request.url), guard.tablet_pass,
                                max_age=PASS_MAX_AGE, httponly=True, samesite="strict")
        return response

    async def hello(request) -> Response:
        if not allowed(request):
            return PlainTextResponse("403: this robot does not know this tablet\n",
                                     status_code=403, headers=HEADERS)
        return Response(status_code=204, headers=HEADERS)

    async def picture(request) -> Response:
        if not allowed(request):
            return PlainTextResponse("403: wrong or missing token\n", status_code=403)
        path = content.picture_path(request.path_params["number"])
        if path is None or not path.is_file():
            return PlainTextResponse("404: no such picture\n", status_code=404)
        return FileResponse(path, headers={"Cache-Control": "private, max-age=3600"})

    async def socket(websocket: WebSocket) -> None:
        reason = guard.why_refused(websocket.query_params.get("token"),
                                   websocket.headers.get("origin"), websocket.headers.get("host"),
                                   websocket.cookies.get(pass_cookie(websocket.url)))
        if reason is not None:
            log.warning("tablet: refused a connection: %s", reason)
            await websocket.close(code=REFUSED_CODE, reason=reason[:120])
            return
        await websocket.accept()
        hub.loop = asyncio.get_running_loop()
        wake = asyncio.Event()
        hub.waiting.add(wake)
        sender = asyncio.create_task(_send_screens(websocket, content, wake))
        try:
            while True:
                message = await websocket.receive()
                if message["type"] == "websocket.disconnect":
                    break
                text = message.get("text")
                reply = (_handle(content, text) if text is not None
                         else {"type": "refused", "reason": "send text, not bytes"})
                await websocket.send_text(json.dumps(reply))
        except WebSocketDisconnect:
            pass
        finally:
            hub.waiting.discard(wake)
            sender.cancel()

    async def no_icon(request) -> Response:
        return Response(status_code=204)

    app = Starlette(routes=[
        Route("/", page),
        Route("/hello", hello),
        Route("/favicon.ico", no_icon),
        Route("/picture/{number:int}", picture),
        WebSocketRoute("/ws", socket),
        Mount("/static", StaticFiles(directory=STATIC), name="static"),
    ])
    app.state.hub = hub
    return app


async def _send_screens(websocket: WebSocket, content: ScreenContent, wake: asyncio.Event) -> None:
    """Send the current screen now and after every change (a burst of changes sends the newest)."""
    sent = -1
    try:
        while True:
            snapshot = content.snapshot()
            if snapshot["v"] != sent:
                await websocket.send_text(json.dumps({"type": "screen", "screen": snapshot}))
                sent = snapshot["v"]
            await wake.wait()
            wake.clear()
    except asyncio.CancelledError:
        return
    except Exception as exc:    # the page went away mid-send: its receive loop ends it
        log.debug("tablet: sending to a page failed: %s", exc)


def _handle(content: ScreenContent, message: str) -> dict:
    """One message from the page; a press is checked against the screen before it is queued."""
    try:
        data = json.loads(message)
    except ValueError:
        return {"type": "refused", "reason": "not JSON"}
    if not isinstance(data, dict) or data.get("type") != "press":
        return {"type": "refused", "reason": "unknown message (expected a press)"}
    prompt, value = data.get("prompt"), data.get("value")
    page, name = data.get("page", ""), data.get("name", "")
    if not all(isinstance(field, str) for field in (prompt, value, page, name)):
        return {"type": "refused", "reason": "a press needs a prompt and a value (strings)"}
    reason = content.press(prompt, value, page, name)
    if reason is not None:
        return {"type": "refused", "reason": reason, "prompt": prompt,
                "answered": content.answered(prompt)}
    return {"type": "accepted", "prompt": prompt, "value": value}
