"""The tablet: a touch screen that happens to be a browser.

`WebTouchScreen` (device.py) implements `robots.devices.TouchScreen`; it keeps what is shown in a
`ScreenContent` (screen.py) and serves it with a `TabletServer` (server.py: uvicorn in a
background thread) running the Starlette app of app.py, guarded by guard.py. The page itself is
static/ (HTML, CSS, JavaScript; nothing loaded from outside).
"""
from robots.tablet.device import WebTouchScreen, parse_address

__all__ = ["WebTouchScreen", "parse_address"]
