"""The tablet page's server, driven as a browser would be (HTTP and a WebSocket over 127.0.0.1):
who may connect, what every page sees, and which presses reach the robot."""
from __future__ import annotations

import asyncio
import json
import threading
import urllib.error
import urllib.request

import pytest
import websockets

from robots.exceptions import RobotError
from robots.tablet import WebTouchScreen, parse_address
from robots.tablet.screen import ScreenContent


@pytest.fixture
def tablet():
    screen = WebTouchScreen("127.0.0.1", 0)
    yield screen
    screen.close()


def origin(screen) -> str:
    return screen.url.split("/?")[0]


def socket_url(screen, token: str | None = None) -> str:
    url = screen.url.replace("http://", "ws://").replace("/?", "/ws?")
    return url if token is None else url.split("token=")[0] + f"token={token}"


async def next_screen(ws) -> dict:
    while True:
        message = json.loads(await asyncio.wait_for(ws.recv(), 10))
        if message["type"] == "screen":
            return message["screen"]


def test_the_page_needs_the_token(tablet):
    with urllib.request.urlopen(tablet.url) as page:
        html = page.read().decode()
        assert page.headers["Referrer-Policy"] == "no-referrer"
    assert "/static/tablet.js" in html and "http" not in html.replace("http-equiv", "")
    bad = tablet.url.split("token=")[0] + "token=guess"
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(bad)
    assert refused.value.code == 403


def test_a_websocket_needs_the_token_and_the_page_origin(tablet):
    async def attempt(url, from_origin):
        async with websockets.connect(url, origin=from_origin) as ws:
            return await next_screen(ws)

    assert asyncio.run(attempt(socket_url(tablet), origin(tablet)))["mode"] == "idle"
    for url, from_origin in ((socket_url(tablet, "guess"), origin(tablet)),
                             (socket_url(tablet), "http://evil.example"),
                             (socket_url(tablet), None)):
        with pytest.raises(websockets.exceptions.InvalidStatus) as refused:
            asyncio.run(attempt(url, from_origin))
        assert refused.value.response.status_code == 403
    assert tablet.take_press() is None


def test_two_pages_see_the_same_screen_and_a_reconnecting_page_gets_it_back(tablet):
    async def scenario():
        async with websockets.connect(socket_url(tablet), origin=origin(tablet)) as one, \
                   websockets.connect(socket_url(tablet), origin=origin(tablet)) as two:
            assert (await next_screen(one))["mode"] == (await next_screen(two))["mode"] == "idle"
            tablet.show("q1", "Coffee?", ("yes", "no"))
            first, second = await next_screen(one), await next_screen(two)
            assert first == second
            assert first["text"] == "Coffee?" and first["buttons"] == ["yes", "no"]
        tablet.caption("Please answer on my screen.")
        async with websockets.connect(socket_url(tablet), origin=origin(tablet)) as again:
            back = await next_screen(again)
        return first, back

    first, back = asyncio.run(scenario())
    assert back["prompt"] == "q1" and back["caption"] == "Please answer on my screen."
    assert back["v"] > first["v"]


def test_presses_for_the_shown_question_are_queued_others_refused(tablet):
    tablet.show("q1", "Coffee?", ("yes", "no"))

    async def presses():
        replies = []
        async with websockets.connect(socket_url(tablet), origin=origin(tablet)) as ws:
            await next_screen(ws)
            for prompt, value in (("q1", "maybe"), ("q0", "yes"), ("q1", "no")):
                await ws.send(json.dumps({"type": "press", "prompt": prompt, "value": value}))
                while (reply := json.loads(await ws.recv()))["type"] == "screen":
                    pass
                replies.append(reply["type"])
            await ws.send("not json")
            replies.append(json.loads(await ws.recv())["type"])
            await ws.send(b"\x00\x01")
            replies.append(json.loads(await ws.recv())["type"])
        return replies

    assert asyncio.run(presses()) == ["refused", "refused", "accepted", "refused", "refused"]
    assert tablet.take_press() == ("q1", "no")
    assert tablet.take_press() is None
    assert tablet.take_press_from() is None


def test_pictures_go_by_url_never_inside_the_json(tablet, tmp_path):
    picture = tmp_path / "map.png"
    picture.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 8)
    tablet.display("Room N2 is down the hall.", str(picture))
    snapshot = tablet.content.snapshot()
    assert snapshot["mode"] == "info" and snapshot["picture"] == "/picture/1"
    assert len(json.dumps(snapshot)) < 200
    base = origin(tablet)
    with urllib.request.urlopen(f"{base}/picture/1?token={tablet.guard.token}") as response:
        assert response.read() == picture.read_bytes()
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(f"{base}/picture/1?token=guess")
    assert refused.value.code == 403


def test_typed_answers_are_accepted_only_where_the_question_takes_text():
    content = ScreenContent()
    content.show("name", "Your name?", ("skip",), typed=False)
    assert "not one of the answers" in content.press("name", "Ada")
    content.show("name", "Your name?", ("skip",), typed=True)
    assert content.press("name", "  Ada  ") is None
    assert "characters" in content.press("name", "x" * 500)
    assert content.take_press() == ("name", "Ada")


def test_showing_the_same_screen_again_pushes_nothing():
    content, pushed = ScreenContent(), []
    content.listeners.append(lambda: pushed.append(content.version))
    content.show("q1", "Coffee?", ("yes", "no"), False)
    content.show("q1", "Coffee?", ("yes", "no"), False)
    content.clear()
    assert pushed == [1, 2]


def test_presses_from_many_threads_are_all_queued_once():
    content = ScreenContent()
    content.show("q", "Pick", tuple(str(i) for i in range(8)), False)
    threads = [threading.Thread(target=lambda i=i: [content.press("q", str(i)) for _ in range(50)])
               for i in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    taken = []
    while (press := content.take_press()) is not None:
        taken.append(press)
    assert len(taken) == 400 and {v for _, v in taken} == {str(i) for i in range(8)}


def test_addresses():
    assert parse_address("8080") == ("127.0.0.1", 8080)
    assert parse_address("0.0.0.0:0") == ("0.0.0.0", 0)
    assert parse_address("[::1]:8080") == ("::1", 8080)
    for bad in ("http", "host:99999", ""):
        with pytest.raises(RobotError, match=r"\[HOST:\]PORT"):
            parse_address(bad)


def test_a_port_in_use_is_a_clear_error(tablet):
    with pytest.raises(RobotError, match="cannot listen"):
        WebTouchScreen("127.0.0.1", tablet.server.port)
